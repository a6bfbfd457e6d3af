//! The scene pass against direct lighting computed here: Lambert's cosine law on the sphere and
//! the sphere's shadow on the floor. Under CI=true a missing adapter fails.

use glam::{Vec3, Vec4Swizzles};
use gpu::{AlbedoMode, Light, MAX_MATERIALS, RenderParams, Scatter, Scene, Shading, render};

mod common;
use common::gpu;

const W: u32 = 320;
const H: u32 = 180;

/// The pixel a world point projects to.
fn pixel(scene: &Scene, p: Vec3) -> (usize, usize) {
    let vp = scene.camera.projection(W as f32 / H as f32, 1.0, 500.0) * scene.camera.view();
    let c = vp * p.extend(1.0);
    let ndc = c.xyz() / c.w;
    (
        ((ndc.x * 0.5 + 0.5) * W as f32) as usize,
        ((0.5 - ndc.y * 0.5) * H as f32) as usize,
    )
}

#[test]
fn irradiance_follows_the_cosine_law_and_shadows_fall_where_geometry_puts_them() {
    let Some(gpu) = gpu() else { return };
    let scene = Scene::sphere();
    let Light::Directional {
        towards,
        irradiance,
        ..
    } = scene.lights[0]
    else {
        panic!()
    };
    let params = RenderParams {
        width: W,
        height: H,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    };
    let frame = render(&gpu, &scene, Scatter::None, &params).unwrap();
    let at = |(x, y): (usize, usize)| frame.irradiance[y * W as usize + x];
    // Points on the sphere (centre (0, 5, 0), radius 5) facing the camera: E = E₀·max(n·l, 0) + ambient.
    let centre = Vec3::new(0.0, 5.0, 0.0);
    for dir in [
        Vec3::new(0.0, 0.3, 1.0),
        Vec3::new(-0.5, 0.5, 1.0),
        Vec3::new(-0.3, 0.4, 0.9),
    ] {
        let n = dir.normalize();
        let e = at(pixel(&scene, centre + 5.0 * n));
        let want = irradiance.x * n.dot(towards).max(0.0) + scene.ambient.x;
        assert!(
            (e[0] - want).abs() < 0.02 * want,
            "n = {n}: {} vs {want}",
            e[0]
        );
    }
    // The floor point in line with the sphere's centre along the light gets only ambient light;
    // a floor point well away from the shadow gets E₀·l_y + ambient.
    let shadowed = centre - towards * (centre.y / towards.y);
    let e = at(pixel(&scene, shadowed));
    assert!((e[0] - scene.ambient.x).abs() < 1e-3, "in shadow: {}", e[0]);
    let lit = at(pixel(&scene, Vec3::new(-9.0, 0.0, 3.0)));
    let want = irradiance.x * towards.y + scene.ambient.x;
    assert!(
        (lit[0] - want).abs() < 1e-3 * want,
        "lit floor: {} vs {want}",
        lit[0]
    );
    // Depth is the view depth of what the pixel sees; strength is 1 on the sphere, 0 on the floor.
    let p = centre + 5.0 * Vec3::Z;
    let g = frame.geometry[pixel(&scene, p).1 * W as usize + pixel(&scene, p).0];
    let view_depth = -(scene.camera.view() * p.extend(1.0)).z;
    assert!((g[0] - view_depth).abs() < 0.05, "{} vs {view_depth}", g[0]);
    assert_eq!(g[1], 1.0);
}

/// Incidence-aware shading: on SSS surfaces each light's irradiance is scaled by the table's
/// ρ(θ)/ρ(0) at that light's incidence angle and the ambient by its hemispherical mean; the
/// non-scattering floor is untouched.
#[test]
fn incidence_table_scales_irradiance_on_sss_surfaces_only() {
    let Some(gpu) = gpu() else { return };
    let scene = Scene::sphere();
    let Light::Directional {
        towards,
        irradiance,
        ..
    } = scene.lights[0]
    else {
        panic!()
    };
    let table: [[f32; 3]; gpu::INCIDENCE_STEPS] =
        std::array::from_fn(|k| [1.0 + 0.1 * k as f32, 1.0, 1.0 + 0.05 * k as f32]);
    let params = RenderParams {
        width: W,
        height: H,
        albedo: AlbedoMode::Post,
        shading: [Shading {
            incidence: table,
            ..Shading::default()
        }; MAX_MATERIALS],
        ..RenderParams::default()
    };
    let frame = render(&gpu, &scene, Scatter::None, &params).unwrap();
    let at = |(x, y): (usize, usize)| frame.irradiance[y * W as usize + x];
    let hemi = gpu::incidence_hemispherical(&table);
    let centre = Vec3::new(0.0, 5.0, 0.0);
    for dir in [
        Vec3::new(0.0, 0.3, 1.0),
        Vec3::new(-0.5, 0.5, 1.0),
        Vec3::new(-0.3, 0.4, 0.9),
    ] {
        let n = dir.normalize();
        let cos_i = n.dot(towards).max(0.0);
        let e = at(pixel(&scene, centre + 5.0 * n));
        let f = gpu::incidence_ratio(&table, cos_i);
        for c in [0, 2] {
            let want = irradiance.x * cos_i * f[c] + scene.ambient.x * hemi[c];
            assert!(
                (e[c] - want).abs() < 0.02 * want,
                "n = {n}, channel {c}: {} vs {want}",
                e[c]
            );
        }
    }
    let lit = at(pixel(&scene, Vec3::new(-9.0, 0.0, 3.0)));
    let want = irradiance.x * towards.y + scene.ambient.x;
    assert!(
        (lit[0] - want).abs() < 1e-3 * want,
        "floor: {} vs {want}",
        lit[0]
    );
}

