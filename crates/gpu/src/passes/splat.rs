//! Splatted translucency, the geometric half of the area gather (Maisch & Ropinski 2020 §5, §6.2,
//! §6.3; splat.wgsl): the light that enters the SSS material where the camera does not see it,
//! one splat per triangle, added to the gathered light.
//!
//! Choices the paper leaves open, or where this departs from it:
//! - The proxy is the scene's mesh itself (every triangle of the material), not a separate
//!   low-poly model; triangles larger than a disc of half the kernel's reach are split into four
//!   until they are not (R′ is tabulated only up to that size: the fins' faces of 54 cm², read at
//!   marble's largest disc, 2.4 cm², came out 11× too bright).
//! - Splats are lit in a compute pass (the scene pass's `shade` at the triangle's centre, with
//!   shadows and the incidence table, without the shadow-map thin-part term, which they replace)
//!   and culled there. The gather counts every pixel the camera sees (at grazing view too, with a
//!   bounded footprint), so a triangle splats exactly where it is *not seen*: its centre's view
//!   depth lies off the G-buffer's at its pixel by more than 10⁻³ of the depth plus the surface's
//!   depth slope over two pixels (their eq. 2; off screen or over the background counts as not
//!   seen), or it is turned away (n·v ≤ 0, their eq. 3), which no face is seen as, however close
//!   to one it lies (a thin slab's back). The paper also requires n·v < 0.2 (eq. 8) and leaves
//!   the grazing band to the splats; at a quarter of the resolution they cannot hold a short
//!   kernel's light there (Skin1's lit rim came out at a tenth of its light), and hidden parts
//!   facing the camera would belong to neither half. Without the slope term, a fixed depth
//!   tolerance took 15 % of the marble sphere's visible triangles for hidden ones (12 % more
//!   light); the distance to the triangle's plane instead fails on curved surfaces at grazing view,
//!   where a pixel's ray meets the surface far from the triangle's plane.
//! - "A quarter of the resolution" is read as a quarter per side: splats accumulate at the
//!   pyramid level whose texels are 4×4 pixels, and each receiver texel's x_o is the mean position
//!   of the material's pixels in it (the gather's position pyramid). Accumulation is additive in
//!   rgba32float where the adapter can blend it (WebGPU's `float32-blendable`), else in
//!   rgba16float, which drops splats below 2⁻¹² of a texel's sum (15 % of a thin slab's light
//!   with 8,192 splats, measured).
//! - Each splat is evaluated at its triangle's centre, R′(|x_i − x_o|, A_i): R′ already averages
//!   the kernel over the triangle's area. Their eq. 9, which moves the point towards x_o by up to
//!   the radius of that disc before the same R′ is read, counts the kernel's peak once per nearby
//!   triangle: under a slab 0.02 cm thin, of triangles 0.25 cm wide, it transmits 1.54× the
//!   kernel's energy where the centres give 0.98 (tested; 2.9× with the kernel 8× narrower).
//!   It is available as [`AreaGatherSetup::splat_clamp`], with x̄ the projection of x_o onto the
//!   splat's plane, x_o − n(n·(x_o − x_i)); the paper prints a plus sign, which leaves the plane.
//! - The upsampling is a cubic B-spline over 4×4 texels (the filter of Sigg & Hadwiger's bicubic
//!   lookup), evaluated with 16 loads so that texels without receivers are left out and the weights
//!   renormalized.

use glam::Vec3;

use crate::error::Result;
use crate::frame::context::{Gpu, bind};
use crate::frame::recording::Recording;
use crate::frame::target::Target;
use crate::frame::timing::Timer;
use crate::gathers::area_gather::{AreaGatherSetup, Gathered};
use crate::passes::Pass;
use crate::passes::gbuffer::NEAR;
use crate::scene::Scene;

