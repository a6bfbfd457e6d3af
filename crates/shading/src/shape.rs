//! How a body's shape changes what a material returns near where light entered (issue 47):
//! tables over the signed curvature and the thickness of the body, per entry angle, from
//! `mc::body`, with the CPU twins of the lookups a shape-aware gather and the real-time scene
//! pass do.
//!
//! Each entry compares a body with the half-space of the same medium, both entered by a pencil
//! beam at θ and tallied on their own surface within a geodesic window W = [`SHAPE_WINDOW`]/σ_tr
//! of the entry (`mc::body::Window`): the energy ratio E = R_W(body)/R_W(half-space) [-], and the
//! exits' shift ⟨x⟩ along the plane of incidence and width ⟨s⟩ (mean distance along the surface)
//! [cm]. The window is there because a sphere's whole-surface reflectance counts light leaving
//! far from the entry, which a gather or a screen-space blur around the entry places elsewhere; it
//! holds ≥ 99.94 % of a half-space's light in Skin1 and ≥ 99.86 % in media of albedo 0.2–0.5
//! (docs/measurements.md, "Shape tables").
//!
//! Lengths are in each channel's diffusion length 1/σ_tr, σ_tr = √(3σa(σa + σs(1 − g))) [cm⁻¹]
//! (the effective transport coefficient of the dipole, Jensen et al. 2001): the signed curvature
//! κ = 1/(σ_tr·R) (> 0: the inside of a sphere of radius R, convex; < 0: the medium around a
//! spherical cavity of radius R, concave; 0: the half-space) and the thickness τ = σ_tr·t of a
//! slab. The half-space is a slab of [`HALF_SPACE_DIFFUSION_LENGTHS`]/σ_tr, run through the same
//! code and window, so that window and binning cancel in the ratios. Angles θ = 0°, 10°, …, 80°
//! ([`INCIDENCE_STEPS`]); the medium is the channel's layer with η relative to the ambient index,
//! in air. Shifts and widths are in cm of the channel's own medium.

use mc::body::{Body, BodySpec, Coefficients, SurfaceGrid, Window, run_bodies};
use mc::{Estimate, Incidence};
use serde::{Deserialize, Serialize};

use crate::angles::{INCIDENCE_STEPS, incidence_ratio};
use crate::error::{Result, ShadingError};

/// The WGSL of the shape table's lookups, `sss_shape_energy(m, curvature, cos_i) -> vec3<f32>`
/// (E), `sss_shape_shift(…)` (⟨x⟩ [cm]), `sss_shape_width(…)` (⟨s⟩ over the half-space's) and
/// `sss_shape_thin(m, curvature, chord, cos_i)` (what a thin body keeps), with `sss_shape_at`,
/// `sss_shape_slab` and `sss_curvature_position(m, κ)` (`wgsl/shape.wgsl`; reads the host's
/// `sss_shape_params`, `sss_shape_grid`, `sss_shape_entry`, `sss_shape_slab_grid` and
/// `sss_shape_slab_entry`; the CPU twins are [`ShapeTable::at`], [`ShapeTable::width_ratio`],
/// [`ShapeTable::thin_factor`], [`ShapeTable::slab_at`] and [`curvature_position`]).
pub const SHAPE_WGSL: &str = include_str!("wgsl/shape.wgsl");

/// Entries of the curvature axis.
pub const CURVATURE_STEPS: usize = 15;

/// The signed curvatures κ = 1/(σ_tr·R) [-] of the table: concave (cavities) below 0, the
/// half-space at 0, convex (spheres) above; lookups clamp to the ends. Denser near 0, where a
/// body of ten diffusion lengths already differs from the half-space by 10–20 % (issue 47's
/// step 1: a sphere of 10/σ_tr returns 1.15×, a cavity 0.87×), and ending at a sphere of
/// 0.5/σ_tr, where the whole body lies within a diffusion length of the entry. The nodes at
/// ±0.75 and ±1.5 are there because E bends between ±0.5 and ±2: on the 11 nodes without them,
/// Skin1's E run halfway (κ = ±0.75, ±1.5) was 1–5 % (up to 5 standard errors) off the linear
/// lookup (docs/measurements.md, "Shape tables").
pub const SHAPE_CURVATURES: [f32; CURVATURE_STEPS] = [
    -2.0, -1.5, -1.0, -0.75, -0.5, -0.25, -0.1, 0.0, 0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0,
];

