//! Light through thin parts in the scene pass: a thin SSS slab lit from behind receives, on the
//! face the camera sees, E·|n·l|·T(θ)/T(0)·table(d) with d the light's path through the slab
//! (thickness / cos θ), read from the shadow map, and T Fresnel's transmittance;
//! a thick one the table's last entry; with translucency off, nothing. Under CI=true a missing
//! adapter fails.

use glam::Vec3;
use gpu::{AlbedoMode, Light, MAX_MATERIALS, RenderParams, Scatter, Scene, render};
use shading::{Shading, TRANSLUCENCY_STEPS, Translucency};

mod common;
use common::gpu;

const SIZE: u32 = 32;

/// A table with a known shape: e^{−d/0.1 cm} × (1, ½, ¼) at d = 0.01 … 2 cm.
fn table() -> Translucency {
    decaying(0.1, 2.0)
}

/// e^{−d/length} × (1, ½, ¼) [length, d in cm] at d = 0.01 … `last` cm.
fn decaying(length: f64, last: f64) -> Translucency {
    let d = Translucency::thicknesses(0.01, last);
    Translucency {
        first_cm: 0.01,
        ratio: (d[1] / d[0]) as f32,
        table: std::array::from_fn(|k| {
            let t = (-d[k] / length).exp() as f32;
            [t, 0.5 * t, 0.25 * t]
        }),
        exit: [[[1.0; 3]; shading::INCIDENCE_STEPS]; TRANSLUCENCY_STEPS],
    }
}

/// The slab y ∈ [−thickness, 0], seen from above, lit from below at 30° from the normal with an
/// irradiance of 2.
fn slab(thickness: f32) -> Scene {
    let towards = Vec3::new(30f32.to_radians().sin(), -30f32.to_radians().cos(), 0.0);
    let mut s = common::slab_scene(thickness, 100.0, towards);
    s.lights = vec![Light::Directional {
        towards,
        irradiance: Vec3::splat(2.0),
        shadow: true,
    }];
    s
}

fn centre(frame: &gpu::Frame) -> [f32; 4] {
    let s = SIZE as usize;
    frame.irradiance[(s / 2) * s + s / 2]
}

#[test]
fn a_slab_lit_from_behind_receives_its_transmitted_light() {
    let Some(gpu) = gpu() else { return };
    let t = table();
    let params = RenderParams {
        width: SIZE,
        height: SIZE,
        albedo: AlbedoMode::Post,
        shading: [Shading {
            translucency: Some(t),
            eta: 1.3,
            ..Shading::default()
        }; MAX_MATERIALS],
        ..RenderParams::default()
    };
    let cos = 30f32.to_radians().cos();
    for thickness in [0.05f32, 0.2, 0.7] {
        let frame = render(&gpu, &slab(thickness), Scatter::None, &params).unwrap();
        let got = centre(&frame);
        // The light crosses the slab along a ray of length thickness/cos, entering at 30°.
        let entry = (1.0 - shading::fresnel(1.3, cos as f64)) / (1.0 - shading::fresnel(1.3, 1.0));
        let want = t.at(thickness / cos).map(|v| 2.0 * cos * entry as f32 * v);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 0.01 * want[c] + 1e-6,
                "d = {thickness}: channel {c}: {} vs {}",
                got[c],
                want[c]
            );
        }
    }
    // Thicker than the table: its last entry.
    let frame = render(&gpu, &slab(4.0), Scatter::None, &params).unwrap();
    let entry = (1.0 - shading::fresnel(1.3, cos as f64)) / (1.0 - shading::fresnel(1.3, 1.0));
    let last = t.table[TRANSLUCENCY_STEPS - 1][0] * 2.0 * cos * entry as f32;
    assert!((centre(&frame)[0] - last).abs() < 1e-6 + 0.01 * last);
    // Off: a surface facing away from the only light is black.
    let off = RenderParams {
        shading: [Shading::default(); MAX_MATERIALS],
        ..params
    };
    let frame = render(&gpu, &slab(0.05), Scatter::None, &off).unwrap();
    assert_eq!(centre(&frame)[..3], [0.0; 3]);
}

#[test]
fn table_lookup_interpolates_in_log_thickness_and_clamps() {
    let t = table();
    let d = Translucency::thicknesses(0.01, 2.0);
    assert!((d[TRANSLUCENCY_STEPS - 1] - 2.0).abs() < 1e-9);
    for (k, (&dk, row)) in d.iter().zip(&t.table).enumerate() {
        let v = t.at(dk as f32);
        assert!((v[1] - row[1]).abs() < 1e-4 * row[1].max(1e-3), "{k}");
    }
    // Half-way in ln d between entries 3 and 4: their mean.
    let mid = (d[3] * d[4]).sqrt() as f32;
    let want = 0.5 * (t.table[3][0] + t.table[4][0]);
    assert!((t.at(mid)[0] - want).abs() < 1e-4 * want);
    assert_eq!(t.at(0.0), t.table[0]);
    assert_eq!(t.at(1e3), t.table[TRANSLUCENCY_STEPS - 1]);
    let mut bad = t;
    bad.ratio = 1.0;
    assert!(bad.validate().unwrap_err().to_string().contains("ratio"));
}

