//! `mc`'s reflectance of a half-space at oblique incidence, Rd(x, y; θ), for the directional
//! surface gather: laid on the modified tangent plane of Frisvad et al. 2014 (the plane through
//! x_i that holds x_o, closest to x_i's tangent plane; [`DirectionalTable::response`]) and
//! carrying the true entry angle's reflectance, it is the exact half-space BSSRDF for the entry
//! direction on a flat surface. [`gather_tables`] builds what a surface gather reads besides its
//! radial profile: the angle tables and (directional) this table.

use crate::angle_tables::AngleTables;
use crate::error::{Result, ShadingError};
use crate::shape::{SHAPE_RUNS_PER_CHANNEL, ShapeTable};
use serde::Serialize;

/// Which Monte Carlo BSSRDF the surface gather integrates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Bssrdf {
    /// Rd(|x_o − x_i|) × ρ(θ_i)/ρ(0).
    Radial,
    /// Rd(x, y; θ_i) in the plane of incidence.
    Directional,
    /// Rd(x, y; θ_i) as `Directional`, scaled for the body's shape at the curvature of the chord
    /// from entry to exit ([`crate::ShapeTable`]): E(κ, θ_i) times the table with its lengths
    /// stretched by ⟨s⟩(κ)/⟨s⟩(0).
    Shape,
}

/// The half width n of the directional tables [`gather_tables`] builds: 385 × 193
/// cells per channel and angle.
pub const DIRECTIONAL_HALF_WIDTH: usize = 192;

/// The angles of a [`DirectionalTable`] [degrees]: 0°, 10°, …, 80° and 85°.
pub const DIRECTIONAL_ANGLES: [f64; 10] =
    [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0];

/// `mc`'s reflectance Rd(x, y; θ) of a half-space per channel at each of
/// [`DIRECTIONAL_ANGLES`], for a beam travelling towards +x, folded onto y ≥ 0 (the mean of the
/// cells at ±y, Rd being even in y).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DirectionalTable {
    /// Half width n: x cells −n…n, y cells 0…n.
    pub half_width: usize,
    /// Each channel's cell side [cm].
    pub cell_cm: [f64; 3],
    /// Rd [cm⁻²], [angle][channel][iy][ix] with iy in 0..=n and ix in 0..=2n; cell (ix, iy) is
    /// centred at ((ix − n)·s, iy·s).
    pub rd: Vec<f32>,
    /// `mc`'s total diffuse reflectance per angle and channel (all of it, also beyond the table)
    /// with its standard error [-].
    pub totals: Vec<[mc::Estimate; 3]>,
}

