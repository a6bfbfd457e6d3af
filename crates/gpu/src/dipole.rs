//! The directional-dipole renderer: the real-time method of the directional-dipole draft (§4.2–4.3)
//! with the full BSSRDF of Frisvad et al. 2014 (`fit::analytic::DirectionalDipole`), evaluated
//! per pixel by Monte Carlo over lit surface points and accumulated over frames.
//!
//! For each SSS pixel x_o and each light, points p are drawn on a disc of radius r* around x_o
//! in the plane perpendicular to the light ray; the light's position/normal map (a light-space
//! G-buffer, the translucent-shadow-map idea the draft implies: Dachsbacher & Stamminger 2003)
//! carries p along the light ray onto the first surface the light reaches, the entry point x_i.
//! The draft leaves this lookup open; we chose the light-perpendicular disc because the flux it
//! intercepts is exact whatever the orientation of the surface at x_i: E⊥·dA⊥ for a directional
//! light, I·cos α·dA⊥/|p − x_light|² for a point light. Points the map marks as non-SSS (an
//! occluder, the floor) are in shadow and contribute nothing, and points on the far side of a
//! thin part reach x_o through the model's back-lit branch (translucency).
//!
//! Radii are importance-sampled from the mixture over the three channels of the truncated
//! exponentials σ_c·e^{−σ_c r}/(1 − e^{−σ_c r*}), σ_c = max(σtr_c, 1/r*) (one-sample
//! multiple importance sampling, balance heuristic), and each sample is divided by its density
//! per unit disc area, [`pdf_area`]. The draft's §4.3 gets this weight wrong twice: its text
//! divides by e^{−σtr r} and its equations multiply by it, both keeping the uniform disc's A_c/N
//! and without the 1/(2πr) of polar sampling; either is biased (test
//! `the_drafts_sampling_weights_are_biased`).
//!
//! Output: π·L_o per pixel (the exitance convention of the separable pipeline, whose images are
//! irradiance × albedo), without the post-scatter albedo: the colour comes from the material's
//! coefficients. Ambient light is not scattered by this method. Every frame adds 1/frames of its
//! estimate, so after `frames` frames the image is their mean (a viewer showing frame f would
//! scale by frames/f); frames differ only in their random numbers, which depend on the pixel,
//! the frame and the seed alone.

use fit::analytic::{DipoleConstants, DirectionalDipole, Medium};
use glam::Mat4;
use wgpu::util::DeviceExt;

use crate::context::{Gpu, cleared_depth, compute_pipeline, mesh_pipeline, texture};
use crate::error::{GpuError, Result};
use crate::mesh::MeshBuffers;
use crate::scene::Scene;
use crate::timing::Timer;

/// Settings of the directional-dipole method for one material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DipoleSetup {
    /// The model's constants per channel (R, G, B).
    pub channels: [DipoleConstants; 3],
    /// Samples per pixel, light and frame.
    pub samples: u32,
    /// Frames accumulated.
    pub frames: u32,
    /// Disc radius r* [cm].
    pub radius_cm: f32,
    /// Side of each light's position/normal map [texels].
    pub map_size: u32,
    /// Seed of the per-pixel random numbers.
    pub seed: u32,
    /// Multiplier of each channel's S_d (1: the model as published; see
    /// [`DipoleSetup::renormalized`]).
    pub scale: [f64; 3],
}

impl DipoleSetup {
    /// The method for a material's three channels, with defaults: 16 samples × 16 frames,
    /// r* = [`default_radius`], 1024² light maps, seed 1.
    pub fn new(media: &[Medium; 3]) -> Result<DipoleSetup> {
        for (c, m) in media.iter().enumerate() {
            m.validate().map_err(|e| {
                GpuError::invalid(format!("material channel {c}"), e, "unusable medium")
            })?;
        }
        let channels = media.map(|m| DirectionalDipole::new(&m).constants());
        Ok(DipoleSetup {
            channels,
            samples: 16,
            frames: 16,
            radius_cm: default_radius(&channels, media) as f32,
            map_size: 1024,
            seed: 1,
            scale: [1.0; 3],
        })
    }

