//! Several SSS materials in one frame: each material's kernel scatters only its own pixels and
//! takes no light from another material's (the rule documented on `gpu::Scatter::Separable`),
//! and each material's shading tables apply to its pixels only. The work skipped where a frame
//! does not need it: pixels without SSS, and kernels smaller than a pixel, without changing the
//! image beyond what the skip states. Under CI=true a missing adapter fails.

use gpu::{
    AlbedoMode, BlurParams, DepthMode, KernelTaps, MAX_MATERIALS, RenderParams, Renderer,
    SUBPIXEL_PX, Scatter, Scene, blur_image, kernel_footprint_px, render,
};
use shading::Shading;

mod common;
use common::gpu;

/// A normalized Gaussian of σ = 1 cm in `taps` taps over ±3σ (the same for R, G and B).
fn gaussian(taps: usize) -> KernelTaps {
    gaussian_sigma(taps, 1.0)
}

/// A normalized Gaussian of standard deviation `sigma` [cm] in `taps` taps over ±3σ.
fn gaussian_sigma(taps: usize, sigma: f32) -> KernelTaps {
    let offsets: Vec<f32> = (0..taps)
        .map(|k| sigma * (-3.0 + 6.0 * k as f32 / (taps - 1) as f32))
        .collect();
    let w: Vec<f32> = offsets
        .iter()
        .map(|x| (-0.5 * (x / sigma).powi(2)).exp())
        .collect();
    let sum: f32 = w.iter().sum();
    KernelTaps {
        passes: vec![(
            [1.0; 3],
            offsets
                .iter()
                .zip(&w)
                .map(|(&x, &w)| [w / sum, w / sum, w / sum, x])
                .collect(),
        )],
        range_cm: 3.0 * sigma,
    }
}

/// One tap of weight 1 at offset 0: light stays where it is.
fn identity() -> KernelTaps {
    KernelTaps {
        passes: vec![([1.0; 3], vec![[1.0, 1.0, 1.0, 0.0]])],
        range_cm: 0.0,
    }
}

/// 1 cm = 4 px at view depth 30 cm, one scale for every pixel, no depth test.
fn blur_params(skip_empty: bool) -> BlurParams {
    BlurParams {
        px_per_cm_at_unit_depth: 30.0 * 4.0,
        sss_width: 1.0,
        depth_mode: DepthMode::None,
        tolerance_cm: None,
        jitter: 0.0,
        fixed_depth: Some(30.0),
        skip_empty,
        fast: false,
    }
}

#[test]
fn no_light_crosses_from_one_material_into_another_and_none_is_lost_at_the_border() {
    let Some(gpu) = gpu() else { return };
    let (w, h) = (64usize, 16usize);
    // Left half material 0, lit with 1; right half material 1, dark; the bottom row has no SSS.
    let geometry: Vec<[f32; 4]> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let strength = if y == h - 1 { 0.0 } else { 1.0 };
            [30.0, strength, if x < w / 2 { 0.0 } else { 1.0 }, 1.0]
        })
        .collect();
    let image: Vec<[f32; 4]> = (0..w * h)
        .map(|i| if i % w < w / 2 { [1.0; 4] } else { [0.0; 4] })
        .collect();
    let kernels = [gaussian(17), gaussian(17)];
    let out = blur_image(
        &gpu,
        &image,
        &geometry,
        (w as u32, h as u32),
        &kernels,
        &blur_params(true),
    )
    .unwrap();
    // Every SSS row, including those whose vertical taps reach the bottom row without SSS (taken
    // as before: its own light, the same in both halves as the rows above it).
    for y in 0..h - 1 {
        for x in 0..w {
            let v = out[y * w + x];
            if x < w / 2 {
                // A uniformly lit material stays uniform up to its border: Σw = 1 per pass.
                for c in 0..3 {
                    assert!((v[c] - 1.0).abs() < 1e-5, "({x}, {y}) material 0: {v:?}");
                }
            } else {
                assert_eq!(&v[..3], &[0.0; 3], "({x}, {y}) material 1 got light");
            }
        }
    }
    // Pixels without SSS do no blur work: they come back 0 (the image keeps their own light).
    assert!(out[(h - 1) * w..].iter().all(|v| v[..3] == [0.0; 3]));
    // Doing that work anyway changes nothing on the SSS pixels.
    let full = blur_image(
        &gpu,
        &image,
        &geometry,
        (w as u32, h as u32),
        &kernels,
        &blur_params(false),
    )
    .unwrap();
    for i in 0..w * (h - 1) {
        for c in 0..3 {
            assert!((out[i][c] - full[i][c]).abs() < 1e-6, "pixel {i}");
        }
    }
    // Control: as one material, light does cross the border (the test above can fail).
    let one: Vec<[f32; 4]> = geometry.iter().map(|g| [g[0], g[1], 0.0, 1.0]).collect();
    let mixed = blur_image(
        &gpu,
        &image,
        &one,
        (w as u32, h as u32),
        &kernels[..1],
        &blur_params(true),
    )
    .unwrap();
    assert!(mixed[w / 2 + 1][0] > 0.05, "{:?}", mixed[w / 2 + 1]);
}

