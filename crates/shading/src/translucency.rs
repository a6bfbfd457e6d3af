//! Light through thin parts: a material's slab transmittance against thickness, and the
//! transmitted light's angular law (tables from `mc::slab`, read by the scene pass).

use crate::angle_tables::exit_angles;
use crate::angles::{INCIDENCE_STEPS, incidence_ratio};
use crate::error::{Result, ShadingError};

/// Photons per channel of [`Translucency::rho_of`]'s half-space run.
pub const RHO_PHOTONS: u64 = 200_000;

/// Entries of a [`Translucency`] table.
pub const TRANSLUCENCY_STEPS: usize = 16;

/// The WGSL of the translucency table's lookups, `sss_translucency(m, d) -> vec3<f32>` (Tt/ρ),
/// `sss_translucency_exit(m, d, cos_o) -> vec3<f32>` (h_T) and `sss_back_face_entry(eta, c)`
/// (`wgsl/translucency.wgsl`; reads the host's `sss_translucency_grid`, `sss_translucency_entry`
/// and `sss_translucency_exit_entry`; the CPU twins are [`Translucency::at`],
/// [`Translucency::exit_at`] and [`crate::back_face_entry`]).
pub const TRANSLUCENCY_WGSL: &str = include_str!("wgsl/translucency.wgsl");

/// Light through thin parts (thesis §4.2's first pass; the SSSS supplement's transmittance), from
/// the material itself: a table of its slab transmittance against thickness.
///
/// For an SSS pixel facing away from a light with a shadow map, the shadow map gives the surface
/// where that light enters; the thickness d is the distance between the two along the light ray,
/// and the scene pass adds E·|n·l|·T(|n·l|)/T(1)·table(d) to the irradiance before the blur,
/// T the Fresnel transmittance into the material. Along the ray is
/// exact for light crossing a slab along its normal; at incidence θ it reads t/cos θ where the
/// refracted path inside is t/cos θt (8 % longer than that at 30° and η = 1.3). Measuring the
/// slab along the normal instead (d·|n·l|) would be exact for slabs but sends d → 0 at every
/// terminator of a thick part, where Tt(0)/ρ (up to 1/ρ) paints a bright band: the light
/// entering next to a terminator is the front-lit light the blur already spreads (there, too,
/// the Fresnel factor of grazing entry fades the rest). The table holds Tt(d)/ρ per channel: the slab's total
/// transmittance (`mc::slab`, normal incidence, per unit incident power) over the material's
/// total diffuse reflectance ρ, because the pipeline multiplies the blurred irradiance by the
/// object's albedo, which for a material is ρ; so a back-lit slab leaves with exitance E·Tt(d).
/// The entering face's normal is not known from a depth map: it is taken as −n (a parallel
/// face). Thicknesses are geometric, d_k = first·ratio^k, interpolated linearly in ln d, held
/// below the first and beyond the last.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Translucency {
    /// The first tabulated thickness [cm].
    pub first_cm: f32,
    /// The ratio between successive thicknesses (> 1).
    pub ratio: f32,
    /// Tt(d_k)/ρ per channel.
    pub table: [[f32; 3]; TRANSLUCENCY_STEPS],
    /// The transmitted light's angular distribution at each thickness d_k: its radiance at exit
    /// angle θ = 0°, 10°, …, 80° relative to a Lambertian surface's, h_T(θ; d_k) per channel
    /// (`mc::exitance::transmitted_radiance_ratio`; all ones: Lambertian). The scene pass gives
    /// transmitted light the radiance h_T at the pixel's view angle: through a 3 mm Skin1 slab,
    /// 0.86 / 0.99 / 1.09 (R/G/B) towards the normal and 0.45 / 0.46 / 0.37 at 85°, where the
    /// reflected light's h is 1.07–1.25 (`mc`, 2·10⁵ photons).
    pub exit: [[[f32; 3]; INCIDENCE_STEPS]; TRANSLUCENCY_STEPS],
}

