//! The shape table in the scene pass (issue 47). Curved bodies: the light entering an SSS
//! surface is multiplied by E per channel at the curvature its vertices were baked with
//! (`Mesh::bake_shape_curvature`: on a sphere 1/R at any scale), and by 1 where nothing was
//! baked. Thin bodies: where a material has a shape table, the light
//! entering an SSS surface is multiplied by what a slab as thin as the body's chord along the
//! light keeps of a half-space's light, relative to what the sphere of the surface's curvature
//! keeps (`shading::ShapeTable::thin_factor`); the chord comes from each light's back map (the
//! next surface behind its shadow map's first, by depth peeling). On a slab t thick lit at θ
//! the chord is t/cos θ, so the factor is E_slab(t, θ); on a sphere the chord is 2R·cos θ and the
//! curvature 1/R, so it is 1: E(κ) already holds what leaves through the sphere's far side; and
//! so on a cylinder of radius r lit across its axis, whose chord is 2r·cos θ and whose normal
//! curvature in the plane of the light is 1/r (its mean curvature, 1/(2r), would read it as a
//! sphere twice as thick).
//! Under CI=true a missing adapter fails.

use glam::Vec3;
use gpu::{
    AlbedoMode, Camera, Light, MAX_MATERIALS, Mesh, RenderParams, Scatter, Scene, Vertex, render,
};
use shading::{SHAPE_THICKNESSES, Shading, ShapeTable};

mod common;
use common::gpu;

const SIZE: u32 = 32;

/// σ_tr [cm⁻¹] per channel: a 10 cm chord is τ = 1, 1.5 and 2.5, inside the slabs' nodes.
const SIGMA_TR: [f64; 3] = [0.1, 0.15, 0.25];

/// A shape table that changes nothing for curved bodies (E = 1) and whose slabs keep
/// 1 − 0.4·(0.25/τ)^½ of a half-space's light (less the thinner, 0.6 at the first node), 2 %
/// less per 10° of entry angle.
fn table() -> ShapeTable {
    let mut t = ShapeTable::ones(SIGMA_TR);
    for (i, row) in t.thickness.iter_mut().enumerate() {
        for (k, entries) in row.iter_mut().enumerate() {
            for e in entries.iter_mut() {
                let tau = SHAPE_THICKNESSES[i] as f64;
                e.energy.value = (1.0 - 0.4 * (0.25 / tau).sqrt()) * (1.0 - 0.02 * k as f64);
            }
        }
    }
    t
}

fn params(shape: Option<ShapeTable>) -> RenderParams {
    RenderParams {
        width: SIZE,
        height: SIZE,
        albedo: AlbedoMode::Post,
        shading: [Shading {
            shape,
            ..Shading::default()
        }; MAX_MATERIALS],
        ..RenderParams::default()
    }
}

fn centre(frame: &gpu::Frame) -> [f32; 4] {
    let s = SIZE as usize;
    frame.irradiance[(s / 2) * s + s / 2]
}

/// The slab y ∈ [−thickness, 0], seen from above, lit from above at 30° with an irradiance of 2.
fn slab(thickness: f32) -> Scene {
    let towards = Vec3::new(30f32.to_radians().sin(), 30f32.to_radians().cos(), 0.0);
    let mut s = common::slab_scene(thickness, 100.0, towards);
    s.lights = vec![Light::Directional {
        towards,
        irradiance: Vec3::splat(2.0),
        shadow: true,
    }];
    s
}

