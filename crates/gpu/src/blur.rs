//! The separable SSS passes: for each SSS material and each term of its kernel, a horizontal then a
//! vertical 1D compute pass; the vertical pass adds sign·result into the output, so rank-N SVD,
//! d'Eon sums of Gaussians and rank-1 kernels all run the same way. A material's passes write only
//! its own pixels and take no light from another material's (see [`crate::Scatter::Separable`]).

use wgpu::util::DeviceExt;

use crate::context::{Gpu, pixels};
use crate::error::{GpuError, Result};

/// A kernel as the shader takes it: per pass, the RGB sign and the taps (RGB weight, offset [cm]).
#[derive(Clone, Debug, PartialEq)]
pub struct GpuKernel {
    /// One entry per separable term, in order: its sign per channel R, G, B (±1) and its taps, each
    /// [weight R, weight G, weight B, offset [cm]].
    pub passes: Vec<([f32; 3], Vec<[f32; 4]>)>,
    /// Largest |offset| [cm].
    pub range_cm: f32,
}

impl GpuKernel {
    /// Converts a `sss fit` kernel file; refuses empty or non-finite taps and non-cm units.
    pub fn from_shader_kernel(k: &fit::taps::ShaderKernel) -> Result<GpuKernel> {
        if k.unit != "cm" {
            return Err(GpuError::invalid("kernel unit", &k.unit, "expected \"cm\""));
        }
        if k.pass.is_empty() || k.pass.iter().any(|p| p.tap.is_empty()) {
            return Err(GpuError::invalid(
                "kernel pass",
                k.pass.len(),
                "needs at least one pass with taps",
            ));
        }
        let mut range = 0.0f32;
        let passes = k
            .pass
            .iter()
            .map(|p| {
                let taps = p
                    .tap
                    .iter()
                    .map(|t| {
                        range = range.max(t.offset.abs() as f32);
                        [
                            t.weight[0] as f32,
                            t.weight[1] as f32,
                            t.weight[2] as f32,
                            t.offset as f32,
                        ]
                    })
                    .collect::<Vec<_>>();
                (p.sign.map(|s| s as f32), taps)
            })
            .collect::<Vec<_>>();
        if passes
            .iter()
            .flat_map(|(s, t)| s.iter().chain(t.iter().flatten()))
            .any(|v| !v.is_finite())
        {
            return Err(GpuError::invalid(
                "kernel taps",
                "NaN/inf",
                "every weight and offset must be finite",
            ));
        }
        Ok(GpuKernel {
            passes,
            range_cm: range,
        })
    }
}

impl GpuKernel {
    /// The kernel's response to a uniform image per channel, Σ_p sign_p·(Σ_t w_t)² (its
    /// integral: 1 for a normalized kernel).
    pub fn total(&self) -> [f32; 3] {
        let mut t = [0.0f32; 3];
        for (sign, taps) in &self.passes {
            for c in 0..3 {
                let s: f32 = taps.iter().map(|w| w[c]).sum();
                t[c] += sign[c] * s * s;
            }
        }
        t
    }

    /// Each tap's cell [cm]: from the midpoint to the next smaller offset to the midpoint to the
    /// next larger one (the outermost cells as wide on their open side as on the other), per pass.
    /// A jittered tap samples uniformly within its cell (supplement Fig. S.6–S.7).
    pub fn cells(&self) -> Vec<Vec<[f32; 2]>> {
        self.passes
            .iter()
            .map(|(_, taps)| {
                let mut sorted: Vec<f32> = taps.iter().map(|t| t[3]).collect();
                sorted.sort_by(f32::total_cmp);
                taps.iter()
                    .map(|t| {
                        let o = t[3];
                        let below = sorted.iter().rev().find(|&&x| x < o).copied();
                        let above = sorted.iter().find(|&&x| x > o).copied();
                        let (lo, hi) = match (below, above) {
                            (Some(b), Some(a)) => (0.5 * (b + o), 0.5 * (o + a)),
                            (Some(b), None) => (0.5 * (b + o), o + 0.5 * (o - b)),
                            (None, Some(a)) => (o - 0.5 * (a - o), 0.5 * (o + a)),
                            (None, None) => (o, o),
                        };
                        [lo, hi]
                    })
                    .collect()
            })
            .collect()
    }

    /// The farthest a tap reaches [cm]: the range, or with jitter the outermost cell bound.
    pub fn reach_cm(&self, jitter: f32) -> f32 {
        if jitter > 0.0 {
            self.cells()
                .iter()
                .flatten()
                .fold(self.range_cm, |r, c| r.max(c[0].abs()).max(c[1].abs()))
        } else {
            self.range_cm
        }
    }

    /// The largest spatial variance [cm²] of the first pass's taps over the channels,
    /// Σw·x²/Σw: the τmax of the supplement's depth factor (§E).
    pub fn variance_cm2(&self) -> f32 {
        let Some((_, taps)) = self.passes.first() else {
            return 0.0;
        };
        (0..3)
            .map(|c| {
                let (m0, m2) = taps.iter().fold((0.0f32, 0.0f32), |(a, b), t| {
                    (a + t[c], b + t[c] * t[3] * t[3])
                });
                if m0 > 0.0 { m2 / m0 } else { 0.0 }
            })
            .fold(0.0, f32::max)
    }

