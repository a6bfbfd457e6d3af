//! A frame of the separable method as data for another WebGPU renderer (the browser page in
//! `web/`): the shaders [`crate::Renderer`] compiles, the mesh, every uniform block and the
//! kernels' taps exactly as it uploads them, and the order of its passes. A page that runs them
//! with the same bindings draws the frame [`crate::render`] draws; it may move a directional
//! light by recomputing its shadow projection from [`WebFrame::shadow_centre`] and
//! [`WebFrame::shadow_radius`] as the renderer does.

use glam::Vec3;
use shading::KernelTaps;

use crate::error::{GpuError, Result};
use crate::params::RenderParams;
use crate::passes::blur::{BLUR_WGSL, steps};
use crate::passes::gbuffer::{FAR, SCENE_WGSL, globals_bytes};
use crate::passes::separable::blur_setup;
use crate::passes::shadow::shadow_size;
use crate::scene::Scene;

/// The shaders, as the renderer compiles them.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WebShaders {
    /// The shadow maps' depth pass (`vs`).
    pub shadow: String,
    /// The scene pass (`vs`, `fs`; three colour targets rgba32float, rgba16float, rg32float and
    /// depth32float).
    pub scene: String,
    /// The scene targets into storage buffers (`main`).
    pub unpack: String,
    /// One 1D pass of the separable blur (`main`).
    pub blur: String,
    /// The recombination and tone mapping (`main`).
    pub combine: String,
}

/// One emitter's shadow map.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WebShadow {
    /// Its view-projection, column-major.
    pub view_proj: [f32; 16],
    /// Whether it casts shadows (else its layer stays cleared).
    pub shadow: bool,
    /// Directional (else a point).
    pub directional: bool,
}

/// One 1D blur pass: its uniform block is `blur_{index}.bin`, its taps and cells
/// `taps_{material}_{pass}.bin` and `cells_{material}_{pass}.bin`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WebBlurStep {
    /// The SSS material whose kernel it applies.
    pub material: usize,
    /// The kernel's separable term.
    pub pass: usize,
    /// Horizontal: light → scratch; else vertical: scratch → scattered (accumulated).
    pub horizontal: bool,
}

/// A frame as data: what [`WebFrame::binaries`] holds and how the passes run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct WebFrame {
    /// Image size [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// Indices to draw (`indices.bin`, u32; `vertices.bin`: 56-byte vertices, position, normal
    /// and albedo as float32x3, strength float32, material uint32, curvature float32x3).
    pub index_count: u32,
    /// Side of each shadow map [texels] (a depth32float 2D array, one layer per emitter).
    pub shadow_size: u32,
    /// Per emitter, in the order of the scene pass's lights.
    pub shadows: Vec<WebShadow>,
    /// The centre [cm] of the sphere a directional light's shadow map covers.
    pub shadow_centre: [f32; 3],
    /// Its radius [cm]: the light's view is orthographic over ±radius, from centre + 3·radius
    /// towards the light, depth 0.1 to 6·radius.
    pub shadow_radius: f32,
    /// The far plane [cm]: the scene targets' geometry clear value.
    pub far: f32,
    /// Byte offset of the lights in `globals.bin` (2 mat4 and 3 vec4) and each light's size (192:
    /// view_proj, inv_view_proj, position or direction, colour, two cell vectors).
    pub lights_offset: usize,
    /// Byte offset of the materials' packed tables in `globals.bin`.
    pub materials_offset: usize,
    /// The blur's passes in order (the scattered buffer is cleared first).
    pub blur: Vec<WebBlurStep>,
    /// The shaders.
    pub wgsl: WebShaders,
    #[serde(skip)]
    binaries: Vec<(String, Vec<u8>)>,
}

