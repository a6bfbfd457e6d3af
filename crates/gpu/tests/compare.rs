//! Rendered kernels against the 2D ground truth (`gpu::compare`), on whatever adapter wgpu finds
//! (lavapipe in CI). Under CI=true a missing adapter fails.

use fit::taps::{Pass, ShaderKernel, Tap, TapSpec};
use fit::{KernelModel, Profile};
use gpu::{RenderParams, Scene, compare_kernels, compare_models};

mod common;
use common::gpu;

/// A small frame of the sphere scene (a lit sphere with a hard shadow edge on it).
fn params() -> RenderParams {
    RenderParams {
        width: 160,
        height: 90,
        ..RenderParams::default()
    }
}

/// A profile that scatters over several pixels of [`params`]' frame (≈ 0.17 cm per pixel at the
/// target): two exponential decays per channel, lengths 0.3, 0.2, 0.1 cm, out to 2 cm.
fn wide_profile() -> Profile {
    Profile::from_fn(0.01, 200, |c, r| {
        let l = [0.3, 0.2, 0.1][c];
        (-r / l).exp() / r.max(0.005) + 0.3 * (-r / (3.0 * l)).exp() / r.max(0.005)
    })
}

/// One tap of weight 1 at offset 0: light stays where it entered.
fn delta() -> ShaderKernel {
    ShaderKernel {
        // A label only: the taps are what is rendered.
        model: KernelModel::Preint,
        material: "delta".into(),
        unit: "cm".into(),
        taps: 1,
        range: 0.0,
        jitter: 0.0,
        pass: vec![Pass {
            sign: [1.0; 3],
            tap: vec![Tap {
                offset: 0.0,
                weight: [1.0; 3],
            }],
        }],
    }
}

/// A delta kernel is no scattering: its image is the irradiance itself, so its error against the
/// ground truth is the Lambert image's, channel by channel (up to f32 rounding), and that error
/// is not zero where the profile spreads light over several pixels.
#[test]
fn a_delta_kernel_has_the_lambert_error() {
    let Some(gpu) = gpu() else { return };
    let cmp = compare_kernels(
        &gpu,
        &Scene::sphere(),
        &params(),
        &wide_profile(),
        &[delta()],
    )
    .unwrap();
    let (l, d) = (cmp.lambert.error, cmp.kernels[0].error);
    for c in 0..3 {
        assert!(l.rms_rel[c] > 1e-3, "channel {c}: {l:?}");
        assert!(
            (d.rms_rel[c] - l.rms_rel[c]).abs() <= 1e-5 * l.rms_rel[c],
            "channel {c}: delta {d:?} vs Lambert {l:?}"
        );
    }
    // The overall error is the RMS over the channels.
    let all = (l.rms_rel.iter().map(|e| e * e).sum::<f64>() / 3.0).sqrt();
    assert!((l.rms_rel_all - all).abs() <= 1e-12 * all);
}

/// A profile whose whole support lies inside the centre pixel (r ≤ 0.02 cm against ≈ 0.17 cm per
/// pixel) scatters nothing at pixel scale: the ground truth is the irradiance, so the Lambert
/// image's error vanishes (up to f32 rounding) and the kernel scale is one pixel of many bins.
#[test]
fn a_profile_inside_one_pixel_leaves_the_irradiance_as_the_truth() {
    let Some(gpu) = gpu() else { return };
    let narrow = Profile::from_fn(0.001, 20, |_, r| (-r / 0.005).exp() / r.max(0.0005));
    let cmp = compare_kernels(&gpu, &Scene::sphere(), &params(), &narrow, &[]).unwrap();
    assert!(cmp.scale.bin > 41, "{:?}", cmp.scale);
    assert!(
        cmp.lambert.error.rms_rel_all < 1e-5,
        "{:?}",
        cmp.lambert.error
    );
}

/// Fitted kernels scatter like the ground truth, so each is closer to it than no scattering at
/// all, in every channel; and rank 3 is closer than rank 1 (the truncated SVD converges to the
/// kernel, Eckart–Young, seen through the image). The cut-out lies inside the frame, on SSS
/// pixels where the irradiance changes.
#[test]
fn fitted_kernels_beat_no_scattering_on_the_sphere() {
    let Some(gpu) = gpu() else { return };
    let svd = |rank| KernelModel::Svd {
        rank,
        renormalize: true,
    };
    let cmp = compare_models(
        &gpu,
        &Scene::sphere(),
        &params(),
        &wide_profile(),
        "test",
        &[KernelModel::Preint, svd(1), svd(3)],
        TapSpec::default(),
    )
    .unwrap();
    let l = cmp.lambert.error;
    let [preint, svd1, svd3] = [0, 1, 2].map(|i| cmp.kernels[i].error);
    for c in 0..3 {
        assert!(
            preint.rms_rel[c] < l.rms_rel[c],
            "channel {c}: preint {preint:?} vs Lambert {l:?}"
        );
    }
    assert!(svd3.rms_rel_all < svd1.rms_rel_all, "{svd3:?} vs {svd1:?}");
    let k = cmp.crop;
    assert!(k.side >= 16 && k.x0 + k.side <= cmp.width && k.y0 + k.side <= cmp.height);
    let centre = (k.y0 + k.side / 2) * cmp.width + k.x0 + k.side / 2;
    assert!(cmp.sss[centre], "the cut-out is centred on the object");
}
