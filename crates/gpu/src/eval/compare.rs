//! Rendered kernels against the 2D ground truth (thesis §6.3, Table 6.4 and Table 6.5): the
//! scene's screen-space irradiance is scattered by each separable kernel on the GPU and, on the
//! CPU, convolved per channel with the full 2D kernel of the profile (`fit::ground_truth`), which
//! is what the thesis calls the ground truth of its renderings.
//!
//! Both sides work at one kernel scale: the view depth of the camera's target, rounded so that a
//! pixel is an odd number `bin` of profile bins (the ground truth is the profile's 2D kernel
//! block-summed by `bin`), with no depth test, so that the only difference left is the kernel's
//! shape. Errors are measured on SSS pixels only (where the scene pass wrote an SSS strength):
//! the RMS of (image − truth) per channel, relative to the truth's mean over those pixels and the
//! three channels. Images are linear RGBA f32, row-major, top row first; lengths are cm.

use fit::convolve::{Image, convolve_2d};
use fit::metrics::bin_kernel;
use fit::taps::{ShaderKernel, TapSpec};
use fit::{KernelModel, Profile};

use crate::error::{GpuError, Result};
use crate::frame::context::Gpu;
use crate::params::RenderParams;
use crate::passes::blur::DepthMode;
use crate::render::{Renderer, Scatter};
use crate::scene::Scene;
use shading::KernelTaps;

/// The kernel scale of a comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KernelScale {
    /// Profile bins per pixel (odd, ≥ 1).
    pub bin: usize,
    /// Pixel size on the surface [cm]: `bin` × the profile's bin width.
    pub cm_per_px: f64,
    /// The view depth [cm] every kernel is applied at ([`RenderParams::fixed_depth`]).
    pub fixed_depth_cm: f32,
}

/// The camera target's view depth rounded so that one pixel there is an odd number of profile
/// bins, for images `height` pixels tall and kernels `sss_width` × their physical size.
pub fn kernel_scale(scene: &Scene, height: u32, p: &Profile, sss_width: f32) -> KernelScale {
    let f = scene.camera.px_per_cm_at_unit_depth(height);
    let depth = (scene.camera.target - scene.camera.position).length();
    let bin =
        (((depth / f) as f64 / p.dr / sss_width.max(1e-6) as f64).round() as usize).max(1) | 1;
    KernelScale {
        bin,
        cm_per_px: p.dr * bin as f64,
        fixed_depth_cm: (bin as f64 * p.dr * f as f64 * sss_width as f64) as f32,
    }
}

/// A square cut-out of the image [px].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    /// Left column [px].
    pub x0: usize,
    /// Top row [px].
    pub y0: usize,
    /// Side length [px].
    pub side: usize,
}

/// An image's error against the ground truth on SSS pixels, relative to the truth's mean there
/// (over pixels and channels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// RMS per channel R, G, B.
    pub rms_rel: [f64; 3],
    /// RMS over the three channels together: √(mean of `rms_rel`²).
    pub rms_rel_all: f64,
}

/// One rendered kernel (or the unscattered image).
#[derive(Clone, Debug, PartialEq)]
pub struct Shown {
    /// What the image shows of the diffuse light: the scattered light on SSS pixels, the
    /// unscattered elsewhere (linear RGBA).
    pub shown: Vec<[f32; 4]>,
    /// The whole frame as rendered (albedo, specular, tone map), sRGB RGBA8.
    pub display: Vec<u8>,
    /// Its error against the ground truth.
    pub error: ImageError,
}

/// Kernels rendered against the 2D ground truth.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Image width [px].
    pub width: usize,
    /// Image height [px].
    pub height: usize,
    /// The one kernel scale of every image and of the truth.
    pub scale: KernelScale,
    /// Where errors are measured: pixels of SSS surfaces.
    pub sss: Vec<bool>,
    /// The irradiance convolved per channel with the 2D ground truth on SSS pixels, the
    /// irradiance elsewhere (linear RGBA).
    pub truth: Vec<[f32; 4]>,
    /// The truth's mean over SSS pixels and channels: the errors' scale.
    pub mean: f64,
    /// No scattering at all (Lambert): the irradiance itself.
    pub lambert: Shown,
    /// One per kernel, in the order given.
    pub kernels: Vec<Shown>,
    /// A cut-out around the strongest irradiance gradient on SSS pixels (a shadow edge), a third
    /// of the shorter image side (at least 16 px).
    pub crop: Crop,
}

