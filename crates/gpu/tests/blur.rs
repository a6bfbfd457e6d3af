//! The GPU blur passes against the CPU reference convolutions of `fit`. These run on whatever
//! adapter wgpu finds; in CI that is Mesa's lavapipe. Under CI=true a missing adapter fails.

use fit::convolve::{Image, convolve_2d, convolve_separable};
use fit::taps::ShaderKernel;
use fit::{Profile, ground_truth, preint, svd};
use gpu::{BlurParams, DepthMode, KernelTaps, blur_image};

mod common;
use common::gpu;

/// A skin-like profile: Rd spacing h = 0.01 cm, two decay lengths per channel.
fn profile() -> Profile {
    Profile::from_fn(0.01, 40, |c, r| {
        let l = [0.08, 0.05, 0.03][c];
        (-r / l).exp() / r.max(0.005) + 0.3 * (-r / (3.0 * l)).exp() / r.max(0.005)
    })
}

/// The pre-integrated kernel of [`profile`] with `taps` taps holding `coverage` of its mass.
fn preint_kernel(taps: usize, coverage: f64) -> KernelTaps {
    let p = profile();
    let seps: Vec<_> = (0..3).map(|c| preint(&ground_truth(&p, c, None))).collect();
    KernelTaps::from_shader_kernel(&ShaderKernel::from_separable(
        fit::KernelModel::Preint,
        "test",
        [&seps[0], &seps[1], &seps[2]],
        taps,
        coverage,
        0.0,
    ))
    .unwrap()
}

/// Pixel size = h: at view depth `z`, px_per_cm_at_unit_depth = z/h.
fn params(z: f32, h: f64, mode: DepthMode) -> BlurParams {
    BlurParams {
        px_per_cm_at_unit_depth: z / h as f32,
        sss_width: 1.0,
        depth_mode: mode,
        tolerance_cm: Some(0.5),
        jitter: 0.0,
        fixed_depth: None,
        skip_empty: true,
        fast: false,
    }
}

fn rgba(channels: [&Image; 3]) -> Vec<[f32; 4]> {
    (0..channels[0].v.len())
        .map(|i| {
            [
                channels[0].v[i] as f32,
                channels[1].v[i] as f32,
                channels[2].v[i] as f32,
                1.0,
            ]
        })
        .collect()
}

/// 1 on the left half, 0 on the right.
fn edge(w: usize, h: usize) -> Image {
    let mut img = Image::new(w, h);
    for y in 0..h {
        for x in 0..w / 2 {
            img.v[y * w + x] = 1.0;
        }
    }
    img
}

fn test_image(w: usize, h: usize) -> Image {
    let mut img = Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            // An edge, a bright square and a smooth ramp.
            let edge = if x < w / 3 { 1.0 } else { 0.0 };
            let square = if (30..38).contains(&x) && (10..18).contains(&y) {
                4.0
            } else {
                0.0
            };
            img.v[y * w + x] = edge + square + 0.2 * (y as f64 / h as f64);
        }
    }
    img
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, b| a.max(b.abs()))
}

/// Both passes of a rank-3 SVD kernel with 17 quadratic taps at constant depth equal the CPU's
/// separable convolution with the same taps: GPU linear interpolation between the two nearest
/// pixels is the CPU's linear splitting of each tap. Bound: 2·10⁻⁶ of the image's maximum
/// (f32 accumulation over 3 × 2 × 17 taps); the fast path 4·10⁻³.
#[test]
fn blur_passes_equal_the_cpu_separable_convolution() {
    let Some(gpu) = gpu() else { return };
    let p = profile();
    let ks: Vec<_> = fit::ground_truths(&p);
    let seps: Vec<_> = ks.iter().map(|k| svd(k, 3).0).collect();
    let kernel = ShaderKernel::from_separable(
        fit::KernelModel::Svd {
            rank: 3,
            renormalize: false,
        },
        "test",
        [&seps[0], &seps[1], &seps[2]],
        17,
        0.95,
        0.0,
    );
    let (w, h) = (64usize, 48usize);
    let img = test_image(w, h);
    let geometry = vec![[30.0f32, 1.0, 0.0, 1.0]; w * h];
    // The fast path (rgba16float texture, one filtered fetch per tap) within its stated bound:
    // half-precision light (relative step 2⁻¹¹ per pass) and the sampler's sub-texel weights.
    for (fast, bound) in [(false, 2e-6), (true, 4e-3)] {
        let mut pr = params(30.0, p.dr, DepthMode::None);
        pr.fast = fast;
        let out = blur_image(
            &gpu,
            &rgba([&img, &img, &img]),
            &geometry,
            (w as u32, h as u32),
            &[KernelTaps::from_shader_kernel(&kernel).unwrap()],
            &pr,
        )
        .unwrap();
        let scale = max_abs(&img.v);
        for c in 0..3 {
            let cpu = convolve_separable(&img, &kernel.to_separable(c, p.dr, 2 * ks[c].half));
            let diff: Vec<f64> = (0..w * h).map(|i| out[i][c] as f64 - cpu.v[i]).collect();
            eprintln!(
                "fast {fast}, channel {c}: max |GPU − CPU| = {:.2e} of the image's maximum",
                max_abs(&diff) / scale
            );
            assert!(
                max_abs(&diff) < bound * scale,
                "fast {fast}, channel {c}: max |GPU − CPU| = {:e}",
                max_abs(&diff)
            );
        }
    }
}

