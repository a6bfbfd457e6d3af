//! The Monte Carlo BSSRDF gathered over the lit surface: the disc gather ([`crate::disc_gather`])
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
//!   surface.
//!
//! Both leave with the exit table h(θ_o; θ_i) (radiance over a Lambertian surface's at the view
//! angle, for light that entered at each sample's θ_i, [`crate::AngleTables`]). Per unit power entering, the profile's annulus averages and
//! the tables' cells are integrals of the exact transport, so on a flat half-space lit at θ the
//! gather returns E·cos θ·Rd(θ) (less what lies beyond the tables), tested.
//!
//! Radii are drawn from the profile's own area density (a mixture over the channels of its CDF
//! per annulus, uniform in area within an annulus) with a share [`UNIFORM_SHARE`] of uniform disc
//! sampling: where the surface curves, the 3-D distance |x_o − x_i| differs from the disc radius,
//! and the uniform share keeps the density positive wherever the response may be.

use crate::angles::{INCIDENCE_STEPS, incidence_ratio};
use crate::disc_gather::{DiscPipelines, Model, Sampling, gather_wgsl};
use crate::error::{GpuError, Result};
use crate::recording::Recording;
use crate::shading::AngleTables;
use crate::target::Target;

/// Which Monte Carlo BSSRDF the surface gather integrates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bssrdf {
    /// Rd(|x_o − x_i|) × ρ(θ_i)/ρ(0).
    Radial,
    /// Rd(x, y; θ_i) in the plane of incidence.
    Directional,
}

/// The share of uniform disc sampling in the radius mixture.
pub const UNIFORM_SHARE: f64 = 0.1;

/// The half width n of the directional tables [`SurfaceGatherSetup::from_mc`] builds: 385 × 193
/// cells per channel and angle.
pub const DIRECTIONAL_HALF_WIDTH: usize = 192;

/// The angles of a [`DirectionalTable`] [degrees]: 0°, 10°, …, 80° and 85°.
pub const DIRECTIONAL_ANGLES: [f64; 10] =
    [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0];

