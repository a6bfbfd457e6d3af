//! The disc gathers' denoiser: what lets a gather of a few samples per pixel stand in one frame.
//! An edge-avoiding à-trous filter (Dammertz et al. 2010; `shaders/denoise.wgsl`), [`LEVELS`]
//! levels of 5 × 5 taps 1, 2, 4, … pixels apart, each tap weighted per channel by a Gaussian of
//! the world distance between the two surface points with that channel's width σ_c [cm], and
//! only over SSS surfaces facing the same hemisphere.
//!
//! What it filters. The gather's estimate is its control variate's deterministic part (what a
//! flat, evenly lit half-space returns at x_o, where x_o is lit) plus what the samples add to it
//! (shaders/disc_gather.wgsl). The first carries the image's sharp detail (normals, view angle,
//! the lit region's border) without noise; the second carries all the noise and, in the mean,
//! only the smooth correction for curvature, uneven light and nearby shadow. The filter runs on
//! the second alone and adds the first back after its last level, and never takes a tap across
//! the border between pixels where x_o is lit and where it is not (the control stops there and
//! the samples' part jumps to make up for it). So it can be wider than a filter of the whole
//! image without blurring what the control carries.
//!
//! Why this filter. The gather's image is the lit surface's light spread by the BSSRDF, so it
//! carries no detail finer than the BSSRDF's own spread: a filter of world width σ_c replaces
//! Rd by Rd convolved with a Gaussian of σ_c (exactly so on a flat surface), a bias that stays
//! small where σ_c is small against the light's spread, and nothing else. Widths in the world,
//! not in pixels, follow the material per channel at any distance from the camera and never
//! cross silhouettes or depth steps (points side by side on screen but apart in depth are apart
//! in the world); a luminance edge-stop (SVGF's) would keep the noise it is there to remove.
//! À-trous reaches tens of pixels with 25 taps a level; a pixel whose level's nearest taps lie
//! beyond every channel's σ is copied, so a level costs only where it can move light. The
//! weights are normalized per pixel and channel: a constant image stays exactly constant, and the
//! mean over a region is kept up to the regions' borders.

use crate::error::Result;
use crate::frame::context::{Gpu, bind, bind_view, compute_pipeline};
use crate::frame::recording::Recording;
use crate::passes::Pass;
use crate::scene::Camera;

/// The least width of a channel that is filtered at all, in pixels of its footprint on screen:
/// below a pixel, the image has no finer detail to keep than the screen can show, and a
/// channel narrower than that (Skin1's blue at 1920×1080: σ = 0.008 cm, 0.7 px on the bust)
/// would keep its noise. On a flat surface it convolves Rd with a Gaussian of one pixel.
pub const FLOOR_PX: f32 = 1.0;

/// Levels of the filter: steps of 1, 2, 4, 8 and 16 pixels (the B3 spline's variance per axis
/// adds up to 341 px², a reach of about ±40 pixels where σ allows it).
pub const LEVELS: u32 = 5;

/// The shader's `Denoise` uniform (shaders/denoise.wgsl), field for field.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DenoiseUniform {
    width: [f32; 4],
    camera: [f32; 4],
    size: [u32; 4],
}

/// WGSL's size of `Denoise`: three vec4 (checked against naga's layout in a test).
pub(crate) const DENOISE_UNIFORM_SIZE: usize = 48;
const _: () = assert!(std::mem::size_of::<DenoiseUniform>() == DENOISE_UNIFORM_SIZE);

/// What the denoiser reads and filters in place.
pub(crate) struct DenoiseInput<'a> {
    /// The image's width and height [px].
    pub size: (u32, u32),
    /// The camera the image was drawn from.
    pub camera: &'a Camera,
    /// Per pixel: xyz the surface point [cm], w 1 on an SSS surface.
    pub position: &'a wgpu::TextureView,
    /// Per pixel: xyz the surface normal.
    pub normal: &'a wgpu::TextureView,
    /// σ per channel [cm]; 0 leaves a channel as it is.
    pub widths_cm: [f32; 3],
    /// The image (RGBA f32 per pixel): the samples' part of the gather (w > 0.5 where x_o is
    /// lit: no tap crosses between pixels it marks lit and unlit), filtered in place and then
    /// joined by `base` (w cleared).
    pub image: &'a wgpu::Buffer,
    /// The gather's deterministic part (rgb): added after the filter.
    pub base: &'a wgpu::Buffer,
}

/// The compiled filter level.
pub(crate) struct Denoise {
    pipeline: wgpu::ComputePipeline,
}

impl Pass for Denoise {
    type Input<'a> = DenoiseInput<'a>;
    /// Nothing: the image is filtered in place.
    type Output = ();

    fn new(gpu: &Gpu) -> Denoise {
        Denoise {
            pipeline: compute_pipeline(
                &gpu.device,
                wgpu::include_wgsl!("../shaders/denoise.wgsl"),
                "denoise",
            ),
        }
    }

    /// Records the [`LEVELS`] levels, between the image and a scratch buffer, ending in the
    /// image.
    fn encode(&self, rec: &mut Recording, input: DenoiseInput<'_>) -> Result<()> {
        let (alloc, enc) = (rec.alloc, &mut rec.enc);
        let (w, h) = input.size;
        let n = (w * h) as usize;
        let scratch = alloc.pixels(n, "denoise scratch");
        let camera = input.camera;
        let footprint = 2.0 * (0.5 * camera.fov_y_deg.to_radians()).tan() / h as f32;
        let [r, g, b] = input.widths_cm;
        let span = rec.timer.as_mut().map(|t| t.span("denoise"));
        for level in 0..LEVELS {
            let (from, to) = if level % 2 == 0 {
                (input.image, &scratch)
            } else {
                (&scratch, input.image)
            };
            let uniform = DenoiseUniform {
                width: [r, g, b, FLOOR_PX],
                camera: camera.position.extend(footprint).into(),
                size: [w, h, 1 << level, u32::from(level + 1 == LEVELS)],
            };
            let ubuf = alloc.uniform("denoise level", bytemuck::bytes_of(&uniform));
            let group = alloc
                .gpu
                .device
                .create_bind_group(&wgpu::BindGroupDescriptor {
                    label: None,
                    layout: &self.pipeline.get_bind_group_layout(0),
                    entries: &[
                        bind(0, &ubuf),
                        bind_view(1, input.position),
                        bind_view(2, input.normal),
                        bind(3, from),
                        bind(4, to),
                        bind(5, input.base),
                    ],
                });
            let writes = match (rec.timer.as_ref(), span) {
                (Some(t), Some(k)) => t.span_writes(k, level == 0, level + 1 == LEVELS),
                _ => None,
            };
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("denoise"),
                timestamp_writes: writes,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        if LEVELS % 2 == 1 {
            enc.copy_buffer_to_buffer(&scratch, 0, input.image, 0, (n * 16) as u64);
        }
        Ok(())
    }
}