#[test]
fn a_thin_slab_keeps_what_the_slab_table_says() {
    let Some(gpu) = gpu() else { return };
    let t = table();
    let cos = 30f32.to_radians().cos();
    // Below the first node (τ < 0.25 in every channel), across the nodes, and beyond the last
    // in blue (τ = 4.5 > 4: a half-space, 1). (The ray through the centre leaves by the bottom
    // face: 18·tan 30° < 20 cm.)
    for thickness in [0.5f32, 3.0, 8.0, 18.0] {
        let frame = render(&gpu, &slab(thickness), Scatter::None, &params(Some(t))).unwrap();
        let got = centre(&frame);
        let want = t.slab_at(thickness, cos).energy.map(|e| 2.0 * cos * e);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 0.005 * want[c],
                "t = {thickness} cm, channel {c}: {} against {}",
                got[c],
                want[c]
            );
        }
        assert!(
            want[0] < 0.99 * 2.0 * cos,
            "the slab keeps less than a half-space"
        );
    }
    // Without the shape table: the lit face's plain irradiance.
    let frame = render(&gpu, &slab(0.5), Scatter::None, &params(None)).unwrap();
    for c in 0..3 {
        assert!((centre(&frame)[c] - 2.0 * cos).abs() < 1e-4, "channel {c}");
    }
}

/// `mesh` around the origin seen along +z from 100 cm (1° field: its centre fills the frame),
/// under a directional light of irradiance 1 from `towards`.
fn seen_along_z(mesh: Mesh, towards: Vec3) -> Scene {
    Scene {
        mesh,
        camera: Camera {
            position: Vec3::new(0.0, 0.0, 100.0),
            target: Vec3::ZERO,
            fov_y_deg: 1.0,
        },
        lights: vec![Light::Directional {
            towards,
            irradiance: Vec3::ONE,
            shadow: true,
        }],
        ambient: Vec3::ZERO,
        specular: 0.0,
        shininess: 1.0,
    }
}

/// A sphere of radius `radius` [cm] seen and lit along +z (irradiance 1).
fn sphere(radius: f32) -> Scene {
    seen_along_z(Mesh::sphere(Vec3::ZERO, radius, [1.0; 3], 1.0), Vec3::Z)
}

#[test]
fn a_sphere_keeps_its_light_and_a_plate_as_thick_does_not() {
    let Some(gpu) = gpu() else { return };
    let t = table();
    // The sphere's chord along the light at its centre is its diameter, 10 cm: as a slab that
    // would keep 1 − 0.4·(0.25/τ)^½, τ = 1 … 2.5 (0.80 … 0.87); as a sphere of its own
    // curvature, all of E(κ) (here 1).
    let frame = render(&gpu, &sphere(5.0), Scatter::None, &params(Some(t))).unwrap();
    for (c, got) in centre(&frame)[..3].iter().enumerate() {
        assert!((got - 1.0).abs() < 0.02, "channel {c}: {got}");
    }
    // A plate 10 cm thick lit along its normal keeps what the slab table says, well below 1.
    let plate = common::slab_scene(10.0, 100.0, Vec3::Y);
    let frame = render(&gpu, &plate, Scatter::None, &params(Some(t))).unwrap();
    let keeps = t.slab_at(10.0, 1.0).energy;
    for (c, (got, want)) in centre(&frame).iter().zip(keeps).enumerate() {
        assert!(want < 0.9, "channel {c}: {want}");
        assert!(
            (got - want).abs() < 0.005 * want,
            "channel {c}: {got} against {want}"
        );
    }
}

/// A cylinder of radius `radius` [cm] along y (from −50 to 50 cm, open ends), seen along +z and
/// lit from `towards` (irradiance 1), a direction across its axis.
fn cylinder(radius: f32, towards: Vec3) -> Scene {
    let segments = 256u32;
    let mut mesh = Mesh::default();
    for j in 0..=segments {
        let phi = std::f32::consts::TAU * j as f32 / segments as f32;
        let n = Vec3::new(phi.cos(), 0.0, phi.sin());
        for y in [-50.0f32, 50.0] {
            mesh.vertices.push(Vertex {
                pos: (radius * n + Vec3::Y * y).into(),
                normal: n.into(),
                albedo: [1.0; 3],
                strength: 1.0,
                material: 0,
                curvature: [0.0; 3],
            });
        }
    }
    for j in 0..segments {
        let (a, b) = (2 * j, 2 * j + 2);
        mesh.indices.extend([a, a + 1, b, a + 1, b + 1, b]);
    }
    seen_along_z(mesh, towards)
}

