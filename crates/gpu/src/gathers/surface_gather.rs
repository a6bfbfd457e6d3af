//! The Monte Carlo BSSRDF gathered over the lit surface: the disc gather ([`crate::gathers::disc_gather`])
//! with the material's own transport from `mc` in place of a diffusion model
//! (`shaders/mc_bssrdf.wgsl`). It is the reference a real-time method is measured against on the
//! same geometry and visibility:
//!
//! - [`Bssrdf::Radial`]: the Monte Carlo profile Rd(r) at the 3-D distance |x_o − x_i|, times
//!   the incidence table ρ(θ_i)/ρ(0): the best any radial-profile method (separable kernels,
//!   pre-integration, the area gather) can reach given exact geometry and visibility;
//! - [`Bssrdf::Directional`]: `mc`'s Rd(x, y; θ) at oblique incidence ([`DirectionalTable`]),
//!   laid on the modified tangent plane of Frisvad et al. 2014 (the plane through x_i that holds
//!   x_o, closest to x_i's tangent plane; [`DirectionalTable::response`]) and carrying the true
//!   entry angle's reflectance: the exact half-space BSSRDF for the entry direction on a flat
//!   surface, read at the exit moved by the view's shift (by reciprocity light seen at θ_o last
//!   scattered δ(θ_o), the table's centroid, further along the view ray over the surface;
//!   [`DirectionalTable::exit_shift`]), which a separable BSSRDF leaves out;
//! - [`Bssrdf::Shape`]: the directional BSSRDF scaled for the body's shape ([`ShapeTable`]):
//!   at the signed curvature of the chord from x_i to x_o, κ = (n_o − n_i)·(x_o − x_i)/|x_o −
//!   x_i|² (1/R on a sphere of radius R and −1/R around a cavity, for any two points of it;
//!   0 on a plane), Rd(x, y; θ_i) times E(κ, θ_i) with its lengths stretched by w =
//!   ⟨s⟩(κ)/⟨s⟩(0): E·Rd(x/w, y/w; θ)/w², which returns E times the half-space's light, spread as
//!   much wider as the body spreads it.
//!
//! Both leave with the exit table h(θ_o; θ_i) (radiance over a Lambertian surface's at the view
//! angle, for light that entered at each sample's θ_i, [`shading::AngleTables`]). Per unit power entering, the profile's annulus averages and
//! the tables' cells are integrals of the exact transport, so on a flat half-space lit at θ the
//! gather returns E·cos θ·Rd(θ) (less what lies beyond the tables), tested.
//!
//! Radii are drawn from the profile's own area density (a mixture over the channels of its CDF
//! per annulus, uniform in area within an annulus, each channel around its own exit shift) with a
//! share [`UNIFORM_SHARE`] of uniform disc sampling, the pixel's samples stratified over the
//! mixture ([`SurfaceGatherSetup::shares`]): where the surface curves, the 3-D distance
//! |x_o − x_i| differs from the disc radius, and the uniform share keeps the density positive
//! wherever the response may be. A control variate takes out what a flat, evenly lit
//! half-space would return ([`SurfaceGatherSetup::lit_tolerance_cm`]; shaders/disc_gather.wgsl):
//! where x_o is lit, the exact flat answer cos θ_i·Rd(θ_i)·h(θ_o; θ_i)·E⊥ plus the samples'
//! response less that flat response's shape (each channel's profile laid on x_o's tangent plane),
//! whose mean is 0, so the samples carry only the curvature, shadows and the table's asymmetry.

use crate::error::{GpuError, Result};
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::gathers::disc_gather::{DiscPipelines, Model, Sampling, gather_wgsl};
use shading::{
    AngleTables, Bssrdf, DIRECTIONAL_ANGLES, DirectionalTable, INCIDENCE_STEPS, PackedShading,
    Shading, ShapeTable, incidence_ratio,
};

/// The share of uniform disc sampling in the radius mixture.
pub const UNIFORM_SHARE: f64 = 0.1;

/// The denoiser's width per channel as a share of that channel's median exit radius
/// ([`SurfaceGatherSetup::denoise_widths_cm`]). The denoiser filters only what the samples add
/// to the control variate (passes/denoise.rs): on a flat, evenly lit surface that is zero-mean
/// noise, which any width leaves unbiased; its mean departs from zero where the surface curves,
/// the light varies or a shadow falls, over the profile's own scale, so the width stays below
/// it: half the median radius. Measured (docs/measurements.md): filtering the whole estimate at
/// that width blurred the sphere's shadow edge against Mitsuba at CI size (4.10 → 4.71 ± 0.25 %
/// at 4 samples); filtering the samples' part alone does not (3.87 ± 0.26 %).
pub const DENOISE_SHARE: f64 = 0.5;

