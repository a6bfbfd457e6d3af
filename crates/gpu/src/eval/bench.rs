//! Timing of the scattering passes (`sss render --bench`), as plain data: one frame of any method,
//! the separable passes in every configuration, what each skip saves, and the directional
//! dipole's frame time.
//!
//! GPU times are the passes' timestamp queries (None where the adapter has none; on a CPU adapter
//! such as lavapipe they do not measure the work, so compare frame-time ratios there); frame
//! times are wall-clock from recording to completion, uploads included, readback not. Every
//! time is the median of several frames on a renderer built once.

use fit::Profile;
use fit::select::{Judge, rank_model};
use glam::Vec3;
use serde::Serialize;

use crate::error::Result;
use crate::frame::context::Gpu;
use crate::gathers::area_gather::{AreaGatherSetup, GatherPattern};
use crate::gathers::dipole::DipoleSetup;
use crate::light::Light;
use crate::params::RenderParams;
use crate::render::{Renderer, SUBPIXEL_PX, Scatter, kernel_footprint_px};
use crate::scene::Scene;
use shading::KernelTaps;

/// Frames per median of the separable benchmark.
const FRAMES: usize = 5;

/// Passes counted as the scattering's GPU time (by the end of their label).
const SSS_PASSES: [&str; 9] = [
    "horizontal",
    "vertical",
    "half-res down",
    "half-res up",
    "blur pack",
    "surface",
    "area level 0",
    "area pyramid",
    "area gather",
];

/// One timed configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Config {
    /// The kernel model (`area-gather` for the area gather).
    pub kernel: String,
    /// Taps per pass (the gather: taps of its pattern).
    pub taps: usize,
    /// Separable terms (None for the area gather).
    pub rank: Option<usize>,
    /// `full` or `half` resolution (half: down- and upsampling counted in its SSS time).
    pub resolution: &'static str,
    /// `exact` or `fast` blur path; for the area gather `layered` or `dense`.
    pub path: &'static str,
    /// Median GPU time of the scattering passes [ms] (None without timestamp queries).
    pub gpu_ms: Option<f64>,
    /// Median frame time [ms].
    pub frame_ms: f64,
    /// `frame_ms` over that of pre-integration at 17 taps, full resolution, exact path.
    pub frame_ratio_to_preint17: f64,
}

/// What a skip saves: the same frame with the skip on and off.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Saving {
    /// GPU time with the skip [ms].
    pub gpu_ms_on: Option<f64>,
    /// GPU time without it [ms].
    pub gpu_ms_off: Option<f64>,
    /// 1 − on/off of the GPU time.
    pub gpu_saved_fraction: Option<f64>,
    /// Frame time with the skip [ms].
    pub frame_ms_on: f64,
    /// Frame time without it [ms].
    pub frame_ms_off: f64,
    /// 1 − on/off of the frame time.
    pub frame_saved_fraction: f64,
}

impl Saving {
    fn new(on: (Option<f64>, f64), off: (Option<f64>, f64)) -> Saving {
        Saving {
            gpu_ms_on: on.0,
            gpu_ms_off: off.0,
            gpu_saved_fraction: on.0.zip(off.0).map(|(a, b)| 1.0 - a / b),
            frame_ms_on: on.1,
            frame_ms_off: off.1,
            frame_saved_fraction: 1.0 - on.1 / off.1,
        }
    }
}

/// Pixels without SSS skipped.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EmptySkip {
    /// Pre-integration at 17 taps with and without the skip.
    #[serde(flatten)]
    pub saving: Saving,
    /// The fraction of the image with SSS.
    pub sss_pixel_fraction: f64,
}

/// Sub-pixel kernels skipped: the scene seen from so far that the kernel reaches 0.8 of
/// [`SUBPIXEL_PX`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SubpixelSkip {
    /// The far scene with and without the skip.
    #[serde(flatten)]
    pub saving: Saving,
    /// How many times farther the camera is.
    pub distance_factor: f32,
    /// The kernel's footprint at the scene's own distance [px].
    pub near_footprint_px: f32,
    /// Its footprint from the far camera [px].
    pub footprint_px: f32,
}