impl Translucency {
    /// The geometric thicknesses of a table from `first_cm` to `last_cm` [cm].
    pub fn thicknesses(first_cm: f64, last_cm: f64) -> [f64; TRANSLUCENCY_STEPS] {
        let q = (last_cm / first_cm).powf(1.0 / (TRANSLUCENCY_STEPS - 1) as f64);
        std::array::from_fn(|k| first_cm * q.powi(k as i32))
    }

    /// The thickness range [cm] of a material's table: from a quarter of the shortest transport
    /// mean free path of its channels to ln(1000)/σtr of the slowest-decaying one (where diffuse
    /// transmittance has fallen by about 10³), held within 20–1000× the first.
    pub fn thickness_range(media: &[fit::analytic::Medium; 3]) -> (f64, f64) {
        let first = 0.25
            * media
                .iter()
                .map(|m| m.transport_mfp())
                .fold(f64::MAX, f64::min);
        let slowest = media
            .iter()
            .map(|m| (3.0 * m.sigma_a * m.sigma_t_reduced()).sqrt())
            .fold(f64::MAX, f64::min);
        let last = (1000f64.ln() / slowest.max(1e-12)).clamp(20.0 * first, 1e3 * first);
        (first, last)
    }

    /// ρ, the total diffuse reflectance per channel of the half-space of the material whose three
    /// channels `spec` holds (a profile-only batch), by one `mc` run of [`RHO_PHOTONS`] per
    /// channel: what [`Translucency::from_mc`] divides by, without simulating a whole profile
    /// (its standard error, about 0.2 % on Skin1, is printed by the caller's table).
    pub fn rho_of(
        spec: &mc::BatchSpec,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<[mc::Estimate; 3]> {
        if spec.channels.len() != 3 {
            return Err(ShadingError::invalid(
                "translucency table: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        let spec = mc::BatchSpec {
            photons: RHO_PHOTONS,
            ..spec.clone()
        };
        let out = mc::run_batch(&spec, progress)?;
        Ok([0, 1, 2].map(|c| out[c].rd))
    }

    /// The table of the material whose three channels `spec` holds (a profile-only batch), by
    /// `mc` slab runs at the [`TRANSLUCENCY_STEPS`] thicknesses of
    /// [`Translucency::thickness_range`], `spec.photons` per channel and thickness; `progress`
    /// receives photon counts. Entries are Tt(d)/ρ with `rho` the total diffuse reflectance of
    /// the material's profile per channel, which must be positive (a channel that does not
    /// scatter, σs = 0, gets 0: it has no diffuse light to carry); the exit tables come from the
    /// same runs in 10° exit bins, read as [`AngleTables`]' exit table is (h_T = 1 where nothing
    /// came through).
    pub fn from_mc(
        spec: &mc::BatchSpec,
        rho: [f64; 3],
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Translucency> {
        if spec.channels.len() != 3 {
            return Err(ShadingError::invalid(
                "translucency table: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        // A channel that does not scatter (σs = 0) has ρ = 0 and no diffuse light to carry
        // through: its entries are 0. (What crosses such a channel unscattered is direct
        // transmission, a clear medium's, not a subsurface term.)
        let dark = |c: usize| spec.channels[c].layer.mu_s == 0.0;
        if let Some(r) = (0..3)
            .filter(|&c| !dark(c))
            .map(|c| rho[c])
            .find(|r| !(r.is_finite() && *r > 0.0))
        {
            return Err(ShadingError::invalid(
                "translucency table: total diffuse reflectance ρ",
                r,
                "must be positive in every channel",
            ));
        }
        let media = [0, 1, 2]
            .map(|c| fit::analytic::Medium::of_layer(&spec.channels[c].layer, spec.n_above));
        let (first, last) = Translucency::thickness_range(&media);
        let d = Translucency::thicknesses(first, last);
        let mut spec = spec.clone();
        for ch in &mut spec.channels {
            ch.grid.na = INCIDENCE_STEPS;
        }
        let rows = mc::slab::transmittance_table(&spec, &d, progress)?;
        let mut table = [[0.0f32; 3]; TRANSLUCENCY_STEPS];
        let mut exit = [[[1.0f32; 3]; INCIDENCE_STEPS]; TRANSLUCENCY_STEPS];
        for (k, row) in rows.iter().enumerate() {
            table[k] = [0, 1, 2].map(|c| {
                if dark(c) {
                    0.0
                } else {
                    (row.tt[c].value / rho[c]) as f32
                }
            });
            for (c, bins) in row.exit.iter().enumerate() {
                if bins.len() == INCIDENCE_STEPS {
                    let h = exit_angles(bins);
                    for (j, v) in h.iter().enumerate() {
                        exit[k][j][c] = v.0;
                    }
                }
            }
        }
        let t = Translucency {
            first_cm: first as f32,
            ratio: (d[1] / d[0]) as f32,
            table,
            exit,
        };
        t.validate()?;
        Ok(t)
    }

    /// The k-th tabulated thickness d_k = first·ratio^k [cm].
    pub fn thickness_cm(&self, k: usize) -> f64 {
        self.first_cm as f64 * (self.ratio as f64).powi(k as i32)
    }

    /// Tt(d)/ρ at thickness `d_cm` (what the scene shader evaluates).
    pub fn at(&self, d_cm: f32) -> [f32; 3] {
        let (i, f) = self.position(d_cm);
        let j = (i + 1).min(TRANSLUCENCY_STEPS - 1);
        [0, 1, 2].map(|c| self.table[i][c] * (1.0 - f) + self.table[j][c] * f)
    }

    /// h_T at thickness `d_cm` and exit cosine `cos_o`: linear in ln d and in θ as
    /// [`Translucency::at`] and [`incidence_ratio`] (what the scene shader evaluates).
    pub fn exit_at(&self, d_cm: f32, cos_o: f32) -> [f32; 3] {
        let (i, f) = self.position(d_cm);
        let j = (i + 1).min(TRANSLUCENCY_STEPS - 1);
        let (a, b) = (
            incidence_ratio(&self.exit[i], cos_o),
            incidence_ratio(&self.exit[j], cos_o),
        );
        [0, 1, 2].map(|c| a[c] * (1.0 - f) + b[c] * f)
    }

    /// The table entry at or below `d_cm` and the fraction towards the next (0 outside).
    fn position(&self, d_cm: f32) -> (usize, f32) {
        let t = (d_cm.max(1e-30) / self.first_cm).ln() / self.ratio.ln();
        if t.is_nan() || t <= 0.0 {
            return (0, 0.0);
        }
        let i = t.floor() as usize;
        if i + 1 >= TRANSLUCENCY_STEPS {
            return (TRANSLUCENCY_STEPS - 1, 0.0);
        }
        (i, t - i as f32)
    }

    /// Checks the table; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if !(self.first_cm.is_finite() && self.first_cm > 0.0) {
            return Err(ShadingError::invalid(
                "translucency first thickness",
                self.first_cm,
                "must be positive [cm]",
            ));
        }
        if !(self.ratio.is_finite() && self.ratio > 1.0) {
            return Err(ShadingError::invalid(
                "translucency ratio",
                self.ratio,
                "must exceed 1",
            ));
        }
        if let Some(v) = self
            .table
            .iter()
            .flatten()
            .find(|v| !(v.is_finite() && **v >= 0.0))
        {
            return Err(ShadingError::invalid(
                "translucency table",
                v,
                "entries must be finite and ≥ 0",
            ));
        }
        if let Some(v) = self
            .exit
            .iter()
            .flatten()
            .flatten()
            .find(|v| !(v.is_finite() && **v >= 0.0))
        {
            return Err(ShadingError::invalid(
                "translucency exit table",
                v,
                "entries must be finite and ≥ 0",
            ));
        }
        Ok(())
    }
}
