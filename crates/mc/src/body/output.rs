//! Normalized results of a body run, each with its standard error, per unit incident power:
//! - totals: Rs (specular, exact), R (diffuse, through the entry side), T (through a slab's far
//!   face, unscattered light included), A (absorbed) [-];
//! - per surface, the exits per unit area of the body's surface [cm⁻²] by (radius along the
//!   surface, azimuth), Σw / (N · ΔA_i · Δφ/π) with ΔA_i the band's area (the azimuth bins fold
//!   ±φ, so a bin holds 2Δφ of the 2π about the entry), and the same integrated over azimuth;
//! - per surface, the exits per unit solid angle of the exit direction [sr⁻¹], Σw / (N · 2π
//!   sin((k+½)Δθ) Δθ) as MCML's `Rd_a`;
//! - per surface, the shift ⟨x⟩ = Σw·x / Σw and the mean radius ⟨s⟩ = Σw·s / Σw [cm] (ratio
//!   estimators: standard error by the delta method, var = N/(N − 1) · Σ(b − r·a)² / (Σa)² for
//!   per-photon scores a = w, b = w·x and ratio r);
//! - per surface, the same three over the window, the exits within the grid's reach
//!   s < nr·dr ([`Window`]): what a renderer's gather or blur around the entry can place.
//!
//! Standard errors of means of per-photon scores as in [`crate::Output`].

use serde::{Deserialize, Serialize};

use super::shape::Shape;
use super::spec::BodySpec;
use super::surface::SurfaceLayout;
use crate::exitance::bin_solid_angle;
use crate::output::{Estimate, estimate};
use crate::tally::Accumulator;

/// What leaves through one surface of the body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SurfaceExits {
    /// Exits per unit area of the surface [cm⁻²] by (radius, azimuth), [ir][iφ] row-major.
    pub profile: Vec<Estimate>,
    /// Exits per unit area of the surface [cm⁻²] by radius, over every azimuth: the body's
    /// `Rd(r)`.
    pub radial: Vec<Estimate>,
    /// Exits per unit solid angle of the direction in air [sr⁻¹] by angle to the local normal.
    pub exit_angle: Vec<Estimate>,
    /// Mean exit coordinate along the plane of incidence [cm] (radius · cos azimuth: positive
    /// ahead of the entry, where the beam travels along the surface); NaN if nothing left here.
    pub shift: Estimate,
    /// Mean distance of the exits from the entry point along the surface [cm]; NaN if nothing
    /// left here.
    pub mean_radius: Estimate,
    /// The exits within the grid's reach.
    pub window: Window,
}

/// The exits of one surface within the grid's reach nr·dr of the entry along the surface (on a
/// slab's far face, of the point below it): the radial bins' light less what the last collects
/// beyond its outer edge. Each number is a per-photon estimate (a photon leaves once), so its
/// standard error is exact, not the bins' combined in quadrature (which would leave out the
/// negative covariance between disjoint bins and overstate it).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// The reach nr·dr [cm].
    pub reach_cm: f64,
    /// The exits within it per unit incident power [-].
    pub r: Estimate,
    /// Their mean coordinate along the plane of incidence [cm], as [`SurfaceExits::shift`]; NaN
    /// if none.
    pub shift: Estimate,
    /// Their mean distance from the entry along the surface [cm], as
    /// [`SurfaceExits::mean_radius`]; NaN if none.
    pub mean_radius: Estimate,
}

/// Everything a body run reports, normalized.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyOutput {
    /// What was run.
    pub spec: BodySpec,
    /// Interaction events (drops) over all photons.
    pub interactions: u64,
    /// Specular reflectance at entry [-] (exact: the unpolarized Fresnel reflectance at θ).
    pub rs: f64,
    /// Diffuse reflectance through the entry side [-].
    pub r: Estimate,
    /// Transmittance through a slab's far face [-]; 0 ± 0 for a sphere or cavity.
    pub t: Estimate,
    /// Absorbed fraction [-].
    pub a: Estimate,
    /// What leaves through the entry side (a sphere's or cavity's whole surface).
    pub reflected: SurfaceExits,
    /// What leaves through a slab's far face; `None` for a sphere or cavity.
    pub transmitted: Option<SurfaceExits>,
}

