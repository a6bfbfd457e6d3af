//! The named choices of a request (method, exit law, albedo split, …), each with the name a
//! user writes and a line of help: one list that the command line's flags and Python's keyword
//! arguments both read, so the two cannot drift apart.

use crate::error::{RenderError, Result};

/// A choice among named values.
pub trait Choice: Copy + PartialEq + Send + Sync + 'static {
    /// What the choice is called in errors, e.g. `method`.
    const WHAT: &'static str;
    /// Every value: its name (kebab-case), the value, a line of help.
    const CHOICES: &'static [(&'static str, Self, &'static str)];

    /// The value named `name` (exactly, case-insensitive); the error lists the names.
    fn parse(name: &str) -> Result<Self> {
        Self::CHOICES
            .iter()
            .find(|(n, _, _)| n.eq_ignore_ascii_case(name.trim()))
            .map(|(_, v, _)| *v)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::CHOICES.iter().map(|(n, _, _)| *n).collect();
                RenderError::invalid(
                    Self::WHAT,
                    format!("{name:?}"),
                    format!("expected one of {}", names.join(", ")),
                )
            })
    }

    /// The value's name.
    fn name(self) -> &'static str {
        Self::CHOICES
            .iter()
            .find(|(_, v, _)| *v == self)
            .map(|(n, _, _)| *n)
            .expect("every value is listed in CHOICES")
    }
}

/// Which exit law the separable method's shading applies to the scattered light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExitLaw {
    /// Lambertian exit.
    Lambertian,
    /// h(θ_o) of light that entered along the normal, at every pixel.
    Normal,
    /// h(θ_o; θ_i) at the entry angle of the pixel's lights (irradiance-weighted).
    Entry,
}

/// How the directional dipole's energy is set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DipoleEnergy {
    /// Frisvad et al.'s model unchanged.
    Published,
    /// Each channel scaled so that its total diffuse reflectance is the Monte Carlo profile's.
    MonteCarlo,
}

impl Choice for gpu::Method {
    const WHAT: &'static str = "method";
    const CHOICES: &'static [(&'static str, Self, &'static str)] = &[
        (
            "separable",
            gpu::Method::Separable,
            "A separable screen-space kernel (thesis §4.2–4.4): a kernel file, or pre-integration \
             fitted to the material, with the incidence, exit and entry-shift tables",
        ),
        (
            "directional-dipole",
            gpu::Method::DirectionalDipole,
            "The directional dipole (Frisvad et al. 2014) integrated per pixel over lit surface \
             points; progressive over frames; ambient light is not scattered",
        ),
        (
            "area-gather",
            gpu::Method::AreaGather,
            "Maisch & Ropinski 2020: the Monte Carlo profile averaged over discs, gathered per \
             pixel over their layered pattern (long mean free paths: milk, marble, jade)",
        ),
        (
            "surface-gather",
            gpu::Method::SurfaceGather,
            "The material's own Monte Carlo BSSRDF integrated per pixel over lit surface points: \
             the reference a real-time method is measured against; progressive over frames",
        ),
    ];
}

impl Choice for ExitLaw {
    const WHAT: &'static str = "exit_law";
    const CHOICES: &'static [(&'static str, Self, &'static str)] = &[
        (
            "entry",
            ExitLaw::Entry,
            "h(θ_o; θ_i) at the entry angle of the pixel's lights, weighted by the irradiance each \
             brings",
        ),
        (
            "on",
            ExitLaw::Normal,
            "h(θ_o) of light that entered along the normal, at every pixel",
        ),
        ("off", ExitLaw::Lambertian, "Lambertian exit"),
    ];
}

impl Choice for DipoleEnergy {
    const WHAT: &'static str = "dipole_energy";
    const CHOICES: &'static [(&'static str, Self, &'static str)] = &[
        (
            "monte-carlo",
            DipoleEnergy::MonteCarlo,
            "Each channel scaled so its total diffuse reflectance equals the Monte Carlo profile's",
        ),
        (
            "published",
            DipoleEnergy::Published,
            "Frisvad et al.'s model unchanged (overestimates total reflectance, e.g. Skin1's by \
             1.5–2.5×)",
        ),
    ];
}

impl Choice for shading::Bssrdf {
    const WHAT: &'static str = "bssrdf";
    const CHOICES: &'static [(&'static str, Self, &'static str)] = &[
        (
            "directional",
            shading::Bssrdf::Directional,
            "mc's Rd(x, y; θ_i) at 0°, 10°, …, 80°, 85° laid on the modified tangent plane, with \
             the entry angle's total reflectance, leaving with h(θ_o; θ_i)",
        ),
        (
            "shape",
            shading::Bssrdf::Shape,
            "directional, scaled by mc's transport in spheres and cavities of the chord's \
             curvature from entry to exit: E(κ, θ_i) times the table with its lengths stretched \
             by ⟨s⟩(κ)/⟨s⟩(0)",
        ),
        (
            "radial",
            shading::Bssrdf::Radial,
            "Rd(|x_o − x_i|) of the Monte Carlo profile × ρ(θ_i)/ρ(0), leaving with h(θ_o; θ_i): \
             the best any radial-profile method can reach",
        ),
    ];
}

impl Choice for gpu::AlbedoMode {
    const WHAT: &'static str = "albedo";
    const CHOICES: &'static [(&'static str, Self, &'static str)] = &[
        (
            "pre-post",
            gpu::AlbedoMode::PrePost,
            "√albedo before and after the scattering (SSSS's default)",
        ),
        (
            "pre",
            gpu::AlbedoMode::Pre,
            "Albedo applied before scattering (blurs texture detail)",
        ),
        (
            "post",
            gpu::AlbedoMode::Post,
            "Albedo applied after scattering (keeps texture detail sharp)",
        ),
    ];
}

impl Choice for gpu::DepthMode {
    const WHAT: &'static str = "depth_test";
    const CHOICES: &'static [(&'static str, Self, &'static str)] = &[
        (
            "lerp",
            gpu::DepthMode::Lerp,
            "Lerp towards the centre sample as the depth difference grows (thesis eq. 4.12)",
        ),
        (
            "reject",
            gpu::DepthMode::Reject,
            "Reject samples across depth discontinuities and renormalize per channel",
        ),
        (
            "none",
            gpu::DepthMode::None,
            "No depth test (light bleeds across silhouettes)",
        ),
        (
            "gaussian",
            gpu::DepthMode::Gaussian,
            "Weight each sample by e^{−Δz²/(2τ)} (SSSS supplement §E), τ = tolerance² or the \
             kernel's largest variance, renormalized per channel",
        ),
    ];
}
