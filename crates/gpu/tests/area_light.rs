//! The area light on the GPU: what the scene pass draws equals its cells' sum (the CPU twin
//! `Emitter::irradiance`, itself tested against Lambert's polygon formula), the penumbra counts
//! exactly the cells a sphere does not hide, and SSS surfaces reflect the light in mirror with the
//! Fresnel reflectance of their η. Under CI=true a missing adapter fails.

use glam::{Vec3, Vec4Swizzles};
use gpu::{AlbedoMode, Camera, Light, MAX_MATERIALS, Mesh, RenderParams, Scatter, Scene, render};
use shading::Shading;

mod common;
use common::gpu;

const W: u32 = 256;
const H: u32 = 192;

/// The pixel a world point projects to.
fn pixel(scene: &Scene, p: Vec3) -> usize {
    let vp = scene.camera.projection(W as f32 / H as f32, 1.0, 500.0) * scene.camera.view();
    let c = vp * p.extend(1.0);
    let ndc = c.xyz() / c.w;
    let (x, y) = (
        ((ndc.x * 0.5 + 0.5) * W as f32) as usize,
        ((0.5 - ndc.y * 0.5) * H as f32) as usize,
    );
    y * W as usize + x
}

fn params(eta: f32) -> RenderParams {
    RenderParams {
        width: W,
        height: H,
        albedo: AlbedoMode::Post,
        shading: [Shading {
            eta,
            ..Shading::default()
        }; MAX_MATERIALS],
        ..RenderParams::default()
    }
}

/// The ray through pixel `i`'s centre: origin and unit direction.
fn pixel_ray(scene: &Scene, i: usize) -> (Vec3, Vec3) {
    let vp = scene.camera.projection(W as f32 / H as f32, 1.0, 500.0) * scene.camera.view();
    let (x, y) = ((i % W as usize) as f32 + 0.5, (i / W as usize) as f32 + 0.5);
    let ndc = glam::Vec2::new(2.0 * x / W as f32 - 1.0, 1.0 - 2.0 * y / H as f32);
    let far = vp.inverse() * ndc.extend(1.0).extend(1.0);
    let o = scene.camera.position;
    (o, (far.xyz() / far.w - o).normalize())
}

/// The point of the sphere (centre c, radius r) that pixel `i`'s centre sees.
fn seen_on_sphere(scene: &Scene, i: usize, c: Vec3, r: f32) -> Vec3 {
    let (o, d) = pixel_ray(scene, i);
    let b = d.dot(o - c);
    let t = -b - (b * b - (o - c).length_squared() + r * r).sqrt();
    o + t * d
}

/// The sphere (centre (0, 5, 0), radius 5) on a floor, under a 12 cm square light.
fn sphere_under_square() -> Scene {
    let mut mesh = Mesh::sphere(Vec3::new(0.0, 5.0, 0.0), 5.0, [1.0; 3], 1.0);
    mesh.append(&Mesh::plane(0.0, 60.0, [1.0; 3]));
    Scene {
        mesh,
        camera: Camera {
            position: Vec3::new(0.0, 16.0, 30.0),
            target: Vec3::new(2.0, 3.0, 0.0),
            fov_y_deg: 40.0,
        },
        lights: vec![
            Light::square(
                Vec3::new(-10.0, 18.0, -8.0),
                Vec3::new(0.0, 5.0, 0.0),
                12.0,
                Vec3::splat(2.0),
                true,
            )
            .unwrap(),
        ],
        ambient: Vec3::ZERO,
        specular: 0.0,
        shininess: 1.0,
    }
}