/// Ranks beyond an image-error target skipped: with the target at 1.05 × the best image RMS of
/// ranks 1–3 at 17 taps, the smallest rank that meets it against always rank 3.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RankSkip {
    /// The chosen rank against rank 3 (full resolution, exact path, 17 taps).
    #[serde(flatten)]
    pub saving: Saving,
    /// The target's image RMS.
    pub target_image_rms: f64,
    /// Image RMS of ranks 1, 2, 3.
    pub image_rms_by_rank: Vec<f64>,
    /// The smallest rank that meets the target.
    pub rank_chosen: usize,
}

/// Every skip's saving.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Skips {
    /// Pixels without SSS.
    pub empty_pixels: EmptySkip,
    /// Sub-pixel kernels.
    pub subpixel_kernels: SubpixelSkip,
    /// Ranks beyond an image-error target.
    pub rank_target: RankSkip,
}

/// The separable benchmark's results.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SeparableBench {
    /// Every configuration: 11/17/25/33 taps × rank 1 (pre-integration), 2, 3 (SVD,
    /// renormalized) × full and half resolution × exact and fast path, then the area gather's
    /// layered and dense patterns when one was given.
    pub configs: Vec<Config>,
    /// What each skip saves on the 17-tap kernels.
    pub skips: Skips,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// What the ranks beyond an image-error target cost: the target 1.05 × the best image RMS of
/// ranks 1–3 at 17 taps, the smallest rank meeting it, and its frame against rank 3's, from the
/// timed `configs`.
fn rank_target(judge: &Judge, material: &str, configs: &[Config]) -> Result<RankSkip> {
    let errors = (1..=3)
        .map(|r| Ok(judge.fit_and_score(rank_model(r), material, 17)?.error()))
        .collect::<Result<Vec<f64>>>()?;
    let target = 1.05 * errors.iter().copied().fold(f64::MAX, f64::min);
    let chosen = errors
        .iter()
        .position(|&e| e <= target)
        .expect("the best rank meets 1.05 × its own error")
        + 1;
    let timed = |rank: usize| {
        configs
            .iter()
            .find(|c| {
                c.taps == 17 && c.rank == Some(rank) && c.resolution == "full" && c.path == "exact"
            })
            .map(|c| (c.gpu_ms, c.frame_ms))
            .expect("17 taps at full resolution on the exact path were timed for ranks 1–3")
    };
    Ok(RankSkip {
        saving: Saving::new(timed(chosen), timed(3)),
        target_image_rms: target,
        image_rms_by_rank: errors,
        rank_chosen: chosen,
    })
}

