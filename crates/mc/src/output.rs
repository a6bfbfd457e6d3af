//! Normalized results of a run, in MCML's units, each with its standard error.
//!
//! Normalization (MCML's `ScaleRdTt`/`ScaleA`), N photons:
//! - `Rd(r)`, `Tt(r)` per unit area [cm⁻²]: Σw / (N · 2π (i+½) dr²);
//! - `Rd(α)`, `Tt(α)` per solid angle [sr⁻¹]: Σw / (N · 2π sin((i+½)da) da);
//! - `Rd(r,α)`, `Tt(r,α)` [cm⁻² sr⁻¹]: Σw / (N · 4π² dr² (i+½) sin(da/2) sin(2α_j)), MCML's
//!   area perpendicular to the exit direction times solid angle;
//! - `A(r,z)` [cm⁻³], `A(z)` [cm⁻¹], `A_l`, `A`, `Rd`, `Tt` [-].
//!
//! The standard error of a mean of N per-photon scores x is √((⟨x²⟩ − ⟨x⟩²)/(N−1)).
//! `Rd(r)` excludes the specular reflection, exactly as MCML's `Rd_r`.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::grid::Grid;
use crate::tally::Accumulator;

/// A Monte Carlo estimate and its standard error (same unit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// The mean.
    pub value: f64,
    /// Its standard error.
    pub se: f64,
}

/// Everything MCML reports for one run (one channel), normalized.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// The grid this channel was tallied on [cm].
    pub grid: Grid,
    /// Photons traced.
    pub photons: u64,
    /// Interaction events (drops) over all photons.
    pub interactions: u64,
    /// Specular reflectance at entry [-] (deterministic).
    pub rsp: f64,
    /// Total diffuse reflectance [-].
    pub rd: Estimate,
    /// Absorbed fraction [-].
    pub a: Estimate,
    /// Total transmittance [-].
    pub tt: Estimate,
    /// Absorbed fraction per layer [-].
    pub a_l: Vec<Estimate>,
    /// Absorption per unit depth [cm⁻¹]; empty when not tallied; standard errors NaN unless
    /// `TallySet::absorption_rz_se`.
    pub a_z: Vec<Estimate>,
    /// Absorption density [cm⁻³], [ir][iz] row-major; empty when not tallied; standard errors
    /// NaN unless `TallySet::absorption_rz_se`.
    pub a_rz: Vec<Estimate>,
    /// Diffuse reflectance per unit area [cm⁻²].
    pub rd_r: Vec<Estimate>,
    /// Diffuse reflectance per solid angle [sr⁻¹].
    pub rd_a: Vec<Estimate>,
    /// [cm⁻² sr⁻¹], [ir][ia] row-major.
    pub rd_ra: Vec<Estimate>,
    /// Transmittance per unit area [cm⁻²].
    pub tt_r: Vec<Estimate>,
    /// Transmittance per solid angle [sr⁻¹].
    pub tt_a: Vec<Estimate>,
    /// [cm⁻² sr⁻¹], [ir][ia] row-major.
    pub tt_ra: Vec<Estimate>,
    /// Diffuse reflectance on the surface grid [cm⁻²], [iy][ix] row-major, 2n + 1 cells of side
    /// dr per axis, cell (i, j) centred at ((j − n)·dr, (i − n)·dr); empty when not tallied.
    pub rd_xy: Vec<Estimate>,
}

/// Mean and standard error of per-photon scores from Σx, Σx², N, times `scale`.
pub(crate) fn estimate(s: f64, s2: f64, n: u64, scale: f64) -> Estimate {
    let nf = n as f64;
    let mean = s / nf;
    let var = if n > 1 {
        ((s2 / nf - mean * mean) / (nf - 1.0)).max(0.0)
    } else {
        0.0
    };
    Estimate {
        value: mean * scale,
        se: var.sqrt() * scale,
    }
}