/// Does the segment from `a` to `b` pass through the sphere (centre c, radius r), and how far
/// (in cm) is it from grazing it?
fn hidden(a: Vec3, b: Vec3, c: Vec3, r: f32) -> (bool, f32) {
    let d = b - a;
    let t = ((c - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    let miss = (a + t * d - c).length() - r;
    (miss < 0.0, miss.abs())
}

#[test]
fn an_area_light_lights_as_its_cells_sum_and_its_penumbra_counts_the_cells_seen() {
    let Some(gpu) = gpu() else { return };
    let scene = sphere_under_square();
    let frame = render(&gpu, &scene, Scatter::None, &params(1.0)).unwrap();
    let cells = scene.lights[0].emitters();
    let centre = Vec3::new(0.0, 5.0, 0.0);
    // Lit points of the sphere: the unshadowed sum of the cells.
    for dir in [
        Vec3::new(-0.4, 0.9, 0.1),
        Vec3::new(-0.2, 0.95, 0.25),
        Vec3::new(-0.6, 0.75, 0.25),
    ] {
        // The point the pixel's centre sees.
        let i = pixel(&scene, centre + 5.0 * dir.normalize());
        let p = seen_on_sphere(&scene, i, centre, 5.0);
        let n = (p - centre) / 5.0;
        let want: f32 = cells.iter().map(|e| e.irradiance(p, n).x).sum();
        let got = frame.irradiance[i][0];
        assert!(
            (got - want).abs() < 0.02 * want,
            "sphere at n = {n}: {got} vs the cells' sum {want}"
        );
    }
    // Floor points in the sphere's penumbra: the sum over the cells whose ray the sphere does
    // not cross. Rays that graze it closer than 0.15 cm (the shadow maps' filter) may go either
    // way: the image must lie between the sums without and with them, and points where they
    // carry over a tenth of the light are skipped.
    let mut checked = 0;
    for k in 0..960 {
        let p = Vec3::new(2.0 + 0.05 * (k % 240) as f32, 0.0, 3.1 + (k / 240) as f32);
        let (mut seen, mut grazing, mut hidden_cells) = (0.0f32, 0.0f32, 0);
        for e in &cells {
            let (h, margin) = hidden(p, e.pos_or_dir.truncate(), centre, 5.0);
            let light = e.irradiance(p, Vec3::Y).x;
            if margin < 0.15 {
                grazing += light;
            } else if h {
                hidden_cells += 1;
            } else {
                seen += light;
            }
        }
        if seen == 0.0 || hidden_cells == 0 || grazing > 0.1 * (seen + grazing) {
            continue;
        }
        let got = frame.irradiance[pixel(&scene, p)][0];
        assert!(
            got >= 0.98 * seen && got <= 1.02 * (seen + grazing),
            "floor at {p}: {got} outside [{seen}, {}] (the cells seen, and with the grazing ones)",
            seen + grazing
        );
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} penumbra points checked");
}

/// A black SSS slab (top face y = 0) under a 6 × 10 cm light facing it, seen from the light's
/// mirror image: where the mirror ray of a pixel's point meets the light, the image is
/// π × F(η, θ) × L at that point's view angle θ, elsewhere 0; probed at the light's centre and
/// at 0.8 and 1.2 half-edges from it along both edges; 0 everywhere at η = 1.
#[test]
fn sss_surfaces_reflect_an_area_light_with_the_fresnel_reflectance() {
    let Some(gpu) = gpu() else { return };
    let radiance = 3.0;
    let (c, u, v) = (
        Vec3::new(0.0, 20.0, -20.0),
        3.0 * Vec3::X,
        5.0 * Vec3::new(0.0, 1.0, 1.0).normalize(),
    );
    let normal = u.cross(v).normalize();
    let scene = Scene {
        mesh: Mesh::cuboid(
            Vec3::new(-30.0, -2.0, -30.0),
            Vec3::new(30.0, 0.0, 30.0),
            [0.0; 3],
            1.0,
        ),
        camera: Camera {
            position: Vec3::new(0.0, 20.0, 20.0),
            target: Vec3::ZERO,
            fov_y_deg: 30.0,
        },
        lights: vec![Light::Area {
            center: c,
            half_u: u,
            half_v: v,
            radiance: Vec3::splat(radiance),
            shadow: true,
        }],
        ambient: Vec3::ZERO,
        specular: 0.0,
        shininess: 1.0,
    };
    assert!(normal.dot(-c) > 0.0, "the light faces the slab");
    let eta = 1.5;
    let frame = render(&gpu, &scene, Scatter::None, &params(eta)).unwrap();
    let matched = render(&gpu, &scene, Scatter::None, &params(1.0)).unwrap();
    let mirrored_camera = scene.camera.position * Vec3::new(1.0, -1.0, 1.0);
    let mut inside = 0;
    for (a, b) in [
        (0.0, 0.0),
        (0.8, 0.0),
        (-0.8, 0.0),
        (1.2, 0.0),
        (-1.2, 0.0),
        (0.0, 0.8),
        (0.0, -0.8),
        (0.0, 1.2),
        (0.0, -1.2),
    ] {
        // The slab point whose mirror ray meets the light at c + a·u + b·v, then what the
        // pixel's centre sees and where its mirror ray meets the light's plane.
        let q = c + a * u + b * v;
        let x = mirrored_camera
            + (q - mirrored_camera) * (-mirrored_camera.y / (q - mirrored_camera).y);
        let i = pixel(&scene, x);
        let (o, d) = pixel_ray(&scene, i);
        let x = o + d * (-o.y / d.y);
        let r = d * Vec3::new(1.0, -1.0, 1.0);
        let hit = x + r * ((c - x).dot(normal) / r.dot(normal)) - c;
        let seen = hit.dot(u).abs() <= u.length_squared() && hit.dot(v).abs() <= v.length_squared();
        let cos = -d.y as f64;
        let want = if seen {
            inside += 1;
            std::f64::consts::PI * shading::fresnel(eta as f64, cos) * radiance as f64
        } else {
            0.0
        };
        for (ch, got) in frame.linear[i][..3].iter().enumerate() {
            assert!(
                (*got as f64 - want).abs() <= 0.01 * want,
                "at {a}·u + {b}·v, channel {ch}: {got} vs π·F·L = {want}"
            );
        }
        assert_eq!(matched.linear[i][0], 0.0, "η = 1 mirrors nothing");
    }
    assert_eq!(
        inside, 5,
        "the probes at 0.8 half-edges and the centre hit the light"
    );
}

/// The methods that gather over the lit surface draw an area light as points in the slots the
/// other lights leave ([`gpu::DISC_LIGHTS`] in all): with one area light the directional dipole
/// renders it; with every slot taken by point lights the area light is refused, naming `lights`.
#[test]
fn the_directional_dipole_takes_an_area_light_in_the_slots_left() {
    let Some(gpu) = gpu() else { return };
    let mut setup = gpu::DipoleSetup::new(
        &[fit::analytic::Medium {
            sigma_a: 0.5,
            sigma_s: 20.0,
            g: 0.0,
            eta: 1.3,
        }; 3],
    )
    .unwrap();
    setup.sampling.frames = 2;
    setup.sampling.map_size = 256;
    let mut scene = sphere_under_square();
    let frame = render(
        &gpu,
        &scene,
        Scatter::DirectionalDipole(&setup),
        &params(1.0),
    )
    .unwrap();
    let lit = frame.scattered.iter().filter(|v| v[0] > 0.0).count();
    assert!(lit > 1000, "{lit} pixels scatter light");
    scene.lights.extend(std::iter::repeat_n(
        Light::Point {
            position: Vec3::new(0.0, 20.0, 0.0),
            intensity: Vec3::ONE,
            shadow: true,
        },
        gpu::DISC_LIGHTS,
    ));
    let err = render(
        &gpu,
        &scene,
        Scatter::DirectionalDipole(&setup),
        &params(1.0),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("lights"), "{err}");
}