/// The exactness of pre-integration on an edge survives the whole GPU path: a dense
/// pre-integrated kernel (one tap per sample) on an edge image equals the CPU's 2D convolution
/// with the ground-truth kernel.
#[test]
fn preintegrated_edge_matches_the_2d_ground_truth_on_the_gpu() {
    let Some(gpu) = gpu() else { return };
    let p = profile();
    let ks: Vec<_> = fit::ground_truths(&p);
    let seps: Vec<_> = ks.iter().map(preint).collect();
    let kernel = ShaderKernel::dense(
        fit::KernelModel::Preint,
        "test",
        [&seps[0], &seps[1], &seps[2]],
    );
    let (w, h) = (120usize, 24usize);
    let edge = edge(w, h);
    let geometry = vec![[30.0f32, 1.0, 0.0, 1.0]; w * h];
    let out = blur_image(
        &gpu,
        &rgba([&edge, &edge, &edge]),
        &geometry,
        (w as u32, h as u32),
        &[KernelTaps::from_shader_kernel(&kernel).unwrap()],
        &params(30.0, p.dr, DepthMode::None),
    )
    .unwrap();
    for c in 0..3 {
        let truth = convolve_2d(&edge, &ks[c]);
        let diff: Vec<f64> = (0..w * h).map(|i| out[i][c] as f64 - truth.v[i]).collect();
        let peak = max_abs(&truth.v);
        assert!(
            max_abs(&diff) < 1e-5 * peak,
            "channel {c}: {:e} of {peak}",
            max_abs(&diff)
        );
    }
}

/// Light does not bleed across a depth discontinuity when the blur follows the surface (lerp)
/// or rejects samples, while without a depth test it does; measured on the dark side of an edge
/// that is also a 10 cm step in depth.
#[test]
fn depth_discontinuities_stop_bleeding() {
    let Some(gpu) = gpu() else { return };
    let p = profile();
    let ks: Vec<_> = fit::ground_truths(&p);
    let seps: Vec<_> = ks.iter().map(preint).collect();
    let kernel = preint_kernel(33, 0.95);
    let (w, h) = (80usize, 8usize);
    let mut img = Image::new(w, h);
    let mut geometry = vec![[30.0f32, 1.0, 0.0, 1.0]; w * h];
    for y in 0..h {
        for x in 0..w {
            if x < w / 2 {
                img.v[y * w + x] = 1.0;
            } else {
                geometry[y * w + x][0] = 40.0;
            }
        }
    }
    let bleed = |mode| {
        let mut pr = params(30.0, p.dr, mode);
        pr.fixed_depth = Some(30.0);
        let out = blur_image(
            &gpu,
            &rgba([&img, &img, &img]),
            &geometry,
            (w as u32, h as u32),
            std::slice::from_ref(&kernel),
            &pr,
        )
        .unwrap();
        let dark: f64 = (0..h)
            .flat_map(|y| (w / 2..w / 2 + 10).map(move |x| (x, y)))
            .map(|(x, y)| out[y * w + x][0] as f64)
            .sum();
        let lit_edge = out[(h / 2) * w + w / 2 - 1][0] as f64;
        (dark / (10 * h) as f64, lit_edge)
    };
    let (none, _) = bleed(DepthMode::None);
    let (lerp, _) = bleed(DepthMode::Lerp);
    let (reject, reject_edge) = bleed(DepthMode::Reject);
    eprintln!(
        "mean light within 10 px of the step: none {none:.4}, lerp {lerp:.2e}, reject {reject:.2e}"
    );
    assert!(none > 0.02, "{none}");
    assert!(
        lerp < 1e-3 * none && reject < 1e-3 * none,
        "lerp {lerp}, reject {reject}, none {none}"
    );
    // Rejection renormalizes: the lit side's last pixel keeps the kernel's whole weight × 1.
    let total: f64 = seps[0]
        .terms
        .iter()
        .map(|t| t.sign * t.a.iter().sum::<f64>().powi(2))
        .sum();
    assert!(
        (reject_edge - total).abs() < 1e-3 * total,
        "{reject_edge} vs {total}"
    );
}