/// How far a triangle's centre may lie in view depth from the surface seen at its pixel and
/// count as that surface: this fraction of the depth [cm per cm] ...
const SEEN_TOLERANCE: f32 = 1e-3;
/// ... plus the surface's depth slope over this many pixels (the centre's offset from the
/// pixel's, up to half a pixel, and the triangle's own extent).
const SEEN_SLOPE_PX: f32 = 2.0;

/// The pyramid level the splats accumulate at: texels of 2² × 2² = 4 × 4 pixels.
const SPLAT_LEVEL: usize = 2;

/// The shader: the shading model's lookups, lighting and the kernel lookup prepended.
pub(crate) const SPLAT_WGSL: &str = const_format::concatcp!(
    shading::LOOKUPS_WGSL,
    include_str!("../shaders/lighting.wgsl"),
    include_str!("../shaders/area_kernel.wgsl"),
    include_str!("../shaders/splat.wgsl")
);

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SplatU {
    view_proj: [[f32; 4]; 4],
    camera_pos: [f32; 4],
    kernel: [u32; 4],
    proj: [f32; 4],
    size: [u32; 4],
    level: [u32; 4],
    far: [f32; 4],
}

/// The size of splat.wgsl's `Splat` (checked against naga's layout in a test).
pub(crate) const SPLAT_UNIFORM_SIZE: usize = 160;
const _: () = assert!(std::mem::size_of::<SplatU>() == SPLAT_UNIFORM_SIZE);

/// One triangle as splat.wgsl's `Tri`: centre and area, outward normal, albedo and material.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Tri {
    centre: [f32; 4],
    normal: [f32; 4],
    albedo: [f32; 4],
}

/// The most splats a frame draws; triangles are not subdivided beyond it.
pub(crate) const MAX_SPLATS: usize = 1 << 20;

/// The splats of `material`: every triangle whose first vertex has SSS and that material, with
/// its centre, area [cm²] and geometric normal turned to the side of its vertices' normals,
/// split at its edges' midpoints into four (recursively) until each part's area is at most
/// `max_area` [cm²] or [`MAX_SPLATS`] would be exceeded. A splat's light is E·A·R′(r, A), and R′
/// is tabulated for discs up to the kernel's reach: a larger triangle would read a smaller disc's
/// average and be counted with its whole area.
fn triangles(scene: &Scene, material: u32, max_area: f32) -> Vec<Tri> {
    let v = &scene.mesh.vertices;
    let mut out = Vec::new();
    let parents: Vec<([Vec3; 3], Vec3, Vec3)> = scene
        .mesh
        .indices
        .chunks_exact(3)
        .filter_map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| v[t[k] as usize]);
            if a.strength <= 0.0 || a.material != material {
                return None;
            }
            let p = [a.pos, b.pos, c.pos].map(Vec3::from);
            let cross = (p[1] - p[0]).cross(p[2] - p[0]);
            let area = 0.5 * cross.length();
            if area.is_nan() || area <= 0.0 {
                return None;
            }
            let shading = Vec3::from(a.normal) + Vec3::from(b.normal) + Vec3::from(c.normal);
            let n = cross.normalize() * if cross.dot(shading) < 0.0 { -1.0 } else { 1.0 };
            Some((p, n, Vec3::from(a.albedo)))
        })
        .collect();
    // Subdivision levels per parent, as many as the budget allows (each level × 4).
    let area = |p: &[Vec3; 3]| 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
    let levels: Vec<u32> = parents
        .iter()
        .map(|(p, _, _)| {
            let ratio = area(p) / max_area.max(f32::MIN_POSITIVE);
            if ratio > 1.0 {
                (ratio.log(4.0).ceil() as u32).min(10)
            } else {
                0
            }
        })
        .collect();
    let total = |cap: u32| -> usize {
        levels
            .iter()
            .map(|&l| 1usize << (2 * l.min(cap)))
            .sum::<usize>()
    };
    let cap = (0..=10)
        .rev()
        .find(|&c| total(c) <= MAX_SPLATS)
        .unwrap_or(0);
    fn split(p: [Vec3; 3], level: u32, emit: &mut dyn FnMut([Vec3; 3])) {
        if level == 0 {
            return emit(p);
        }
        let m = [
            (p[0] + p[1]) / 2.0,
            (p[1] + p[2]) / 2.0,
            (p[2] + p[0]) / 2.0,
        ];
        for q in [
            [p[0], m[0], m[2]],
            [m[0], p[1], m[1]],
            [m[2], m[1], p[2]],
            m,
        ] {
            split(q, level - 1, emit);
        }
    }
    for ((p, n, albedo), level) in parents.into_iter().zip(levels) {
        split(p, level.min(cap), &mut |q| {
            out.push(Tri {
                centre: ((q[0] + q[1] + q[2]) / 3.0).extend(area(&q)).into(),
                normal: n.extend(0.0).into(),
                albedo: albedo.extend(material as f32).into(),
            })
        });
    }
    out
}