/// Index of the half-space, κ = 0, among [`SHAPE_CURVATURES`].
pub const HALF_SPACE_NODE: usize = 7;

/// Entries of the thickness axis.
pub const THICKNESS_STEPS: usize = 5;

/// The slab thicknesses τ = σ_tr·t [-] of the table, doubling; below the first the first entry,
/// beyond the last the half-space (a slab of 4/σ_tr already returns what a half-space returns
/// within its standard error).
pub const SHAPE_THICKNESSES: [f32; THICKNESS_STEPS] = [0.25, 0.5, 1.0, 2.0, 4.0];

/// The geodesic window W·σ_tr [-] within which returned light is counted.
pub const SHAPE_WINDOW: f64 = 8.0;

/// The half-space's thickness in diffusion lengths [-] (as `mc`'s `bodies` example).
pub const HALF_SPACE_DIFFUSION_LENGTHS: f64 = 1000.0;

/// Runs per channel of a table: the half-space, the curved bodies and the slabs at each angle.
pub const SHAPE_RUNS_PER_CHANNEL: u64 =
    ((CURVATURE_STEPS - 1 + THICKNESS_STEPS + 1) * INCIDENCE_STEPS) as u64;

/// Photons per run a table is built with by default, a third of the angle tables' 10⁵ per angle
/// (`render` takes a third of its `incidence_photons`): a table is [`SHAPE_RUNS_PER_CHANNEL`]
/// (20 bodies × 9 angles) runs per channel, and Skin1's builds in about 8 s on two cores with
/// energy ratios to 0.5–2.5 % (docs/measurements.md, "Shape tables").
pub const SHAPE_PHOTONS: u64 = 100_000 / 3;

/// One body against the half-space at one angle, in one channel.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeEntry {
    /// E = R_W(body)/R_W(half-space) [-]: the diffuse reflectance within the window over the
    /// half-space's (exactly 1 ± 0 for the half-space itself).
    pub energy: Estimate,
    /// ⟨x⟩ of the exits within the window along the plane of incidence [cm], positive ahead of
    /// the entry (`mc::body::SurfaceExits::shift`, windowed).
    pub shift_cm: Estimate,
    /// ⟨s⟩ of the exits within the window, their mean distance from the entry along the surface
    /// [cm] (`mc::body::SurfaceExits::mean_radius`, windowed).
    pub width_cm: Estimate,
}

impl ShapeEntry {
    /// The entry of a medium that returns nothing (one that does not scatter): no change of
    /// energy, no shift, no width, all exact.
    pub const ONES: ShapeEntry = ShapeEntry {
        energy: Estimate {
            value: 1.0,
            se: 0.0,
        },
        shift_cm: Estimate {
            value: 0.0,
            se: 0.0,
        },
        width_cm: Estimate {
            value: 0.0,
            se: 0.0,
        },
    };

    /// The entry of a body whose window is `body` against the half-space's `half`, from
    /// independent runs: E = R_b/R_h with the standard error of a ratio of independent
    /// estimates, √(se_b² + E²·se_h²)/R_h, and the body's shift and width. Where the half-space
    /// returned nothing, [`ShapeEntry::ONES`]; where only the body returned nothing, E = 0 and
    /// the half-space's shift and width (what they multiply is 0; a lookup between nodes stays
    /// finite).
    pub fn relative(body: &Window, half: &Window) -> ShapeEntry {
        let (b, h) = (body.r, half.r);
        if h.value.is_nan() || h.value <= 0.0 {
            return ShapeEntry::ONES;
        }
        let e = b.value / h.value;
        let energy = Estimate {
            value: e,
            se: b.se.hypot(e * h.se) / h.value,
        };
        let of = if b.value > 0.0 { body } else { half };
        ShapeEntry {
            energy,
            shift_cm: of.shift,
            width_cm: of.mean_radius,
        }
    }

    /// The half-space's own entry: E = 1 exactly, its shift and width ([`ShapeEntry::ONES`]
    /// where it returned nothing).
    pub fn half_space(half: &Window) -> ShapeEntry {
        if half.r.value > 0.0 {
            ShapeEntry {
                energy: ShapeEntry::ONES.energy,
                shift_cm: half.shift,
                width_cm: half.mean_radius,
            }
        } else {
            ShapeEntry::ONES
        }
    }
}

/// One node's entries, [θ index][channel].
pub type ShapeRow = [[ShapeEntry; 3]; INCIDENCE_STEPS];

