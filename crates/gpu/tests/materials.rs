//! Several SSS materials in one frame: each material's kernel scatters only its own pixels and
//! takes no light from another material's (the rule documented on `gpu::Scatter::Separable`),
//! each material's shading tables apply to its pixels only, and pixels without SSS do no blur
//! work without changing the image. Under CI=true a missing adapter fails.

use gpu::{
    AlbedoMode, BlurParams, DepthMode, GpuKernel, MAX_MATERIALS, RenderParams, Scatter, Scene,
    Shading, blur_image, render,
};

mod common;
use common::gpu;

/// A normalized Gaussian of σ = 1 cm in `taps` taps over ±3σ (the same for R, G and B).
fn gaussian(taps: usize) -> GpuKernel {
    let offsets: Vec<f32> = (0..taps)
        .map(|k| -3.0 + 6.0 * k as f32 / (taps - 1) as f32)
        .collect();
    let w: Vec<f32> = offsets.iter().map(|x| (-0.5 * x * x).exp()).collect();
    let sum: f32 = w.iter().sum();
    GpuKernel {
        passes: vec![(
            [1.0; 3],
            offsets
                .iter()
                .zip(&w)
                .map(|(&x, &w)| [w / sum, w / sum, w / sum, x])
                .collect(),
        )],
        range_cm: 3.0,
    }
}

/// One tap of weight 1 at offset 0: light stays where it is.
fn identity() -> GpuKernel {
    GpuKernel {
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
    shading[1].exit = [[2.0; 3]; gpu::INCIDENCE_STEPS];
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