    /// The same model rescaled per channel so that its total diffuse reflectance at normal
    /// incidence equals `rd_total` (e.g. `mc`'s): scale_c = rd_total_c / ∫Rd_c dA, the model's
    /// integral taken over 10³ transport mean free paths. The directional dipole overestimates
    /// the total (e.g. Skin1 at η = 1: 0.88 / 0.60 / 0.45 against Monte Carlo's ≈ 0.55 / 0.29 /
    /// 0.16, mostly from its real source's near-surface dipole term); this keeps its dependence
    /// on position and direction and fixes its energy.
    pub fn renormalized(mut self, media: &[Medium; 3], rd_total: [f64; 3]) -> Result<DipoleSetup> {
        for c in 0..3 {
            let model = fit::analytic::Model::DirectionalDipole
                .radial(&media[c])
                .map_err(|e| GpuError::invalid(format!("material channel {c}"), e, "unusable"))?
                .total(1e3 * media[c].transport_mfp());
            if !(rd_total[c].is_finite() && rd_total[c] >= 0.0) {
                return Err(GpuError::invalid(
                    format!("total reflectance of channel {c}"),
                    rd_total[c],
                    "must be finite and ≥ 0",
                ));
            }
            self.scale[c] = if model > 0.0 {
                rd_total[c] / model
            } else {
                0.0
            };
        }
        Ok(self)
    }

    /// Checks the settings; the error names the field.
    pub fn validate(&self) -> Result<()> {
        if !(1..=4096).contains(&self.samples) {
            return Err(GpuError::invalid(
                "samples",
                self.samples,
                "must lie in 1..=4096",
            ));
        }
        if !(1..=65536).contains(&self.frames) {
            return Err(GpuError::invalid(
                "frames",
                self.frames,
                "must lie in 1..=65536",
            ));
        }
        if !(self.radius_cm.is_finite() && self.radius_cm > 0.0) {
            return Err(GpuError::invalid(
                "disc radius",
                self.radius_cm,
                "must be positive and finite [cm]",
            ));
        }
        if let Some(v) = self.scale.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(GpuError::invalid("scale", v, "must be finite and ≥ 0"));
        }
        if !(64..=8192).contains(&self.map_size) {
            return Err(GpuError::invalid(
                "light map size",
                self.map_size,
                "must lie in 64..=8192 texels",
            ));
        }
        Ok(())
    }

    /// The radius sampling rate of each channel, σ_c = max(σtr_c, 1/r*) [cm⁻¹].
    pub fn rates(&self) -> [f64; 3] {
        self.channels
            .map(|k| k.sigma_tr.max(1.0 / self.radius_cm as f64))
    }
}

/// The default disc radius [cm]: ln 10³/σtr of the slowest-decaying channel, which keeps all but
/// ~10⁻³ of its exponential; a channel without absorption (σtr = 0) asks for 100 transport mean
/// free paths instead.
pub fn default_radius(channels: &[DipoleConstants; 3], media: &[Medium; 3]) -> f64 {
    channels
        .iter()
        .zip(media)
        .map(|(k, m)| {
            if k.sigma_tr > 0.0 {
                1000f64.ln() / k.sigma_tr
            } else {
                100.0 * m.transport_mfp()
            }
        })
        .fold(0.0, f64::max)
}

/// A radius [cm] from the truncated exponential σe^{−σr}/(1 − e^{−σr*}) on [0, r*) for a uniform
/// number `u` in [0, 1) (inverse CDF; the shader's twin).
pub fn sample_radius(u: f64, rate: f64, r_max: f64) -> f64 {
    -(1.0 - u * (1.0 - (-rate * r_max).exp())).ln() / rate
}

/// The density per unit disc area [cm⁻²] of a point at radius `r` [cm] when a channel is picked
/// uniformly and its radius drawn by [`sample_radius`]: the mixture's radial density over 2πr.
pub fn pdf_area(r: f64, rates: &[f64; 3], r_max: f64) -> f64 {
    let radial: f64 = rates
        .iter()
        .map(|&s| s * (-s * r).exp() / (1.0 - (-s * r_max).exp()))
        .sum::<f64>()
        / 3.0;
    radial / (2.0 * std::f64::consts::PI * r)
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DipoleLight {
    view_proj: [[f32; 4]; 4],
    pos_or_dir: [f32; 4],
    color: [f32; 4],
}

/// The shader's `Dipole` uniform (shaders/dipole.wgsl), field for field.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct DipoleUniform {
    lights: [DipoleLight; DIPOLE_LIGHTS],
    camera_pos: [f32; 4],
    d: [f32; 4],
    sigma_tr: [f32; 4],
    d_e: [f32; 4],
    backlit: [f32; 4],
    norm: [f32; 4],
    rate: [f32; 4],
    boundary: [f32; 4],
    disc: [f32; 4],
    size: [u32; 4],
    frame: [u32; 4],
}

/// The dipole shader with the shared Fresnel function prepended.
pub(crate) const DIPOLE_WGSL: &str = concat!(
    include_str!("shaders/fresnel.wgsl"),
    include_str!("shaders/dipole.wgsl")
);