/// The media a table of the first three channels of `spec` runs: each channel's layer with η
/// relative to the ambient index above it, in air.
pub fn channel_media(spec: &mc::BatchSpec) -> [Coefficients; 3] {
    [0, 1, 2].map(|c| {
        let l = &spec.channels[c].layer;
        Coefficients {
            n: l.n / spec.n_above,
            mu_a: l.mu_a,
            mu_s: l.mu_s,
            g: l.g,
        }
    })
}

/// The body of signed curvature `kappa` [-] in a medium of σ_tr = `sigma_tr` [cm⁻¹]: a sphere of
/// radius 1/(κσ_tr) for κ > 0, a cavity of radius 1/(|κ|σ_tr) for κ < 0, the half-space for 0.
pub fn curved_body(kappa: f64, sigma_tr: f64) -> Body {
    let radius_cm = 1.0 / (kappa.abs() * sigma_tr);
    if kappa > 0.0 {
        Body::Sphere { radius_cm }
    } else if kappa < 0.0 {
        Body::Cavity { radius_cm }
    } else {
        half_space(sigma_tr)
    }
}

/// The half-space of a medium of σ_tr = `sigma_tr` [cm⁻¹]: a slab of
/// [`HALF_SPACE_DIFFUSION_LENGTHS`]/σ_tr.
pub fn half_space(sigma_tr: f64) -> Body {
    Body::Slab {
        thickness_cm: HALF_SPACE_DIFFUSION_LENGTHS / sigma_tr,
    }
}

/// A table's run of `body` in the medium `c` at θ = `theta_deg`: one surface bin reaching the
/// window W = [`SHAPE_WINDOW`]/σ_tr, so that the run's `reflected.window` is the table's.
pub fn shape_run(body: Body, c: Coefficients, theta_deg: f64, photons: u64, seed: u64) -> BodySpec {
    BodySpec {
        body,
        coefficients: c,
        incidence: Incidence { theta_deg },
        grid: SurfaceGrid {
            dr: SHAPE_WINDOW / c.sigma_tr(),
            nr: 1,
            n_azimuth: 1,
            n_exit: 1,
        },
        photons,
        seed,
    }
}

/// The energy factor, shift and width at one point of a surface, per channel, as a shader reads
/// them (what [`ShapeTable::at`] and [`ShapeTable::slab_at`] return).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeFactors {
    /// E [-]: multiplies the light the half-space's tables give.
    pub energy: [f32; 3],
    /// ⟨x⟩ [cm] ahead of the entry along the light's direction over the surface.
    pub shift_cm: [f32; 3],
    /// ⟨s⟩ [cm], the returned light's mean distance from the entry along the surface.
    pub width_cm: [f32; 3],
}

/// A material's shape table: per channel, what a sphere, a cavity or a slab returns near the
/// entry against the half-space, over curvature and thickness in the channel's diffusion
/// lengths, at θ = 0°, 10°, …, 80°.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeTable {
    /// σ_tr per channel [cm⁻¹], the unit of κ and τ.
    pub sigma_tr: [f64; 3],
    /// [κ node of [`SHAPE_CURVATURES`]][θ][channel]; the [`HALF_SPACE_NODE`] is the half-space
    /// (E = 1).
    pub curvature: [ShapeRow; CURVATURE_STEPS],
    /// [τ node of [`SHAPE_THICKNESSES`]][θ][channel]: slabs.
    pub thickness: [ShapeRow; THICKNESS_STEPS],
}

impl ShapeTable {
    /// The table of a material that returns nothing in any channel: every entry
    /// [`ShapeEntry::ONES`].
    pub fn ones(sigma_tr: [f64; 3]) -> ShapeTable {
        let row = [[ShapeEntry::ONES; 3]; INCIDENCE_STEPS];
        ShapeTable {
            sigma_tr,
            curvature: [row; CURVATURE_STEPS],
            thickness: [row; THICKNESS_STEPS],
        }
    }