/// [`compare_kernels`] for kernel models fitted here to `p` (`material` names it for models
/// with published parameters, e.g. manual's Table A.1), each sampled into taps by `spec`.
pub fn compare_models(
    gpu: &Gpu,
    scene: &Scene,
    base: &RenderParams,
    p: &Profile,
    material: &str,
    models: &[KernelModel],
    spec: TapSpec,
) -> Result<Comparison> {
    let truths: Vec<fit::Kernel2> = fit::ground_truths(p);
    let kernels = models
        .iter()
        .map(|m| {
            let fitted = m.fit_truths(&truths, material)?;
            ShaderKernel::from_fitted(&fitted, material, spec)
        })
        .collect::<fit::Result<Vec<_>>>()?;
    compare_with(gpu, scene, base, p, &truths, &kernels)
}

/// Every kernel rendered on `scene` with `base`'s settings at one kernel scale
/// ([`kernel_scale`]) and without a depth test, against the CPU 2D convolution of the same
/// irradiance with the ground truth of `p` binned to pixels.
pub fn compare_kernels(
    gpu: &Gpu,
    scene: &Scene,
    base: &RenderParams,
    p: &Profile,
    kernels: &[ShaderKernel],
) -> Result<Comparison> {
    let truths: Vec<fit::Kernel2> = fit::ground_truths(p);
    compare_with(gpu, scene, base, p, &truths, kernels)
}