/// The surface gather of one material: its Monte Carlo tables and the sampling.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceGatherSetup {
    /// Which BSSRDF.
    pub bssrdf: Bssrdf,
    /// The profile's radial bin width [cm].
    pub dr_cm: f64,
    /// Rd per bin and channel [cm⁻²] (annulus averages, MCML's overflow bin left out).
    pub profile: Vec<[f64; 3]>,
    /// ρ(θ)/ρ(0) and h(θ) (only the exit table is used by [`Bssrdf::Directional`]).
    pub angles: AngleTables,
    /// The directional tables (required by [`Bssrdf::Directional`] and [`Bssrdf::Shape`]).
    pub directional: Option<DirectionalTable>,
    /// The shape table (required by [`Bssrdf::Shape`]).
    pub shape: Option<ShapeTable>,
    /// How the disc gather samples; the default radius is the profile's extent.
    pub sampling: Sampling,
}

impl SurfaceGatherSetup {
    /// The gather of a Monte Carlo `profile` with the material's angle tables, radial or (with
    /// `directional`) directional; 16 samples × 16 frames, r* the profile's extent, 1024² light
    /// maps, seed 1.
    pub fn new(
        profile: &fit::Profile,
        angles: AngleTables,
        directional: Option<DirectionalTable>,
    ) -> Result<SurfaceGatherSetup> {
        let bins = profile.r.len();
        let rows: Vec<[f64; 3]> = (0..bins)
            .map(|i| std::array::from_fn(|c| profile.rd[c][i]))
            .collect();
        let setup = SurfaceGatherSetup {
            bssrdf: if directional.is_some() {
                Bssrdf::Directional
            } else {
                Bssrdf::Radial
            },
            dr_cm: profile.dr,
            profile: rows,
            angles,
            directional,
            shape: None,
            sampling: Sampling {
                samples: 16,
                frames: 16,
                radius_cm: Self::default_radius_cm(profile),
                map_size: 1024,
                seed: 1,
                denoise: false,
            },
        };
        setup.validate()?;
        Ok(setup)
    }

    /// The disc radius r* [cm] of a gather of `profile` unless told otherwise: the profile's
    /// extent.
    pub fn default_radius_cm(profile: &fit::Profile) -> f32 {
        (profile.dr * profile.r.len() as f64) as f32
    }

    /// The radius [cm] within which [`shading::gather_tables`] must hold the directional table
    /// for a gather of `profile`: the default disc radius over √2, so that every cell lies on the
    /// disc (the 3-D distance |x_o − x_i| is never shorter than the in-plane one).
    pub fn table_radius_cm(profile: &fit::Profile) -> f64 {
        Self::default_radius_cm(profile) as f64 / std::f64::consts::SQRT_2
    }

    /// Checks the tables and settings; the error names the field.
    pub fn validate(&self) -> Result<()> {
        self.sampling.validate()?;
        if !(self.dr_cm.is_finite() && self.dr_cm > 0.0) {
            return Err(GpuError::invalid(
                "profile bin width",
                self.dr_cm,
                "must be positive [cm]",
            ));
        }
        if self.profile.is_empty() {
            return Err(GpuError::invalid("profile", 0, "needs at least one bin"));
        }
        if let Some(v) = self
            .profile
            .iter()
            .flatten()
            .find(|v| !(v.is_finite() && **v >= 0.0))
        {
            return Err(GpuError::invalid(
                "profile",
                v,
                "Rd must be finite and ≥ 0 in every bin",
            ));
        }
        if self.bssrdf != Bssrdf::Radial {
            let Some(t) = &self.directional else {
                return Err(GpuError::invalid(
                    "directional table",
                    "none",
                    "the directional BSSRDF needs mc's Rd(x, y; θ) tables",
                ));
            };
            t.validate()?;
        }
        if self.bssrdf == Bssrdf::Shape {
            let Some(t) = &self.shape else {
                return Err(GpuError::invalid(
                    "shape table",
                    "none",
                    "the shape-aware BSSRDF needs mc's transport in curved bodies",
                ));
            };
            t.validate()?;
        }
        Ok(())
    }

