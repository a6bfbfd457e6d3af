//! A reference run as `scripts/references/images.py --arrays` leaves it (view.json, arrays.npz):
//! read into the page's scene (its view, its material) and its image tone-mapped as the
//! renderer's recombination shows a frame; what does not fit is refused, naming the folder.

use std::path::Path;

use npyz::WriterBuilder;
use render::{NamedMaterial, Reference};

const WIDTH: usize = 6;
const HEIGHT: usize = 4;

/// Skin1 behind an index-matched boundary, as images.py writes the material of its scenes.
const SKIN1_ETA1: &str = "name = \"skin1 (eta 1.0)\"\nunit = \"cm\"\nsigma_a = [0.32, 1.7, 4.8]\nsigma_s = [7.4, 8.8, 10.1]\ng = [0.0, 0.0, 0.0]\neta = 1.0\n";

/// Writes a reference folder whose image holds radiance `value(k)` / π at pixel k (row-major),
/// with `shape` as the array's shape.
fn folder(dir: &Path, shape: [u64; 3], value: impl Fn(usize) -> f64) {
    let view = serde_json::json!({
        "name": "sphere", "scene": "sphere", "width": WIDTH, "height": HEIGHT,
        "camera": [0.0, 9.0, 24.0], "target": [-1.5, 6.5, 3.0], "fov_deg": 16.0,
        "boxes": ["-5.2,10.4,-2:-4.2,11.4,12"], "lights": ["point:-12,20,14:500"],
        "floor_albedo": [0.0, 0.0, 0.0], "specular": 0.0, "ambient": 0.0,
        "object_albedo": [0.5, 0.3, 0.2], "material_toml": SKIN1_ETA1,
    });
    std::fs::write(dir.join("view.json"), view.to_string()).unwrap();
    let mut npz = npyz::npz::NpzWriter::create(dir.join("arrays.npz")).unwrap();
    let n = (shape[0] * shape[1] * shape[2]) as usize;
    let mut w = npz
        .array::<f64>("reference", Default::default())
        .unwrap()
        .default_dtype()
        .shape(&shape)
        .begin_nd()
        .unwrap();
    w.extend((0..n).map(|i| value(i / 3) / std::f64::consts::PI))
        .unwrap();
    w.finish().unwrap();
}

/// Narkowicz's ACES fit and the sRGB encoding, 8 bits, written out from their definitions.
fn aces_srgb(x: f64) -> u8 {
    let t = ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
    let s = if t <= 0.0031308 {
        12.92 * t
    } else {
        1.055 * t.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

#[test]
fn a_reference_folder_becomes_a_scene_in_its_own_view_with_its_image() {
    let dir = tempfile::tempdir().unwrap();
    // π × radiance from 0 to 4.6 across the image: black to nearly white.
    let x = |k: usize| 0.2 * k as f64;
    folder(dir.path(), [HEIGHT as u64, WIDTH as u64, 3], x);
    let r = Reference::read(dir.path()).unwrap();
    assert_eq!(r.material.slug, "skin1-eta-1-0");
    assert_eq!(r.material.material.eta, 1.0);
    assert_eq!(r.scene.name, "sphere");
    let v = r.scene.view.as_ref().unwrap();
    assert_eq!(v.size, (WIDTH as u32, HEIGHT as u32));
    assert_eq!(v.camera.2, 16.0);
    assert_eq!(v.lights.len(), 1);
    assert_eq!(v.boxes.len(), 1);
    let mut frame = gpu::RenderRequest::default();
    v.apply(&mut frame);
    assert_eq!((frame.width, frame.height), (WIDTH as u32, HEIGHT as u32));
    assert_eq!(frame.camera, Some(glam::Vec3::new(0.0, 9.0, 24.0)));
    assert_eq!(frame.object_albedo, vec![glam::Vec3::new(0.5, 0.3, 0.2)]);
    let png = r.scene.reference.unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    let mut rgba = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut rgba).unwrap();
    for k in 0..WIDTH * HEIGHT {
        let expected = aces_srgb(x(k));
        for c in 0..3 {
            let got = rgba[4 * k + c];
            assert!(
                got.abs_diff(expected) <= 1,
                "pixel {k}: {got} against {expected}"
            );
        }
    }
    assert_eq!(rgba[3], 255);
    assert_eq!(aces_srgb(0.0), 0);
}

#[test]
fn an_image_of_another_size_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    folder(dir.path(), [HEIGHT as u64 + 1, WIDTH as u64, 3], |_| 0.5);
    let e = Reference::read(dir.path()).unwrap_err().to_string();
    assert!(
        e.contains("reference") && e.contains("view.json says"),
        "{e}"
    );
}

#[test]
fn the_page_takes_the_references_material_and_refuses_another() {
    let dir = tempfile::tempdir().unwrap();
    folder(dir.path(), [HEIGHT as u64, WIDTH as u64, 3], |_| 0.5);
    let run = Reference::read(dir.path()).unwrap();
    // No material given: the reference's, and the reference's scene replaces the listed sphere.
    let listed = ["sphere".to_string(), "fin".to_string()];
    let (m, scenes) = Reference::page(None, &listed, vec![run.clone()]).unwrap();
    assert_eq!(m.slug, "skin1-eta-1-0");
    let names: Vec<&str> = scenes.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["fin", "sphere"]);
    assert!(scenes[1].view.is_some() && scenes[0].view.is_none());
    // Nothing listed: the references' scenes only.
    let (_, scenes) = Reference::page(None, &[], vec![run.clone()]).unwrap();
    assert_eq!(scenes.len(), 1);
    // Skin1 as built in has η = 1.4: not the medium the reference shows.
    let skin1 = NamedMaterial {
        slug: "skin1".into(),
        material: mc::Material::builtin("skin1").unwrap(),
    };
    let e = Reference::page(Some(skin1), &[], vec![run])
        .unwrap_err()
        .to_string();
    assert!(e.contains("reference") && e.contains("η = 1"), "{e}");
}