fn compare_with(
    gpu: &Gpu,
    scene: &Scene,
    base: &RenderParams,
    p: &Profile,
    truths: &[fit::Kernel2],
    kernels: &[ShaderKernel],
) -> Result<Comparison> {
    if !(base.sss_width.is_finite() && base.sss_width > 0.0) {
        return Err(GpuError::invalid(
            "sss_width",
            base.sss_width,
            "a comparison needs kernels of positive size",
        ));
    }
    if scene.material_count() > 1 {
        return Err(GpuError::invalid(
            "materials",
            scene.material_count(),
            "a comparison against one profile needs a scene of one SSS material",
        ));
    }
    let scale = kernel_scale(scene, base.height, p, base.sss_width);
    let params = RenderParams {
        depth_mode: DepthMode::None,
        fixed_depth: Some(scale.fixed_depth_cm),
        ..*base
    };
    let (w, h) = (base.width as usize, base.height as usize);
    let renderer = Renderer::new(gpu);
    let lambert = renderer.render(gpu, scene, Scatter::None, &params)?;
    let sss: Vec<bool> = lambert.geometry.iter().map(|g| g[1] > 0.0).collect();
    let truth = ground_truth_image(&lambert.irradiance, &sss, w, h, truths, scale.bin);
    let crop = strongest_edge(&lambert.irradiance, &sss, w, h);
    let (sum, n) = (0..w * h)
        .filter(|&i| sss[i])
        .fold((0.0, 0usize), |(s, n), i| {
            (
                s + truth[i][..3].iter().map(|&v| v as f64).sum::<f64>() / 3.0,
                n + 1,
            )
        });
    let mean = sum / n.max(1) as f64;
    let error = |img: &[[f32; 4]]| image_error(img, &truth, &sss, mean);
    let lambert = Shown {
        error: error(&lambert.irradiance),
        shown: lambert.irradiance,
        display: lambert.display,
    };
    let kernels = kernels
        .iter()
        .map(|k| {
            let frame = renderer.render(
                gpu,
                scene,
                Scatter::Separable(&[KernelTaps::from_shader_kernel(k)?]),
                &params,
            )?;
            Ok(shown(&frame, &sss, &error))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Comparison {
        width: w,
        height: h,
        scale,
        sss,
        truth,
        mean,
        lambert,
        kernels,
        crop,
    })
}

/// Each channel of the irradiance convolved with its 2D ground truth block-summed by `bin`, on
/// SSS pixels; other pixels keep the irradiance.
fn ground_truth_image(
    irradiance: &[[f32; 4]],
    sss: &[bool],
    w: usize,
    h: usize,
    truths: &[fit::Kernel2],
    bin: usize,
) -> Vec<[f32; 4]> {
    let mut truth = irradiance.to_vec();
    for (c, k) in truths.iter().enumerate() {
        let img = Image {
            width: w,
            height: h,
            v: irradiance.iter().map(|v| v[c] as f64).collect(),
        };
        let conv = convolve_2d(&img, &bin_kernel(k, bin));
        for i in 0..w * h {
            if sss[i] {
                truth[i][c] = conv.v[i] as f32;
            }
        }
    }
    truth
}

/// The cut-out centred (where the image allows) on the SSS pixel with the largest
/// |∂E/∂x| + |∂E/∂y| of the irradiance summed over channels (forward differences).
fn strongest_edge(irradiance: &[[f32; 4]], sss: &[bool], w: usize, h: usize) -> Crop {
    let side = (w.min(h) / 3).max(16).min(w).min(h);
    let grad = |i: usize| {
        let (x, y) = (i % w, i / w);
        if x + 1 >= w || y + 1 >= h || !sss[i] {
            return 0.0;
        }
        let e = |j: usize| irradiance[j].iter().take(3).sum::<f32>();
        (e(i + 1) - e(i)).abs() + (e(i + w) - e(i)).abs()
    };
    let best = (0..w * h)
        .max_by(|&i, &j| grad(i).total_cmp(&grad(j)))
        .unwrap_or(0);
    Crop {
        x0: (best % w).saturating_sub(side / 2).min(w - side),
        y0: (best / w).saturating_sub(side / 2).min(h - side),
        side,
    }
}

/// RMS of `img` − `truth` on SSS pixels per channel and over all three, divided by `mean`.
/// What `frame` shows of the diffuse light (scattered on SSS pixels), scored by `error`.
fn shown(
    frame: &crate::render::Frame,
    sss: &[bool],
    error: &dyn Fn(&[[f32; 4]]) -> ImageError,
) -> Shown {
    let shown: Vec<[f32; 4]> = (0..sss.len())
        .map(|i| {
            if sss[i] {
                frame.scattered[i]
            } else {
                frame.irradiance[i]
            }
        })
        .collect();
    Shown {
        error: error(&shown),
        shown,
        display: frame.display.clone(),
    }
}

impl Comparison {
    /// The area gather ([`crate::gathers::area_gather`]) rendered on `scene` with `base`'s settings and
    /// scored against this comparison's truth as the kernels are. It works at each pixel's true
    /// depth (the fixed kernel scale and the disabled depth test do not apply to it), so where
    /// the scene's depth varies it departs from the fixed-scale truth by design; on a surface at
    /// the target's depth it is the same integral. Its splats replace the shadow-map light through
    /// thin parts (`base`'s translucency tables are left out), and they add light from parts the
    /// camera does not see, which the screen-space truth lacks: near silhouettes that counts as
    /// error here.
    pub fn area_gather(
        &self,
        gpu: &Gpu,
        scene: &Scene,
        base: &RenderParams,
        setup: &crate::AreaGatherSetup,
    ) -> Result<Shown> {
        let mut params = *base;
        for s in &mut params.shading {
            s.translucency = None;
        }
        let frame = Renderer::new(gpu).render(gpu, scene, Scatter::AreaGather(setup), &params)?;
        let error = |img: &[[f32; 4]]| image_error(img, &self.truth, &self.sss, self.mean);
        Ok(shown(&frame, &self.sss, &error))
    }
}

/// A linear colour as the renderer's recombination shows it: × `exposure`, ACES (Narkowicz's
/// fit), then sRGB, as 8-bit values.
pub fn tone_map(v: [f32; 3], exposure: f32) -> [u8; 3] {
    v.map(|x| {
        let x = (x * exposure).max(0.0);
        let t = ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
        let s = if t <= 0.0031308 {
            12.92 * t
        } else {
            1.055 * t.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5) as u8
    })
}

fn image_error(img: &[[f32; 4]], truth: &[[f32; 4]], sss: &[bool], mean: f64) -> ImageError {
    let mut sq = [0.0f64; 3];
    let mut n = 0usize;
    for i in (0..img.len()).filter(|&i| sss[i]) {
        for (c, s) in sq.iter_mut().enumerate() {
            *s += ((img[i][c] - truth[i][c]) as f64).powi(2);
        }
        n += 1;
    }
    let n = n.max(1) as f64;
    let scale = mean.max(1e-300);
    ImageError {
        rms_rel: sq.map(|s| (s / n).sqrt() / scale),
        rms_rel_all: (sq.iter().sum::<f64>() / 3.0 / n).sqrt() / scale,
    }
}
