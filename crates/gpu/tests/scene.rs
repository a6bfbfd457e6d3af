//! The scene pass against direct lighting computed here: Lambert's cosine law on the sphere and
//! the sphere's shadow on the floor. Under CI=true a missing adapter fails.

use glam::{Vec3, Vec4Swizzles};
use gpu::{AlbedoMode, Light, MAX_MATERIALS, RenderParams, Scatter, Scene, render};
use shading::Shading;

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

/// A `W`×`H` frame with the albedo applied after scattering (the irradiance buffer holds E).
fn post_albedo() -> RenderParams {
    RenderParams {
        width: W,
        height: H,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    }
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
    let frame = render(&gpu, &scene, Scatter::None, &post_albedo()).unwrap();
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
    let table: [[f32; 3]; shading::INCIDENCE_STEPS] =
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
    let hemi = shading::incidence_hemispherical(&table);
    let centre = Vec3::new(0.0, 5.0, 0.0);
    for dir in [
        Vec3::new(0.0, 0.3, 1.0),
        Vec3::new(-0.5, 0.5, 1.0),
        Vec3::new(-0.3, 0.4, 0.9),
    ] {
        let n = dir.normalize();
        let cos_i = n.dot(towards).max(0.0);
        let e = at(pixel(&scene, centre + 5.0 * n));
        let f = shading::incidence_ratio(&table, cos_i);
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

/// Exit-angle-aware shading multiplies what leaves each SSS pixel by h(θ_o; θ_i) at its view
/// angle and at its light's angle of incidence, and changes nothing else: without scattering or
/// specular light, the ratio of the linear images with and without an exit table is the table at
/// the angle between the sphere's normal and the direction to the camera and at the sun's
/// incidence there (the normal-entry row where the sun is behind the surface), linear in both
/// angles between 10° entries (the CPU twin `exit_ratio`),
/// including factors above 1 (the packed albedo's shared scale), and 1 on the floor.
#[test]
fn an_exit_table_scales_each_sss_pixel_by_its_view_and_entry_angles() {
    let Some(gpu) = gpu() else { return };
    let mut scene = Scene::sphere();
    scene.specular = 0.0;
    assert_eq!(scene.lights.len(), 1);
    let Light::Directional { towards, .. } = scene.lights[0] else {
        panic!()
    };
    let plain = RenderParams {
        width: W,
        height: H,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    };
    let table: shading::ExitTable = std::array::from_fn(|i| {
        std::array::from_fn(|k| {
            let e = 1.0 + 0.04 * i as f32;
            [(1.0 + 0.1 * k as f32) * e, (1.0 - 0.08 * k as f32) / e, 2.0]
        })
    });
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
        let cos_o = n.dot((scene.camera.position - p).normalize());
        let cos_i = n.dot(towards.normalize());
        let want = shading::exit_ratio(&table, cos_o, if cos_i > 0.0 { cos_i } else { 1.0 });
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

/// Does the segment from `a` to `b` cross the box `lo`–`hi` (slab test)?
fn crosses_box(a: Vec3, b: Vec3, lo: Vec3, hi: Vec3) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for k in 0..3 {
        if d[k].abs() < 1e-9 {
            if a[k] < lo[k] || a[k] > hi[k] {
                return false;
            }
            continue;
        }
        let (u, v) = ((lo[k] - a[k]) / d[k], (hi[k] - a[k]) / d[k]);
        t0 = t0.max(u.min(v));
        t1 = t1.min(u.max(v));
    }
    t0 < t1
}

/// A point light close to the scene (inside the objects' bounding sphere, so its shadow map's
/// near plane lies at its minimum and depth is far from linear): the 3 mm fin of `Scene::fin`
/// hides the 1 mm fin's face 3 cm behind it from the light, and floor points the rays reach are
/// lit by I·cos θ/d². Regression: a depth bias of 0.0015 in NDC depth spanned 3 cm there, and the
/// 3 mm fin cast no shadow on the 1 mm one.
#[test]
fn an_occluder_centimetres_in_front_shadows_under_a_close_point_light() {
    let Some(gpu) = gpu() else { return };
    let light = Vec3::new(-10.5, 9.9, 6.7);
    let intensity = 500.0;
    let mut scene = Scene::fin();
    scene.lights = vec![Light::Point {
        position: light,
        intensity: Vec3::splat(intensity),
        shadow: true,
    }];
    scene.ambient = Vec3::ZERO;
    // Between the fins, looking at the 1 mm fin's face towards the light (x = 4.5).
    scene.camera = gpu::Camera {
        position: Vec3::new(2.3, 6.0, 4.0),
        target: Vec3::new(4.5, 2.0, 0.5),
        fov_y_deg: 80.0,
    };
    let frame = render(&gpu, &scene, Scatter::None, &post_albedo()).unwrap();
    let boxes = [
        (Vec3::new(1.5, 0.0, -3.0), Vec3::new(1.8, 9.0, 3.0)),
        (Vec3::new(4.5, 0.0, -2.0), Vec3::new(4.6, 6.0, 2.0)),
    ];
    let (centre, radius) = (Vec3::new(-4.0, 4.0, 0.0), 4.0);
    let blocked = |a: Vec3, b: Vec3| {
        let d = b - a;
        let t = ((centre - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
        (a + t * d - centre).length() < radius
            || boxes.iter().any(|&(lo, hi)| crosses_box(a, b, lo, hi))
    };
    // Whether `from` is hidden from p, where that is certain: the same answer for the segment
    // moved 0.3 cm sideways in four directions (rays closer than that to an edge or to the
    // tessellated sphere may go either way, through the shadow maps' filter and the mesh).
    let hidden = |p: Vec3, from: Vec3| -> Option<bool> {
        // Start just off the surface so its own face does not count.
        let a = p + 0.02 * (from - p).normalize();
        let axis = (from - a).normalize();
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        let answer = blocked(a, from);
        [e1, -e1, e2, -e2]
            .iter()
            .all(|&o| blocked(a + 0.3 * o, from + 0.3 * o) == answer)
            .then_some(answer)
    };
    let vp = scene.camera.projection(W as f32 / H as f32, 1.0, 500.0) * scene.camera.view();
    let (mut dark, mut lit) = (0, 0);
    let face = (0..12 * 12).map(|k| {
        let p = Vec3::new(
            4.5,
            0.3 + 0.5 * (k % 12) as f32,
            -1.9 + 0.3 * (k / 12) as f32,
        );
        (p, -Vec3::X)
    });
    let floor = (0..12 * 12).map(|k| {
        let p = Vec3::new(
            2.0 + 0.2 * (k % 12) as f32,
            0.0,
            -2.0 + 0.5 * (k / 12) as f32,
        );
        (p, Vec3::Y)
    });
    for (p, n) in face.chain(floor) {
        let c = vp * p.extend(1.0);
        let ndc = c.xyz() / c.w;
        if c.w <= 0.0 || ndc.x.abs() > 0.95 || ndc.y.abs() > 0.95 {
            continue;
        }
        // Seen by the camera, and certain whether the light sees it.
        if hidden(p, scene.camera.position) != Some(false) {
            continue;
        }
        let Some(shadowed) = hidden(p, light) else {
            continue;
        };
        let (x, y) = (
            ((ndc.x * 0.5 + 0.5) * W as f32) as usize,
            ((0.5 - ndc.y * 0.5) * H as f32) as usize,
        );
        let e = frame.irradiance[y * W as usize + x][0];
        let d = light - p;
        let want = if shadowed {
            0.0
        } else {
            intensity * n.dot(d.normalize()).max(0.0) / d.length_squared()
        };
        let full = intensity * n.dot(d.normalize()).max(0.0) / d.length_squared();
        assert!(
            (e - want).abs() < 0.03 * full,
            "{p} (normal {n}): {e}, want {want} ({})",
            if shadowed { "in shadow" } else { "lit" }
        );
        if shadowed { dark += 1 } else { lit += 1 }
    }
    assert!(
        dark >= 20 && lit >= 10,
        "{dark} shadowed and {lit} lit points checked"
    );
}