#[test]
fn a_cylinder_lit_across_its_axis_keeps_its_light() {
    let Some(gpu) = gpu() else { return };
    let t = table();
    // Head-on (the chord 10 cm = 2r along the normal) and at 40° across the axis (2r·cos 40°):
    // as a slab of that chord's thickness it would keep 0.80 … 0.87 head-on.
    for deg in [0f32, 40.0] {
        let towards = Vec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        let frame = render(
            &gpu,
            &cylinder(5.0, towards),
            Scatter::None,
            &params(Some(t)),
        )
        .unwrap();
        let lambert = deg.to_radians().cos();
        for (c, got) in centre(&frame)[..3].iter().enumerate() {
            assert!(
                (got / lambert - 1.0).abs() < 0.02,
                "{deg}°, channel {c}: {} of the plain irradiance",
                got / lambert
            );
        }
    }
}

/// A shape table whose curved bodies return E = 1 + (c + 1)·κ/8 in channel c (κ = 1/(σ_tr·R), at
/// every angle, between the nodes exactly as linear interpolation reads it) and whose
/// half-space's exits lie 0.3 cm from the entry on average.
fn curved_table() -> ShapeTable {
    let mut t = ShapeTable::ones(SIGMA_TR);
    for (i, row) in t.curvature.iter_mut().enumerate() {
        for entries in row.iter_mut() {
            for (c, e) in entries.iter_mut().enumerate() {
                e.energy.value = 1.0 + (c + 1) as f64 * shading::SHAPE_CURVATURES[i] as f64 / 8.0;
                e.width_cm.value = 0.3;
            }
        }
    }
    t
}

#[test]
fn a_sphere_reads_e_at_its_baked_curvature() {
    let Some(gpu) = gpu() else { return };
    let t = curved_table();
    let p = params(Some(t));
    // A 2 cm sphere: κ = 1/(σ_tr·2 cm) = 5, 3.3 and 2 per channel, at or beyond the last node
    // (2): E = 1.25, 1.5 and 1.75. A 20 cm one: κ = 0.5, 0.33, 0.2: E = 1.06, 1.08, 1.08.
    for radius in [2.0f32, 20.0] {
        let mut scene = sphere(radius);
        let unbaked = render(&gpu, &scene, Scatter::None, &p).unwrap();
        scene.mesh.bake_shape_curvature(&p.shading).unwrap();
        let baked = render(&gpu, &scene, Scatter::None, &p).unwrap();
        let want = t.at(1.0 / radius, 1.0).energy;
        for (c, &want) in want.iter().enumerate() {
            // The sphere's chord keeps all (thin factor 1, as above) within 2 %.
            let (got, plain) = (centre(&baked)[c], centre(&unbaked)[c]);
            assert!(
                (got / plain - want).abs() < 0.005 * want,
                "R = {radius} cm, channel {c}: {} against E = {want}",
                got / plain
            );
            assert!(want > 1.05, "the table reads E > 1 here");
            assert!((plain - 1.0).abs() < 0.02, "unbaked: E(0) = 1, {plain}");
        }
    }
    // Each channel reads E at its own curvature: 0.05, 0.1 and −0.2 cm⁻¹ set on every vertex
    // (κ = 0.5, 0.67 and −0.8: E = 1.06, 1.17, 0.7).
    let mut scene = sphere(20.0);
    let plain = render(&gpu, &scene, Scatter::None, &p).unwrap();
    let curvature = [0.05f32, 0.1, -0.2];
    for v in &mut scene.mesh.vertices {
        v.curvature = curvature;
    }
    let set = render(&gpu, &scene, Scatter::None, &p).unwrap();
    for (c, &k) in curvature.iter().enumerate() {
        let want = t.at(k, 1.0).energy[c];
        let got = centre(&set)[c] / centre(&plain)[c];
        assert!(
            (got - want).abs() < 0.005 * want,
            "channel {c} at {k} cm⁻¹: {got} against E = {want}"
        );
    }
}
