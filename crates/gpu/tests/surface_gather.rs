//! The Monte Carlo BSSRDF gathered over the lit surface (`gpu::surface_gather`), radial and
//! directional, from physics:
//! - a thick flat slab (a half-space for Skin1) lit by a distant light at θ = 0° and 60°: the
//!   gather returns E·cos θ·h(0)·Rd(θ), Rd(θ) `mc`'s total diffuse reflectance at that incidence,
//!   within its standard error and what lies beyond the tables;
//! - a 2 mm slab lit from behind: the GPU equals a CPU quadrature of the same estimator over
//!   the disc (the light enters the far face, the camera sees the near one);
//! - the image's error to its own converged limit falls as 1/√frames;
//! - with the control variate a flat, evenly lit half-space has no pixel noise in one frame
//!   (the radial response is the control's shape exactly);
//! - the directional table lies on the plane through both points (Frisvad et al.'s modified
//!   tangent plane: between two points of a sphere, the bisector plane);
//! - the shape-aware gather is the directional one on a plane (the chord's curvature is 0) and
//!   brighter on a sphere by the energy E(1/R) that `mc` returns from a sphere.
//!
//! Under CI=true a missing adapter fails.

use glam::Vec3;
use gpu::{RenderParams, Scatter, SurfaceGatherSetup, render};
use shading::Bssrdf;
use std::f64::consts::PI;

mod common;
use common::{
    EdgeView, centre_mean, centre_values, gpu, profile, setup, shadow_edge_scene, skin1,
    slab_scene, spec,
};

const SIZE: u32 = 48;
const PHOTONS: u64 = 100_000;

fn setups() -> (SurfaceGatherSetup, SurfaceGatherSetup) {
    let (s, p) = (spec(PHOTONS, 7), profile());
    let radial = setup(&s, &p, Bssrdf::Radial);
    let directional = setup(&s, &p, Bssrdf::Directional);
    (radial, directional)
}

fn params() -> RenderParams {
    RenderParams {
        width: SIZE,
        height: SIZE,
        ..RenderParams::default()
    }
}

fn towards(theta_deg: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin(), t.cos(), 0.0)
}