/// Times the separable passes on `scene` with kernels fitted to `p` (`material` names it), at
/// the size, kernel width and settings of `base` (the bench varies the resolution and the blur
/// path); with `area`, also the area gather's layered pattern and the brute-force 2D gather over
/// the kernel's reach at the target's distance (at most 64 px).
pub fn separable(
    gpu: &Gpu,
    scene: &Scene,
    (p, material): (&Profile, &str),
    base: &RenderParams,
    area: Option<&AreaGatherSetup>,
) -> Result<SeparableBench> {
    let params = *base;
    let (height, sss_width) = (params.height, params.sss_width);
    let renderer = Renderer::new(gpu);
    // Median over the frames of the SSS passes' GPU time (None without timestamps) and the frame.
    let measure_with =
        |scene: &Scene, scatter: Scatter, params: &RenderParams| -> Result<(Option<f64>, f64)> {
            let (mut sss, mut wall) = (Vec::new(), Vec::new());
            for _ in 0..FRAMES {
                let t = renderer.time(gpu, scene, scatter, params)?;
                sss.push(
                    t.passes
                        .iter()
                        .filter(|p| SSS_PASSES.iter().any(|k| p.label.ends_with(k)))
                        .map(|p| p.ms)
                        .sum::<f64>(),
                );
                wall.push(t.wall_ms);
            }
            Ok((gpu.timestamps.then(|| median(sss)), median(wall)))
        };
    let measure = |scene: &Scene, k: &KernelTaps, params: &RenderParams| {
        measure_with(scene, Scatter::Separable(std::slice::from_ref(k)), params)
    };
    let judge = Judge::new(p);
    let mut configs = Vec::new();
    let mut preint17 = None;
    for rank in 1..=3usize {
        let model = rank_model(rank);
        for taps in [11, 17, 25, 33] {
            let k = KernelTaps::from_shader_kernel(&judge.kernel(model, material, taps)?)?;
            for (half, fast) in [(false, false), (true, false), (false, true), (true, true)] {
                let (gpu_ms, frame_ms) = measure(
                    scene,
                    &k,
                    &RenderParams {
                        half_res: half,
                        fast,
                        ..params
                    },
                )?;
                if rank == 1 && taps == 17 && !half && !fast {
                    preint17 = Some((k.clone(), gpu_ms, frame_ms));
                }
                configs.push(Config {
                    kernel: model.to_string(),
                    taps,
                    rank: Some(rank),
                    resolution: if half { "half" } else { "full" },
                    path: if fast { "fast" } else { "exact" },
                    gpu_ms,
                    frame_ms,
                    frame_ratio_to_preint17: f64::NAN,
                });
            }
        }
    }
    let (k, on_gpu, on_frame) = preint17.expect("17 taps were timed");
    if let Some(setup) = area {
        let dist = (scene.camera.position - scene.camera.target).length();
        let reach =
            setup.kernel.r_max_cm() * sss_width * scene.camera.px_per_cm_at_unit_depth(height)
                / dist;
        let dense = GatherPattern::dense((reach.ceil() as u32).clamp(1, 64));
        for (path, pattern) in [("layered", setup.pattern), ("dense", dense)] {
            let s = AreaGatherSetup {
                pattern,
                ..setup.clone()
            };
            let (gpu_ms, frame_ms) = measure_with(scene, Scatter::AreaGather(&s), &params)?;
            configs.push(Config {
                kernel: "area-gather".into(),
                taps: pattern.taps().len(),
                rank: None,
                resolution: "full",
                path,
                gpu_ms,
                frame_ms,
                frame_ratio_to_preint17: f64::NAN,
            });
        }
    }
    for c in &mut configs {
        c.frame_ratio_to_preint17 = c.frame_ms / on_frame;
    }

    // Pixels without SSS: the same frame with every pixel running every tap.
    let off = measure(
        scene,
        &k,
        &RenderParams {
            skip_empty: false,
            ..params
        },
    )?;
    let small = Renderer::new(gpu).render(
        gpu,
        scene,
        Scatter::None,
        &RenderParams {
            width: 192,
            height: 108,
            ..params
        },
    )?;
    let sss_pixel_fraction =
        small.geometry.iter().filter(|g| g[1] > 0.0).count() as f64 / small.geometry.len() as f64;

    // Sub-pixel kernels: the scene seen from so far that the kernel reaches 0.8 of the
    // threshold (a far-away object; it covers fewer pixels too).
    let near_px = kernel_footprint_px(scene, 0, &k, &params);
    let factor = (near_px / (0.8 * SUBPIXEL_PX)).max(1.0);
    let mut far = scene.clone();
    far.camera.position = far.camera.target + factor * (far.camera.position - far.camera.target);
    let far_px = kernel_footprint_px(&far, 0, &k, &params);
    let far_on = measure(&far, &k, &params)?;
    let far_off = measure(
        &far,
        &k,
        &RenderParams {
            skip_subpixel: false,
            ..params
        },
    )?;

    Ok(SeparableBench {
        skips: Skips {
            empty_pixels: EmptySkip {
                saving: Saving::new((on_gpu, on_frame), off),
                sss_pixel_fraction,
            },
            subpixel_kernels: SubpixelSkip {
                saving: Saving::new(far_on, far_off),
                distance_factor: factor,
                near_footprint_px: near_px,
                footprint_px: far_px,
            },
            rank_target: rank_target(&judge, material, &configs)?,
        },
        configs,
    })
}

