//! The directional-dipole renderer against a CPU evaluation of the same estimator's expectation:
//! on a slab lit by a directional light at 45°, π·L_o at the pixels seen head-on equals
//! π·E·T(ω_o)·∫_disc T(ω_i)·S_d(x_i(p), ω_i; x_o) dA⊥, integrated here by quadrature over the
//! disc (f64, `fit`'s model), for light arriving on the face the camera sees (front-lit) and
//! through a 2 mm slab from the other side (back-lit: translucency). The quadrature itself is
//! tied to the model's total reflectance: for a large disc on the front face it equals
//! E·cos θ·T(ω_o)·Rd(θ)/(4C_φ(1/η)). A distant point light gives the same. Under CI=true a
//! missing adapter fails.

use fit::analytic::{DirectionalDipole, Medium, SurfacePoint, fresnel_moments::c_phi};
use glam::Vec3;
use gpu::{DipoleSetup, Light, RenderParams, Scatter, render};
use nalgebra::Vector3;
use std::f64::consts::PI;

mod common;
use common::{centre_mean, gpu, slab_scene};

const SIZE: u32 = 48;

fn skin1() -> [Medium; 3] {
    let (sa, ss) = ([0.32, 1.7, 4.8], [7.4, 8.8, 10.1]);
    [0, 1, 2].map(|c| Medium {
        sigma_a: sa[c],
        sigma_s: ss[c],
        g: 0.0,
        eta: 1.3,
    })
}

/// π·L_o by quadrature over the disc of radius `r_max` around x_o = (0, y_o, 0) in the plane
/// perpendicular to `towards`, the light entering the top face y = `y_top` (normal +y); the
/// exit normal is `n_o`; the camera looks along ∓y.
fn quadrature(
    media: &[Medium; 3],
    towards: Vector3<f64>,
    y_top: f64,
    y_o: f64,
    n_o: Vector3<f64>,
    r_max: f64,
) -> [f64; 3] {
    let l = towards.normalize();
    let t1 = l.cross(&Vector3::z()).normalize();
    let t2 = l.cross(&t1);
    let o = SurfacePoint {
        x: Vector3::new(0.0, y_o, 0.0),
        n: n_o,
    };
    let (nr, nphi) = (600, 256);
    let mut out = [0.0; 3];
    for (c, m) in media.iter().enumerate() {
        let dd = DirectionalDipole::new(m);
        let t_in = 1.0 - shading::fresnel(m.eta, l.y);
        let t_out = 1.0 - shading::fresnel(m.eta, 1.0);
        let mut sum = 0.0;
        for i in 0..nr {
            // Radii graded towards the centre, where S_d peaks.
            let (a, b) = (
                (i as f64 / nr as f64).powi(2),
                ((i + 1) as f64 / nr as f64).powi(2),
            );
            let (r, dr) = (0.5 * (a + b) * r_max, (b - a) * r_max);
            for j in 0..nphi {
                let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * PI;
                let p = o.x + r * (phi.cos() * t1 + phi.sin() * t2);
                // Along the light ray onto the top face.
                let x_i = p + l * ((y_top - p.y) / l.y);
                let i = SurfacePoint {
                    x: x_i,
                    n: Vector3::y(),
                };
                sum += dd.s_d(&i, &l, &o) * r * dr;
            }
        }
        out[c] = PI * t_out * t_in * sum * 2.0 * PI / nphi as f64;
    }
    out
}

fn check(name: &str, got: [f64; 3], want: [f64; 3], tol: f64) {
    eprintln!("{name}: GPU {got:.5?}, quadrature {want:.5?}");
    for c in 0..3 {
        assert!(
            (got[c] / want[c] - 1.0).abs() < tol,
            "{name} channel {c}: GPU {} vs quadrature {}",
            got[c],
            want[c]
        );
    }
}

#[test]
fn front_lit_slab_matches_the_quadrature_and_the_models_total_reflectance() {
    let media = skin1();
    let towards = Vector3::new(1.0, 1.0, 0.0).normalize();
    let mut setup = DipoleSetup::new(&media).unwrap();
    // The quadrature on a large disc is the model's total reflectance at 45°.
    let big = quadrature(
        &media,
        towards,
        0.0,
        0.0,
        Vector3::y(),
        8.0 * setup.sampling.radius_cm as f64,
    );
    for (c, m) in media.iter().enumerate() {
        let dd = DirectionalDipole::new(m);
        let (n, r_max) = (3000, 8.0 * setup.sampling.radius_cm as f64);
        let mut total = 0.0;
        for i in 0..n {
            let (a, b) = (
                (i as f64 / n as f64).powi(2),
                ((i + 1) as f64 / n as f64).powi(2),
            );
            let (r, dr) = (0.5 * (a + b) * r_max, (b - a) * r_max);
            for j in 0..128 {
                let phi = (j as f64 + 0.5) / 128.0 * 2.0 * PI;
                total += dd.rd_xy(r * phi.cos(), r * phi.sin(), 45.0) * r * dr * 2.0 * PI / 128.0;
            }
        }
        let t_out = 1.0 - shading::fresnel(m.eta, 1.0);
        let want = 45f64.to_radians().cos() * t_out * total / (4.0 * c_phi(1.0 / m.eta));
        assert!(
            (big[c] / want - 1.0).abs() < 0.01,
            "{c}: {} vs {want}",
            big[c]
        );
    }
    let Some(gpu) = gpu() else { return };
    setup.sampling.samples = 32;
    setup.sampling.frames = 8;
    setup.sampling.map_size = 2048;
    let scene = slab_scene(4.0, 200.0, Vec3::new(1.0, 1.0, 0.0).normalize());
    let params = RenderParams {
        width: SIZE,
        height: SIZE,
        ..RenderParams::default()
    };
    let frame = render(&gpu, &scene, Scatter::DirectionalDipole(&setup), &params).unwrap();
    let want = quadrature(
        &media,
        towards,
        0.0,
        0.0,
        Vector3::y(),
        setup.sampling.radius_cm as f64,
    );
    check("front-lit", centre_mean(&frame, SIZE), want, 0.02);
    // A point light 300 cm away along the same direction with intensity E·(300 cm)²: across the
    // disc its direction turns by < 0.5° and its irradiance changes by < 2 %.
    let mut point = scene.clone();
    point.lights = vec![Light::Point {
        position: 300.0 * Vec3::new(1.0, 1.0, 0.0).normalize(),
        intensity: Vec3::splat(300.0 * 300.0),
        shadow: true,
    }];
    let frame = render(&gpu, &point, Scatter::DirectionalDipole(&setup), &params).unwrap();
    check(
        "front-lit, point light",
        centre_mean(&frame, SIZE),
        want,
        0.03,
    );
}

