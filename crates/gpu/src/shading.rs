//! How SSS surfaces are shaded around the scattering, per material: the total diffuse reflectance
//! against the angle of incidence, the radiance against the exit angle, and the light carried
//! through thin parts (tables from `mc`, read by the scene pass).

use crate::angles::{INCIDENCE_STEPS, incidence_ratio};
use crate::entry_shift::EntryShift;
use crate::error::{GpuError, Result};

/// How the surfaces of one SSS material are shaded around the scattering; the default is off
/// (plain Lambertian entry and exit, no light through thin parts).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// Incidence-aware shading: the material's total diffuse reflectance at incidence
    /// θ = 0°, 10°, …, 80° relative to normal incidence, ρ(θ)/ρ(0) per channel (beyond 80° the
    /// last value). The scene pass multiplies each light's irradiance on SSS surfaces by it, and
    /// the ambient light by its cosine-weighted hemispherical mean. All ones: off.
    pub incidence: [[f32; 3]; INCIDENCE_STEPS],
    /// Exit-angle-aware shading: the radiance leaving the SSS material at polar angle θ_o
    /// relative to that of a Lambertian surface with the same total reflectance, for light that
    /// entered at θ_i, h(θ_o; θ_i) per channel (`mc::exitance`), [θ_i][θ_o] at 0°, 10°, …, 80°
    /// (beyond 80° the last value): [`ExitTable`]. The scattered light of each SSS pixel is
    /// multiplied by h at the pixel's view angle and at the cosine of incidence of its lights,
    /// weighted by the irradiance each brings unshadowed (the normal-entry row where none faces
    /// it; a table whose rows are all the normal-entry one applies that law everywhere). All ones:
    /// off (Lambertian exit).
    pub exit: ExitTable,
    /// Light through thin parts of SSS surfaces (None: off).
    pub translucency: Option<Translucency>,
    /// Entry-shifted shading: light entering at θ leaves a half-space δ(θ) ahead of its entry
    /// on average ([`EntryShift`]); the scene pass shades each SSS pixel with the light that
    /// entered δ behind it along each light's propagation over the surface (that point's
    /// shadow, and its normal from the surface's curvature), which the radial blur then
    /// spreads. [`EntryShift::NONE`]: off.
    pub entry_shift: EntryShift,
    /// The relative refractive index η of the material's smooth boundary (1: index-matched).
    /// SSS surfaces reflect area lights in mirror with the Fresnel reflectance F(η, θ) at the
    /// view angle, and light entering the back face of a thin part at incidence θ is scaled by
    /// the Fresnel transmittance T(θ)/T(0) (the translucency table holds normal incidence).
    pub eta: f32,
}

impl Shading {
    /// Checks the tables; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if let Some(t) = &self.translucency {
            t.validate()?;
        }
        self.entry_shift.validate()?;
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(GpuError::invalid("eta", self.eta, "must be positive"));
        }
        // Exit factors reach the shader through pack_albedo's 8-bit shared scale of at most 4:
        // with albedos ≤ 1, h up to 4 is exact to 8 bits.
        let incidence: Vec<f32> = self.incidence.iter().flatten().copied().collect();
        let exit: Vec<f32> = self.exit.iter().flatten().flatten().copied().collect();
        for (what, table, max) in [
            ("incidence table", incidence, None),
            ("exit table", exit, Some(4.0)),
        ] {
            if let Some(v) = table
                .iter()
                .find(|v| !(v.is_finite() && **v >= 0.0 && max.is_none_or(|m| **v <= m)))
            {
                let reason = match max {
                    Some(m) => format!("entries must be finite, ≥ 0 and ≤ {m}"),
                    None => "entries must be finite and ≥ 0".into(),
                };
                return Err(GpuError::invalid(what, v, reason));
            }
        }
        Ok(())
    }
}