impl Output {
    /// Normalizes channel `c` of an accumulator. `grid` is that channel's grid in cm (batch runs
    /// tally every channel on its own grid).
    pub fn from_accumulator(acc: &Accumulator, c: usize, grid: Grid, rsp: f64) -> Self {
        let l = acc.layout;
        let n = acc.photons.max(1);
        // Loops run over this channel's grid; strides are the layout's (the largest of a batch).
        let (nr, na, nz) = (grid.nr, grid.na, grid.nz);
        let (sa, sz) = (l.na, l.nz);
        let da = grid.da();
        let area = |ir: usize| 2.0 * PI * (ir as f64 + 0.5) * grid.dr * grid.dr;
        let solid = |ia: usize| 2.0 * PI * ((ia as f64 + 0.5) * da).sin() * da;
        // MCML's exact Rd_ra scale: 4π² dr² (i+½) sin(da/2) sin(2α_j).
        let area_solid = |ir: usize, ia: usize| {
            4.0 * PI
                * PI
                * grid.dr
                * grid.dr
                * (ir as f64 + 0.5)
                * (da / 2.0).sin()
                * (2.0 * (ia as f64 + 0.5) * da).sin()
        };

        // 2D exit tallies, and their marginals: one exit per photon makes Σw² additive.
        let exit = |off: usize| {
            let at = |ir: usize, ia: usize| (acc.s(off + ir * sa + ia), acc.s2(off + ir * sa + ia));
            let add = |(s, s2): (f64, f64), (a, b): (f64, f64)| (s + a, s2 + b);
            let ra: Vec<Estimate> = (0..nr * na)
                .map(|i| {
                    let (s, s2) = at(i / na, i % na);
                    estimate(s, s2, n, 1.0 / area_solid(i / na, i % na))
                })
                .collect();
            let r: Vec<Estimate> = (0..nr)
                .map(|ir| {
                    let (s, s2) = (0..na).map(|ia| at(ir, ia)).fold((0.0, 0.0), add);
                    estimate(s, s2, n, 1.0 / area(ir))
                })
                .collect();
            let a: Vec<Estimate> = (0..na)
                .map(|ia| {
                    let (s, s2) = (0..nr).map(|ir| at(ir, ia)).fold((0.0, 0.0), add);
                    estimate(s, s2, n, 1.0 / solid(ia))
                })
                .collect();
            let (s, s2) = (0..nr * na)
                .map(|i| at(i / na, i % na))
                .fold((0.0, 0.0), add);
            (ra, r, a, estimate(s, s2, n, 1.0))
        };
        let (rd_ra, rd_r, rd_a, rd) = exit(l.rd_ra(c));
        let (tt_ra, tt_r, tt_a, tt) = exit(l.tt_ra(c));

        let a_l = (0..l.layers)
            .map(|i| estimate(acc.s(l.a_l(c) + i), acc.s2(l.a_l(c) + i), n, 1.0))
            .collect();
        let a = estimate(acc.s(l.a_total(c)), acc.s2(l.a_total(c)), n, 1.0);
        let (a_rz, a_z) = if l.rz {
            // Without per-photon moments the standard errors are not estimated.
            let cell = |j: usize, scale: f64| {
                let e = estimate(acc.s(j), acc.s2(j), n, scale);
                Estimate {
                    se: if l.rz_se { e.se } else { f64::NAN },
                    ..e
                }
            };
            let o = l.a_rz(c);
            let a_rz = (0..nr * nz)
                .map(|i| cell(o + (i / nz) * sz + i % nz, 1.0 / (area(i / nz) * grid.dz)))
                .collect();
            let o = l.a_z(c);
            let a_z = (0..nz).map(|i| cell(o + i, 1.0 / grid.dz)).collect();
            (a_rz, a_z)
        } else {
            (Vec::new(), Vec::new())
        };
        let o = l.rd_xy(c);
        let rd_xy = (0..l.xy_cells())
            .map(|i| estimate(acc.s(o + i), acc.s2(o + i), n, 1.0 / (grid.dr * grid.dr)))
            .collect();
        Output {
            rd_xy,
            grid,
            photons: acc.photons,
            interactions: acc.interactions,
            rsp,
            rd,
            a,
            tt,
            a_l,
            a_z,
            a_rz,
            rd_r,
            rd_a,
            rd_ra,
            tt_r,
            tt_a,
            tt_ra,
        }
    }
}