/// Doubling the view depth halves the blur radius (eq. 4.11): the 10–90% width of a blurred edge.
#[test]
fn doubling_the_depth_halves_the_blur_radius() {
    let Some(gpu) = gpu() else { return };
    let p = profile();
    let kernel = preint_kernel(65, 0.99);
    let (w, h) = (400usize, 4usize);
    let img = edge(w, h);
    let width = |z: f32| {
        let geometry = vec![[z, 1.0, 0.0, 1.0]; w * h];
        // Pixel size h at z = 10 cm: a kernel of ~1 cm spans ~100 px there.
        let pr = params(10.0, p.dr, DepthMode::None);
        let out = blur_image(
            &gpu,
            &rgba([&img, &img, &img]),
            &geometry,
            (w as u32, h as u32),
            std::slice::from_ref(&kernel),
            &pr,
        )
        .unwrap();
        let row: Vec<f64> = (0..w).map(|x| out[w + x][0] as f64).collect();
        let (hi, lo) = (row[0], row[w - 1]);
        let cross = |level: f64| {
            let t = lo + level * (hi - lo);
            let i = row.iter().position(|&v| v < t).unwrap();
            (i - 1) as f64 + (row[i - 1] - t) / (row[i - 1] - row[i])
        };
        cross(0.1) - cross(0.9)
    };
    let (near, far) = (width(10.0), width(20.0));
    eprintln!("10–90% edge width: {near:.2} px at 10 cm, {far:.2} px at 20 cm");
    assert!((near / far - 2.0).abs() < 0.05, "{near} / {far}");
}

/// The supplement's depth factor (§E), renormalized: each sample's weight × e^{−Δz²/(2τ)}, the
/// weight lost given to the samples kept. Light 1 on the left of a depth step of 0.5 cm, 0 on the
/// right, √τ = 0.5 cm: every pixel is the sum here (taps on whole pixels, so no interpolation).
/// And the physics the renormalization restores: a uniformly lit tilted plane (depth rising
/// linearly across the image) keeps its exitance, where the factor alone would darken it.
#[test]
fn the_gaussian_depth_factor_weights_samples_across_a_depth_step() {
    let Some(gpu) = gpu() else { return };
    let w_taps: Vec<f32> = [1.0f32, 4.0, 6.0, 4.0, 1.0]
        .iter()
        .map(|w| w / 16.0)
        .collect();
    let kernel = KernelTaps {
        passes: vec![(
            [1.0; 3],
            (0..5)
                .map(|t| {
                    let o = 2.0 * (t as f32 - 2.0);
                    [w_taps[t], w_taps[t], w_taps[t], o]
                })
                .collect(),
        )],
        range_cm: 4.0,
    };
    let (w, h) = (32usize, 8usize);
    let pr = BlurParams {
        // 1 cm = 1 px at the fixed depth.
        px_per_cm_at_unit_depth: 30.0,
        sss_width: 1.0,
        depth_mode: DepthMode::Gaussian,
        tolerance_cm: Some(0.5),
        jitter: 0.0,
        fixed_depth: Some(30.0),
        skip_empty: true,
        fast: false,
    };
    let run = |image: &[[f32; 4]], depth: &dyn Fn(usize) -> f32| {
        let geometry: Vec<[f32; 4]> = (0..w * h).map(|i| [depth(i % w), 1.0, 0.0, 1.0]).collect();
        blur_image(
            &gpu,
            image,
            &geometry,
            (w as u32, h as u32),
            std::slice::from_ref(&kernel),
            &pr,
        )
        .unwrap()
    };
    let left = |x: usize| x < w / 2;
    let image: Vec<[f32; 4]> = (0..w * h)
        .map(|i| if left(i % w) { [1.0; 4] } else { [0.0; 4] })
        .collect();
    let out = run(&image, &|x| if left(x) { 30.0 } else { 30.5 });
    let across = (-0.5f32).exp();
    for x in 0..w {
        let (mut lit, mut kept) = (0.0f32, 0.0f32);
        for (t, wt) in w_taps.iter().enumerate() {
            let xs = (x as i32 + 2 * (t as i32 - 2)).clamp(0, w as i32 - 1) as usize;
            let f = wt * if left(xs) == left(x) { 1.0 } else { across };
            kept += f;
            if left(xs) {
                lit += f;
            }
        }
        let want = lit / kept;
        let got = out[4 * w + x][0];
        assert!((got - want).abs() < 1e-5, "x = {x}: {got} vs {want}");
    }
    // Light crosses the step, damped: the first dark pixel gets some, less than without a step.
    assert!(out[4 * w + w / 2][0] > 0.01 && out[4 * w + w / 2][0] < 0.25);
    // A tilted plane, 0.3 cm deeper per pixel, uniformly lit: exitance kept.
    let tilted = run(&vec![[1.0; 4]; w * h], &|x| 30.0 + 0.3 * x as f32);
    for v in &tilted {
        assert!((v[0] - 1.0).abs() < 1e-5, "{v:?}");
    }
}