    /// ∫Rd dA over the profile's bins per channel [-].
    pub fn profile_total(&self) -> [f64; 3] {
        let dr = self.dr_cm;
        std::array::from_fn(|c| {
            self.profile
                .iter()
                .enumerate()
                .map(|(i, v)| v[c] * std::f64::consts::PI * dr * dr * (2 * i + 1) as f64)
                .sum()
        })
    }

    /// The cumulative share of each channel's ∫Rd dA up to and including each bin, exactly 1 at
    /// the last (1 throughout for a channel that reflects nothing): what the shader's radii are
    /// drawn from.
    pub fn cdf(&self) -> Vec<[f64; 3]> {
        let (dr, total) = (self.dr_cm, self.profile_total());
        let mut acc = [0.0f64; 3];
        let mut cdf: Vec<[f64; 3]> = (self.profile.iter().enumerate())
            .map(|(i, v)| {
                std::array::from_fn(|c| {
                    acc[c] += v[c] * std::f64::consts::PI * dr * dr * (2 * i + 1) as f64;
                    if total[c] > 0.0 {
                        acc[c] / total[c]
                    } else {
                        1.0
                    }
                })
            })
            .collect();
        if let Some(last) = cdf.last_mut() {
            *last = [1.0; 3];
        }
        cdf
    }

    /// The radius [cm] within which each channel returns `fraction` of its ∫Rd dA, uniform in
    /// area within a bin (as the shader draws radii); 0 for a channel that reflects nothing.
    pub fn radius_holding(&self, fraction: f64) -> [f64; 3] {
        let (dr, total, cdf) = (self.dr_cm, self.profile_total(), self.cdf());
        let goal = fraction.clamp(0.0, 1.0);
        std::array::from_fn(|c| {
            if total[c] <= 0.0 {
                return 0.0;
            }
            let i = cdf
                .iter()
                .position(|v| v[c] >= goal)
                .unwrap_or(cdf.len() - 1);
            let below = if i > 0 { cdf[i - 1][c] } else { 0.0 };
            let t = ((goal - below) / (cdf[i][c] - below)).clamp(0.0, 1.0);
            let (inner, outer) = (i as f64 * dr, (i + 1) as f64 * dr);
            (inner * inner + t * (outer * outer - inner * inner)).sqrt()
        })
    }

    /// The denoiser's width σ per channel [cm]: [`DENOISE_SHARE`] of the channel's median exit
    /// radius ([`SurfaceGatherSetup::radius_holding`] of ½).
    pub fn denoise_widths_cm(&self) -> [f32; 3] {
        self.radius_holding(0.5).map(|r| (DENOISE_SHARE * r) as f32)
    }

    /// How far [cm] from a pixel's surface point x_o the first surface its light ray meets may
    /// lie for x_o to count as lit, the control variate's test (shaders/disc_gather.wgsl): the
    /// widest channel's median exit radius. Light-map interpolation moves a lit x_o's own entry
    /// by far less; a shadow caster that close to the surface is then taken for lit, which costs
    /// variance, never bias (the estimate is unbiased for any control).
    pub fn lit_tolerance_cm(&self) -> f64 {
        self.radius_holding(0.5).into_iter().fold(0.0, f64::max)
    }

    /// Each channel's share of the radius mixture. A pixel's samples are stratified over the
    /// mixture (sample k of N draws from [k/N, (k+1)/N) of it), so where every component can have
    /// a sample of its own (N above the channels that reflect anything) the shares are whole
    /// numbers of samples: round(N·[`UNIFORM_SHARE`]), at least one, uniform, the rest split
    /// evenly over those channels, the last (bluest) taking the odd ones; each component then
    /// gets exactly its count in every pixel, not a count that varies from pixel to pixel. With
    /// fewer samples (1 − [`UNIFORM_SHARE`]) split evenly. 0 for a channel that reflects
    /// nothing.
    pub fn shares(&self) -> [f64; 3] {
        self.mixture().0
    }

    /// The share of uniform disc sampling ([`SurfaceGatherSetup::shares`]), all of it where no
    /// channel reflects anything.
    pub fn uniform_share(&self) -> f64 {
        self.mixture().1
    }