impl DirectionalTable {
    /// The tables of the three channels of `spec` (a profile-only batch of one material), each
    /// angle a run of `spec.photons` per channel with seed `spec.seed` + angle index; channel c's
    /// cells of side `reach_cm[c]`/n. `progress` receives photon counts.
    pub fn from_mc(
        spec: &mc::BatchSpec,
        half_width: usize,
        reach_cm: [f64; 3],
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<DirectionalTable> {
        if spec.channels.len() != 3 {
            return Err(ShadingError::invalid(
                "directional table: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        if !(8..=512).contains(&half_width) {
            return Err(ShadingError::invalid(
                "directional table: half width",
                half_width,
                "must lie in 8..=512 cells",
            ));
        }
        if let Some(r) = reach_cm.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(ShadingError::invalid(
                "directional table: reach",
                r,
                "must be positive [cm]",
            ));
        }
        let n = half_width;
        let cell_cm = reach_cm.map(|r| r / n as f64);
        let (side, rows) = (2 * n + 1, n + 1);
        let mut rd = Vec::with_capacity(DIRECTIONAL_ANGLES.len() * 3 * side * rows);
        let mut totals = Vec::new();
        mc::incidence::surface_grid_runs(
            spec,
            n,
            &cell_cm,
            &DIRECTIONAL_ANGLES,
            progress,
            |_, out| {
                for o in out {
                    for iy in 0..rows {
                        let (a, b) = (n + iy, n - iy);
                        for ix in 0..side {
                            let v =
                                0.5 * (o.rd_xy[a * side + ix].value + o.rd_xy[b * side + ix].value);
                            rd.push(v as f32);
                        }
                    }
                }
                totals.push([out[0].rd, out[1].rd, out[2].rd]);
            },
        )?;
        Ok(DirectionalTable {
            half_width: n,
            cell_cm,
            rd,
            totals,
        })
    }

    /// Checks the table's shape and entries; the error names the field.
    pub fn validate(&self) -> Result<()> {
        let n = self.half_width;
        let want = DIRECTIONAL_ANGLES.len() * 3 * (n + 1) * (2 * n + 1);
        if self.rd.len() != want {
            return Err(ShadingError::invalid(
                "directional table",
                self.rd.len(),
                format!("must hold {want} cells for half width {n}"),
            ));
        }
        if let Some(v) = self.rd.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(ShadingError::invalid(
                "directional table",
                v,
                "Rd must be finite and ≥ 0 in every cell",
            ));
        }
        if self.totals.len() != DIRECTIONAL_ANGLES.len() {
            return Err(ShadingError::invalid(
                "directional table: totals",
                self.totals.len(),
                format!("must hold one per angle, {}", DIRECTIONAL_ANGLES.len()),
            ));
        }
        if let Some(v) = self
            .totals
            .iter()
            .flatten()
            .find(|e| !(e.value.is_finite() && e.value >= 0.0))
        {
            return Err(ShadingError::invalid(
                "directional table: totals",
                v.value,
                "each total reflectance must be finite and ≥ 0",
            ));
        }
        Ok(())
    }

    /// Channel `c` at angle index `k` and local (x, y) [cm] (y folded), as the shader reads it:
    /// bilinear between the cells' centres, the nodes at x = (ix − n)·s and |y| = iy·s, falling
    /// to 0 one cell beyond the outermost. Each node's tent integrates to s² (2s² for iy > 0,
    /// counted on both sides of the fold) and is symmetric about it, so the interpolant holds
    /// the cells' integral and centroid ([`DirectionalTable::integral`],
    /// [`DirectionalTable::centroid_cm`]) exactly; unlike the cells it is continuous, so two
    /// reads a little apart (a sample's entry and the gather's control variate's) differ a
    /// little, never by a whole cell's noise.
    pub fn at(&self, k: usize, c: usize, x: f64, y: f64) -> f64 {
        let n = self.half_width;
        let s = self.cell_cm[c];
        let (fx, fy) = (x / s + n as f64, y.abs() / s);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let node = |ix: f64, iy: f64| {
            if ix < 0.0 || ix > (2 * n) as f64 || iy > n as f64 {
                0.0
            } else {
                self.rd[((k * 3 + c) * (n + 1) + iy as usize) * (2 * n + 1) + ix as usize] as f64
            }
        };
        (1.0 - ty) * ((1.0 - tx) * node(x0, y0) + tx * node(x0 + 1.0, y0))
            + ty * ((1.0 - tx) * node(x0, y0 + 1.0) + tx * node(x0 + 1.0, y0 + 1.0))
    }

    /// The response at x_o per unit power entering at x_i [cm⁻²] for `d` = x_o − x_i [cm], the
    /// entry's unit normal `ni` and the unit direction towards the light `wi` (the shader's
    /// twin, shaders/mc_bssrdf.wgsl). The table is laid on the modified tangent plane of Frisvad
    /// et al. 2014 (§3.3), normal n* = n_i less its part along d (n_i where d is 0 or along
    /// n_i), which holds x_o: θ* = ∠(wi, n*), x along the propagation −wi projected on that
    /// plane, y across it, x² + y² = |d|². Its amount is the true entry angle's: the table at θ*
    /// times Rd(θ_i)/Rd(θ*), `mc`'s total reflectances (each linear in θ between the table's
    /// angles). On a flat surface
    /// (d ⊥ n_i) this is the table at θ_i in the plane of incidence.
    ///
    /// `exit` moves the exit point per channel ([`DirectionalTable::exit_shift`]; zeros for the
    /// separable BSSRDF): channel c reads the table at the in-plane coordinates of d + exit[c]
    /// on the plane that d defines.
    pub fn response(
        &self,
        d: glam::DVec3,
        ni: glam::DVec3,
        wi: glam::DVec3,
        exit: [glam::DVec3; 3],
    ) -> [f64; 3] {
        let r = d.length();
        let mut n_star = ni;
        if r > 0.0 {
            let tilted = ni - ni.dot(d / r) * (d / r);
            if tilted.length() > 1e-6 {
                n_star = tilted.normalize();
            }
        }
        let cos_star = wi.dot(n_star);
        let mut along = -wi + cos_star * n_star;
        if along.length() < 1e-4 {
            // Normal incidence: any direction in the plane (the shader's choice).
            let axis = if n_star.x.abs() > 0.9 {
                glam::DVec3::Y
            } else {
                glam::DVec3::X
            };
            along = axis - axis.dot(n_star) * n_star;
        }
        let along = along.normalize();
        let (k, f) = Self::angle_index(cos_star);
        let (star, entry) = (self.total_at(cos_star), self.total_at(wi.dot(ni)));
        std::array::from_fn(|c| {
            if star[c] > 0.0 {
                let dc = d + exit[c];
                let x = dc.dot(along);
                let y = (dc.length_squared() - x * x).max(0.0).sqrt();
                let v = (1.0 - f) * self.at(k, c, x, y) + f * self.at((k + 1).min(9), c, x, y);
                v * entry[c] / star[c]
            } else {
                0.0
            }
        })
    }

    /// The table's angle index and the weight of the next at cos θ: θ = 0°, 10°, …, 80° at
    /// indices 0–8, 85° at 9, held beyond.
    fn angle_index(cos_t: f64) -> (usize, f64) {
        let theta = cos_t.clamp(0.0, 1.0).acos().to_degrees();
        let t = if theta > 80.0 {
            8.0 + (theta - 80.0) / 5.0
        } else {
            theta / 10.0
        };
        let k = t.floor().min(9.0);
        (k as usize, (t - k).clamp(0.0, 1.0))
    }

    /// `mc`'s total diffuse reflectance at cos θ per channel, linear in θ between the table's
    /// angles.
    fn total_at(&self, cos_t: f64) -> [f64; 3] {
        let (k, f) = Self::angle_index(cos_t);
        let (a, b) = (self.totals[k], self.totals[(k + 1).min(9)]);
        std::array::from_fn(|c| (1.0 - f) * a[c].value + f * b[c].value)
    }

    /// ∫∫ Rd dx dy over the table at angle index `k` per channel [-] (the unfolded plane: rows
    /// y > 0 count twice).
    pub fn integral(&self, k: usize) -> [f64; 3] {
        self.moments(k).map(|(m0, _)| m0)
    }

    /// The centroid δ = ∫∫ x·Rd dx dy / ∫∫ Rd dx dy [cm] of the table at angle index `k` per
    /// channel (0 where it holds nothing): how far ahead of its entry, along the propagation, the
    /// light entering at that angle returns (`crate::EntryShift`'s moment, on this table's
    /// grid). By reciprocity also how far along the view ray's propagation over the surface the
    /// light seen at that exit angle last scattered ([`DirectionalTable::exit_shift`]).
    pub fn centroid_cm(&self, k: usize) -> [f64; 3] {
        self.moments(k)
            .map(|(m0, m1)| if m0 > 0.0 { m1 / m0 } else { 0.0 })
    }

    /// ∫∫ Rd dx dy and ∫∫ x·Rd dx dy at angle index `k` per channel (rows y > 0 count twice).
    fn moments(&self, k: usize) -> [(f64, f64); 3] {
        let n = self.half_width;
        std::array::from_fn(|c| {
            let s = self.cell_cm[c];
            let (mut m0, mut m1) = (0.0, 0.0);
            for iy in 0..=n {
                let mult = if iy == 0 { 1.0 } else { 2.0 };
                for ix in 0..=2 * n {
                    let i = ((k * 3 + c) * (n + 1) + iy) * (2 * n + 1) + ix;
                    let w = mult * self.rd[i] as f64;
                    m0 += w;
                    m1 += w * (ix as f64 - n as f64) * s;
                }
            }
            (m0 * s * s, m1 * s * s)
        })
    }

    /// Where the light a camera sees leaving at x_o (unit normal `no`, unit direction towards
    /// the camera `wo`) last scattered, relative to x_o, per channel [cm]: δ(θ_o) along the view
    /// ray's propagation over the surface, t_v = −wo less its part along `no` (zero where the
    /// camera looks along the normal, |t_v| ≤ 1e-4), δ the table's centroid at θ_o (linear in θ
    /// between its angles). The reciprocal of the entry's shift: a separable BSSRDF Rd(x_o −
    /// x_i; θ_i)·h(θ_o; θ_i) leaves it out, and the gathers evaluate Rd at x_o plus this offset.
    pub fn exit_shift(&self, no: glam::DVec3, wo: glam::DVec3) -> [glam::DVec3; 3] {
        let cos_o = no.dot(wo);
        let t = -wo + cos_o * no;
        if t.length() <= 1e-4 {
            return [glam::DVec3::ZERO; 3];
        }
        let (k, f) = Self::angle_index(cos_o.max(0.0));
        let (a, b) = (self.centroid_cm(k), self.centroid_cm((k + 1).min(9)));
        let t = t.normalize();
        std::array::from_fn(|c| ((1.0 - f) * a[c] + f * b[c]) * t)
    }

    /// The reach [cm] of each channel's table for a material: ln(10⁸)/σtr (where diffusion has
    /// fallen by 10⁸, so the light scattered deep into a shadow is kept: with ln(10⁴)/σtr, Skin1's
    /// blue stopped 0.63 cm from the entry and left the middle of a 1.3 cm shadow band black;
    /// 100 transport mean free paths without absorption), at most `r_max_cm`.
    pub fn reach(media: &[fit::analytic::Medium; 3], r_max_cm: f64) -> [f64; 3] {
        media.map(|m| {
            let sigma_tr = (3.0 * m.sigma_a * m.sigma_t_reduced()).sqrt();
            let r = if sigma_tr > 0.0 {
                1e8f64.ln() / sigma_tr
            } else {
                100.0 * m.transport_mfp()
            };
            r.min(r_max_cm)
        })
    }
}

/// The tables a surface gather of `bssrdf` reads for the material whose three channels `spec`
/// holds (a profile-only batch): the angle tables (incidence for [`Bssrdf::Radial`], exit for
/// all), for [`Bssrdf::Directional`] and [`Bssrdf::Shape`] the [`DirectionalTable`] of half
/// width [`DIRECTIONAL_HALF_WIDTH`] reaching [`DirectionalTable::reach`] within `r_max_cm` (the
/// gather's disc radius over √2, so every cell lies on the disc: the 3-D distance |x_o − x_i| is
/// never shorter than the disc radius), each run of `spec.photons` per channel and angle, and for
/// [`Bssrdf::Shape`] the [`ShapeTable`] with a third of those photons per run (as a render's).
/// `progress` receives photon counts.
pub fn gather_tables(
    spec: &mc::BatchSpec,
    bssrdf: Bssrdf,
    r_max_cm: f64,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<GatherTables> {
    let radial = bssrdf == Bssrdf::Radial;
    let angles = AngleTables::from_mc(spec, radial, true, progress)?;
    if radial {
        return Ok(GatherTables {
            angles,
            directional: None,
            shape: None,
        });
    }
    let media =
        [0, 1, 2].map(|c| fit::analytic::Medium::of_layer(&spec.channels[c].layer, spec.n_above));
    let reach = DirectionalTable::reach(&media, r_max_cm);
    let table = DirectionalTable::from_mc(spec, DIRECTIONAL_HALF_WIDTH, reach, progress)?;
    let shape = match bssrdf {
        Bssrdf::Shape => {
            let third = mc::BatchSpec {
                photons: (spec.photons / 3).max(1),
                ..spec.clone()
            };
            Some(ShapeTable::from_mc(&third, progress)?)
        }
        _ => None,
    };
    Ok(GatherTables {
        angles,
        directional: Some(table),
        shape,
    })
}

/// What [`gather_tables`] builds.
#[derive(Clone, Debug, PartialEq)]
pub struct GatherTables {
    /// ρ(θ)/ρ(0) (radial) and h(θ_o; θ_i).
    pub angles: AngleTables,
    /// Rd(x, y; θ) (directional and shape-aware).
    pub directional: Option<DirectionalTable>,
    /// What curved bodies return against the half-space (shape-aware).
    pub shape: Option<ShapeTable>,
}

/// The batch runs [`gather_tables`] makes (for progress bars: each traces `spec.photons` per
/// walk group): the angle tables', the directional tables' and the shape table's (in runs of a
/// whole batch's photons).
pub fn gather_batch_runs(bssrdf: Bssrdf) -> u64 {
    let angle_runs = AngleTables::angles(bssrdf == Bssrdf::Radial, true).len();
    let table_runs = match bssrdf {
        Bssrdf::Radial => 0,
        Bssrdf::Directional | Bssrdf::Shape => DIRECTIONAL_ANGLES.len(),
    };
    // The shape table's runs trace a third of the photons each, per channel.
    let shape_runs = match bssrdf {
        Bssrdf::Shape => SHAPE_RUNS_PER_CHANNEL.div_ceil(3),
        _ => 0,
    };
    (angle_runs + table_runs) as u64 + shape_runs
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A table whose angle k holds one cell, at x = (k − 2)·s in channel c (s = 0.01·(c + 1) cm),
    /// once on the axis and once off it (y = 2s, which stands for ±y).
    fn table() -> DirectionalTable {
        let n = 4;
        let mut rd = vec![0.0f32; DIRECTIONAL_ANGLES.len() * 3 * (n + 1) * (2 * n + 1)];
        for k in 0..DIRECTIONAL_ANGLES.len() {
            for c in 0..3 {
                let ix = (n + k).min(2 * n) - 2;
                for iy in [0, 2] {
                    rd[((k * 3 + c) * (n + 1) + iy) * (2 * n + 1) + ix] = 1.0;
                }
            }
        }
        DirectionalTable {
            half_width: n,
            cell_cm: [0.01, 0.02, 0.03],
            rd,
            totals: vec![
                [mc::Estimate {
                    value: 1.0,
                    se: 0.0
                }; 3];
                DIRECTIONAL_ANGLES.len()
            ],
        }
    }

    #[test]
    fn the_centroid_is_the_first_moment_along_the_propagation() {
        let t = table();
        for k in 0..DIRECTIONAL_ANGLES.len() {
            let cells = ((4 + k).min(8) - 2) as f64 - 4.0;
            for c in 0..3 {
                let want = cells * t.cell_cm[c];
                assert!((t.centroid_cm(k)[c] - want).abs() < 1e-12, "{k} {c}");
            }
        }
    }

    #[test]
    fn the_exit_shift_points_away_from_the_camera_by_the_centroid_at_the_view_angle() {
        let t = table();
        let n = DVec3::Y;
        // Straight above: no tangential direction, no shift.
        assert_eq!(t.exit_shift(n, n), [DVec3::ZERO; 3]);
        // At 30° from +y (index 3: 1 cell) and at 25° (half-way between 2 and 3: 0.5 cell),
        // along −x, away from the camera.
        for (deg, cells) in [(30.0f64, 1.0), (25.0, 0.5)] {
            let wo = DVec3::new(deg.to_radians().sin(), deg.to_radians().cos(), 0.0);
            for (c, s) in t.exit_shift(n, wo).iter().enumerate() {
                let want = DVec3::new(-cells * t.cell_cm[c], 0.0, 0.0);
                assert!((*s - want).length() < 1e-9, "{deg}° {c}: {s:?}");
            }
        }
    }

    /// The bilinear read is piecewise bilinear between the nodes, so the midpoint rule on a grid
    /// a quarter of a cell fine, aligned with them, integrates it exactly: over the whole plane
    /// (both sides of the fold) it must give the cells' integral and centroid.
    #[test]
    fn the_bilinear_read_keeps_the_cells_integral_and_centroid() {
        let mut t = table();
        // Uneven values, so that no symmetry hides an error.
        for (i, v) in t.rd.iter_mut().enumerate() {
            *v = ((i * 7919) % 13) as f32 + 0.5;
        }
        let n = t.half_width as i64;
        for (k, c) in [(0, 0), (4, 1), (9, 2)] {
            let s = t.cell_cm[c];
            let h = s / 4.0;
            let (mut m0, mut m1) = (0.0, 0.0);
            for i in -4 * (n + 2)..4 * (n + 2) {
                for j in -4 * (n + 2)..4 * (n + 2) {
                    let (x, y) = ((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
                    let v = t.at(k, c, x, y) * h * h;
                    m0 += v;
                    m1 += v * x;
                }
            }
            let (want0, want1) = (t.integral(k)[c], t.centroid_cm(k)[c]);
            assert!((m0 / want0 - 1.0).abs() < 1e-9, "{k} {c}: {m0} vs {want0}");
            assert!(
                (m1 / m0 - want1).abs() < 1e-9 * s,
                "{k} {c}: {} vs {want1}",
                m1 / m0
            );
        }
    }

    #[test]
    fn the_response_reads_each_channel_at_its_moved_exit() {
        let t = table();
        // Normal incidence (angle 0: the cell at x = −2s), the exit 2 cells ahead of it.
        let (ni, wi) = (DVec3::Y, DVec3::Y);
        for c in 0..3 {
            let s = t.cell_cm[c];
            let d = DVec3::new(-2.0 * s, 0.0, 0.0);
            let mut exit = [DVec3::ZERO; 3];
            assert!(t.response(d, ni, wi, exit)[c] > 0.0);
            exit[c] = DVec3::new(s, 0.0, 0.0);
            assert_eq!(t.response(d, ni, wi, exit)[c], 0.0);
        }
    }
}
