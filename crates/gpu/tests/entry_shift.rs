//! Entry-shifted shading (`Shading::entry_shift`) against geometry computed here: each SSS pixel
//! is shaded with the light that entered δ(θ) behind it along the light's propagation over the
//! surface.
//! - On a flat surface under a distant light that is an exact translation of the irradiance by
//!   δ along the propagation: across a straight shadow edge, ∫(E − E′) dx = δ·E_lit, whatever
//!   the shadow filter does to the edge's shape.
//! - Seen obliquely, by reciprocity, the light leaving towards the camera at θ_o last scattered
//!   δ(θ_o) further along the view ray's propagation over the surface: seen from the side the
//!   light comes from, the edge moves forward by δ(θ_i) + δ(θ_o), from the other side by
//!   δ(θ_i) − δ(θ_o).
//! - On a sphere the normal turns: a point past the terminator gets the light of the point
//!   δ(θ_i) behind it and δ(θ_o) away from the camera, I·max(n′·l, 0) with n′ that point's
//!   normal, and the unshifted shading leaves it black.
//!
//! Under CI=true a missing adapter fails.

use glam::Vec3;
use gpu::{AlbedoMode, Camera, Light, MAX_MATERIALS, RenderParams, Scatter, Scene, render};
use shading::{EntryShift, INCIDENCE_STEPS, Shading};

mod common;
use common::{EdgeView, gpu, shadow_edge_scene};

/// A table δ(θ) = d_c·sin θ [cm] at the incidence table's angles.
fn table(d: [f32; 3]) -> EntryShift {
    let mut t = EntryShift::NONE;
    for k in 0..INCIDENCE_STEPS {
        let s = (10.0 * k as f32).to_radians().sin();
        t.shift_cm[k] = d.map(|v| v * s);
    }
    t
}

fn params(width: u32, height: u32, shift: EntryShift) -> RenderParams {
    RenderParams {
        width,
        height,
        albedo: AlbedoMode::Post,
        shading: [Shading {
            entry_shift: shift,
            ..Shading::default()
        }; MAX_MATERIALS],
        ..RenderParams::default()
    }
}

/// How far forward [cm] the shift `d` (δ(θ) = d·sin θ) moves the straight shadow edge of
/// `scene` (`shadow_edge_scene`: the edge at x = 0, its shadow on the −x side, light from −x at
/// 60°) per channel, seen as `view` says: ∫ (E − E′) dx over the lit irradiance, which a
/// translation by δ makes δ whatever the shadow filter does to the edge's shape. Also the lit
/// irradiance.
fn edge_moved(gpu: &gpu::Gpu, scene: &gpu::Scene, view: &EdgeView, d: [f32; 3]) -> ([f64; 3], f64) {
    let size = view.size;
    let plain = render(
        gpu,
        scene,
        Scatter::None,
        &params(size, size, EntryShift::NONE),
    )
    .unwrap();
    let shifted = render(gpu, scene, Scatter::None, &params(size, size, table(d))).unwrap();
    let w = size as usize;
    let line = |f: &gpu::Frame, i: usize, c: usize| view.line_mean(&f.irradiance, i, c);
    // The lit end of the image (the edge is in the middle).
    let lit = line(&plain, 2, 0).max(line(&plain, w - 3, 0));
    let moved = std::array::from_fn(|c| {
        (0..w)
            .map(|i| line(&plain, i, c) - line(&shifted, i, c))
            .sum::<f64>()
            * view.px
            / lit
    });
    (moved, lit)
}

#[test]
fn a_flat_surface_moves_its_shadow_edge_forward_by_the_shift() {
    let Some(gpu) = gpu() else { return };
    let (sin, cos) = 60f32.to_radians().sin_cos();
    let size = 256u32;
    let d = [0.05, 0.1, 0.2];
    let view = EdgeView {
        size,
        px: 3.0 / size as f64,
        along_rows: false,
    };
    let (moved, lit) = edge_moved(&gpu, &shadow_edge_scene(1.5), &view, d);
    assert!(
        (lit - cos as f64).abs() < 1e-3,
        "lit irradiance {lit} vs cos 60° {cos}"
    );
    for (c, dc) in d.iter().enumerate() {
        let want = (dc * sin) as f64;
        eprintln!(
            "channel {c}: the shadow edge moved {:.4} cm forward; δ(60°) = {want:.4} cm",
            moved[c]
        );
        assert!(
            (moved[c] / want - 1.0).abs() < 0.02,
            "channel {c}: {} vs {want}",
            moved[c]
        );
    }
}