/// One directional-dipole configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DipoleRow {
    /// Always `directional-dipole`.
    pub method: &'static str,
    /// Lights in the scene.
    pub lights: usize,
    /// Samples per pixel and light.
    pub samples: u32,
    /// Progressive frames per render.
    pub frames: u32,
    /// Median dipole GPU time per frame [ms] (None without timestamp queries).
    pub dipole_ms_per_frame: Option<f64>,
    /// Median wall time of a whole render [ms].
    pub render_wall_ms: f64,
    /// Whether the adapter has timestamp queries.
    pub timestamps: bool,
}

/// One frame's time: what `sss render --bench frame` reports for any method.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameBench {
    /// Median frame time [ms]: recording to completion, uploads included, readback not.
    pub frame_ms: f64,
    /// Median of the sum of the passes' GPU times [ms] (None without timestamp queries).
    pub gpu_ms: Option<f64>,
    /// Frames timed (after one that compiles the pipelines).
    pub frames: usize,
}

/// The frame of `scatter` at `params` timed: [`FRAMES`] frames on a renderer built once, after
/// one untimed frame that compiles its pipelines (the disc gathers compile on their first).
pub fn frame(
    gpu: &Gpu,
    scene: &Scene,
    scatter: Scatter,
    params: &RenderParams,
) -> Result<FrameBench> {
    let renderer = Renderer::new(gpu);
    renderer.time(gpu, scene, scatter, params)?;
    let (mut wall, mut passes) = (Vec::new(), Vec::new());
    for _ in 0..FRAMES {
        let t = renderer.time(gpu, scene, scatter, params)?;
        wall.push(t.wall_ms);
        passes.push(t.passes.iter().map(|p| p.ms).sum::<f64>());
    }
    Ok(FrameBench {
        frame_ms: median(wall),
        gpu_ms: gpu.timestamps.then(|| median(passes)),
        frames: FRAMES,
    })
}

/// Directional-dipole frame times at 1920×1080 (median of 3 renders of `base.frames` frames
/// each): 8 and 16 samples per pixel and light, with the scene's lights and with 4 lights (the
/// draft's target is 3–5 lights under 100 ms per frame, ideally 16 ms).
pub fn dipole(gpu: &Gpu, scene: &Scene, base: &DipoleSetup) -> Result<Vec<DipoleRow>> {
    let params = RenderParams {
        width: 1920,
        height: 1080,
        ..RenderParams::default()
    };
    let mut four = scene.clone();
    while four.lights.len() < 4 {
        let k = four.lights.len() as f32;
        four.lights.push(Light::Directional {
            towards: Vec3::new((1.7 * k).cos(), 1.0, (1.7 * k).sin()).normalize(),
            irradiance: Vec3::splat(0.4),
            shadow: true,
        });
    }
    let mut rows = Vec::new();
    for s in [scene, &four] {
        for samples in [8, 16] {
            let mut setup = *base;
            setup.sampling.samples = samples;
            let (mut per_frame, mut wall) = (Vec::new(), Vec::new());
            for _ in 0..3 {
                let t = std::time::Instant::now();
                let f = crate::render(gpu, s, Scatter::DirectionalDipole(&setup), &params)?;
                wall.push(t.elapsed().as_secs_f64() * 1e3);
                let ms: f64 = f
                    .times
                    .iter()
                    .filter(|t| t.label.starts_with("directional dipole"))
                    .map(|t| t.ms)
                    .sum();
                per_frame.push(ms / setup.sampling.frames as f64);
            }
            rows.push(DipoleRow {
                method: "directional-dipole",
                lights: s.lights.len(),
                samples,
                frames: setup.sampling.frames,
                dipole_ms_per_frame: gpu.timestamps.then(|| median(per_frame)),
                render_wall_ms: median(wall),
                timestamps: gpu.timestamps,
            });
        }
    }
    Ok(rows)
}