/// Banding (supplement Fig. S.6–S.7): a pre-integrated kernel of 13 taps blurs an edge in visible
/// steps where 65 taps are smooth; jittering the 13 taps within their cells brings the
/// row-averaged edge close to the 65-tap one (each row draws its own jitter). RMS against 65 taps
/// over the edge's 400 px, for 13 taps, 13 with a third jittered, 13 all jittered.
#[test]
fn jittering_thirteen_taps_removes_their_banding() {
    let Some(gpu) = gpu() else { return };
    let p = profile();
    let (w, h) = (400usize, 64usize);
    let img = edge(w, h);
    let geometry = vec![[10.0f32, 1.0, 0.0, 1.0]; w * h];
    let row_mean = |kernel: &KernelTaps, jitter: f32| -> Vec<f64> {
        // Pixel size h at 10 cm: the kernel spans ~100 px.
        let mut pr = params(10.0, p.dr, DepthMode::None);
        pr.jitter = jitter;
        let out = blur_image(
            &gpu,
            &rgba([&img, &img, &img]),
            &geometry,
            (w as u32, h as u32),
            std::slice::from_ref(kernel),
            &pr,
        )
        .unwrap();
        (0..w)
            .map(|x| (0..h).map(|y| out[y * w + x][0] as f64).sum::<f64>() / h as f64)
            .collect()
    };
    let fine = row_mean(&preint_kernel(65, 0.99), 0.0);
    let coarse = preint_kernel(13, 0.99);
    let rms = |v: &[f64]| {
        (v.iter()
            .zip(&fine)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            / w as f64)
            .sqrt()
    };
    let (banded, third, all) = (
        rms(&row_mean(&coarse, 0.0)),
        rms(&row_mean(&coarse, 1.0 / 3.0)),
        rms(&row_mean(&coarse, 1.0)),
    );
    eprintln!(
        "edge RMS against 65 taps: 13 taps {banded:.5}, a third jittered {third:.5}, all jittered {all:.5}"
    );
    assert!(banded > 1e-3, "13 taps show no banding to remove: {banded}");
    assert!(
        third < banded && all < 0.5 * banded,
        "{banded} {third} {all}"
    );
}

/// The material rule with signed kernels: an SVD rank-3 kernel (terms with negative lobes) on a
/// lit material beside a dark one. No light crosses, and the renormalization at the border,
/// taken over |w| for signed terms, keeps the lit side bounded (within 25 % of its light).
#[test]
fn signed_svd_terms_stay_bounded_at_a_material_border() {
    let Some(gpu) = gpu() else { return };
    let p = profile();
    let ks: Vec<_> = fit::ground_truths(&p);
    let seps: Vec<_> = ks.iter().map(|k| svd(k, 3).0).collect();
    let kernel = KernelTaps::from_shader_kernel(&ShaderKernel::from_separable(
        fit::KernelModel::Svd {
            rank: 3,
            renormalize: true,
        },
        "test",
        [&seps[0], &seps[1], &seps[2]],
        17,
        0.95,
        0.0,
    ))
    .unwrap();
    assert!(
        kernel
            .passes
            .iter()
            .any(|(_, taps)| taps.iter().any(|t| t[0] < 0.0)),
        "the test needs negative lobes"
    );
    let (w, h) = (96usize, 32usize);
    let geometry: Vec<[f32; 4]> = (0..w * h)
        .map(|i| [30.0, 1.0, if i % w < w / 2 { 0.0 } else { 1.0 }, 1.0])
        .collect();
    let image: Vec<[f32; 4]> = (0..w * h)
        .map(|i| if i % w < w / 2 { [1.0; 4] } else { [0.0; 4] })
        .collect();
    let out = blur_image(
        &gpu,
        &image,
        &geometry,
        (w as u32, h as u32),
        &[kernel.clone(), kernel],
        &params(30.0, p.dr, DepthMode::None),
    )
    .unwrap();
    for (i, v) in out.iter().enumerate() {
        for c in 0..3 {
            if i % w < w / 2 {
                assert!((v[c] - 1.0).abs() < 0.25, "pixel {i}: {v:?}");
            } else {
                assert_eq!(v[c], 0.0, "pixel {i} got light");
            }
        }
    }
}