impl Default for Shading {
    fn default() -> Self {
        Shading {
            incidence: [[1.0; 3]; INCIDENCE_STEPS],
            exit: [[[1.0; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS],
            translucency: None,
            entry_shift: EntryShift::NONE,
            eta: 1.0,
        }
    }
}

/// An exit table h(θ_o; θ_i) per channel, [θ_i][θ_o] at 0°, 10°, …, 80°: the angular law of the
/// reflected light depends on the angle it entered at. For isotropic scattering behind a matched
/// boundary the radiance leaving at cosine μ is ∝ H(μ)/(μ + μ₀) for light entering at cosine μ₀
/// (Chandrasekhar 1960): towards the normal for normal entry and high albedo, flat or towards
/// grazing angles for oblique entry.
pub type ExitTable = [[[f32; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS];

/// Photons per channel of [`Translucency::rho_of`]'s half-space run.
pub const RHO_PHOTONS: u64 = 200_000;

/// Entries of a [`Translucency`] table.
pub const TRANSLUCENCY_STEPS: usize = 16;

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
#[derive(Clone, Copy, Debug, PartialEq)]
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
            return Err(GpuError::invalid(
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
    /// the material's profile per channel, which must be positive; the exit tables come from the
    /// same runs in 10° exit bins, read as [`AngleTables`]' exit table is (h_T = 1 where nothing
    /// came through).
    pub fn from_mc(
        spec: &mc::BatchSpec,
        rho: [f64; 3],
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Translucency> {
        if spec.channels.len() != 3 {
            return Err(GpuError::invalid(
                "translucency table: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        if let Some(r) = rho.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(GpuError::invalid(
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
            table[k] = [0, 1, 2].map(|c| (row.tt[c].value / rho[c]) as f32);
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
            return Err(GpuError::invalid(
                "translucency first thickness",
                self.first_cm,
                "must be positive [cm]",
            ));
        }
        if !(self.ratio.is_finite() && self.ratio > 1.0) {
            return Err(GpuError::invalid(
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
            return Err(GpuError::invalid(
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
            return Err(GpuError::invalid(
                "translucency exit table",
                v,
                "entries must be finite and ≥ 0",
            ));
        }
        Ok(())
    }
}

/// A material's angle tables by `mc`: profile-only batch runs of its channels with
/// [`INCIDENCE_STEPS`] exit-angle bins of 10°.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleTables {
    /// ρ(θ)/ρ(0) per channel at θ = 0°, 10°, …, 80° ([`Shading::incidence`]).
    pub incidence: [[f32; 3]; INCIDENCE_STEPS],
    /// The standard error of each `incidence` entry (the runs at each angle are independent;
    /// 0 at 0°, where the ratio is 1 by definition).
    pub incidence_se: [[f32; 3]; INCIDENCE_STEPS],
    /// h(θ_o; θ_i) per channel, [θ_i][θ_o] ([`Shading::exit`]).
    pub exit: ExitTable,
    /// The standard error of each `exit` entry.
    pub exit_se: ExitTable,
}

impl AngleTables {
    /// No angle dependence: plain Lambertian entry and exit.
    pub const ONES: AngleTables = AngleTables {
        incidence: [[1.0; 3]; INCIDENCE_STEPS],
        incidence_se: [[0.0; 3]; INCIDENCE_STEPS],
        exit: [[[1.0; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS],
        exit_se: [[[0.0; 3]; INCIDENCE_STEPS]; INCIDENCE_STEPS],
    };

    /// The beam angles [degrees] the tables need: every table angle for either table (the exit
    /// table has a row per angle of entry); none when neither is asked for.
    pub fn angles(incidence: bool, exit: bool) -> Vec<f64> {
        if incidence || exit {
            (0..INCIDENCE_STEPS).map(|k| 10.0 * k as f64).collect()
        } else {
            Vec::new()
        }
    }

    /// The tables of the three channels of `spec` (a profile-only batch of one material; its
    /// exit-angle bins are set to [`INCIDENCE_STEPS`] here), each run of `spec.photons` per
    /// channel and angle ([`AngleTables::angles`]); `progress` receives photon counts. The
    /// incidence table is ρ(θ)/ρ(0) (all ones unless `incidence`); the exit table h(θ_o; θ_i)
    /// (all ones unless `exit`) has the run at each θ_i as its row: at θ_o = 0° the first exit
    /// bin's, at 10°…80° the mean of the two bins around the angle. Refuses a material that
    /// reflects nothing in some channel (at normal incidence, or for the exit table at any
    /// angle).
    pub fn from_mc(
        spec: &mc::BatchSpec,
        incidence: bool,
        exit: bool,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<AngleTables> {
        let mut tables = AngleTables::ONES;
        let angles = AngleTables::angles(incidence, exit);
        if angles.is_empty() {
            return Ok(tables);
        }
        if spec.channels.len() != 3 {
            return Err(GpuError::invalid(
                "angle tables: channels",
                spec.channels.len(),
                "one material (three channels) per table",
            ));
        }
        let mut spec = spec.clone();
        for ch in &mut spec.channels {
            ch.grid.na = INCIDENCE_STEPS;
        }
        let rows = mc::incidence::rd_table(&spec, &angles, progress)?;
        let rd0 = &rows[0].rd;
        if let Some(c) = (0..3).find(|&c| rd0[c].value.is_nan() || rd0[c].value <= 0.0) {
            return Err(GpuError::invalid(
                format!("angle tables: diffuse reflectance at normal incidence of channel {c}"),
                rd0[c].value,
                "the material reflects nothing there",
            ));
        }
        if incidence {
            for (k, row) in rows.iter().enumerate().skip(1) {
                for (c, (r, r0)) in row.rd.iter().zip(rd0).enumerate() {
                    let ratio = r.value / r0.value;
                    tables.incidence[k][c] = ratio as f32;
                    // (0 where nothing came back: NaN.max(0) is 0.)
                    tables.incidence_se[k][c] =
                        (ratio * (r.se / r.value).hypot(r0.se / r0.value)).max(0.0) as f32;
                }
            }
        }
        if exit {
            for (i, row) in rows.iter().enumerate() {
                for (c, channel) in row.exit.iter().enumerate() {
                    if channel.len() < INCIDENCE_STEPS {
                        return Err(GpuError::invalid(
                            format!(
                                "exit table: light reflected at {}° incidence in channel {c}",
                                10 * i
                            ),
                            row.rd[c].value,
                            "the material reflects nothing there",
                        ));
                    }
                    for (k, (h, se)) in exit_angles(channel).into_iter().enumerate() {
                        tables.exit[i][k][c] = h;
                        tables.exit_se[i][k][c] = se;
                    }
                }
            }
        }
        Ok(tables)
    }
}

/// An exit table's entries at θ = 0°, 10°, …, 80° with their standard errors from `mc`'s
/// [`INCIDENCE_STEPS`] exit bins of 10°: at 0° the first bin's, at 10°…80° the mean of the two
/// bins around the angle.
fn exit_angles(bins: &[mc::exitance::ExitBin]) -> [(f32, f32); INCIDENCE_STEPS] {
    std::array::from_fn(|k| {
        let (a, b) = (&bins[k.saturating_sub(1)].h, &bins[k].h);
        (
            (0.5 * (a.value + b.value)) as f32,
            (0.5 * (a.se.powi(2) + b.se.powi(2)).sqrt()) as f32,
        )
    })
}

/// h(θ_o; θ_i) from an exit table at exit cosine `cos_o` and entry cosine `cos_i`: linear in θ_o
/// and in θ_i between entries, the 80° values beyond (what scene.wgsl's `exit_table` evaluates).
pub fn exit_ratio(table: &ExitTable, cos_o: f32, cos_i: f32) -> [f32; 3] {
    let t = cos_i.clamp(0.0, 1.0).acos().to_degrees() / 10.0;
    let i = (t.floor() as usize).min(INCIDENCE_STEPS - 1);
    let j = (i + 1).min(INCIDENCE_STEPS - 1);
    let f = (t - i as f32).clamp(0.0, 1.0);
    let (a, b) = (
        incidence_ratio(&table[i], cos_o),
        incidence_ratio(&table[j], cos_o),
    );
    [0, 1, 2].map(|c| a[c] * (1.0 - f) + b[c] * f)
}

/// The cosine-weighted hemispherical mean 2∫₀^{π/2} f(θ) cos θ sin θ dθ of an incidence table:
/// the factor for diffuse (ambient) light.
pub fn incidence_hemispherical(table: &[[f32; 3]; INCIDENCE_STEPS]) -> [f32; 3] {
    let n = 900;
    let mut acc = [0.0f64; 3];
    for k in 0..n {
        let theta = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
        let f = incidence_ratio(table, theta.cos() as f32);
        let w = 2.0 * theta.cos() * theta.sin() * std::f64::consts::FRAC_PI_2 / n as f64;
        for c in 0..3 {
            acc[c] += w * f[c] as f64;
        }
    }
    acc.map(|x| x as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn incidence_table_lookup_and_hemispherical_mean() {
        // A constant table is that constant everywhere; 2∫cos θ sin θ dθ = 1.
        let ones = [[1.0f32; 3]; INCIDENCE_STEPS];
        assert_eq!(incidence_ratio(&ones, 0.3), [1.0; 3]);
        for h in incidence_hemispherical(&ones) {
            assert!((h - 1.0).abs() < 1e-5, "{h}");
        }
        // A table linear in θ is reproduced between entries and held beyond 80°.
        let table: [[f32; 3]; INCIDENCE_STEPS] =
            std::array::from_fn(|k| [1.0 + 0.1 * k as f32, 1.0, 2.0 - 0.1 * k as f32]);
        let r = incidence_ratio(&table, 35f32.to_radians().cos());
        assert!(
            (r[0] - 1.35).abs() < 1e-4 && (r[2] - 1.65).abs() < 1e-4,
            "{r:?}"
        );
        assert_eq!(incidence_ratio(&table, 0.0), table[8]);
        // Hemispherical mean of f(θ) = 1 + θ/100 rad⁻¹… checked against direct quadrature of the
        // interpolant: for R, 2∫(1 + 0.01·θ°)cos θ sin θ dθ with θ° clamped at 80.
        let n = 20_000;
        let direct: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
                let deg = t.to_degrees().min(80.0);
                (1.0 + 0.01 * deg) * 2.0 * t.cos() * t.sin() * std::f64::consts::FRAC_PI_2
                    / n as f64
            })
            .sum();
        let h = incidence_hemispherical(&table);
        assert!((h[0] as f64 - direct).abs() < 1e-4, "{} vs {direct}", h[0]);
    }
}
