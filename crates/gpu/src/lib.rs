//! `gpu`: separable subsurface scattering applied in screen space with wgpu, headless
//! (Jimenez et al. 2015; Freude 2014 §4.2–4.4).
//!
//! Pipeline per frame: shadow maps → scene pass (irradiance with the chosen albedo split, specular,
//! linear view depth, SSS strength, into rgba32float targets) → unpack to storage buffers → for
//! each separable term of the kernel a horizontal and a vertical compute pass → recombine
//! (× post-scatter albedo, + specular, tone map). World units are cm; kernel tap offsets are cm on
//! the surface. Everything runs without a window; results are read back as float images.
//!
//! Conventions: images are row-major, top row first, RGBA f32 per pixel. A pixel at view depth z
//! spans z/f cm with f = height/(2·tan(fov_y/2)) (`px_per_cm_at_unit_depth`).

mod blur;
mod context;
mod error;
mod mesh;
mod render;
mod scene;

pub use blur::{BlurParams, DepthMode, GpuKernel, blur_image};
pub use context::Gpu;
pub use error::{GpuError, Result};
pub use mesh::{Mesh, Vertex};
pub use render::{
    Frame, INCIDENCE_STEPS, PassTime, RenderParams, incidence_hemispherical, incidence_ratio,
    render,
};
pub use scene::{AlbedoMode, Camera, Light, Scene};