/// Exit-aware translucency: the transmitted light leaves with the slab's own angular
/// distribution h_T(θ; d) (`mc`: the law of darkening for thick slabs, tested there), not the
/// reflected light's h. The scene pass multiplies it by h_T/h at the pixel's view angle (the
/// recombination multiplies every scattered light by h), here straight down (θ = 0), as the CPU
/// twin `Translucency::exit_at` reads the table: linear in ln d between thicknesses.
#[test]
fn transmitted_light_leaves_with_its_own_angular_distribution() {
    let Some(gpu) = gpu() else { return };
    let mut t = table();
    // h_T growing with the thickness index and falling with the angle; the reflection's h 1.25.
    t.exit = std::array::from_fn(|k| {
        std::array::from_fn(|j| [1.0 + 0.1 * k as f32, 1.0, 2.0 - j as f32 / 8.0])
    });
    let shading = Shading {
        translucency: Some(t),
        exit: [[[1.25; 3]; shading::INCIDENCE_STEPS]; shading::INCIDENCE_STEPS],
        eta: 1.3,
        ..Shading::default()
    };
    let params = RenderParams {
        width: SIZE,
        height: SIZE,
        albedo: AlbedoMode::Post,
        shading: [shading; MAX_MATERIALS],
        ..RenderParams::default()
    };
    let cos = 30f32.to_radians().cos();
    let entry = (1.0 - shading::fresnel(1.3, cos as f64)) / (1.0 - shading::fresnel(1.3, 1.0));
    for thickness in [0.05f32, 0.2, 0.7] {
        let got = centre(&render(&gpu, &slab(thickness), Scatter::None, &params).unwrap());
        let d = thickness / cos;
        let h = t.exit_at(d, 1.0);
        let want: Vec<f32> = (0..3)
            .map(|c| 2.0 * cos * entry as f32 * t.at(d)[c] * h[c] / 1.25)
            .collect();
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 0.01 * want[c] + 1e-6,
                "d = {thickness}: channel {c}: {} vs {} (h_T {:?})",
                got[c],
                want[c],
                h
            );
        }
    }
}

/// A 5 cm sphere lit from the side, with a table decaying over 2 mm: a dark-side point whose
/// normal makes cos θ = c with the light lies behind a chord of 2Rc, so the light crossing the
/// sphere adds at most E·c·table(2Rc) ≤ E·max_c c·table(2Rc) to its irradiance (the entry's
/// Fresnel factor ≤ 1, h_T/h = 1 here). Near the terminator the chord shrinks to 0 within a
/// shadow-map texel; reading the thickness there as if the map resolved it put speckles of a
/// thin slab's transmittance (a 0.03 cm reading behind a 0.65 cm chord) on the dark side,
/// 2.7× this bound.
#[test]
fn a_curved_body_transmits_no_more_than_its_chords_allow() {
    let Some(gpu) = gpu() else { return };
    let mut scene = Scene::sphere();
    scene.ambient = Vec3::ZERO;
    scene.lights = vec![Light::Directional {
        towards: Vec3::new(-1.0, 0.0, 0.0),
        irradiance: Vec3::ONE,
        shadow: true,
    }];
    let t = decaying(0.2, 20.0);
    let shading = |translucency| Shading {
        translucency,
        eta: 1.3,
        ..Shading::default()
    };
    let params = |s: Shading| RenderParams {
        width: 192,
        height: 192,
        albedo: AlbedoMode::Post,
        shading: [s; MAX_MATERIALS],
        ..RenderParams::default()
    };
    let on = render(&gpu, &scene, Scatter::None, &params(shading(Some(t)))).unwrap();
    let off = render(&gpu, &scene, Scatter::None, &params(shading(None))).unwrap();
    let radius = 5.0f32;
    let bound: [f32; 3] = std::array::from_fn(|ch| {
        (1..=1000)
            .map(|k| {
                let c = k as f32 / 1000.0;
                c * t.at(2.0 * radius * c)[ch]
            })
            .fold(0.0, f32::max)
    });
    let mut lit_through = 0;
    let mut worst = 0.0f32;
    for (a, b) in on.irradiance.iter().zip(&off.irradiance) {
        for ch in 0..3 {
            worst = worst.max((a[ch] - b[ch]) / bound[ch]);
            lit_through += (a[ch] - b[ch] > 0.01 * bound[ch]) as usize;
        }
    }
    eprintln!(
        "largest added light {worst:.3} of the chords' bound; {lit_through} channel-pixels above 0.01 of it"
    );
    assert!(worst <= 1.1, "{worst} of the chords' bound");
    // The light does cross near the terminator, where the chords are short.
    assert!(lit_through > 30, "{lit_through} channel-pixels lit through");
}