/// A camera straight above the sphere looks down at it (regression: a +y up vector made the view
/// matrix degenerate and the image black).
#[test]
fn a_camera_straight_above_sees_the_sphere() {
    let Some(gpu) = gpu() else { return };
    let mut scene = Scene::sphere();
    scene.camera.position = Vec3::new(0.0, 30.0, 0.0);
    scene.camera.target = Vec3::ZERO;
    let params = RenderParams {
        width: W,
        height: H,
        ..RenderParams::default()
    };
    let frame = render(&gpu, &scene, Scatter::None, &params).unwrap();
    let centre = (H as usize / 2) * W as usize + W as usize / 2;
    // The sphere's top (y = 10) is 20 cm below the camera, and it scatters (strength 1).
    assert!(
        (frame.geometry[centre][0] - 20.0).abs() < 0.1,
        "{:?}",
        frame.geometry[centre]
    );
    assert_eq!(frame.geometry[centre][1], 1.0);
    assert!(frame.irradiance[centre][0] > 0.0);
}

/// Exit-angle-aware shading multiplies what leaves each SSS pixel by h(θ) at its view angle and
/// changes nothing else: without scattering or specular light, the ratio of the linear images with
/// and without an exit table is the table at the angle between the sphere's normal and the
/// direction to the camera (linear in θ between 10° entries: the CPU twin `incidence_ratio`),
/// including factors above 1 (the packed albedo's shared scale), and 1 on the floor.
#[test]
fn an_exit_table_scales_each_sss_pixel_by_its_view_angle() {
    let Some(gpu) = gpu() else { return };
    let mut scene = Scene::sphere();
    scene.specular = 0.0;
    let plain = RenderParams {
        width: W,
        height: H,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    };
    let mut table = [[1.0f32; 3]; gpu::INCIDENCE_STEPS];
    for (k, row) in table.iter_mut().enumerate() {
        *row = [1.0 + 0.1 * k as f32, 1.0 - 0.08 * k as f32, 2.0];
    }
    let exit = RenderParams {
        shading: [Shading {
            exit: table,
            ..Shading::default()
        }; MAX_MATERIALS],
        ..plain
    };
    let a = render(&gpu, &scene, Scatter::None, &plain).unwrap();
    let b = render(&gpu, &scene, Scatter::None, &exit).unwrap();
    let centre = Vec3::new(0.0, 5.0, 0.0);
    for dir in [
        Vec3::new(0.0, 0.3, 1.0),
        Vec3::new(-0.5, 0.5, 1.0),
        Vec3::new(0.6, 0.2, 0.8),
        Vec3::new(-0.95, 0.1, 0.3),
    ] {
        let n = dir.normalize();
        let p = centre + 5.0 * n;
        let (x, y) = pixel(&scene, p);
        let i = y * W as usize + x;
        let want = gpu::incidence_ratio(&table, n.dot((scene.camera.position - p).normalize()));
        for (c, h) in want.iter().enumerate() {
            let r = b.linear[i][c] / a.linear[i][c];
            assert!(
                (r - h).abs() < 0.03 * h,
                "n = {n}, channel {c}: ratio {r} vs h = {h}"
            );
        }
    }
    let floor = pixel(&scene, Vec3::new(8.0, 0.0, 6.0));
    let i = floor.1 * W as usize + floor.0;
    assert!(a.linear[i][0] > 0.0, "the floor point is lit");
    for c in 0..3 {
        assert!(
            (b.linear[i][c] / a.linear[i][c] - 1.0).abs() < 1e-6,
            "floor: {:?} vs {:?}",
            b.linear[i],
            a.linear[i]
        );
    }
}