#[test]
fn a_lit_half_space_returns_mcs_reflectance_at_that_incidence() {
    let (mut radial, mut directional) = setups();
    // What the tables hold against mc's totals: the directional table at index 6 is 60°.
    let d = directional.directional.as_ref().unwrap();
    let (profile_total, table0, table60) = (radial.profile_total(), d.integral(0), d.integral(6));
    // The profile total's standard error: each photon scores one annulus once, so the bins'
    // errors add in quadrature (their small negative covariance only lowers it).
    let p = profile();
    let profile_se: [f64; 3] = std::array::from_fn(|c| {
        (p.se[c].iter().enumerate())
            .map(|(i, se)| (se * std::f64::consts::PI * p.dr * p.dr * (2 * i + 1) as f64).powi(2))
            .sum::<f64>()
            .sqrt()
    });
    let (rd0, rd60) = (d.totals[0], d.totals[6]);
    let Some(gpu) = gpu() else { return };
    for s in [&mut radial, &mut directional] {
        s.sampling.samples = 32;
        s.sampling.frames = 8;
        s.sampling.map_size = 2048;
    }
    for (theta, k) in [(0.0f32, 0usize), (60.0, 6)] {
        let scene = slab_scene(4.0, 200.0, towards(theta));
        let cos = (theta as f64).to_radians().cos();
        for (name, setup) in [("radial", &radial), ("directional", &directional)] {
            let frame = render(&gpu, &scene, Scatter::SurfaceGather(setup), &params()).unwrap();
            let got = centre_mean(&frame, SIZE);
            for c in 0..3 {
                // Seen along the normal, light that entered at θ: h(0°; θ).
                let h0 = setup.angles.exit[k][0][c] as f64;
                let per_e = got[c] / (cos * h0);
                // The estimator's own expectation; what lies beyond the tables at 0° (the
                // directional table against its own run's total: the same photons, so the
                // difference is light outside the table, not noise; the profile reaches 32
                // mean free paths, beyond which nothing measurable is left); and the
                // expectation's own relative standard error (the profile's run is independent
                // of mc's totals).
                let (own, beyond, own_se) = match name {
                    "radial" => {
                        let ratio = setup.angles.incidence[k][c] as f64;
                        (
                            ratio * profile_total[c],
                            0.0,
                            profile_se[c] / profile_total[c],
                        )
                    }
                    _ => {
                        let t = if k == 0 { table0 } else { table60 };
                        (t[c], 1.0 - table0[c] / rd0[c].value, 0.0)
                    }
                };
                let mc = if k == 0 { rd0[c] } else { rd60[c] };
                eprintln!(
                    "{name} θ = {theta}° channel {c}: gather {per_e:.5}, its expectation {own:.5}, mc Rd(θ) {:.5} ± {:.5} (beyond the tables {:.2} %)",
                    mc.value,
                    mc.se,
                    100.0 * beyond
                );
                assert!(
                    (per_e / own - 1.0).abs() < 0.02,
                    "{name} {theta}° channel {c}: {per_e} vs {own}"
                );
                // The tables reach far enough to hold all but 1 % of mc's light (a bound of its
                // own: a table that loses light fails here rather than widening the tolerance),
                // and never more than all of it (10⁻⁴: the table's f32 sums).
                assert!(
                    (-1e-4..0.01).contains(&beyond),
                    "{name} channel {c}: {:.2} % of mc's Rd at 0° lies beyond the tables",
                    100.0 * beyond
                );
                // Against mc at that incidence: 3 standard errors of each independent run
                // involved (the radial incidence ratio's runs are independent of the
                // directional tables', the profile's of both), the GPU's 2 %, the 1 % beyond the
                // tables and ±1 % for its change with θ.
                let se = 3.0
                    * (mc.se / mc.value)
                        .hypot(rd0[c].se / rd0[c].value)
                        .hypot(own_se);
                let tol = se + 0.02 + 0.01 + 0.01;
                assert!(
                    (per_e / mc.value - 1.0).abs() < tol,
                    "{name} {theta}° channel {c}: {per_e} vs mc {} (tolerance {tol})",
                    mc.value
                );
            }
        }
    }
}

/// π·L_o of the same estimator by quadrature over the disc of the setup's radius around
/// x_o = (0, −d, 0) (normal −y, the camera below), the light entering the top face y = 0 from
/// `towards`: h(0)·∫ E⊥·response(x_i(p)) dA⊥.
fn quadrature(setup: &SurfaceGatherSetup, towards: Vec3, thickness: f64) -> [f64; 3] {
    let l = towards.as_dvec3().normalize();
    let t1 = l.cross(glam::DVec3::Z).normalize();
    let t2 = l.cross(t1);
    let xo = glam::DVec3::new(0.0, -thickness, 0.0);
    let r_max = setup.sampling.radius_cm as f64;
    let (nr, nphi) = (4000, 128);
    let cos_i = l.y;
    let mut out = [0.0; 3];
    for i in 0..nr {
        let (a, b) = (
            (i as f64 / nr as f64).powi(2),
            ((i + 1) as f64 / nr as f64).powi(2),
        );
        let (r, dr) = (0.5 * (a + b) * r_max, (b - a) * r_max);
        for j in 0..nphi {
            let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * PI;
            let p = xo + r * (phi.cos() * t1 + phi.sin() * t2);
            let xi = p + l * ((0.0 - p.y) / l.y);
            let d = xo - xi;
            let response = match &setup.directional {
                None => setup.radial_response(d.length(), cos_i),
                Some(t) => t.response(d, glam::DVec3::Y, l, [glam::DVec3::ZERO; 3]),
            };
            for c in 0..3 {
                out[c] += response[c] * r * dr * 2.0 * PI / nphi as f64;
            }
        }
    }
    // Seen along the normal, light that entered at θ_i: h(0°; θ_i).
    let h = shading::exit_ratio(&setup.angles.exit, 1.0, cos_i as f32);
    std::array::from_fn(|c| out[c] * h[c] as f64)
}