    /// The table of the three channels of `spec` (one material, as `EntryShift::from_mc`'s):
    /// per channel, the half-space, the bodies of [`SHAPE_CURVATURES`] and the slabs of
    /// [`SHAPE_THICKNESSES`] at θ = 0°, 10°, …, 80°, each a `mc::body` run of `spec.photons`
    /// seeded by `spec.seed` (`run_body` mixes in the body, medium and angle, so the runs are
    /// independent), in air with η = n_layer/n_above. A channel that does not scatter (σs = 0)
    /// is not run and gets [`ShapeEntry::ONES`]. `progress` receives photon counts
    /// ([`SHAPE_RUNS_PER_CHANNEL`] runs of `spec.photons` per scattering channel).
    ///
    /// Requirements: three channels; a scattering channel absorbs (σa > 0: the table's lengths
    /// are in 1/σ_tr, and around a cavity only absorption ends a walk).
    pub fn from_mc(spec: &mc::BatchSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<ShapeTable> {
        if spec.channels.len() != 3 {
            return Err(ShadingError::invalid(
                "shape table: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        let media = channel_media(spec);
        let sigma_tr = media.map(|m| m.sigma_tr());
        let lit: Vec<usize> = (0..3).filter(|&c| media[c].mu_s > 0.0).collect();
        for &c in &lit {
            if !(sigma_tr[c].is_finite() && sigma_tr[c] > 0.0) {
                return Err(ShadingError::invalid(
                    format!("shape table: σ_tr of channel {c} [cm⁻¹]"),
                    sigma_tr[c],
                    "must be positive and finite (a scattering channel must absorb: σa > 0)",
                ));
            }
        }
        // Per lit channel and angle: the half-space, the curved bodies but the half-space, the
        // slabs; in that order.
        let bodies = |s: f64| {
            let curved = SHAPE_CURVATURES
                .iter()
                .filter(|&&k| k != 0.0)
                .map(move |&k| curved_body(k as f64, s));
            let slabs = SHAPE_THICKNESSES.iter().map(move |&t| Body::Slab {
                thickness_cm: t as f64 / s,
            });
            std::iter::once(half_space(s)).chain(curved).chain(slabs)
        };
        let per_angle = bodies(1.0).count();
        let specs: Vec<BodySpec> = (lit.iter())
            .flat_map(|&c| {
                (0..INCIDENCE_STEPS).flat_map(move |k| {
                    bodies(sigma_tr[c]).map(move |b| {
                        shape_run(b, media[c], 10.0 * k as f64, spec.photons, spec.seed)
                    })
                })
            })
            .collect();
        let out = run_bodies(&specs, progress)?;
        let mut table = ShapeTable::ones(sigma_tr);
        for (j, &c) in lit.iter().enumerate() {
            for k in 0..INCIDENCE_STEPS {
                let o = &out[(j * INCIDENCE_STEPS + k) * per_angle..][..per_angle];
                let window = |i: usize| &o[i].reflected.window;
                let half = window(0);
                let mut next = 1..;
                for (i, &kappa) in SHAPE_CURVATURES.iter().enumerate() {
                    table.curvature[i][k][c] = if kappa == 0.0 {
                        ShapeEntry::half_space(half)
                    } else {
                        ShapeEntry::relative(window(next.next().expect("unbounded")), half)
                    };
                }
                for i in 0..THICKNESS_STEPS {
                    let body = window(next.next().expect("unbounded"));
                    table.thickness[i][k][c] = ShapeEntry::relative(body, half);
                }
            }
        }
        table.validate()?;
        Ok(table)
    }

    /// Checks the table: σ_tr finite and ≥ 0, every value and standard error finite, standard
    /// errors and energies ≥ 0, widths ≥ 0, and the half-space's energy exactly 1; the error
    /// names the entry.
    pub fn validate(&self) -> Result<()> {
        for (c, s) in self.sigma_tr.iter().enumerate() {
            if !(s.is_finite() && *s >= 0.0) {
                return Err(ShadingError::invalid(
                    format!("shape table: σ_tr of channel {c} [cm⁻¹]"),
                    s,
                    "must be finite and ≥ 0",
                ));
            }
        }
        let axes = [
            ("κ", &SHAPE_CURVATURES[..], &self.curvature[..]),
            ("τ", &SHAPE_THICKNESSES[..], &self.thickness[..]),
        ];
        for (axis, nodes, rows) in axes {
            for (i, row) in rows.iter().enumerate() {
                for (k, entries) in row.iter().enumerate() {
                    for (c, e) in entries.iter().enumerate() {
                        let at = format!("{axis} = {}, θ = {}°, channel {c}", nodes[i], 10 * k);
                        let numbers = [
                            ("energy", e.energy, 0.0),
                            ("shift [cm]", e.shift_cm, f64::NEG_INFINITY),
                            ("width [cm]", e.width_cm, 0.0),
                        ];
                        for (what, v, least) in numbers {
                            if !(v.value.is_finite() && v.value >= least) {
                                return Err(ShadingError::invalid(
                                    format!("shape table: {what} at {at}"),
                                    v.value,
                                    format!("must be finite and ≥ {least}"),
                                ));
                            }
                            if !(v.se.is_finite() && v.se >= 0.0) {
                                return Err(ShadingError::invalid(
                                    format!("shape table: {what} SE at {at}"),
                                    v.se,
                                    "must be finite and ≥ 0",
                                ));
                            }
                        }
                        let half = axis == "κ" && i == HALF_SPACE_NODE;
                        if half && e.energy != ShapeEntry::ONES.energy {
                            return Err(ShadingError::invalid(
                                format!("shape table: energy at {at}"),
                                e.energy.value,
                                "must be 1 ± 0 (the half-space against itself)",
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The mean distance from the entry at which a half-space returns light entering along the
    /// normal, ⟨s⟩ at κ = 0 and θ = 0, per channel [cm] (0 where a channel does not scatter): the
    /// scale [`crate::curvature::light_scale_curvature`] averages a surface's curvature over.
    pub fn light_scale(&self) -> [f32; 3] {
        let half = &self.curvature[HALF_SPACE_NODE][0];
        [0, 1, 2].map(|c| half[c].width_cm.value.max(0.0) as f32)
    }

    /// κ = curvature/σ_tr per channel [-] for a signed curvature `curvature_per_cm` = ±1/R
    /// [cm⁻¹] (> 0 convex).
    pub fn kappa(&self, curvature_per_cm: f32) -> [f32; 3] {
        self.sigma_tr.map(|s| curvature_per_cm / s as f32)
    }

    /// E, ⟨x⟩ and ⟨s⟩ per channel where the surface has signed curvature `curvature_per_cm` =
    /// ±1/R [cm⁻¹] along the light's direction over it (> 0 convex, < 0 concave) and the light
    /// enters at cos θ = `cos_i`: κ per channel ([`ShapeTable::kappa`]), linear in κ between the
    /// nodes of [`SHAPE_CURVATURES`] and clamped to its ends (NaN: the half-space), linear in θ
    /// between 0°, 10°, …, 80° and the 80° entry beyond (as [`incidence_ratio`]). At κ = 0, E = 1.
    pub fn at(&self, curvature_per_cm: f32, cos_i: f32) -> ShapeFactors {
        let kappa = self.kappa(curvature_per_cm);
        let nodes = [0, 1, 2].map(|c| {
            let (i, f) = curvature_position(kappa[c]);
            (&self.curvature[i], &self.curvature[i + 1], f)
        });
        lookup(nodes, cos_i)
    }

    /// ⟨s⟩(κ)/⟨s⟩(0) per channel: how much wider than the half-space's the returned light
    /// spreads where the surface's signed curvature is `curvature_per_cm` [cm⁻¹], entered at
    /// cos θ = `cos_i` ([`ShapeTable::at`]'s widths); 1 where the half-space returns nothing.
    pub fn width_ratio(&self, curvature_per_cm: f32, cos_i: f32) -> [f32; 3] {
        let (body, half) = (
            self.at(curvature_per_cm, cos_i).width_cm,
            self.at(0.0, cos_i).width_cm,
        );
        [0, 1, 2].map(|c| {
            if half[c] > 0.0 {
                body[c] / half[c]
            } else {
                1.0
            }
        })
    }

    /// E, ⟨x⟩ and ⟨s⟩ per channel of a slab `thickness_cm` [cm] thick entered at cos θ = `cos_i`:
    /// τ = σ_tr·t per channel, linear in ln τ between the nodes of [`SHAPE_THICKNESSES`], the
    /// first entry below the first (and for t ≤ 0 or NaN), the half-space (E = 1) beyond the last;
    /// in θ as [`ShapeTable::at`].
    pub fn slab_at(&self, thickness_cm: f32, cos_i: f32) -> ShapeFactors {
        let half = &self.curvature[HALF_SPACE_NODE];
        let nodes =
            [0, 1, 2].map(
                |c| match thickness_position(self.sigma_tr[c] as f32 * thickness_cm) {
                    Some((i, f)) => (&self.thickness[i], &self.thickness[i + 1], f),
                    None => (half, half, 0.0),
                },
            );
        lookup(nodes, cos_i)
    }
}

impl ShapeTable {
    /// What a body keeps of the light E(κ, θ) gives where it is thinner along the light than its
    /// curvature makes it, per channel (≤ 1): light entering at cos θ = `cos_i` where the body's
    /// chord along the light ray is `chord_cm` [cm] and its signed curvature `curvature_per_cm`
    /// [cm⁻¹]. A slab t thick has the chord t/cos θ (the light's straight line, as a depth map
    /// from the light measures it), a sphere of radius R the chord 2R·cos θ; so the body is read
    /// as a slab t = chord·cos θ, and the sphere of its curvature as the slab t_κ = 2cos²θ/κ
    /// (none where it is concave or flat: t_κ = ∞, E_slab = 1). The factor is
    /// E_slab(t)/E_slab(t_κ) ([`ShapeTable::slab_at`]), at most 1: on a sphere 1 (E(κ) already
    /// holds what leaves through its far side), on a flat plate E_slab(t). 1 where the chord is
    /// unknown (≤ 0 or NaN) or E_slab(t_κ) is 0.
    pub fn thin_factor(&self, curvature_per_cm: f32, chord_cm: f32, cos_i: f32) -> [f32; 3] {
        // Unknown: 0, negative or NaN.
        if chord_cm.is_nan() || chord_cm <= 0.0 {
            return [1.0; 3];
        }
        let c = cos_i.clamp(0.0, 1.0);
        let slab = self.slab_at(chord_cm * c, cos_i).energy;
        let own = if curvature_per_cm > 0.0 {
            self.slab_at(2.0 * c * c / curvature_per_cm, cos_i).energy
        } else {
            [1.0; 3]
        };
        [0, 1, 2].map(|k| {
            if own[k] > 0.0 {
                (slab[k] / own[k]).min(1.0)
            } else {
                1.0
            }
        })
    }
}

/// The curvature node at or below κ [-] and the fraction towards the next: κ clamped to
/// the ends [−2, 2], NaN read as 0; at κ = 2, the node before it and fraction 1.
pub fn curvature_position(kappa: f32) -> (usize, f32) {
    let k = SHAPE_CURVATURES;
    let kappa = if kappa.is_nan() {
        0.0
    } else {
        kappa.clamp(k[0], k[CURVATURE_STEPS - 1])
    };
    let i = (0..CURVATURE_STEPS - 1)
        .rev()
        .find(|&i| k[i] <= kappa)
        .unwrap_or(0);
    (i, (kappa - k[i]) / (k[i + 1] - k[i]))
}

/// The thickness node at or below τ [-] and the fraction towards the next, linear in ln τ: the
/// first node (fraction 0) for τ ≤ the first or NaN; `None` beyond the last (the half-space); at
/// the last, the node before it and fraction 1.
pub fn thickness_position(tau: f32) -> Option<(usize, f32)> {
    let t = SHAPE_THICKNESSES;
    if tau > t[THICKNESS_STEPS - 1] {
        return None;
    }
    if tau.is_nan() || tau <= t[0] {
        return Some((0, 0.0));
    }
    let i = (0..THICKNESS_STEPS - 1)
        .rev()
        .find(|&i| t[i] <= tau)
        .unwrap_or(0);
    Some((i, (tau / t[i]).ln() / (t[i + 1] / t[i]).ln()))
}

/// Per channel c, the value between rows `a` and `b` at fraction f of `nodes[c]` = (a, b, f),
/// each row read in θ by [`incidence_ratio`] (the channels' rows gathered into one angle table
/// per quantity and side, so that each is read once).
fn lookup(nodes: [(&ShapeRow, &ShapeRow, f32); 3], cos_i: f32) -> ShapeFactors {
    let read = |q: fn(&ShapeEntry) -> Estimate| {
        let side = |upper: bool| {
            let table: [[f32; 3]; INCIDENCE_STEPS] = std::array::from_fn(|k| {
                [0, 1, 2].map(|c| {
                    let row = if upper { nodes[c].1 } else { nodes[c].0 };
                    q(&row[k][c]).value as f32
                })
            });
            incidence_ratio(&table, cos_i)
        };
        let (lo, hi) = (side(false), side(true));
        [0, 1, 2].map(|c| {
            let f = nodes[c].2;
            lo[c] * (1.0 - f) + hi[c] * f
        })
    };
    ShapeFactors {
        energy: read(|e| e.energy),
        shift_cm: read(|e| e.shift_cm),
        width_cm: read(|e| e.width_cm),
    }
}
