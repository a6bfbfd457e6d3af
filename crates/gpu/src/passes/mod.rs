//! The passes of a frame, each a type built once per renderer that records its work into a
//! frame's recording ([`Pass`]; the gathers of [`crate::gathers`] too): the shadow maps
//! ([`shadow`]), the scene pass with the shading tables ([`gbuffer`]), the separable kernels
//! ([`separable`]: the blur of [`blur`] at full or half resolution, [`half`]), the
//! recombination ([`combine`]), the disc gathers' denoiser ([`denoise`]) and the splats of light entering where the camera does not see
//! ([`splat`]).

use crate::error::Result;
use crate::frame::context::Gpu;
use crate::frame::recording::Recording;

pub mod blur;
pub(crate) mod combine;
pub mod denoise;
pub(crate) mod gbuffer;
pub(crate) mod half;
pub(crate) mod separable;
pub(crate) mod shadow;
pub(crate) mod splat;

/// The shape of every pass of a frame: compiled once per renderer ([`Pass::new`]), then recording
/// its work into a frame's [`Recording`] from what it reads ([`Pass::Input`]) and returning what
/// the passes after it read ([`Pass::Output`]).
pub(crate) trait Pass {
    /// What one recording reads.
    type Input<'a>;
    /// What it leaves for the passes after it.
    type Output;
    /// Compiles the pass's pipelines.
    fn new(gpu: &Gpu) -> Self;
    /// Records the pass into the frame.
    fn encode(&self, rec: &mut Recording, input: Self::Input<'_>) -> Result<Self::Output>;
}