impl WebFrame {
    /// The frame `crate::render` draws of `scene` with `kernels` (one per SSS material) at
    /// `params`: full resolution, the exact blur path, no shape tables (their thin bodies need the
    /// back maps, which the page does not draw); other settings are refused by name.
    pub fn new(scene: &Scene, kernels: &[KernelTaps], params: &RenderParams) -> Result<WebFrame> {
        if crate::passes::shadow::back_layers(scene, params) > 0 {
            return Err(GpuError::invalid(
                "shape",
                "on",
                "a web frame draws no back maps (the shape table's thin bodies): shape off",
            ));
        }
        if params.half_res || params.fast {
            return Err(GpuError::invalid(
                "resolution",
                if params.half_res { "half" } else { "fast" },
                "a web frame runs the full-resolution exact blur",
            ));
        }
        if kernels.len() < scene.material_count() {
            return Err(GpuError::invalid(
                "kernels",
                kernels.len(),
                "one per SSS material of the scene",
            ));
        }
        let (w, h) = (params.width, params.height);
        let (kernels, blur_params) = blur_setup(scene, kernels, params);
        let emitters = scene.emitters();
        let shadows = emitters
            .iter()
            .map(|e| WebShadow {
                view_proj: scene.light_view_proj(e).to_cols_array(),
                shadow: e.shadow,
                directional: e.pos_or_dir.w == 0.0,
            })
            .collect();
        let (centre, radius): (Vec3, f32) = scene.shadow_bounds();
        let steps = steps(&kernels, &blur_params, (w, h));
        let mut binaries = vec![
            (
                "globals.bin".to_string(),
                globals_bytes(scene, params, false),
            ),
            (
                "vertices.bin".to_string(),
                bytemuck::cast_slice(&scene.mesh.vertices).to_vec(),
            ),
            (
                "indices.bin".to_string(),
                bytemuck::cast_slice(&scene.mesh.indices).to_vec(),
            ),
            (
                "combine.bin".to_string(),
                bytemuck::cast_slice(&[w, h, params.exposure.to_bits(), 0]).to_vec(),
            ),
        ];
        for (i, s) in steps.iter().enumerate() {
            binaries.push((
                format!("blur_{i}.bin"),
                bytemuck::bytes_of(&s.uniform).to_vec(),
            ));
        }
        for (m, k) in kernels.iter().enumerate() {
            let cells = k.cells();
            for (p, (_, taps)) in k.passes.iter().enumerate() {
                binaries.push((
                    format!("taps_{m}_{p}.bin"),
                    bytemuck::cast_slice(taps).to_vec(),
                ));
                binaries.push((
                    format!("cells_{m}_{p}.bin"),
                    bytemuck::cast_slice(&cells[p]).to_vec(),
                ));
            }
        }
        Ok(WebFrame {
            width: w,
            height: h,
            index_count: scene.mesh.indices.len() as u32,
            shadow_size: shadow_size(emitters.len().max(1) as u32),
            shadows,
            shadow_centre: centre.into(),
            shadow_radius: radius,
            far: FAR,
            lights_offset: 2 * 64 + 3 * 16,
            materials_offset: 2 * 64 + 3 * 16 + crate::light::MAX_EMITTERS * 192,
            blur: steps
                .iter()
                .map(|s| WebBlurStep {
                    material: s.material,
                    pass: s.pass,
                    horizontal: s.horizontal,
                })
                .collect(),
            wgsl: WebShaders {
                shadow: include_str!("shaders/shadow.wgsl").into(),
                scene: SCENE_WGSL.into(),
                unpack: include_str!("shaders/unpack.wgsl").into(),
                blur: BLUR_WGSL.into(),
                combine: include_str!("shaders/combine.wgsl").into(),
            },
            binaries,
        })
    }

    /// The frame's buffers as named files: `globals.bin`, `vertices.bin`, `indices.bin`,
    /// `combine.bin`, `blur_{i}.bin`, `taps_{m}_{p}.bin`, `cells_{m}_{p}.bin`.
    pub fn binaries(&self) -> &[(String, Vec<u8>)] {
        &self.binaries
    }
}