/// `mc`'s reflectance Rd(x, y; θ) of a half-space per channel at each of
/// [`DIRECTIONAL_ANGLES`], for a beam travelling towards +x, folded onto y ≥ 0 (the mean of the
/// cells at ±y, Rd being even in y).
#[derive(Clone, Debug, PartialEq)]
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
            return Err(GpuError::invalid(
                "directional table: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        if !(8..=512).contains(&half_width) {
            return Err(GpuError::invalid(
                "directional table: half width",
                half_width,
                "must lie in 8..=512 cells",
            ));
        }
        if let Some(r) = reach_cm.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(GpuError::invalid(
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

    /// Channel `c` at angle index `k` and local (x, y) [cm] (y folded), as the shader reads it:
    /// the cell holding the point, 0 outside.
    pub fn at(&self, k: usize, c: usize, x: f64, y: f64) -> f64 {
        let n = self.half_width;
        let s = self.cell_cm[c];
        let ix = (x / s + n as f64 + 0.5).floor();
        let iy = (y.abs() / s + 0.5).floor();
        if ix < 0.0 || ix > (2 * n) as f64 || iy > n as f64 {
            return 0.0;
        }
        self.rd[((k * 3 + c) * (n + 1) + iy as usize) * (2 * n + 1) + ix as usize] as f64
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
    pub fn response(&self, d: glam::DVec3, ni: glam::DVec3, wi: glam::DVec3) -> [f64; 3] {
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
        let x = d.dot(along.normalize());
        let y = (r * r - x * x).max(0.0).sqrt();
        let (k, f) = Self::angle_index(cos_star);
        let (star, entry) = (self.total_at(cos_star), self.total_at(wi.dot(ni)));
        std::array::from_fn(|c| {
            if star[c] > 0.0 {
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
        let n = self.half_width;
        std::array::from_fn(|c| {
            let s = self.cell_cm[c];
            let mut sum = 0.0;
            for iy in 0..=n {
                let mult = if iy == 0 { 1.0 } else { 2.0 };
                for ix in 0..=2 * n {
                    let i = ((k * 3 + c) * (n + 1) + iy) * (2 * n + 1) + ix;
                    sum += mult * self.rd[i] as f64;
                }
            }
            sum * s * s
        })
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
    /// The directional tables (required by [`Bssrdf::Directional`]).
    pub directional: Option<DirectionalTable>,
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
            sampling: Sampling {
                samples: 16,
                frames: 16,
                radius_cm: (profile.dr * bins as f64) as f32,
                map_size: 1024,
                seed: 1,
            },
        };
        setup.validate()?;
        Ok(setup)
    }

    /// The gather of the material whose three channels `spec` holds (a profile-only batch),
    /// with its Monte Carlo `profile`: the angle tables (incidence for [`Bssrdf::Radial`], exit
    /// for both) and, for [`Bssrdf::Directional`], the [`DirectionalTable`] of half width
    /// [`DIRECTIONAL_HALF_WIDTH`] reaching [`DirectionalTable::reach`] within r*/√2 (so every
    /// cell lies on the disc: the 3-D distance |x_o − x_i| is never shorter than the disc
    /// radius), each run of `spec.photons` per channel and angle. `progress` receives photon
    /// counts.
    pub fn from_mc(
        spec: &mc::BatchSpec,
        profile: &fit::Profile,
        bssrdf: Bssrdf,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<SurfaceGatherSetup> {
        let radial = bssrdf == Bssrdf::Radial;
        let angles = AngleTables::from_mc(spec, radial, true, progress)?;
        let mut setup = SurfaceGatherSetup::new(profile, angles, None)?;
        if !radial {
            let media = [0, 1, 2]
                .map(|c| fit::analytic::Medium::of_layer(&spec.channels[c].layer, spec.n_above));
            let r_max = setup.sampling.radius_cm as f64 / std::f64::consts::SQRT_2;
            let reach = DirectionalTable::reach(&media, r_max);
            let table = DirectionalTable::from_mc(spec, DIRECTIONAL_HALF_WIDTH, reach, progress)?;
            setup.directional = Some(table);
            setup.bssrdf = Bssrdf::Directional;
        }
        setup.validate()?;
        Ok(setup)
    }

    /// The batch runs [`SurfaceGatherSetup::from_mc`] makes (for progress bars: each traces
    /// `spec.photons` per walk group): the angle tables' and the directional tables'.
    pub fn batch_runs(bssrdf: Bssrdf) -> u64 {
        let angle_runs = AngleTables::angles(bssrdf == Bssrdf::Radial, true).len();
        let table_runs = match bssrdf {
            Bssrdf::Radial => 0,
            Bssrdf::Directional => DIRECTIONAL_ANGLES.len(),
        };
        (angle_runs + table_runs) as u64
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
        if self.bssrdf == Bssrdf::Directional {
            let Some(t) = &self.directional else {
                return Err(GpuError::invalid(
                    "directional table",
                    "none",
                    "the directional BSSRDF needs mc's Rd(x, y; θ) tables",
                ));
            };
            let n = t.half_width;
            let want = DIRECTIONAL_ANGLES.len() * 3 * (n + 1) * (2 * n + 1);
            if t.rd.len() != want {
                return Err(GpuError::invalid(
                    "directional table",
                    t.rd.len(),
                    format!("must hold {want} cells for half width {n}"),
                ));
            }
            if let Some(v) = t.rd.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                return Err(GpuError::invalid(
                    "directional table",
                    v,
                    "Rd must be finite and ≥ 0 in every cell",
                ));
            }
            if t.totals.len() != DIRECTIONAL_ANGLES.len() {
                return Err(GpuError::invalid(
                    "directional table: totals",
                    t.totals.len(),
                    format!("must hold one per angle, {}", DIRECTIONAL_ANGLES.len()),
                ));
            }
            if let Some(v) = t
                .totals
                .iter()
                .flatten()
                .find(|e| !(e.value.is_finite() && e.value >= 0.0))
            {
                return Err(GpuError::invalid(
                    "directional table: totals",
                    v.value,
                    "each total reflectance must be finite and ≥ 0",
                ));
            }
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

    /// Each channel's share of the radius mixture: (1 − [`UNIFORM_SHARE`]) split over the
    /// channels that reflect anything.
    pub fn shares(&self) -> [f64; 3] {
        let total = self.profile_total();
        let live = total.iter().filter(|t| **t > 0.0).count();
        total.map(|t| {
            if t > 0.0 {
                (1.0 - UNIFORM_SHARE) / live as f64
            } else {
                0.0
            }
        })
    }

    /// The share of uniform disc sampling: [`UNIFORM_SHARE`], or all of it where no channel
    /// reflects anything.
    pub fn uniform_share(&self) -> f64 {
        if self.shares().iter().all(|s| *s == 0.0) {
            1.0
        } else {
            UNIFORM_SHARE
        }
    }

    /// The density per unit disc area [cm⁻²] of a radius the shader draws (its CPU twin).
    pub fn pdf_area(&self, r: f64) -> f64 {
        let r_max = self.sampling.radius_cm as f64;
        let mut p = self.uniform_share() / (std::f64::consts::PI * r_max * r_max);
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
}

/// The Monte Carlo model and the disc gather.
pub(crate) const MC_BSSRDF_WGSL: &str = gather_wgsl!("shaders/mc_bssrdf.wgsl");

/// WGSL's size of `Tables`: 5 vec4, 9 vec4 of incidence, 9 × 9 vec4 of exit and 10 vec4 of the
/// directional tables' total reflectances, 16 bytes each (checked against naga's layout in a test).
pub(crate) const TABLES_UNIFORM_SIZE: usize =
    (5 + INCIDENCE_STEPS + INCIDENCE_STEPS * INCIDENCE_STEPS + DIRECTIONAL_ANGLES.len()) * 16;
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
        .filter(|_| setup.bssrdf == Bssrdf::Directional);
    let uniform = TablesUniform {
        radial: [
            setup.dr_cm as f32,
            setup.sampling.radius_cm,
            setup.uniform_share() as f32,
            0.0,
        ],
        share: rgb(shares),
        total: rgb(total),
        cell: rgb(directional.map_or([1.0; 3], |t| t.cell_cm)),
        shape: [
            directional.is_some() as u32,
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
    };
    // The cumulative share of each channel's ∫Rd dA, exactly 1 at the last bin.
    let dr = setup.dr_cm;
    let mut acc = [0.0f64; 3];
    let mut cdf: Vec<[f32; 4]> = setup
        .profile
        .iter()
        .enumerate()
        .map(|(i, v)| {
            for c in 0..3 {
                acc[c] += v[c] * std::f64::consts::PI * dr * dr * (2 * i + 1) as f64;
            }
            rgb(std::array::from_fn(|c| {
                if total[c] > 0.0 {
                    acc[c] / total[c]
                } else {
                    1.0
                }
            }))
        })
        .collect();
    if let Some(last) = cdf.last_mut() {
        *last = [1.0; 4];
    }
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
        },
        wgsl: MC_BSSRDF_WGSL,
        buffers: vec![&ubuf, &pbuf, &cbuf, &dbuf],
    };
    crate::disc_gather::encode(rec, target, &setup.sampling, &model, pipelines)
}