    /// The channels' shares and the uniform share.
    fn mixture(&self) -> ([f64; 3], f64) {
        let total = self.profile_total();
        let live: Vec<usize> = (0..3).filter(|&c| total[c] > 0.0).collect();
        let mut shares = [0.0; 3];
        if live.is_empty() {
            return (shares, 1.0);
        }
        let n = self.sampling.samples as usize;
        if n <= live.len() {
            for &c in &live {
                shares[c] = (1.0 - UNIFORM_SHARE) / live.len() as f64;
            }
            return (shares, UNIFORM_SHARE);
        }
        let uniform = ((n as f64 * UNIFORM_SHARE).round() as usize).clamp(1, n - live.len());
        let (rest, k) = (n - uniform, live.len());
        for (j, &c) in live.iter().enumerate() {
            let count = rest / k + usize::from(j >= k - rest % k);
            shares[c] = count as f64 / n as f64;
        }
        (shares, uniform as f64 / n as f64)
    }

    /// The density per unit disc area [cm⁻²] at `r` from the disc's centre of the points the
    /// shader draws where every channel is drawn around that centre (the radial BSSRDF, or a view
    /// along the normal: no exit shift), its `model_pdf_disc`'s CPU twin.
    pub fn pdf_area(&self, r: f64) -> f64 {
        let r_max = self.sampling.radius_cm as f64;
        let mut p = if r < r_max {
            self.uniform_share() / (std::f64::consts::PI * r_max * r_max)
        } else {
            0.0
        };
        let bin = (r / self.dr_cm) as usize;
        if let Some(v) = self.profile.get(bin) {
            let (shares, total) = (self.shares(), self.profile_total());
            for c in 0..3 {
                if shares[c] > 0.0 {
                    p += shares[c] * v[c] / total[c];
                }
            }
        }
        p
    }

    /// The radial response Rd(r)·ρ(θ_i)/ρ(0) per unit power entering at `cos_i` for a 3-D
    /// distance `r` [cm] (the shader's [`Bssrdf::Radial`] twin) [cm⁻²].
    pub fn radial_response(&self, r: f64, cos_i: f64) -> [f64; 3] {
        let bin = (r / self.dr_cm) as usize;
        let ratio = incidence_ratio(&self.angles.incidence, cos_i as f32);
        match self.profile.get(bin) {
            Some(v) => std::array::from_fn(|c| v[c] * ratio[c] as f64),
            None => [0.0; 3],
        }
    }
}

/// The shader's `Tables` uniform (shaders/mc_bssrdf.wgsl), field for field.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TablesUniform {
    radial: [f32; 4],
    share: [f32; 4],
    total: [f32; 4],
    cell: [f32; 4],
    shape: [u32; 4],
    incidence: [[f32; 4]; INCIDENCE_STEPS],
    exit: [[f32; 4]; INCIDENCE_STEPS * INCIDENCE_STEPS],
    directional_total: [[f32; 4]; DIRECTIONAL_ANGLES.len()],
    exit_shift: [[f32; 4]; DIRECTIONAL_ANGLES.len()],
    directional_integral: [[f32; 4]; DIRECTIONAL_ANGLES.len()],
    shape_params: [f32; 4],
    shape_grid: [[f32; 4]; 4],
    shape_entries: [[f32; 4]; SHAPE_ENTRIES],
    shape_slab_grid: [[f32; 4]; 2],
    shape_slab: [[f32; 4]; SLAB_ENTRIES],
}

/// The shape table's vec4 in `Tables` (as in `shading::PackedShading`): the curved bodies', the
/// slabs'.
const SHAPE_ENTRIES: usize = 3 * shading::CURVATURE_STEPS * INCIDENCE_STEPS;
const SLAB_ENTRIES: usize = shading::THICKNESS_STEPS * INCIDENCE_STEPS;

/// The Monte Carlo model and the disc gather.
pub(crate) const MC_BSSRDF_WGSL: &str = gather_wgsl!(
    shading::INCIDENCE_WGSL,
    shading::EXIT_WGSL,
    shading::SHAPE_WGSL,
    include_str!("../shaders/mc_bssrdf.wgsl")
);

