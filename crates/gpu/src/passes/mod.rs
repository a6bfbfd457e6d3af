//! The passes of a frame, each a type built once per renderer (`new`) that records its work into
//! a frame's recording (`encode`): the shadow maps ([`shadow`]), the scene pass with the shading
//! tables ([`gbuffer`]), the separable blur ([`blur`]) at full or half resolution ([`half`]),
//! the recombination ([`combine`]) and the splats of light entering where the camera does not
//! see ([`splat`]).

pub mod blur;
pub(crate) mod combine;
pub(crate) mod gbuffer;
pub(crate) mod half;
pub(crate) mod shadow;
pub(crate) mod splat;
