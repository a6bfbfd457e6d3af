//! `gpu`: separable subsurface scattering applied in screen space with wgpu, headless
//! (Jimenez et al. 2015; Freude 2014 §4.2–4.4).
//!
//! Pipeline per frame: shadow maps → scene pass (irradiance with the chosen albedo split, specular,
//! linear view depth, SSS strength and material, into render targets) → unpack to storage buffers
//! → for each SSS material (up to [`MAX_MATERIALS`] per frame) and each separable term of its
//! kernel a horizontal and a vertical compute pass over that material's pixels → recombine
//! (× post-scatter albedo, + specular, tone map). World units are cm; kernel tap offsets are cm on
//! the surface. Everything runs without a window; results are read back as float images.
//!
//! [`compare_models`] ([`compare`]) renders kernel models beside the CPU 2D ground truth of the
//! same irradiance and measures their image errors (thesis Tables 6.4 and 6.5).
//!
//! The other method, [`Scatter::DirectionalDipole`] ([`dipole`]), replaces the separable passes:
//! position/normal maps from the camera and from each light, then progressive Monte Carlo frames
//! that integrate the directional dipole over the lit surface points around each pixel.
//!
//! [`Scatter::SurfaceGather`] ([`surface_gather`]) integrates the material's own Monte Carlo
//! BSSRDF (`mc`'s profile, or its Rd(x, y; θ) at oblique incidence) the same way: the reference
//! any real-time method is measured against on the same geometry and visibility.
//!
//! For large scattering distances, [`Scatter::AreaGather`] ([`area_gather`]) gathers an area
//! pre-integrated kernel over Maisch & Ropinski's layered sampling pattern instead.
//!
//! The tables a material is shaded with (incidence, exit, entry shift, translucency, the
//! directional table) come from the `shading` crate as plain data; this crate uploads them.
//!
//! Conventions: images are row-major, top row first, RGBA f32 per pixel. A pixel at view depth z
//! spans z/f cm with f = height/(2·tan(fov_y/2)) (`px_per_cm_at_unit_depth`).

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]

mod error;
pub mod eval;
mod frame;
pub mod gathers;
mod light;
mod mesh;
mod params;
mod passes;
mod render;
pub mod request;
mod scene;
mod web;

pub use error::{GpuError, Result};
pub use eval::compare::{Comparison, compare_kernels, compare_models};
pub use frame::context::{Gpu, quiet_headless_vulkan};
pub use frame::timing::PassTime;
pub use gathers::area_gather::{AreaGatherSetup, AreaKernel, GatherPattern};
pub use gathers::dipole::DipoleSetup;
pub use gathers::disc_gather::{DISC_LIGHTS, Sampling};
pub use gathers::surface_gather::SurfaceGatherSetup;
pub use light::{AREA_CELLS, Emitter, Light, MAX_EMITTERS, emitters};
pub use mesh::{Mesh, Vertex};
pub use params::{MAX_MATERIALS, RenderParams};
pub use passes::blur::{BlurParams, DepthMode, blur_image};
pub use passes::denoise::{FLOOR_PX as DENOISE_FLOOR_PX, LEVELS as DENOISE_LEVELS};
pub use render::{Frame, FrameTime, Renderer, SUBPIXEL_PX, Scatter, kernel_footprint_px, render};
pub use request::{Method, RenderRequest};
pub use scene::{AlbedoMode, Camera, Scene};
pub use shading::KernelTaps;
pub use web::{WebBlurStep, WebFrame, WebShaders, WebShadow};

#[cfg(test)]
mod tests {
    /// A shader's file name, its source, and its uniform struct's name and the byte size of the
    /// Rust twin uploaded into it (None: no uniform twin).
    type Shader = (&'static str, &'static str, Option<(&'static str, usize)>);

    const SHADERS: [Shader; 15] = [
        (
            "denoise.wgsl",
            include_str!("shaders/denoise.wgsl"),
            Some(("Denoise", crate::passes::denoise::DENOISE_UNIFORM_SIZE)),
        ),
        (
            "scene.wgsl",
            crate::passes::gbuffer::SCENE_WGSL,
            Some(("Globals", crate::passes::gbuffer::GLOBALS_SIZE)),
        ),
        ("shadow.wgsl", include_str!("shaders/shadow.wgsl"), None),
        ("unpack.wgsl", include_str!("shaders/unpack.wgsl"), None),
        (
            "blur.wgsl + blur_exact.wgsl",
            crate::passes::blur::BLUR_WGSL,
            Some(("Params", crate::passes::blur::BLUR_UNIFORM_SIZE)),
        ),
        (
            "blur.wgsl + blur_fast.wgsl",
            crate::passes::blur::BLUR_FAST_WGSL,
            Some(("Params", crate::passes::blur::BLUR_UNIFORM_SIZE)),
        ),
        (
            "half.wgsl",
            include_str!("shaders/half.wgsl"),
            Some(("Params", crate::passes::half::HALF_UNIFORM_SIZE)),
        ),
        (
            "combine.wgsl",
            include_str!("shaders/combine.wgsl"),
            Some(("Params", 16)),
        ),
        (
            "surface.wgsl",
            include_str!("shaders/surface.wgsl"),
            Some(("View", crate::gathers::area_gather::VIEW_UNIFORM_SIZE)),
        ),
        (
            "area_kernel.wgsl + area_gather.wgsl",
            crate::gathers::area_gather::AREA_GATHER_WGSL,
            Some(("Params", crate::gathers::area_gather::GATHER_UNIFORM_SIZE)),
        ),
        (
            "fresnel + lighting + area_kernel + splat.wgsl",
            crate::passes::splat::SPLAT_WGSL,
            Some(("Splat", crate::passes::splat::SPLAT_UNIFORM_SIZE)),
        ),
        (
            "dipole_maps.wgsl",
            include_str!("shaders/dipole_maps.wgsl"),
            Some(("View", 64)),
        ),
        (
            "fresnel + dipole + disc_gather.wgsl",
            crate::gathers::dipole::DIPOLE_WGSL,
            Some(("Dipole", crate::gathers::dipole::DIPOLE_UNIFORM_SIZE)),
        ),
        (
            "fresnel + dipole + disc_gather.wgsl (Gather)",
            crate::gathers::dipole::DIPOLE_WGSL,
            Some(("Gather", crate::gathers::disc_gather::GATHER_UNIFORM_SIZE)),
        ),
        (
            "fresnel + mc_bssrdf + disc_gather.wgsl",
            crate::gathers::surface_gather::MC_BSSRDF_WGSL,
            Some((
                "Tables",
                crate::gathers::surface_gather::TABLES_UNIFORM_SIZE,
            )),
        ),
    ];

    /// Without an adapter: every shader parses and validates with naga, and each uniform struct
    /// has the byte size of the `#[repr(C)]` struct Rust uploads into it.
    #[test]
    fn every_shader_validates_and_its_uniform_matches_rust() {
        for (name, src, uniform) in SHADERS {
            let module = naga::front::wgsl::parse_str(src)
                .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(src)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::default(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            if let Some((ty, size)) = uniform {
                let mut layouter = naga::proc::Layouter::default();
                layouter.update(module.to_ctx()).unwrap();
                let (handle, _) = module
                    .types
                    .iter()
                    .find(|(_, t)| t.name.as_deref() == Some(ty))
                    .unwrap_or_else(|| panic!("{name}: no struct {ty}"));
                assert_eq!(layouter[handle].size as usize, size, "{name}: {ty}");
            }
        }
    }
}