/// The lights the dipole shader holds: directional and point lights only (an area light's
/// cells would need their own emission lobe and many more light maps).
pub const DIPOLE_LIGHTS: usize = 4;

/// WGSL's size of `Dipole`: 4 lights × 96 + 11 vec4 × 16 bytes (checked against naga's layout in
/// a test).
pub(crate) const DIPOLE_UNIFORM_SIZE: usize = DIPOLE_LIGHTS * 96 + 11 * 16;
const _: () = assert!(std::mem::size_of::<DipoleUniform>() == DIPOLE_UNIFORM_SIZE);

const MAP_FORMATS: [wgpu::TextureFormat; 2] = [
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba32Float,
];

/// Position and normal maps, one array layer per view.
struct Maps {
    position: wgpu::Texture,
    normal: wgpu::Texture,
}

fn draw_maps(
    gpu: &Gpu,
    enc: &mut wgpu::CommandEncoder,
    mesh: &MeshBuffers,
    views: &[Mat4],
    (w, h): (u32, u32),
) -> Maps {
    let dev = &gpu.device;
    let layers = views.len().max(1) as u32;
    let texture = |label: &str, format| {
        texture(
            dev,
            label,
            (w, h, layers),
            format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        )
    };
    let maps = Maps {
        position: texture("dipole positions", MAP_FORMATS[0]),
        normal: texture("dipole normals", MAP_FORMATS[1]),
    };
    let depth = texture("dipole depth", wgpu::TextureFormat::Depth32Float);
    let module = dev.create_shader_module(wgpu::include_wgsl!("shaders/dipole_maps.wgsl"));
    let pipeline = mesh_pipeline(dev, &module, "dipole maps", &MAP_FORMATS);
    for (layer, vp) in views.iter().enumerate() {
        let ubuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dipole map view"),
            contents: bytemuck::bytes_of(&vp.to_cols_array_2d()),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: ubuf.as_entire_binding(),
            }],
        });
        let layer_view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer as u32,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let (pv, nv, dv) = (
            layer_view(&maps.position),
            layer_view(&maps.normal),
            layer_view(&depth),
        );
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("dipole maps"),
            color_attachments: &[clear(&pv), clear(&nv)],
            depth_stencil_attachment: Some(cleared_depth(&dv)),
            ..Default::default()
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        mesh.draw(&mut pass);
    }
    maps
}