#[test]
fn an_oblique_view_moves_the_shadow_edge_by_the_exit_angles_shift_too() {
    let Some(gpu) = gpu() else { return };
    // The same edge seen at θ_o = 45° from far (θ_o within 0.2° over the frame), from the side
    // the light comes from (−x) and from the other (+x). The camera's up is y, so image rows run
    // along x, each spanning px/cos θ_o of it.
    let (sin60, theta_o) = (60f32.to_radians().sin(), 45f32.to_radians());
    let (size, distance, half_view) = (256u32, 400.0f32, 1.5f32);
    let view = EdgeView {
        size,
        px: 2.0 * half_view as f64 / size as f64 / theta_o.cos() as f64,
        along_rows: true,
    };
    let d = [0.05f32, 0.1, 0.2];
    for side in [-1.0f32, 1.0] {
        let mut scene = shadow_edge_scene(half_view);
        scene.camera = Camera {
            position: distance * Vec3::new(side * theta_o.sin(), theta_o.cos(), 0.0),
            target: Vec3::ZERO,
            fov_y_deg: 2.0 * (half_view / distance).atan().to_degrees(),
        };
        let (moved, _) = edge_moved(&gpu, &scene, &view, d);
        for (c, dc) in d.iter().enumerate() {
            let (entry, exit) = ((dc * sin60) as f64, (dc * theta_o.sin()) as f64);
            let want = entry + side as f64 * exit;
            eprintln!(
                "camera on the {} side, channel {c}: the edge moved {:.4} cm forward; \
                 δ(60°) ± δ(45°) = {want:.4} cm",
                if side > 0.0 { "+x" } else { "light's" },
                moved[c]
            );
            assert!(
                (moved[c] - want).abs() < 0.02 * (entry + exit),
                "side {side}, channel {c}: {} vs {want}",
                moved[c]
            );
        }
    }
}

#[test]
fn a_sphere_is_lit_past_its_terminator_by_the_shift() {
    let Some(gpu) = gpu() else { return };
    let mut scene = Scene::sphere();
    let towards = Vec3::new(1.0, 0.3, -0.2).normalize();
    // Without a shadow map: what reaches each point is its cosine alone.
    scene.lights = vec![Light::Directional {
        towards,
        irradiance: Vec3::ONE,
        shadow: false,
    }];
    scene.ambient = Vec3::ZERO;
    scene.specular = 0.0;
    let (w, h) = (640u32, 360u32);
    let d = [0.2f32, 0.4, 0.8];
    let shift = table(d);
    let plain = render(&gpu, &scene, Scatter::None, &params(w, h, EntryShift::NONE)).unwrap();
    let shifted = render(&gpu, &scene, Scatter::None, &params(w, h, shift)).unwrap();
    let (centre, radius) = (Vec3::new(0.0, 5.0, 0.0), 5.0f32);
    // Points on the great circle through the terminator that faces the camera, at angle a from
    // it (n·l = sin a).
    let to_camera = (scene.camera.position - centre).normalize();
    let u = (to_camera - to_camera.dot(towards) * towards).normalize();
    let vp = scene.camera.projection(w as f32 / h as f32, 1.0, 5000.0) * scene.camera.view();
    for a_deg in [-10.0f32, -6.0, -3.0, 2.0, 6.0, 20.0] {
        let a = a_deg.to_radians();
        let n = a.cos() * u + a.sin() * towards;
        let x = centre + radius * n;
        let clip = vp * x.extend(1.0);
        let (px, py) = (
            ((clip.x / clip.w * 0.5 + 0.5) * w as f32) as usize,
            ((0.5 - clip.y / clip.w * 0.5) * h as f32) as usize,
        );
        let i = py * w as usize + px;
        // The entry δ(θ_i) behind along the propagation over the surface and δ(θ_o) along the
        // view ray's, on the sphere.
        let t = (-towards + n.dot(towards) * n).normalize();
        let to_eye = (scene.camera.position - x).normalize();
        let t_view = (-to_eye + n.dot(to_eye) * n).normalize();
        let cos_i = n.dot(towards);
        for c in 0..3 {
            let (delta, delta_o) = (shift.at(cos_i)[c], shift.at(n.dot(to_eye))[c]);
            let n2 = (x - delta * t + delta_o * t_view - centre).normalize();
            let want = n2.dot(towards).max(0.0);
            let got = shifted.irradiance[i][c];
            eprintln!(
                "a = {a_deg}°, channel {c}: {got:.4} (δ behind: {want:.4}; unshifted {:.4})",
                plain.irradiance[i][c]
            );
            assert!(
                (got - want).abs() < 0.015,
                "a = {a_deg}°, channel {c}: {got} vs {want}"
            );
            assert!((plain.irradiance[i][c] - cos_i.max(0.0)).abs() < 0.015);
        }
    }
}