#[test]
fn each_material_of_a_pair_gets_its_own_kernel_and_shading() {
    let Some(gpu) = gpu() else { return };
    let mut scene = Scene::pair();
    scene.specular = 0.0;
    assert_eq!(scene.material_count(), 2);
    let (w, h) = (256u32, 144u32);
    let params = RenderParams {
        width: w,
        height: h,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    };
    // Material 0 blurred, material 1 left as it is.
    let kernels = [gaussian(17), identity()];
    let frame = render(&gpu, &scene, Scatter::Separable(&kernels), &params).unwrap();
    let (mut left, mut right, mut moved) = (0, 0, 0.0f32);
    for i in 0..(w * h) as usize {
        let g = frame.geometry[i];
        if g[1] <= 0.0 {
            continue;
        }
        let (s, e) = (frame.scattered[i], frame.irradiance[i]);
        if g[2] == 1.0 {
            right += 1;
            for c in 0..3 {
                assert!(
                    (s[c] - e[c]).abs() <= 1e-5 * e[c].max(1e-3),
                    "material 1 pixel {i}: {s:?} vs {e:?}"
                );
            }
        } else {
            assert_eq!(g[2], 0.0, "pixel {i}");
            left += 1;
            moved = moved.max((s[0] - e[0]).abs() / e[0].max(1e-3));
        }
    }
    assert!(left > 1000 && right > 1000, "{left} / {right} pixels");
    assert!(moved > 0.05, "material 0 was not blurred: {moved}");

    // Shading per material: an exit factor of 2 on material 1 doubles its light only.
    let mut shading = [Shading::default(); MAX_MATERIALS];
    shading[1].exit = [[[2.0; 3]; shading::INCIDENCE_STEPS]; shading::INCIDENCE_STEPS];
    let plain = render(&gpu, &scene, Scatter::None, &params).unwrap();
    let lifted = render(
        &gpu,
        &scene,
        Scatter::None,
        &RenderParams { shading, ..params },
    )
    .unwrap();
    for i in 0..(w * h) as usize {
        let g = plain.geometry[i];
        if g[1] <= 0.0 || plain.linear[i][0] < 1e-3 {
            continue;
        }
        let want = if g[2] == 1.0 { 2.0 } else { 1.0 };
        let r = lifted.linear[i][0] / plain.linear[i][0];
        assert!((r - want).abs() < 0.02, "pixel {i}: ratio {r}, want {want}");
    }

    // Too few kernels for the scene's materials: refused, naming the field.
    let err = render(&gpu, &scene, Scatter::Separable(&kernels[..1]), &params).unwrap_err();
    assert!(err.to_string().contains("kernels"), "{err}");
}

#[test]
fn a_point_kernel_keeps_the_total_response_of_any_kernel() {
    // Two passes with signs (an SVD-like rank 2) and a plain Gaussian.
    let mut k = gaussian(9);
    k.passes
        .push(([-1.0, 1.0, -1.0], vec![[0.2, 0.1, 0.3, 0.5]; 3]));
    for k in [gaussian(9), k] {
        let (t, p) = (k.total(), k.point());
        assert_eq!(p.passes.len(), 1);
        assert_eq!(p.passes[0].1.len(), 1);
        for c in 0..3 {
            assert!(
                (p.total()[c] - t[c]).abs() < 1e-6,
                "{:?} vs {t:?}",
                p.total()
            );
        }
    }
    // A normalized kernel's response is 1.
    assert!((gaussian(17).total()[0] - 1.0).abs() < 1e-6);
}