#[test]
fn light_through_a_thin_slab_matches_the_quadrature() {
    let (mut radial, mut directional) = setups();
    let Some(gpu) = gpu() else { return };
    let thickness = 0.2;
    let dir = towards(45.0);
    let scene = slab_scene(thickness as f32, -200.0, dir);
    for (name, setup) in [("radial", &mut radial), ("directional", &mut directional)] {
        setup.sampling.samples = 32;
        setup.sampling.frames = 8;
        setup.sampling.map_size = 2048;
        let frame = render(&gpu, &scene, Scatter::SurfaceGather(setup), &params()).unwrap();
        let got = centre_mean(&frame, SIZE);
        let want = quadrature(setup, dir, thickness);
        eprintln!("{name} back-lit: GPU {got:.5?}, quadrature {want:.5?}");
        for c in 0..3 {
            assert!(want[c] > 0.0);
            assert!(
                (got[c] / want[c] - 1.0).abs() < 0.03,
                "{name} channel {c}: GPU {} vs quadrature {}",
                got[c],
                want[c]
            );
        }
    }
}

/// RMS over the pixels of the green channel's difference between two images.
fn rms(a: &gpu::Frame, b: &gpu::Frame) -> f64 {
    let n = a.scattered.len() as f64;
    (a.scattered
        .iter()
        .zip(&b.scattered)
        .map(|(x, y)| (x[1] as f64 - y[1] as f64).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

/// Frames are independent estimates with one variance σ² per pixel, so the mean of f frames is
/// off its limit by σ/√f. Against a reference of F = 64 frames of another seed the measured RMS
/// is σ·√(1/f + 1/F): 1 frame against 16 must be √((1 + 1/64)/(1/16 + 1/64)) = 3.61× noisier.
#[test]
fn the_error_to_the_limit_falls_as_one_over_root_frames() {
    let (mut radial, _) = setups();
    let Some(gpu) = gpu() else { return };
    // A curved body: on a flat, evenly lit slab the control variate leaves no noise to measure
    // (the next test).
    let scene = gpu::Scene::sphere();
    radial.sampling.samples = 4;
    radial.sampling.map_size = 1024;
    let with = |frames: u32, seed: u32| {
        let mut s = radial.clone();
        s.sampling.frames = frames;
        s.sampling.seed = seed;
        render(&gpu, &scene, Scatter::SurfaceGather(&s), &params()).unwrap()
    };
    let reference = with(64, 2);
    let (one, sixteen) = (with(1, 1), with(16, 1));
    let ratio = rms(&one, &reference) / rms(&sixteen, &reference);
    let want = ((1.0f64 + 1.0 / 64.0) / (1.0 / 16.0 + 1.0 / 64.0)).sqrt();
    eprintln!("RMS error ratio 1 frame / 16 frames: {ratio:.3} (1/√frames: {want:.3})");
    assert!((ratio / want - 1.0).abs() < 0.15, "{ratio} vs {want}");
}

/// The control variate: on a flat half-space evenly lit, the response at each sample is the
/// control's own shape times the flat answer (the profile at the 3-D distance on the plane,
/// which is the distance on x_o's tangent plane; the directional table at the light's angle to
/// that plane), so every pixel of one frame of 4 samples holds E·cos θ·Rd(θ)·h exactly, up to
/// the rounding of positions (an f32 distance on the far side of a bin's or cell's edge: ≤ 1.5 %
/// in Skin1's blue, whose cells are smallest). Without it the same frame's pixels scatter by
/// 20–56 % of their mean.
#[test]
fn a_flat_evenly_lit_half_space_is_gathered_without_noise() {
    let (mut radial, mut directional) = setups();
    let Some(gpu) = gpu() else { return };
    for s in [&mut radial, &mut directional] {
        s.sampling.samples = 4;
        s.sampling.frames = 1;
    }
    for (theta, k) in [(0.0f32, 0usize), (60.0, 6)] {
        let scene = slab_scene(4.0, 200.0, towards(theta));
        let cos = (theta as f64).to_radians().cos();
        for (name, setup) in [("radial", &radial), ("directional", &directional)] {
            let frame = render(&gpu, &scene, Scatter::SurfaceGather(setup), &params()).unwrap();
            for c in 0..3 {
                let v = centre_values(&frame, SIZE, c);
                let mean = v.iter().sum::<f64>() / v.len() as f64;
                let sd =
                    (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt();
                let h0 = setup.angles.exit[k][0][c] as f64;
                let expected = match name {
                    "radial" => setup.angles.incidence[k][c] as f64 * setup.profile_total()[c],
                    _ => setup.directional.as_ref().unwrap().totals[k][c].value,
                } * cos
                    * h0;
                eprintln!(
                    "{name} θ = {theta}° channel {c}: pixel noise {:.2e} of the mean; mean / E·cos θ·Rd(θ)·h {:.6}",
                    sd / mean,
                    mean / expected
                );
                assert!(
                    sd / mean < 0.02,
                    "{name} {theta}° channel {c}: noise {}",
                    sd / mean
                );
            }
        }
    }
}

/// The radial and directional setups of Skin1 at η = 1 for the shadow-edge tests, sampled
/// densely (16 samples × 16 frames, 8192² light maps).
fn edge_setups() -> (SurfaceGatherSetup, SurfaceGatherSetup) {
    let material = shading::Material {
        eta: 1.0,
        ..skin1()
    };
    let config = shading::SimConfig::thesis().unwrap();
    let s = config.batch(&[&material], PHOTONS, 7, true).unwrap();
    let p = shading::profile::simulate(
        &config.batch(&[&material], 4 * PHOTONS, 101, true).unwrap(),
        "mc",
        &|_| {},
    )
    .unwrap()
    .profile;
    let mut radial = setup(&s, &p, Bssrdf::Radial);
    let mut directional = setup(&s, &p, Bssrdf::Directional);
    for s in [&mut radial, &mut directional] {
        s.sampling.samples = 16;
        s.sampling.frames = 16;
        s.sampling.map_size = 8192;
    }
    (radial, directional)
}

/// How far forward [cm] of lit exitance per channel the directional gather moves light across
/// the straight shadow edge of `scene` (light from −x at 60°, the edge at x = 0, its shadow on
/// the −x side) against the radial gather, seen as `view` says: ∫ (M_radial − M_directional) dx
/// over lit exitance. Each profile is taken over its own lit exitance: the two totals come from
/// different mc runs.
fn edge_moved(
    gpu: &gpu::Gpu,
    scene: &gpu::Scene,
    view: &EdgeView,
    (radial, directional): &(SurfaceGatherSetup, SurfaceGatherSetup),
) -> [f64; 3] {
    let params = RenderParams {
        width: view.size,
        height: view.size,
        ..RenderParams::default()
    };
    let rad = render(gpu, scene, Scatter::SurfaceGather(radial), &params).unwrap();
    let dir = render(gpu, scene, Scatter::SurfaceGather(directional), &params).unwrap();
    let w = view.size as usize;
    let line = |f: &gpu::Frame, i: usize, c: usize| view.line_mean(&f.scattered, i, c);
    // Which end of the image is lit: the brighter one in the radial image.
    let lit_first = line(&rad, 2, 0) > line(&rad, w - 3, 0);
    std::array::from_fn(|c| {
        let far = if lit_first { 2..10 } else { w - 10..w - 2 };
        let lit = |f: &gpu::Frame| far.clone().map(|i| line(f, i, c)).sum::<f64>() / 8.0;
        let (lit_rad, lit_dir) = (lit(&rad), lit(&dir));
        (0..w)
            .map(|i| line(&rad, i, c) / lit_rad - line(&dir, i, c) / lit_dir)
            .sum::<f64>()
            * view.px
    })
}

/// The orientation of the directional BSSRDF against `mc`'s physics: light entering at 60°
/// exits shifted forward along the light's tangential propagation, mc's Rd(x, y; 60°) having its
/// centroid δ ahead of the entry (as Wang & Jacques' far-field centre). Across a straight shadow
/// edge with the lit side ahead, an exitance profile across the edge is M·G(x − e), G the
/// distribution function of the exit offset's x, so the difference of two BSSRDFs' profiles
/// integrates to M·(mean_radial − mean_directional) = −M·δ over a window holding both tails,
/// wherever the edge e lies: the directional gather keeps δ·M per unit length of the edge out of
/// the lit region's border; a reversed table would add it. Seen from straight above, the view's
/// exit shift is 0.
#[test]
fn the_directional_bssrdf_carries_light_forward_across_a_shadow_edge() {
    let setups = edge_setups();
    // The centroid of mc's table at 60° (index 6) per channel [cm]: the mean of the exit
    // offset along the propagation, x.
    let delta = setups.1.directional.as_ref().unwrap().centroid_cm(6);
    let Some(gpu) = gpu() else { return };
    // Pixels of 1/64 cm: the blue exit distribution is about 0.1 cm wide.
    let size = 384u32;
    let view = EdgeView {
        size,
        px: 6.0 / size as f64,
        along_rows: false,
    };
    let moved = edge_moved(&gpu, &shadow_edge_scene(3.0), &view, &setups);
    for (c, (&measured, &shift)) in moved.iter().zip(&delta).enumerate() {
        eprintln!(
            "channel {c}: light the directional BSSRDF moves forward = {measured:.4} cm of lit exitance; mc's centroid at 60° {shift:.4} cm"
        );
        assert!(shift > 0.0, "mc's table is not shifted forward");
        assert!(
            (measured / shift - 1.0).abs() < 0.2,
            "channel {c}: {measured} vs {shift}"
        );
    }
}

/// The view's exit shift (reciprocity: light seen at θ_o last scattered δ(θ_o) further along the
/// view ray's propagation over the surface): the edge of the test above seen at θ_o = 45°
/// from far, from the side the light comes from and from the other, moves by δ(60°) − δ(45°)
/// and δ(60°) + δ(45°), the table's centroids; without the exit shift by δ(60°) from both.
#[test]
fn an_oblique_view_moves_the_gathers_shadow_edge_by_the_exit_angles_centroid_too() {
    let setups = edge_setups();
    let t = setups.1.directional.as_ref().unwrap();
    let entry = t.centroid_cm(6);
    // δ(45°), between the table's 40° and 50°, as the shader reads it (its CPU twin), pointing
    // away from the camera.
    let wo = glam::DVec3::new(0.5f64.sqrt(), 0.5f64.sqrt(), 0.0);
    let shift = t.exit_shift(glam::DVec3::Y, wo);
    let exit: [f64; 3] = std::array::from_fn(|c| {
        assert!(
            shift[c].x < 0.0 && shift[c].y.abs() < 1e-12,
            "{:?}",
            shift[c]
        );
        shift[c].length()
    });
    let Some(gpu) = gpu() else { return };
    let (size, distance, half_view) = (384u32, 400.0f32, 2.0f32);
    let theta_o = 45f32.to_radians();
    // The camera's up is y: rows run along x, each px/cos θ_o of it.
    let view = EdgeView {
        size,
        px: 2.0 * half_view as f64 / size as f64 / theta_o.cos() as f64,
        along_rows: true,
    };
    let mut failed = Vec::new();
    for side in [-1.0f32, 1.0] {
        let mut scene = shadow_edge_scene(half_view);
        scene.camera = gpu::Camera {
            position: distance * Vec3::new(side * theta_o.sin(), theta_o.cos(), 0.0),
            target: Vec3::ZERO,
            fov_y_deg: 2.0 * (half_view / distance).atan().to_degrees(),
        };
        let moved = edge_moved(&gpu, &scene, &view, &setups);
        for c in 0..3 {
            let want = entry[c] + side as f64 * exit[c];
            eprintln!(
                "camera on the {} side, channel {c}: moved {:.4} cm; δ(60°) ± δ(45°) = {want:.4} cm ({:.4} ± {:.4})",
                if side > 0.0 { "far" } else { "light's" },
                moved[c],
                entry[c],
                exit[c]
            );
            if (moved[c] - want).abs() >= 0.2 * (entry[c] + exit[c]) {
                failed.push(format!("side {side}, channel {c}: {} vs {want}", moved[c]));
            }
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}

/// A square area light 10 cm from a thick flat slab, 37° off its normal and turned 39° away from
/// the slab (its emission lobe matters, cos 39° = 0.78): the radial gather
/// (which draws the light as a few new points each frame) returns, per unit of the exit table,
/// the profile's total times the incidence ratio integrated over the light's irradiance,
/// ∫ ρ(θ)/ρ(0) dE, computed here from the light's points on a fine grid (`Light::point_on`,
/// whose mean is tested against Lambert's polygon formula), at five points of the image's
/// central region.
#[test]
fn an_area_light_gathers_as_its_irradiance_weighted_by_the_incidence_table() {
    let (s, p) = (spec(PHOTONS, 7), profile());
    let mut radial = setup(&s, &p, Bssrdf::Radial);
    let Some(gpu) = gpu() else { return };
    radial.sampling.samples = 32;
    radial.sampling.frames = 16;
    radial.sampling.map_size = 2048;
    let mut scene = slab_scene(4.0, 30.0, Vec3::Y);
    let light = gpu::Light::square(
        Vec3::new(6.0, 8.0, 0.0),
        Vec3::new(-10.0, 4.0, 0.0),
        6.0,
        Vec3::splat(0.1),
        true,
    )
    .unwrap();
    scene.lights = vec![light];
    let frame = render(&gpu, &scene, Scatter::SurfaceGather(&radial), &params()).unwrap();
    let got = centre_mean(&frame, SIZE);
    // The central 16 of 48 pixels span a third of the 2·30·tan 2° cm view.
    let half = (30.0f32 * 2f32.to_radians().tan()) / 3.0;
    let m = 128;
    let mut want = [0.0f64; 3];
    let mut plain = 0.0f64;
    for (x, z) in [
        (0.0, 0.0),
        (-half, -half),
        (half, -half),
        (-half, half),
        (half, half),
    ] {
        let at = Vec3::new(x, 0.0, z);
        for k in 0..m * m {
            let st = (
                ((k % m) as f32 + 0.5) / m as f32,
                ((k / m) as f32 + 0.5) / m as f32,
            );
            let e = light.point_on(st).unwrap();
            let de = e.irradiance(at, Vec3::Y).x as f64 / (5 * m * m) as f64;
            let cos = (e.pos_or_dir.truncate() - at).normalize().y;
            let ratio = shading::incidence_ratio(&radial.angles.incidence, cos);
            // Seen along the normal, light that entered at this point's angle: h(0°; θ_i).
            let h = shading::exit_ratio(&radial.angles.exit, 1.0, cos);
            for c in 0..3 {
                want[c] += de * (ratio[c] * h[c]) as f64;
            }
            plain += de;
        }
    }
    let total = radial.profile_total();
    for c in 0..3 {
        let expect = want[c] * total[c];
        eprintln!(
            "channel {c}: gather {:.5}, expected {expect:.5} (E = {plain:.5})",
            got[c]
        );
        assert!(
            (got[c] / expect - 1.0).abs() < 0.025,
            "channel {c}: {} vs {expect}",
            got[c]
        );
    }
}

/// The directional table lies on Frisvad et al.'s modified tangent plane, the plane through x_i
/// that holds x_o: for two points of a sphere it is the plane whose normal bisects theirs (the
/// chord is perpendicular to the bisector), and the amount is the true entry angle's. A distant
/// light straight above the point x_o enters x_i, 60° around the sphere, at 60°; the bisector
/// plane meets the light at 30°. So the response is the flat one on that plane (the table at
/// 30°) times Rd(60°)/Rd(30°); a rotation of the whole changes nothing. A synthetic table,
/// distinct per angle, channel and cell and uneven in x, so a wrong plane or direction shows.
#[test]
fn the_directional_table_lies_on_the_plane_through_both_points() {
    use glam::{DMat3, DVec3};
    use shading::DIRECTIONAL_ANGLES;
    let n = 8;
    let cells = DIRECTIONAL_ANGLES.len() * 3 * (n + 1) * (2 * n + 1);
    let rd = (0..cells)
        .map(|i| {
            let (ix, iy, kc) = (
                i % (2 * n + 1),
                i / (2 * n + 1) % (n + 1),
                i / ((2 * n + 1) * (n + 1)),
            );
            (1.0 + kc as f32) * (1.0 + 0.3 * ix as f32) / (1.0 + iy as f32)
        })
        .collect();
    let totals = (0..DIRECTIONAL_ANGLES.len())
        .map(|k| {
            [0, 1, 2].map(|c| shading::Estimate {
                value: 0.4 + 0.03 * k as f64 + 0.1 * c as f64,
                se: 0.0,
            })
        })
        .collect();
    let t = shading::DirectionalTable {
        half_width: n,
        cell_cm: [0.1, 0.12, 0.15],
        rd,
        totals,
    };
    // A chord of 0.5 cm, within every channel's table (8 cells of 0.1–0.15 cm).
    let radius = 0.5;
    let (ni, no, wi) = (
        DVec3::new(60f64.to_radians().sin(), 0.0, 60f64.to_radians().cos()),
        DVec3::Z,
        DVec3::Z,
    );
    let d = radius * (no - ni);
    let bisector = (ni + no).normalize();
    let got = t.response(d, ni, wi, [glam::DVec3::ZERO; 3]);
    let flat = t.response(d, bisector, wi, [glam::DVec3::ZERO; 3]);
    for c in 0..3 {
        let want = flat[c] * t.totals[6][c].value / t.totals[3][c].value;
        assert!(flat[c] > 0.0);
        assert!(
            (got[c] / want - 1.0).abs() < 1e-4,
            "channel {c}: {} against the bisector plane's {want}",
            got[c]
        );
    }
    // The same pair turned anywhere.
    let turn = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1);
    let turned = t.response(turn * d, turn * ni, turn * wi, [glam::DVec3::ZERO; 3]);
    for c in 0..3 {
        assert!(
            (turned[c] / got[c] - 1.0).abs() < 1e-4,
            "channel {c} turned"
        );
    }
    // Behind the table's reach from x_i, where the old plane (n_i's) would read it, nothing
    // changes sign: the response is finite and non-negative everywhere around the sphere.
    for k in 0..36 {
        let a = (10.0 * k as f64).to_radians();
        let xo = DVec3::new(a.sin(), 0.0, a.cos());
        let v = t.response(radius * (xo - ni), ni, wi, [glam::DVec3::ZERO; 3]);
        assert!(v.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
}

/// On a plane every chord's curvature is 0: the shape-aware gather is the directional one (E = 1,
/// w = 1) where the body is thick (a 4 cm slab: τ > 4 in every channel), and where it is thin
/// (a 1.5 mm slab lit at 30°, chord 1.5 mm/cos 30°) that times what a slab that thin keeps,
/// E_slab(0.15 cm, 30°) (the two share their samples, so the ratio is exact up to rounding).
/// On the sphere scene (R = 5 cm), light entering a sphere returns E(1/(σ_tr·R)) > 1 times
/// what a half-space returns (`mc` in spheres): the lit centre, where the light arriving around
/// it is nearly uniform over the spread, is brighter by E (the stretch w moves light, it adds
/// none), within 2 % (the two gathers share their samples; what remains is the light's fall-off
/// across the stretched spread).
#[test]
fn the_shape_aware_gather_is_the_directional_one_on_a_plane_and_brighter_on_a_sphere() {
    let (s, p) = (spec(30_000, 11), profile());
    let mut directional = setup(&s, &p, Bssrdf::Directional);
    let mut shape = setup(&s, &p, Bssrdf::Shape);
    let Some(gpu) = gpu() else { return };
    for x in [&mut directional, &mut shape] {
        x.sampling.samples = 32;
        x.sampling.frames = 8;
    }
    let plane = slab_scene(4.0, 200.0, towards(30.0));
    let sphere = gpu::Scene::sphere();
    let thin = slab_scene(0.15, 200.0, towards(30.0));
    let mut means = Vec::new();
    for scene in [&plane, &sphere, &thin] {
        let m: Vec<[f64; 3]> = [&directional, &shape]
            .map(|x| {
                let frame = render(&gpu, scene, Scatter::SurfaceGather(x), &params()).unwrap();
                centre_mean(&frame, SIZE)
            })
            .to_vec();
        means.push(m);
    }
    let table = shape.shape.as_ref().unwrap();
    let energy = table.at(1.0 / 5.0, 1.0).energy;
    let slab = table.slab_at(0.15, 30f32.to_radians().cos()).energy;
    assert!(slab[0] < 0.8, "red, τ = 0.4: the slab keeps less: {slab:?}");
    for c in 0..3 {
        let (d, s) = (means[0][0][c], means[0][1][c]);
        assert!((s / d - 1.0).abs() < 1e-5, "plane, channel {c}: {s} vs {d}");
        let (d, s) = (means[2][0][c], means[2][1][c]);
        let keeps = slab[c].min(1.0) as f64;
        assert!(
            (s / d / keeps - 1.0).abs() < 1e-4,
            "thin plane, channel {c}: shape/directional {} against E_slab {keeps}",
            s / d
        );
        let ratio = means[1][1][c] / means[1][0][c];
        eprintln!(
            "sphere, channel {c}: shape/directional {ratio:.4}, E(1/R) {:.4}",
            energy[c]
        );
        assert!(
            (ratio / energy[c] as f64 - 1.0).abs() < 0.02,
            "sphere, channel {c}: shape/directional {ratio} (E {})",
            energy[c]
        );
    }
}

/// The radius mixture's shares: with a sample for every component they are whole numbers of a
/// pixel's N samples (the samples are stratified over the mixture, so each component gets exactly
/// its count in every pixel), at least one uniform, the rest within one of each other; with fewer
/// the even split; always summing to 1.
#[test]
fn the_mixture_gives_each_component_whole_samples() {
    let (mut radial, _) = setups();
    for n in [1u32, 2, 3, 4, 5, 8, 16, 17, 64] {
        radial.sampling.samples = n;
        let (shares, uniform) = (radial.shares(), radial.uniform_share());
        let sum = uniform + shares.iter().sum::<f64>();
        assert!((sum - 1.0).abs() < 1e-12, "N = {n}: {sum}");
        if n <= 3 {
            assert_eq!(
                uniform,
                gpu::gathers::surface_gather::UNIFORM_SHARE,
                "N = {n}"
            );
            continue;
        }
        let counts: Vec<f64> = shares.iter().map(|s| s * n as f64).collect();
        assert!(
            counts.iter().all(|c| (c - c.round()).abs() < 1e-9),
            "N = {n}: {counts:?}"
        );
        assert!(uniform * n as f64 >= 1.0 - 1e-9, "N = {n}: {uniform}");
        let (lo, hi) = (
            counts.iter().cloned().fold(f64::MAX, f64::min),
            counts.iter().cloned().fold(0.0, f64::max),
        );
        assert!(hi - lo <= 1.0 + 1e-9, "N = {n}: {counts:?}");
    }
}