impl BodyOutput {
    pub(crate) fn from_accumulator(
        spec: &BodySpec,
        acc: &Accumulator,
        layout: SurfaceLayout,
        rs: f64,
    ) -> Self {
        let n = acc.photons.max(1);
        let shape = Shape::from(spec.body);
        let reflected = surface(acc, layout, shape, layout.surface(true));
        let transmitted = spec
            .body
            .has_far_face()
            .then(|| surface(acc, layout, shape, layout.surface(false)));
        let total = |entry_side: bool| {
            let o = layout.surface(entry_side);
            let (s, s2) = (0..layout.cells()).fold((0.0, 0.0), |(s, s2), i| {
                (s + acc.s(o + i), s2 + acc.s2(o + i))
            });
            estimate(s, s2, n, 1.0)
        };
        let ia = layout.tally_layout().a_total(0);
        BodyOutput {
            spec: *spec,
            interactions: acc.interactions,
            rs,
            r: total(true),
            t: total(false),
            a: estimate(acc.s(ia), acc.s2(ia), n, 1.0),
            reflected,
            transmitted,
        }
    }
}

/// The surface whose block starts at `o`, normalized.
fn surface(acc: &Accumulator, layout: SurfaceLayout, shape: Shape, o: usize) -> SurfaceExits {
    let g = layout.grid;
    let n = acc.photons.max(1);
    let area = |ir: usize| shape.band_area(ir as f64 * g.dr, (ir + 1) as f64 * g.dr);
    // A band wholly beyond a sphere's antipode has no area and no exits.
    let per_area = |s: f64, s2: f64, a: f64| {
        if a > 0.0 {
            estimate(s, s2, n, 1.0 / a)
        } else {
            Estimate {
                value: 0.0,
                se: 0.0,
            }
        }
    };
    let fold = g.d_azimuth() / std::f64::consts::PI;
    let cell = |i: usize| (acc.s(o + i), acc.s2(o + i));
    let profile = (0..layout.cells())
        .map(|i| {
            let (s, s2) = cell(i);
            per_area(s, s2, area(i / g.n_azimuth) * fold)
        })
        .collect();
    let radial = (0..g.nr)
        .map(|ir| {
            let (s, s2) = (0..g.n_azimuth)
                .map(|k| cell(ir * g.n_azimuth + k))
                .fold((0.0, 0.0), |(a, b), (s, s2)| (a + s, b + s2));
            per_area(s, s2, area(ir))
        })
        .collect();
    let exit_angle = (0..g.n_exit)
        .map(|k| {
            let (s, s2) = cell(layout.exits() + k);
            estimate(s, s2, n, 1.0 / bin_solid_angle(k, g.d_exit()))
        })
        .collect();
    let (sw, sw2) = (0..layout.cells())
        .map(cell)
        .fold((0.0, 0.0), |(a, b), (s, s2)| (a + s, b + s2));
    // Moments whose weights' sums are `a`: Σb at k, Σab at k + 1.
    let moment = |a: (f64, f64), k: usize| ratio(a, cell(k), acc.s(o + k + 1), n);
    let m = layout.moments();
    let w = layout.window();
    let (ww, ww2) = cell(w);
    SurfaceExits {
        profile,
        radial,
        exit_angle,
        shift: moment((sw, sw2), m),
        mean_radius: moment((sw, sw2), m + 2),
        window: Window {
            reach_cm: layout.reach(),
            r: estimate(ww, ww2, n, 1.0),
            shift: moment((ww, ww2), w + 1),
            mean_radius: moment((ww, ww2), w + 3),
        },
    }
}

/// The ratio Σb/Σa of per-photon scores a, b over `n` photons, from (Σa, Σa²), (Σb, Σb²) and
/// Σab, with the delta method's standard error √(N/(N − 1) · Σ(b − r·a)²) / Σa,
/// Σ(b − r·a)² = Σb² − 2rΣab + r²Σa².
fn ratio((sa, sa2): (f64, f64), (sb, sb2): (f64, f64), sab: f64, n: u64) -> Estimate {
    if sa <= 0.0 {
        return Estimate {
            value: f64::NAN,
            se: f64::NAN,
        };
    }
    let r = sb / sa;
    let nf = n as f64;
    let spread = (sb2 - 2.0 * r * sab + r * r * sa2).max(0.0);
    let se = if n > 1 {
        (nf / (nf - 1.0) * spread).sqrt() / sa
    } else {
        0.0
    };
    Estimate { value: r, se }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The delta method's error of a ratio: for b = c·a exactly, the ratio is c with no error;
    /// for independent a and b it is the propagated relative error.
    #[test]
    fn ratio_of_proportional_scores_has_no_error() {
        let a = [0.5, 0.25, 1.0, 0.0];
        let c = 1.7;
        let sa = a.iter().sum::<f64>();
        let sa2 = a.iter().map(|x| x * x).sum::<f64>();
        let e = ratio((sa, sa2), (c * sa, c * c * sa2), c * sa2, a.len() as u64);
        assert!((e.value - c).abs() < 1e-15 && e.se < 1e-7, "{e:?}");
        let none = ratio((0.0, 0.0), (0.0, 0.0), 0.0, 4);
        assert!(none.value.is_nan() && none.se.is_nan());
    }
}