#[test]
fn skipping_empty_pixels_and_subpixel_kernels_leaves_the_image_as_stated() {
    let Some(gpu) = gpu() else { return };
    let renderer = Renderer::new(&gpu);
    let scene = Scene::sphere();
    // σ = 0.05 cm: 1.4 px at the sphere's distance here.
    let k = [gaussian_sigma(17, 0.05)];
    let params = RenderParams {
        width: 192,
        height: 108,
        ..RenderParams::default()
    };
    // Pixels without SSS doing no work: the same image to rounding.
    let on = renderer
        .render(&gpu, &scene, Scatter::Separable(&k), &params)
        .unwrap();
    let off = renderer
        .render(
            &gpu,
            &scene,
            Scatter::Separable(&k),
            &RenderParams {
                skip_empty: false,
                ..params
            },
        )
        .unwrap();
    for (a, b) in on.linear.iter().zip(&off.linear) {
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-5 * b[c].max(1.0),
                "{a:?} vs {b:?}"
            );
        }
    }
    // The sphere 3× as far: the kernel reaches below half a pixel.
    let mut far = scene.clone();
    far.camera.position = far.camera.target + 3.0 * (far.camera.position - far.camera.target);
    let footprint = kernel_footprint_px(&far, 0, &k[0], &params);
    assert!(footprint < SUBPIXEL_PX, "{footprint} px");
    assert!(kernel_footprint_px(&scene, 0, &k[0], &params) > 1.0);
    let skipped = renderer
        .render(&gpu, &far, Scatter::Separable(&k), &params)
        .unwrap();
    let blurred = renderer
        .render(
            &gpu,
            &far,
            Scatter::Separable(&k),
            &RenderParams {
                skip_subpixel: false,
                ..params
            },
        )
        .unwrap();
    let (mut sum_skipped, mut sum_blurred, mut count) = (0.0f64, 0.0f64, 0);
    for i in 0..skipped.geometry.len() {
        if skipped.geometry[i][1] <= 0.0 {
            continue;
        }
        count += 1;
        // Skipped: the unblurred light (the kernel's total response is 1).
        let (s, e) = (skipped.scattered[i], skipped.irradiance[i]);
        for c in 0..3 {
            assert!(
                (s[c] - e[c]).abs() <= 1e-5 * e[c].max(1e-3),
                "{s:?} vs {e:?}"
            );
        }
        sum_skipped += s[0] as f64;
        sum_blurred += blurred.scattered[i][0] as f64;
    }
    assert!(count > 20, "{count} SSS pixels");
    // Blurring by less than half a pixel moves light but keeps it: the totals agree.
    assert!(
        (sum_skipped / sum_blurred - 1.0).abs() < 0.02,
        "{sum_skipped} vs {sum_blurred}"
    );
}