/// The compiled lighting, splatting and upsampling pipelines.
pub(crate) struct Splats {
    light: wgpu::ComputePipeline,
    draw: wgpu::RenderPipeline,
    up: wgpu::ComputePipeline,
    format: wgpu::TextureFormat,
}

impl Pass for Splats {
    /// The target, the area gather's set-up, the width factor, the scene pass's lighting bindings and what the gather left.
    type Input<'a> = (
        &'a Target<'a>,
        &'a AreaGatherSetup,
        f32,
        [wgpu::BindGroupEntry<'a>; 3],
        &'a Gathered,
    );
    /// Nothing: the splats add into the target's scattered light.
    type Output = ();

    fn new(gpu: &Gpu) -> Splats {
        let dev = &gpu.device;
        let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("splat"),
            source: wgpu::ShaderSource::Wgsl(SPLAT_WGSL.into()),
        });
        let compute =
            |entry: &str| crate::frame::context::entry_pipeline(dev, &module, entry, entry);
        let format = if gpu.float32_blend {
            wgpu::TextureFormat::Rgba32Float
        } else {
            wgpu::TextureFormat::Rgba16Float
        };
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let draw = dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("splats"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: Some(wgpu::BlendState {
                        color: add,
                        alpha: add,
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Splats {
            light: compute("light"),
            draw,
            up: compute("up"),
            format,
        }
    }

    /// Records the splats of `material` and adds their upsampled light to the target's scattered
    /// light on the material's pixels.
    fn encode(
        &self,
        rec: &mut Recording,
        (target, setup, sss_width, lighting, gathered): Self::Input<'_>,
    ) -> Result<()> {
        let Target {
            scene,
            size: (w, h),
            gbuffer,
            scattered,
            ..
        } = *target;
        let (alloc, enc, timer) = (rec.alloc, &mut rec.enc, &mut rec.timer.as_mut());
        // Splats no larger than a disc of half the kernel's reach, within the table's rows.
        let reach = sss_width * setup.kernel.r_max_cm();
        let tris = triangles(scene, 0, std::f32::consts::PI * (0.5 * reach).powi(2));
        if tris.is_empty() {
            return Ok(());
        }
        let dev = &alloc.gpu.device;
        let level = SPLAT_LEVEL.min(gathered.levels.len() - 1);
        let lv = gathered.levels[level];
        let proj = scene
            .camera
            .projection(w as f32 / h as f32, NEAR, crate::passes::gbuffer::FAR);
        let u = SplatU {
            view_proj: crate::passes::gbuffer::camera_view_proj(scene, (w, h)).to_cols_array_2d(),
            camera_pos: scene
                .camera
                .position
                .extend(if setup.splat_clamp { 1.0 } else { 0.0 })
                .into(),
            kernel: setup.kernel.uniform(sss_width),
            proj: [
                proj.x_axis.x,
                proj.y_axis.y,
                sss_width * setup.kernel.r_max_cm(),
                NEAR,
            ],
            size: [w, h, lv[1], lv[2]],
            level: [lv[0], level as u32, tris.len() as u32, 0],
            far: [
                crate::passes::gbuffer::FAR * 0.999,
                SEEN_TOLERANCE,
                SEEN_SLOPE_PX,
                crate::gathers::area_gather::GRAZING,
            ],
        };
        let ubuf = alloc.uniform("splat params", bytemuck::bytes_of(&u));
        let tbuf = alloc.storage("triangles", bytemuck::cast_slice(&tris));
        let lit = alloc.pixels(tris.len(), "splat light");
        let compute = |enc: &mut wgpu::CommandEncoder,
                       pipeline: &wgpu::ComputePipeline,
                       label: &str,
                       entries: &[wgpu::BindGroupEntry],
                       groups: (u32, u32),
                       timer: &mut Option<&mut Timer>| {
            let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.get_bind_group_layout(0),
                entries,
            });
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: timer.as_mut().map(|t| t.writes(label)),
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        };
        let [globals, shadows, sampler] = lighting;
        compute(
            enc,
            &self.light,
            "splat light",
            &[
                globals,
                shadows,
                sampler,
                bind(3, &ubuf),
                bind(4, &tbuf),
                bind(5, &lit),
                bind(7, &gbuffer.geometry),
            ],
            ((tris.len() as u32).div_ceil(64), 1),
            timer,
        );
        let target = alloc.texture(
            "splats",
            (lv[1], lv[2], 1),
            self.format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let view = target.create_view(&Default::default());
        {
            let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &self.draw.get_bind_group_layout(0),
                entries: &[
                    bind(3, &ubuf),
                    bind(4, &tbuf),
                    bind(6, &lit),
                    bind(8, &gathered.table),
                    bind(9, &gathered.pos),
                ],
            });
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("splats"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: timer.as_mut().map(|t| t.render_writes("splats")),
                ..Default::default()
            });
            pass.set_pipeline(&self.draw);
            pass.set_bind_group(0, &bind, &[]);
            pass.draw(0..6, 0..tris.len() as u32);
        }
        compute(
            enc,
            &self.up,
            "splat upsampling",
            &[
                bind(3, &ubuf),
                bind(7, &gbuffer.geometry),
                bind(9, &gathered.pos),
                wgpu::BindGroupEntry {
                    binding: 10,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                bind(11, scattered),
            ],
            (w.div_ceil(8), h.div_ceil(8)),
            timer,
        );
        Ok(())
    }
}

