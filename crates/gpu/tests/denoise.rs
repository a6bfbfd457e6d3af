//! The surface gather in one frame (a few samples per pixel, one frame, `Sampling::denoise`):
//! the denoiser (`gpu`'s passes/denoise.rs) and the gather's stratified samples, from physics
//! and statistics:
//! - a thick flat slab lit at 0° and 60° still returns E·cos θ·h(0; θ)·Rd(θ), the tables'
//!   integral of `mc`'s transport, within 1 % (and the mean's own standard error);
//! - the denoiser moves no light: the mean over the SSS pixels of the sphere scene (silhouettes,
//!   a floor, a terminator) stays within 0.5 % of the same frame's undenoised mean;
//! - it takes no light across a depth step: beside a block's lit top, the slab 3 cm below in the
//!   block's shadow stays as dark as the gather leaves it (a filter blind to depth puts 13 % of
//!   the top's light there);
//! - it takes out the noise a filter of its widths takes out of white noise, or more: two seeds'
//!   difference shrinks at least as much as the filter's Σ a² predicts (its weights computed
//!   here on the plane, the shader's CPU twin).
//!
//! Under CI=true a missing adapter fails.

use glam::Vec3;
use gpu::{Camera, Mesh, RenderParams, Scatter, Scene, SurfaceGatherSetup, render};
use shading::Bssrdf;

mod common;
use common::{gpu, profile, setup, slab_scene, spec};

/// The slab's camera height [cm]: a 128-pixel image spans 1.4 cm, 0.011 cm a pixel, so that
/// Skin1's widths (0.008–0.05 cm) span pixels.
const CAMERA_CM: f32 = 20.0;

/// Skin1's directional gather of 4 samples in one frame (1024² light maps).
fn one_frame() -> SurfaceGatherSetup {
    let mut s = setup(&spec(100_000, 7), &profile(), Bssrdf::Directional);
    s.sampling.samples = 4;
    s.sampling.frames = 1;
    s
}

fn params(size: u32) -> RenderParams {
    RenderParams {
        width: size,
        height: size,
        ..RenderParams::default()
    }
}

fn with(setup: &SurfaceGatherSetup, denoise: bool, seed: u32) -> SurfaceGatherSetup {
    let mut s = setup.clone();
    s.sampling.denoise = denoise;
    s.sampling.seed = seed;
    s
}

/// The frame of `setup` with seed `seed`, without and with the denoiser.
fn both(
    gpu: &gpu::Gpu,
    scene: &Scene,
    setup: &SurfaceGatherSetup,
    seed: u32,
    params: &RenderParams,
) -> (gpu::Frame, gpu::Frame) {
    let frame = |denoise| {
        render(
            gpu,
            scene,
            Scatter::SurfaceGather(&with(setup, denoise, seed)),
            params,
        )
        .unwrap()
    };
    (frame(false), frame(true))
}

