//! How SSS surfaces are shaded around the scattering, per material: the total diffuse reflectance
//! against the angle of incidence, the radiance against the exit angle, and the light carried
//! through thin parts (tables from `mc`, read by the scene pass).

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
    /// Exit-angle-aware shading: the radiance leaving the SSS material at polar angle
    /// θ = 0°, 10°, …, 80° relative to that of a Lambertian surface with the same total
    /// reflectance, h(θ) per channel (`mc::exitance`; beyond 80° the last value). The scattered
    /// light of each SSS pixel is multiplied by h at the pixel's view angle. All ones: off
    /// (Lambertian exit).
    pub exit: [[f32; 3]; INCIDENCE_STEPS],
    /// Light through thin parts of SSS surfaces (None: off).
    pub translucency: Option<Translucency>,
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
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(GpuError::invalid("eta", self.eta, "must be positive"));
        }
        // Exit factors reach the shader through pack_albedo's 8-bit shared scale of at most 4:
        // with albedos ≤ 1, h up to 4 is exact to 8 bits.
        for (what, table, max) in [
            ("incidence table", &self.incidence, None),
            ("exit table", &self.exit, Some(4.0)),
        ] {
            if let Some(v) = table
                .iter()
                .flatten()
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
            exit: [[1.0; 3]; INCIDENCE_STEPS],
            translucency: None,
            eta: 1.0,
        }
    }
}

/// Entries of [`Shading::incidence`] and [`Shading::exit`]: θ = 0°, 10°, …, 80°.
pub const INCIDENCE_STEPS: usize = 9;

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
}

impl Translucency {
    /// The geometric thicknesses of a table from `first_cm` to `last_cm` [cm].
    pub fn thicknesses(first_cm: f64, last_cm: f64) -> [f64; TRANSLUCENCY_STEPS] {
        let q = (last_cm / first_cm).powf(1.0 / (TRANSLUCENCY_STEPS - 1) as f64);
        std::array::from_fn(|k| first_cm * q.powi(k as i32))
    }

    /// Tt(d)/ρ at thickness `d_cm` (what the scene shader evaluates).
    pub fn at(&self, d_cm: f32) -> [f32; 3] {
        let t = (d_cm.max(1e-30) / self.first_cm).ln() / self.ratio.ln();
        if t.is_nan() || t <= 0.0 {
            return self.table[0];
        }
        let i = t.floor() as usize;
        if i + 1 >= TRANSLUCENCY_STEPS {
            return self.table[TRANSLUCENCY_STEPS - 1];
        }
        let f = t - i as f32;
        [0, 1, 2].map(|c| self.table[i][c] * (1.0 - f) + self.table[i + 1][c] * f)
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
        Ok(())
    }
}

/// ρ(θ)/ρ(0) at cos θ = `cos_i` from an incidence table (or h(θ) from an exit table), linear in θ
/// between entries (what the scene shader evaluates).
pub fn incidence_ratio(table: &[[f32; 3]; INCIDENCE_STEPS], cos_i: f32) -> [f32; 3] {
    let t = cos_i.clamp(0.0, 1.0).acos().to_degrees() / 10.0;
    let i = (t.floor() as usize).min(INCIDENCE_STEPS - 1);
    if i + 1 >= INCIDENCE_STEPS {
        return table[INCIDENCE_STEPS - 1];
    }
    let f = t - i as f32;
    [0, 1, 2].map(|c| table[i][c] * (1.0 - f) + table[i + 1][c] * f)
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