impl Splats {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Mesh, Vertex};

    /// Splitting keeps the area, the normal's side and the centroid, and stops at `max_area`.
    #[test]
    fn large_triangles_split_into_parts_of_the_same_total_area() {
        let vertex = |x: f32, z: f32| Vertex {
            pos: [x, 0.0, z],
            normal: [0.0, -1.0, 0.0],
            albedo: [1.0; 3],
            strength: 1.0,
            material: 0,
            curvature: [0.0; 3],
        };
        let mut scene = Scene::named("sphere").unwrap();
        scene.mesh = Mesh {
            vertices: vec![vertex(0.0, 0.0), vertex(4.0, 0.0), vertex(0.0, 4.0)],
            indices: vec![0, 1, 2],
        };
        let whole = triangles(&scene, 0, 100.0);
        assert_eq!(whole.len(), 1);
        assert_eq!(whole[0].centre[3], 8.0);
        assert_eq!(whole[0].normal[1], -1.0);
        let parts = triangles(&scene, 0, 1.0);
        assert_eq!(parts.len(), 16);
        assert!(
            parts
                .iter()
                .all(|t| t.centre[3] == 0.5 && t.normal[1] == -1.0)
        );
        let centroid = parts
            .iter()
            .fold(Vec3::ZERO, |s, t| s + Vec3::from_slice(&t.centre[..3]))
            / 16.0;
        assert!((centroid - Vec3::new(4.0 / 3.0, 0.0, 4.0 / 3.0)).length() < 1e-5);
        assert!(triangles(&scene, 1, 1.0).is_empty(), "another material");
    }
}