#[test]
fn half_resolution_keeps_the_light_and_stays_close_to_full_resolution() {
    let Some(gpu) = gpu() else { return };
    let renderer = Renderer::new(&gpu);
    let mut scene = Scene::pair();
    scene.specular = 0.0;
    // Material 0 with a 0.3 cm Gaussian (~5 px here), material 1 with a 0.1 cm one.
    let kernels = [gaussian_sigma(17, 0.3), gaussian_sigma(17, 0.1)];
    let params = RenderParams {
        width: 320,
        height: 180,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    };
    let full = renderer
        .render(&gpu, &scene, Scatter::Separable(&kernels), &params)
        .unwrap();
    let half = renderer
        .render(
            &gpu,
            &scene,
            Scatter::Separable(&kernels),
            &RenderParams {
                half_res: true,
                ..params
            },
        )
        .unwrap();
    for material in [0.0, 1.0] {
        let (mut sf, mut sh, mut se, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
        for i in 0..full.geometry.len() {
            let g = full.geometry[i];
            if g[1] <= 0.0 || g[2] != material {
                continue;
            }
            let (a, b) = (full.scattered[i][0] as f64, half.scattered[i][0] as f64);
            sf += a;
            sh += b;
            se += (a - b).powi(2);
            n += 1;
        }
        assert!(n > 1000, "{n}");
        let mean = sf / n as f64;
        let rms = (se / n as f64).sqrt() / mean;
        eprintln!(
            "material {material}: half/full light {:.4}, RMS difference {:.2} % of the mean",
            sh / sf,
            100.0 * rms
        );
        // The light is kept (within 1 %), and the image differs mostly along silhouettes and
        // the shadow edge, where 2×2 blocks average across them.
        assert!((sh / sf - 1.0).abs() < 0.01, "{}", sh / sf);
        assert!(rms < 0.08, "{rms}");
    }
}

#[test]
fn the_fast_path_renders_what_the_exact_path_does_and_takes_one_material() {
    let Some(gpu) = gpu() else { return };
    let renderer = Renderer::new(&gpu);
    let scene = Scene::sphere();
    let k = [gaussian_sigma(17, 0.3)];
    let params = RenderParams {
        width: 256,
        height: 144,
        ..RenderParams::default()
    };
    let exact = renderer
        .render(&gpu, &scene, Scatter::Separable(&k), &params)
        .unwrap();
    for half_res in [false, true] {
        let fast = renderer
            .render(
                &gpu,
                &scene,
                Scatter::Separable(&k),
                &RenderParams {
                    fast: true,
                    half_res,
                    ..params
                },
            )
            .unwrap();
        let reference = if half_res {
            renderer
                .render(
                    &gpu,
                    &scene,
                    Scatter::Separable(&k),
                    &RenderParams { half_res, ..params },
                )
                .unwrap()
        } else {
            exact.clone()
        };
        let (mut se, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
        for i in 0..exact.geometry.len() {
            if exact.geometry[i][1] > 0.0 {
                let (a, b) = (
                    fast.scattered[i][1] as f64,
                    reference.scattered[i][1] as f64,
                );
                se += (a - b).powi(2);
                sum += b;
                n += 1;
            }
        }
        let rms = (se / n as f64).sqrt() / (sum / n as f64);
        eprintln!(
            "fast against exact (half resolution: {half_res}): RMS {:.3} % of the mean",
            100.0 * rms
        );
        assert!(rms < 0.01, "{rms}");
    }
    // Two materials: refused, naming the field.
    let err = renderer
        .render(
            &gpu,
            &Scene::pair(),
            Scatter::Separable(&[gaussian(9), gaussian(9)]),
            &RenderParams {
                fast: true,
                ..params
            },
        )
        .unwrap_err();
    assert!(err.to_string().contains("materials"), "{err}");
}

/// A renderer keeps its buffers and textures between frames (`Renderer::render`): a frame drawn
/// after others of different sizes, scenes, kernels and paths is bit for bit the frame a fresh
/// renderer draws, so nothing of one frame leaks into the next.
#[test]
fn a_renderer_kept_between_frames_draws_each_frame_as_a_fresh_one() {
    let Some(gpu) = gpu() else { return };
    let renderer = Renderer::new(&gpu);
    let pair = Scene::pair();
    let kernels = [gaussian_sigma(17, 0.3), gaussian_sigma(17, 0.1)];
    let params = RenderParams {
        width: 160,
        height: 90,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    };
    let first = renderer
        .render(&gpu, &pair, Scatter::Separable(&kernels), &params)
        .unwrap();
    // In between: half resolution, a larger frame of another scene on the fast path, no SSS.
    let sphere = Scene::sphere();
    let between = [
        (
            &pair,
            Scatter::Separable(&kernels),
            RenderParams {
                half_res: true,
                ..params
            },
        ),
        (
            &sphere,
            Scatter::Separable(std::slice::from_ref(&kernels[1])),
            RenderParams {
                width: 200,
                height: 120,
                fast: true,
                ..params
            },
        ),
        (&pair, Scatter::None, params),
    ];
    for (scene, scatter, p) in between {
        renderer.render(&gpu, scene, scatter, &p).unwrap();
    }
    let again = renderer
        .render(&gpu, &pair, Scatter::Separable(&kernels), &params)
        .unwrap();
    let fresh = render(&gpu, &pair, Scatter::Separable(&kernels), &params).unwrap();
    for (name, f) in [("again", &again), ("fresh", &fresh)] {
        assert!(first.linear == f.linear, "{name}: final image differs");
        assert!(
            first.scattered == f.scattered,
            "{name}: scattered light differs"
        );
        assert!(
            first.irradiance == f.irradiance,
            "{name}: irradiance differs"
        );
        assert!(first.geometry == f.geometry, "{name}: geometry differs");
        assert_eq!(first.display, f.display, "{name}: display image differs");
    }
    // The frame in between changed something: the test would notice a stale buffer.
    assert!(first.scattered.iter().any(|p| p[0] > 0.0));
}