/// Mean and standard error of the mean of channel `c` over the pixels of `frame` in `rows` ×
/// `cols` (the pixels taken as independent).
fn block(
    frame: &gpu::Frame,
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
    c: usize,
) -> (f64, f64) {
    let w = frame.width as usize;
    let v: Vec<f64> = rows
        .flat_map(|y| cols.clone().map(move |x| y * w + x))
        .map(|i| frame.scattered[i][c] as f64)
        .collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// On a flat lit slab the filter sees a constant plus noise, and a constant it keeps exactly: the
/// denoised frame's mean is the estimator's, the directional table's integral at the entry angle
/// (E·cos θ·h(0; θ) per unit of it). Tolerance: 1 % (the physics bound on what the
/// one-frame method may lose) plus three standard errors of the undenoised frame's mean over the
/// same pixels (the estimate's own noise, which the filter does not remove from a mean).
#[test]
fn one_denoised_frame_of_a_lit_half_space_returns_the_tables_reflectance() {
    let setup = one_frame();
    let table = setup.directional.as_ref().unwrap();
    let Some(gpu) = gpu() else { return };
    const SIZE: u32 = 128;
    for (theta, k) in [(0.0f32, 0usize), (60.0, 6)] {
        let t = theta.to_radians();
        let scene = slab_scene(4.0, CAMERA_CM, Vec3::new(t.sin(), t.cos(), 0.0));
        let (raw, den) = both(&gpu, &scene, &setup, 3, &params(SIZE));
        for (c, own) in table.integral(k).into_iter().enumerate() {
            let norm = (theta as f64).to_radians().cos() * setup.angles.exit[k][0][c] as f64;
            let (got, _) = block(&den, 16..112, 16..112, c);
            let (_, se) = block(&raw, 16..112, 16..112, c);
            let (got, se) = (got / norm, se / norm);
            let tol = 0.01 * own + 3.0 * se;
            eprintln!(
                "θ = {theta}° channel {c}: denoised one frame {got:.5}, the tables' {:.5} (± {:.5}: 1 % + 3 SE)",
                own, tol
            );
            assert!(
                (got - own).abs() < tol,
                "θ = {theta}° channel {c}: {got} vs {}",
                own
            );
        }
    }
}

/// The sum of channel c over the frame's SSS pixels (those the gather wrote).
fn total(frame: &gpu::Frame, c: usize) -> f64 {
    frame.scattered.iter().map(|v| v[c] as f64).sum()
}

/// The filter's weights are normalized per pixel, so it moves light only where a pixel's
/// neighbourhood is cut (silhouettes, the floor's border, the image's edge) and there by a share
/// of the local gradient: over the sphere scene's SSS pixels its mean stays within 0.5 % of the
/// frame it filters (the bound).
#[test]
fn the_denoiser_keeps_the_light_it_filters() {
    let setup = one_frame();
    let Some(gpu) = gpu() else { return };
    let scene = Scene::sphere();
    let p = RenderParams {
        width: 640,
        height: 360,
        ..RenderParams::default()
    };
    let (raw, den) = both(&gpu, &scene, &setup, 5, &p);
    for c in 0..3 {
        let (a, b) = (total(&raw, c), total(&den, c));
        eprintln!(
            "channel {c}: undenoised {a:.4}, denoised {b:.4} ({:+.3} %)",
            100.0 * (b / a - 1.0)
        );
        assert!(
            a > 0.0 && (b / a - 1.0).abs() < 0.005,
            "channel {c}: {b} vs {a}"
        );
    }
}

/// A block of the material whose top (y = 3) ends at x = 0 beside the slab's top (y = 0), lit
/// from −x at 60° (the block's shadow covers the slab from x = 0 to 3·tan 60° = 5.2 cm), seen
/// from straight above over x ∈ [−1, 1] cm: on screen the lit top and the dark slab meet at the
/// middle column, 3 cm apart in depth.
fn step_scene() -> Scene {
    let (sin, cos) = 60f32.to_radians().sin_cos();
    let mut scene = slab_scene(4.0, 100.0, Vec3::new(-sin, cos, 0.0));
    scene.mesh = Mesh::cuboid(
        Vec3::new(-20.0, -4.0, -20.0),
        Vec3::new(0.0, 3.0, 20.0),
        [1.0; 3],
        1.0,
    );
    scene.mesh.append(&Mesh::cuboid(
        Vec3::new(0.0, -4.0, -20.0),
        Vec3::new(20.0, 0.0, 20.0),
        [1.0; 3],
        1.0,
    ));
    scene.camera = Camera {
        position: Vec3::new(0.0, 100.0, 0.0),
        target: Vec3::ZERO,
        fov_y_deg: 2.0 * (1.0f32 / 100.0).atan().to_degrees(),
    };
    scene
}

/// Beside the step the slab is in the block's shadow and 3 cm (many diffusion lengths) from the
/// lit top: what the gather returns there is the light that crossed the body, a small share of
/// the top's. The denoiser may add to it no more than 0.5 % of the top's light over the eight
/// columns next to the step (with the depth coordinate dropped from the weight's distance the
/// filter adds 13 % of the top's light there: checked).
#[test]
fn the_denoiser_takes_no_light_across_a_depth_step() {
    let setup = one_frame();
    let Some(gpu) = gpu() else { return };
    const SIZE: u32 = 128;
    let scene = step_scene();
    let (raw, den) = both(&gpu, &scene, &setup, 9, &params(SIZE));
    // Which half is the lit top: the brighter.
    let half = SIZE as usize / 2;
    let (left, _) = block(&raw, 0..128, 8..half - 8, 0);
    let (right, _) = block(&raw, 0..128, half + 8..120, 0);
    let (top, dark) = if left > right {
        (0..half, half..half + 8)
    } else {
        (half..128, half - 8..half)
    };
    for c in 0..3 {
        let (lit, _) = block(&raw, 0..128, top.clone(), c);
        let (before, _) = block(&raw, 0..128, dark.clone(), c);
        let (after, _) = block(&den, 0..128, dark.clone(), c);
        eprintln!(
            "channel {c}: lit top {lit:.5}, beside the step undenoised {before:.6}, denoised {after:.6}"
        );
        assert!(lit > 0.0, "channel {c}: the top is not lit");
        assert!(
            after - before < 0.005 * lit,
            "channel {c}: {after} vs {before} (lit {lit})"
        );
    }
}

/// The filter's weights on a plane seen face-on (`footprint` cm per pixel) for one channel of
/// width `sigma` [cm]: the à-trous levels of passes/denoise.rs applied to a unit impulse (the
/// shader's CPU twin), returning Σ a², the variance a white noise keeps.
fn white_noise_share(sigma: f64, footprint: f64) -> f64 {
    const N: usize = 129;
    let b3 = [0.0625, 0.25, 0.375, 0.25, 0.0625];
    let mut img = vec![0.0f64; N * N];
    img[(N / 2) * N + N / 2] = 1.0;
    for level in 0..gpu::DENOISE_LEVELS {
        let step = 1i64 << level;
        if step as f64 * footprint > sigma {
            continue;
        }
        let mut out = vec![0.0; N * N];
        for y in 0..N as i64 {
            for x in 0..N as i64 {
                let (mut sum, mut weight) = (0.0, 0.0);
                for dy in -2..=2i64 {
                    for dx in -2..=2i64 {
                        let (qx, qy) = (x + step * dx, y + step * dy);
                        if qx < 0 || qy < 0 || qx >= N as i64 || qy >= N as i64 {
                            continue;
                        }
                        let d2 =
                            ((step * step * (dx * dx + dy * dy)) as f64) * footprint * footprint;
                        let w = b3[(dx + 2) as usize]
                            * b3[(dy + 2) as usize]
                            * (-d2 / (2.0 * sigma * sigma)).exp();
                        sum += w * img[qy as usize * N + qx as usize];
                        weight += w;
                    }
                }
                out[y as usize * N + x as usize] = sum / weight;
            }
        }
        img = out;
    }
    img.iter().map(|a| a * a).sum()
}

/// The RMS over `rows` × `cols` of channel c of the difference of two frames.
fn rms_difference(a: &gpu::Frame, b: &gpu::Frame, c: usize) -> f64 {
    let w = a.width as usize;
    let mut acc = 0.0;
    let mut n = 0.0;
    for y in 16..112 {
        for x in 16..112 {
            acc += (a.scattered[y * w + x][c] as f64 - b.scattered[y * w + x][c] as f64).powi(2);
            n += 1.0;
        }
    }
    (acc / n).sqrt()
}

/// Two seeds' frames differ by their noise alone on a flat slab under a near point light. A linear filter of weights
/// a keeps Σ a² of a white noise's variance, and more of it is removed where neighbouring pixels'
/// errors are anticorrelated (the samples' per-pixel rotations are interleaved gradient noise):
/// the denoised difference's RMS is at most √(Σ a²) of the undenoised one's, per channel, at the
/// widths the setup gives (10 % allowed for the RMS's own scatter over 96² pixels).
#[test]
fn the_denoiser_takes_out_what_its_widths_promise() {
    let setup = one_frame();
    let widths = setup.denoise_widths_cm();
    let Some(gpu) = gpu() else { return };
    const SIZE: u32 = 128;
    // A point light 5 cm above the slab: its rays fan out, so a sample's entry and the flat
    // control variate's read the tables at slightly different points, and 100 000 photons leave
    // the table's tail cells noisy: the samples keep 16–33 % of noise per pixel (under an even
    // directional light they keep almost none: surface_gather.rs).
    let mut scene = slab_scene(4.0, CAMERA_CM, Vec3::Y);
    scene.lights = vec![gpu::Light::Point {
        position: Vec3::new(1.0, 5.0, 0.0),
        intensity: Vec3::ONE,
        shadow: true,
    }];
    // The slab's top seen face-on through 4°.
    let footprint = CAMERA_CM as f64 * 2.0 * (2.0f64).to_radians().tan() / SIZE as f64;
    let frame = |denoise, seed| {
        render(
            &gpu,
            &scene,
            Scatter::SurfaceGather(&with(&setup, denoise, seed)),
            &params(SIZE),
        )
        .unwrap()
    };
    let (raw1, raw2, den1, den2) = (
        frame(false, 1),
        frame(false, 2),
        frame(true, 1),
        frame(true, 2),
    );
    for (c, &width) in widths.iter().enumerate() {
        // A channel narrower than the floor is filtered at the floor.
        let width = width.max(gpu::DENOISE_FLOOR_PX * footprint as f32);
        let share = white_noise_share(width as f64, footprint).sqrt();
        let ratio = rms_difference(&den1, &den2, c) / rms_difference(&raw1, &raw2, c);
        let mean =
            raw1.scattered.iter().map(|v| v[c] as f64).sum::<f64>() / raw1.scattered.len() as f64;
        eprintln!(
            "channel {c}: σ = {:.4} cm ({:.1} px), pixel noise {:.2e} of the mean, noise kept {ratio:.3}, white noise would keep {share:.3}",
            width,
            width as f64 / footprint,
            rms_difference(&raw1, &raw2, c) / std::f64::consts::SQRT_2 / mean
        );
        assert!(ratio < 1.1 * share, "channel {c}: {ratio} vs {share}");
    }
}