    /// One pass of one tap at offset 0 with the kernel's total response: what the kernel
    /// amounts to when its footprint is below a pixel (light stays where it is).
    pub fn point(&self) -> GpuKernel {
        let t = self.total();
        GpuKernel {
            passes: vec![(
                t.map(|v| if v < 0.0 { -1.0 } else { 1.0 }),
                vec![[t[0].abs().sqrt(), t[1].abs().sqrt(), t[2].abs().sqrt(), 0.0]],
            )],
            range_cm: 0.0,
        }
    }
}

/// How samples across depth discontinuities are treated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthMode {
    /// No test: light bleeds across silhouettes.
    None,
    /// Lerp towards the centre sample as |Δz| grows (thesis eq. 4.12, SSSS "follow surface").
    Lerp,
    /// Reject samples with |Δz| > tolerance and give their weight to the rest, per channel
    /// (what production engines do).
    Reject,
    /// Multiply each sample's weight by e^{−Δz²/(2τ)} (the SSSS supplement §E: a Gaussian
    /// profile evaluated at the 3D distance factors into the screen-space one times this), with
    /// τ = tolerance² and by default the kernel's largest variance τmax (× width²), and give the
    /// weight lost to the samples kept, per channel, as [`DepthMode::Reject`] does. The
    /// supplement does not renormalize; but its factor alone drops a share cos θ of the light on
    /// a surface tilted by θ from the view (the area element 1/cos θ between screen and surface
    /// is missing): measured on the reference sphere, energy 0.68/0.77/0.80 of Mitsuba's against
    /// 0.90/0.86/0.84 for lerp. Renormalized, a uniformly lit tilted plane keeps its exitance.
    Gaussian,
}

/// Blur settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlurParams {
    /// Pixels per cm at view depth 1 cm (see [`crate::Camera::px_per_cm_at_unit_depth`]).
    pub px_per_cm_at_unit_depth: f32,
    /// Global width multiplier (1 = the kernel's physical size).
    pub sss_width: f32,
    /// How samples across depth discontinuities are treated.
    pub depth_mode: DepthMode,
    /// Depth difference [cm] at which a sample is fully replaced or rejected (Gaussian: √τ);
    /// None: each kernel's range × `sss_width` (Gaussian: √τmax × `sss_width`).
    pub tolerance_cm: Option<f32>,
    /// The fraction of taps jittered per pixel (the SSSS supplement, Fig. S.6–S.7): each pixel
    /// picks that share of its taps at random, and each picked tap samples a uniform random
    /// position within its cell ([`GpuKernel::cells`]) instead of its offset, turning the banding
    /// of few taps into noise; 0: off.
    pub jitter: f32,
    /// Use this view depth [cm] for every pixel's kernel scale (comparisons with a fixed-scale
    /// CPU reference); None: each pixel's own depth.
    pub fixed_depth: Option<f32>,
    /// Pixels without SSS strength and pixels of other materials do no tap work (a horizontal
    /// pass gives pixels without SSS Σw·centre, what their zero-width kernel would, for the
    /// vertical pass to sample). Off: every pixel runs every tap, only to measure the saving; the
    /// output on the pass's own pixels is the same.
    pub skip_empty: bool,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniform {
    width: u32,
    height: u32,
    taps: u32,
    horizontal: u32,
    sign: [f32; 4],
    /// Σ of the taps' weights (rgb).
    tap_sum: [f32; 4],
    px_per_cm_at_unit_depth: f32,
    sss_width: f32,
    tolerance: f32,
    mode: u32,
    jitter: f32,
    accumulate: u32,
    fixed_depth: f32,
    material: u32,
    skip_empty: u32,
    _pad: [u32; 3],
}

/// The size of blur.wgsl's `Params` (checked against naga's layout in a test).
pub(crate) const BLUR_UNIFORM_SIZE: usize = 96;
const _: () = assert!(std::mem::size_of::<Uniform>() == BLUR_UNIFORM_SIZE);

/// The compiled blur pipeline.
pub(crate) struct Blur {
    pipeline: wgpu::ComputePipeline,
}

impl Blur {
    pub(crate) fn new(gpu: &Gpu) -> Blur {
        Blur {
            pipeline: crate::context::compute_pipeline(
                &gpu.device,
                wgpu::include_wgsl!("shaders/blur.wgsl"),
                "blur",
            ),
        }
    }

