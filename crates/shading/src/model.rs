//! The shading model of one SSS material: every table a renderer reads around the scattering,
//! with the boundary's index (what the scene pass of `gpu` uploads per material).

use crate::angle_tables::ExitTable;
use crate::angles::INCIDENCE_STEPS;
use crate::entry_shift::EntryShift;
use crate::error::{Result, ShadingError};
use crate::shape::ShapeTable;
use crate::translucency::Translucency;

/// How the surfaces of one SSS material are shaded around the scattering; the default is off
/// (plain Lambertian entry and exit, no light through thin parts).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
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
    /// Shape-aware shading (None: off): light entering a curved body returns E(κ, θ) times what
    /// a half-space returns near its entry ([`ShapeTable`]); the scene pass multiplies each
    /// light's entering light on SSS surfaces by E at the surface's curvature at the scale the
    /// light travels (baked per vertex, [`crate::curvature`]), which makes a convex part brighter and
    /// a concave one darker before the blur spreads the light; and where the body is thinner
    /// along the light than its curvature makes it (its chord from a back-face depth map per
    /// light), by [`ShapeTable::thin_factor`]: the light a slab that thin loses through its far
    /// side.
    pub shape: Option<ShapeTable>,
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
        if let Some(t) = &self.shape {
            t.validate()?;
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(ShadingError::invalid("eta", self.eta, "must be positive"));
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
                return Err(ShadingError::invalid(what, v, reason));
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
            shape: None,
            eta: 1.0,
        }
    }
}