/// Encodes the method's passes: the camera's and each light's position/normal maps, then
/// `setup.frames` accumulation passes adding π·L_o/frames into `out` (which is cleared first).
#[allow(clippy::too_many_arguments)]
pub(crate) fn encode(
    gpu: &Gpu,
    enc: &mut wgpu::CommandEncoder,
    scene: &Scene,
    setup: &DipoleSetup,
    camera_view_proj: Mat4,
    (w, h): (u32, u32),
    mesh: &MeshBuffers,
    out: &wgpu::Buffer,
    timer: &mut Option<&mut Timer>,
) -> Result<()> {
    setup.validate()?;
    let dev = &gpu.device;
    let cam = draw_maps(gpu, enc, mesh, &[camera_view_proj], (w, h));
    let emitters = scene.emitters();
    let light_vps: Vec<Mat4> = emitters.iter().map(|l| scene.light_view_proj(l)).collect();
    let lights = draw_maps(gpu, enc, mesh, &light_vps, (setup.map_size, setup.map_size));
    let mut u_lights = [DipoleLight {
        view_proj: Mat4::IDENTITY.to_cols_array_2d(),
        pos_or_dir: [0.0; 4],
        color: [0.0; 4],
    }; DIPOLE_LIGHTS];
    for (i, (light, vp)) in emitters.iter().zip(&light_vps).enumerate() {
        u_lights[i] = DipoleLight {
            view_proj: vp.to_cols_array_2d(),
            pos_or_dir: light.pos_or_dir.into(),
            color: light.power.extend(i as f32).into(),
        };
    }
    let k = &setup.channels;
    let rgb = |f: &dyn Fn(&DipoleConstants) -> f64| {
        [f(&k[0]) as f32, f(&k[1]) as f32, f(&k[2]) as f32, 0.0]
    };
    let rates = setup.rates();
    let base = DipoleUniform {
        lights: u_lights,
        camera_pos: scene.camera.position.extend(1.0).into(),
        d: rgb(&|c| c.d),
        sigma_tr: rgb(&|c| c.sigma_tr),
        d_e: rgb(&|c| c.d_e),
        backlit: rgb(&|c| c.backlit_depth),
        norm: {
            let n = [0, 1, 2].map(|c| (k[c].norm * setup.scale[c]) as f32);
            [n[0], n[1], n[2], 0.0]
        },
        rate: [rates[0] as f32, rates[1] as f32, rates[2] as f32, 0.0],
        boundary: [
            k[0].a as f32,
            k[0].c_phi as f32,
            k[0].c_e as f32,
            k[0].eta as f32,
        ],
        disc: [
            setup.radius_cm,
            1.0 / (setup.samples as f32 * setup.frames as f32),
            0.0,
            0.0,
        ],
        size: [w, h, emitters.len() as u32, setup.samples],
        frame: [0, setup.seed, setup.map_size, 0],
    };
    let pipeline = compute_pipeline(
        dev,
        wgpu::ShaderModuleDescriptor {
            label: Some("directional dipole"),
            source: wgpu::ShaderSource::Wgsl(DIPOLE_WGSL.into()),
        },
        "directional dipole",
    );
    let array = |t: &wgpu::Texture, dim| {
        t.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(dim),
            ..Default::default()
        })
    };
    let views = [
        array(&cam.position, wgpu::TextureViewDimension::D2),
        array(&cam.normal, wgpu::TextureViewDimension::D2),
        array(&lights.position, wgpu::TextureViewDimension::D2Array),
        array(&lights.normal, wgpu::TextureViewDimension::D2Array),
    ];
    enc.clear_buffer(out, 0, None);
    let span = timer
        .as_mut()
        .map(|t| t.span(&format!("directional dipole ({} frames)", setup.frames)));
    for frame in 0..setup.frames {
        let uniform = DipoleUniform {
            frame: [frame, setup.seed, setup.map_size, 0],
            ..base
        };
        let ubuf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dipole frame"),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: ubuf.as_entire_binding(),
        }];
        entries.extend(views.iter().enumerate().map(|(i, v)| wgpu::BindGroupEntry {
            binding: 1 + i as u32,
            resource: wgpu::BindingResource::TextureView(v),
        }));
        entries.push(wgpu::BindGroupEntry {
            binding: 5,
            resource: out.as_entire_binding(),
        });
        let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let writes = match (timer.as_ref(), span) {
            (Some(t), Some(k)) => t.span_writes(k, frame == 0, frame + 1 == setup.frames),
            _ => None,
        };
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("directional dipole"),
            timestamp_writes: writes,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ over the disc of radius R of e^{−σr} dA = (2π/σ²)(1 − e^{−σR}(1 + σR)), estimated
    /// with the sampler and density used on the GPU (unbiased: within 1 %), and with the draft's
    /// two weights for the same samples, A_c/N·Σf·e^{−σr} (its equations) and A_c/N·Σf/e^{−σr}
    /// (its text), which are off by far more.
    #[test]
    fn the_drafts_sampling_weights_are_biased() {
        let (sigma, r_max) = (2.0, 3.0);
        let rates = [sigma, 0.5, 5.0];
        let exact = 2.0 * std::f64::consts::PI / (sigma * sigma)
            * (1.0 - (-sigma * r_max).exp() * (1.0 + sigma * r_max));
        let n = 200_000u64;
        let area = std::f64::consts::PI * r_max * r_max;
        let (mut ours, mut eqs, mut text) = (0.0, 0.0, 0.0);
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..n {
            let c = ((next() * 3.0) as usize).min(2);
            let r = sample_radius(next(), rates[c], r_max);
            let f = (-sigma * r).exp();
            ours += f / pdf_area(r, &rates, r_max);
            eqs += area * f * (-sigma * r).exp();
            text += area * f / (-sigma * r).exp();
        }
        let (ours, eqs, text) = (ours / n as f64, eqs / n as f64, text / n as f64);
        assert!((ours / exact - 1.0).abs() < 0.01, "{ours} vs {exact}");
        assert!((eqs / exact - 1.0).abs() > 0.1, "{eqs} vs {exact}");
        assert!((text / exact - 1.0).abs() > 0.1, "{text} vs {exact}");
    }

    #[test]
    fn sampled_radii_stay_on_the_disc_and_follow_the_exponential() {
        let (rate, r_max) = (3.0, 2.0);
        assert_eq!(sample_radius(0.0, rate, r_max), 0.0);
        assert!(sample_radius(1.0 - 1e-12, rate, r_max) <= r_max * (1.0 + 1e-9));
        // The median of the truncated exponential: e^{−σm} = (1 + e^{−σR})/2.
        let m = sample_radius(0.5, rate, r_max);
        let expected = -((1.0 + (-rate * r_max).exp()) / 2.0).ln() / rate;
        assert!((m - expected).abs() < 1e-12);
    }
}