    /// Records every pass of every material's kernel (`kernels[m]` on the pixels of material m):
    /// src → tmp (horizontal) → dst (vertical, accumulated). `dst` is cleared first. With
    /// `timer`, each 1D pass gets begin/end timestamps.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        kernels: &[GpuKernel],
        params: &BlurParams,
        (width, height): (u32, u32),
        src: &wgpu::Buffer,
        geometry: &wgpu::Buffer,
        tmp: &wgpu::Buffer,
        dst: &wgpu::Buffer,
        timer: &mut Option<&mut crate::timing::Timer>,
    ) {
        enc.clear_buffer(dst, 0, None);
        let mode = match params.depth_mode {
            DepthMode::None => 0,
            DepthMode::Lerp => 1,
            DepthMode::Reject => 2,
            DepthMode::Gaussian => 3,
        };
        let passes = kernels.iter().enumerate().flat_map(|(m, k)| {
            k.passes
                .iter()
                .enumerate()
                .map(move |(p, pass)| (m, k, p, pass))
        });
        for (material, k, p, (sign, taps)) in passes {
            let taps_buf = gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("taps"),
                    contents: bytemuck::cast_slice(taps),
                    usage: wgpu::BufferUsages::STORAGE,
                });
            let sum = taps.iter().fold([0.0f32; 4], |a, t| {
                [a[0] + t[0], a[1] + t[1], a[2] + t[2], 0.0]
            });
            let tolerance = params
                .tolerance_cm
                .unwrap_or(
                    params.sss_width
                        * match params.depth_mode {
                            DepthMode::Gaussian => k.variance_cm2().sqrt(),
                            _ => k.range_cm,
                        },
                )
                .max(1e-12);
            let cells = gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("tap cells"),
                    contents: bytemuck::cast_slice(&k.cells()[p]),
                    usage: wgpu::BufferUsages::STORAGE,
                });
            for horizontal in [true, false] {
                let u = Uniform {
                    width,
                    height,
                    taps: taps.len() as u32,
                    horizontal: horizontal as u32,
                    sign: [sign[0], sign[1], sign[2], 0.0],
                    tap_sum: sum,
                    px_per_cm_at_unit_depth: params.px_per_cm_at_unit_depth,
                    sss_width: params.sss_width,
                    tolerance,
                    mode,
                    jitter: params.jitter,
                    accumulate: (!horizontal) as u32,
                    fixed_depth: params.fixed_depth.unwrap_or(0.0),
                    material: material as u32,
                    skip_empty: params.skip_empty as u32,
                    _pad: [0; 3],
                };
                let ubuf = gpu
                    .device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("blur params"),
                        contents: bytemuck::bytes_of(&u),
                        usage: wgpu::BufferUsages::UNIFORM,
                    });
                let (from, to) = if horizontal { (src, tmp) } else { (tmp, dst) };
                let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: None,
                    layout: &self.pipeline.get_bind_group_layout(0),
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: ubuf.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: taps_buf.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: from.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: geometry.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: to.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 5,
                            resource: cells.as_entire_binding(),
                        },
                    ],
                });
                let label = format!(
                    "{}pass {} {}",
                    if kernels.len() > 1 {
                        format!("material {} ", material + 1)
                    } else {
                        String::new()
                    },
                    p + 1,
                    if horizontal { "horizontal" } else { "vertical" }
                );
                let writes = timer.as_mut().map(|t| t.writes(&label));
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(&label),
                    timestamp_writes: writes,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &bind, &[]);
                pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
            }
        }
    }
}

/// Applies the kernels' passes to an image (RGBA per pixel, row-major) with per-pixel
/// `geometry` (x: view depth [cm], y: SSS strength, z: material index): the blur stage alone, for
/// tests and CPU comparisons. Pixels without SSS strength come back 0 with `skip_empty`.
pub fn blur_image(
    gpu: &Gpu,
    image: &[[f32; 4]],
    geometry: &[[f32; 4]],
    (width, height): (u32, u32),
    kernels: &[GpuKernel],
    params: &BlurParams,
) -> Result<Vec<[f32; 4]>> {
    let n = (width * height) as usize;
    if image.len() != n || geometry.len() != n {
        return Err(GpuError::invalid(
            "image size",
            image.len(),
            format!("expected {width}×{height} = {n} pixels"),
        ));
    }
    if kernels.is_empty() {
        return Err(GpuError::invalid("kernels", 0, "at least one"));
    }
    if let Some(g) = geometry
        .iter()
        .find(|g| g[1] > 0.0 && !(g[2] >= 0.0 && (g[2] as usize) < kernels.len()))
    {
        return Err(GpuError::invalid(
            "pixel material",
            g[2],
            format!(
                "SSS pixels need one of the {} kernels' indices",
                kernels.len()
            ),
        ));
    }
    let upload = |data: &[[f32; 4]]| {
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("upload"),
                contents: bytemuck::cast_slice(data),
                usage: wgpu::BufferUsages::STORAGE,
            })
    };
    let (src, geom) = (upload(image), upload(geometry));
    let (tmp, dst) = (pixels(gpu, n, "tmp"), pixels(gpu, n, "dst"));
    let blur = Blur::new(gpu);
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    blur.encode(
        gpu,
        &mut enc,
        kernels,
        params,
        (width, height),
        &src,
        &geom,
        &tmp,
        &dst,
        &mut None,
    );
    gpu.queue.submit([enc.finish()]);
    let bytes = gpu.read_buffer(&dst, (n * 16) as u64)?;
    Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec())
}