/// WGSL's size of `Tables`: 5 vec4, 9 vec4 of incidence, 9 × 9 vec4 of exit, 10 vec4 of the
/// directional tables' total reflectances, 10 of their centroids and 10 of their integrals, and
/// 1 + 4 + 405 + 2 + 45 of
/// the shape table, 16 bytes each (checked against naga's layout in a test).
pub(crate) const TABLES_UNIFORM_SIZE: usize = (5
    + INCIDENCE_STEPS
    + INCIDENCE_STEPS * INCIDENCE_STEPS
    + 3 * DIRECTIONAL_ANGLES.len()
    + 5
    + SHAPE_ENTRIES
    + 2
    + SLAB_ENTRIES)
    * 16;
const _: () = assert!(std::mem::size_of::<TablesUniform>() == TABLES_UNIFORM_SIZE);

fn rgb(v: [f64; 3]) -> [f32; 4] {
    [v[0] as f32, v[1] as f32, v[2] as f32, 0.0]
}

/// Encodes the surface gather's passes adding π·L_o into `out`.
pub(crate) fn encode(
    rec: &mut Recording,
    target: &Target,
    setup: &SurfaceGatherSetup,
    pipelines: &DiscPipelines,
) -> Result<()> {
    setup.validate()?;
    let (total, shares) = (setup.profile_total(), setup.shares());
    let directional = setup
        .directional
        .as_ref()
        .filter(|_| setup.bssrdf != Bssrdf::Radial);
    // The shape table as the scene pass uploads it (off: E = 1, w = 1).
    let shape = PackedShading::new(&Shading {
        shape: setup.shape.filter(|_| setup.bssrdf == Bssrdf::Shape),
        ..Shading::default()
    });
    let uniform = TablesUniform {
        radial: [
            setup.dr_cm as f32,
            setup.sampling.radius_cm,
            setup.uniform_share() as f32,
            setup.lit_tolerance_cm() as f32,
        ],
        share: rgb(shares),
        total: rgb(total),
        cell: rgb(directional.map_or([1.0; 3], |t| t.cell_cm)),
        shape: [
            match setup.bssrdf {
                Bssrdf::Radial => 0,
                Bssrdf::Directional => 1,
                Bssrdf::Shape => 2,
            },
            directional.map_or(0, |t| t.half_width as u32),
            setup.profile.len() as u32,
            0,
        ],
        incidence: setup.angles.incidence.map(|v| rgb(v.map(f64::from))),
        exit: std::array::from_fn(|i| {
            rgb(setup.angles.exit[i / INCIDENCE_STEPS][i % INCIDENCE_STEPS].map(f64::from))
        }),
        directional_total: std::array::from_fn(|k| {
            rgb(directional.map_or([0.0; 3], |t| t.totals[k].map(|e| e.value)))
        }),
        exit_shift: std::array::from_fn(
            |k| rgb(directional.map_or([0.0; 3], |t| t.centroid_cm(k))),
        ),
        directional_integral: std::array::from_fn(|k| {
            rgb(directional.map_or([0.0; 3], |t| t.integral(k)))
        }),
        shape_params: shape.shape_params,
        shape_grid: shape.shape_grid,
        shape_entries: shape.shape,
        shape_slab_grid: shape.shape_slab_grid,
        shape_slab: shape.shape_slab,
    };
    let cdf: Vec<[f32; 4]> = setup.cdf().into_iter().map(rgb).collect();
    let profile: Vec<[f32; 4]> = setup.profile.iter().map(|v| rgb(*v)).collect();
    let alloc = rec.alloc;
    let ubuf = alloc.uniform("mc bssrdf tables", bytemuck::bytes_of(&uniform));
    let pbuf = alloc.storage("mc profile", bytemuck::cast_slice(&profile));
    let cbuf = alloc.storage("mc profile cdf", bytemuck::cast_slice(&cdf));
    let dbuf = match directional {
        Some(t) => alloc.storage("mc directional", bytemuck::cast_slice(&t.rd)),
        None => alloc.storage("mc directional (unused)", &[0u8; 16]),
    };
    let model = Model {
        label: match setup.bssrdf {
            Bssrdf::Radial => "surface gather (radial)",
            Bssrdf::Directional => "surface gather (directional)",
            Bssrdf::Shape => "surface gather (shape-aware)",
        },
        wgsl: MC_BSSRDF_WGSL,
        buffers: vec![&ubuf, &pbuf, &cbuf, &dbuf],
        chords: setup.bssrdf == Bssrdf::Shape,
        denoise_cm: Some(setup.denoise_widths_cm()),
    };
    crate::gathers::disc_gather::encode(rec, target, &setup.sampling, &model, pipelines)
}