#[test]
fn light_through_a_thin_slab_matches_the_quadrature() {
    let media = skin1();
    let towards = Vector3::new(1.0, 1.0, 0.0).normalize();
    let mut setup = DipoleSetup::new(&media).unwrap();
    let Some(gpu) = gpu() else { return };
    setup.sampling.samples = 32;
    setup.sampling.frames = 8;
    setup.sampling.map_size = 2048;
    let thickness = 0.2;
    let scene = slab_scene(thickness, -200.0, Vec3::new(1.0, 1.0, 0.0).normalize());
    let params = RenderParams {
        width: SIZE,
        height: SIZE,
        ..RenderParams::default()
    };
    let frame = render(&gpu, &scene, Scatter::DirectionalDipole(&setup), &params).unwrap();
    let want = quadrature(
        &media,
        towards,
        0.0,
        -thickness as f64,
        -Vector3::y(),
        setup.sampling.radius_cm as f64,
    );
    assert!(want.iter().all(|&v| v > 0.0));
    check("back-lit", centre_mean(&frame, SIZE), want, 0.02);
}

/// Validation: bad settings are refused with the field named.
#[test]
fn bad_settings_are_refused() {
    let mut setup = DipoleSetup::new(&skin1()).unwrap();
    setup.sampling.samples = 0;
    assert!(
        setup
            .validate()
            .unwrap_err()
            .to_string()
            .contains("samples")
    );
    setup.sampling.samples = 4;
    setup.sampling.radius_cm = f32::NAN;
    assert!(setup.validate().unwrap_err().to_string().contains("radius"));
    let mut bad = skin1();
    bad[1].sigma_a = -1.0;
    assert!(
        DipoleSetup::new(&bad)
            .unwrap_err()
            .to_string()
            .contains("sigma_a")
    );
}

/// Issue #30's report: a thick flat slab of Skin1's coefficients at η = 1 under a distant light
/// at 60° seemed to return 0.85 / 0.84 / 0.79 of the normal-incidence reflectance per unit
/// irradiance, where `mc` gives 1.16 / 1.27 / 1.33. The model itself does not: its total
/// reflectance at 60° over that at 0° is 1.075 / 1.215 / 1.354 (`DirectionalDipole::total_rd`,
/// the same quadrature as above). The renderer must return that ratio per unit irradiance
/// E·cos θ, within the disc's truncation (measured by the quadrature on the renderer's disc).
#[test]
fn oblique_light_on_an_index_matched_half_space_follows_the_models_total() {
    let media = skin1().map(|m| Medium { eta: 1.0, ..m });
    let mut setup = DipoleSetup::new(&media).unwrap();
    let r = setup.sampling.radius_cm as f64;
    let at = |theta: f64| {
        let t = theta.to_radians();
        quadrature(
            &media,
            Vector3::new(t.sin(), t.cos(), 0.0),
            0.0,
            0.0,
            Vector3::y(),
            r,
        )
    };
    let (q0, q60) = (at(0.0), at(60.0));
    let model: [f64; 3] = std::array::from_fn(|c| {
        let dd = DirectionalDipole::new(&media[c]);
        dd.total_rd(60.0) / dd.total_rd(0.0)
    });
    let on_disc: [f64; 3] = std::array::from_fn(|c| q60[c] / (0.5 * q0[c]));
    eprintln!("model Rd(60°)/Rd(0): {model:.4?}, on the renderer's disc: {on_disc:.4?}");
    for c in 0..3 {
        assert!(
            (on_disc[c] / model[c] - 1.0).abs() < 0.03,
            "{c}: {on_disc:?} vs {model:?}"
        );
    }
    let Some(gpu) = gpu() else { return };
    setup.sampling.samples = 32;
    setup.sampling.frames = 8;
    setup.sampling.map_size = 2048;
    let params = RenderParams {
        width: SIZE,
        height: SIZE,
        ..RenderParams::default()
    };
    let mut got = [[0.0; 3]; 2];
    for (k, theta) in [0f32, 60.0].into_iter().enumerate() {
        let t = theta.to_radians();
        let scene = slab_scene(4.0, 200.0, Vec3::new(t.sin(), t.cos(), 0.0));
        let frame = render(&gpu, &scene, Scatter::DirectionalDipole(&setup), &params).unwrap();
        got[k] = centre_mean(&frame, SIZE);
    }
    let ratio: [f64; 3] = std::array::from_fn(|c| got[1][c] / (0.5 * got[0][c]));
    check("60° over 0° per unit irradiance", ratio, on_disc, 0.03);
}
