//! Render settings: what a frame is drawn with, besides the scene and the scattering.

use crate::passes::blur::DepthMode;
use crate::scene::AlbedoMode;
use shading::Shading;

/// Render settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderParams {
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// How the albedo is split around the scattering; [`crate::Scatter::DirectionalDipole`] ignores it.
    pub albedo: AlbedoMode,
    /// Kernel width multiplier (1 = physical size).
    pub sss_width: f32,
    /// How the blur treats samples across depth discontinuities.
    pub depth_mode: DepthMode,
    /// Depth tolerance [cm] (see [`crate::BlurParams::tolerance_cm`]); None: from each kernel.
    pub tolerance_cm: Option<f32>,
    /// The fraction of taps jittered per pixel within their cells (see
    /// [`crate::BlurParams::jitter`]); 0: off.
    pub jitter: f32,
    /// Fixed view depth [cm] for the kernel scale (see [`crate::BlurParams::fixed_depth`]).
    pub fixed_depth: Option<f32>,
    /// Exposure before tone mapping.
    pub exposure: f32,
    /// Pixels without SSS do no blur work (they keep their unscattered light either way; off
    /// only to measure what the skip saves).
    pub skip_empty: bool,
    /// A material whose kernel reaches less than [`crate::SUBPIXEL_PX`] from any of its pixels (far
    /// away, or a tiny kernel) is not blurred: its kernel is replaced by one tap holding the
    /// kernel's total response ([`crate::KernelTaps::point`]). Off only to measure what that saves.
    pub skip_subpixel: bool,
    /// The blur's fast path (see [`crate::BlurParams::fast`]): one filtered texture fetch per
    /// tap at half precision; one SSS material per frame.
    pub fast: bool,
    /// Run the separable passes at half resolution (2×2 blocks averaged, then a depth- and
    /// material-aware bilinear upsampling; `half.rs`), a quarter of the blur's work.
    pub half_res: bool,
    /// Per SSS material (the vertices' `material` index): how its surfaces are shaded.
    pub shading: [Shading; MAX_MATERIALS],
}

/// The most SSS materials one frame holds (each with its kernel and [`Shading`]).
pub const MAX_MATERIALS: usize = 4;

impl Default for RenderParams {
    fn default() -> Self {
        RenderParams {
            width: 1920,
            height: 1080,
            albedo: AlbedoMode::PrePost,
            sss_width: 1.0,
            depth_mode: DepthMode::Lerp,
            tolerance_cm: None,
            jitter: 0.0,
            fixed_depth: None,
            exposure: 1.0,
            skip_empty: true,
            skip_subpixel: true,
            half_res: false,
            fast: false,
            shading: [Shading::default(); MAX_MATERIALS],
        }
    }
}
