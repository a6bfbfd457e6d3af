//! Hostile Wavefront OBJ files for [`Mesh::from_obj`] (written to temporary files, since it reads
//! a path): no panic, no hang, and what loads is drawable: triangles whose indices exist, finite
//! positions and normals, scaled to the requested height. Refusals are `GpuError::Mesh` naming
//! the file. No GPU is needed.

use testkit::hostile;

use std::path::Path;

use gpu::{GpuError, Mesh};
use proptest::prelude::*;

/// A unit cube: named object, normals, a material library and quads, a pentagon written with
/// relative indices, and texture coordinates.
const CUBE: &str = "# cube\nmtllib cube.mtl\no cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nv 0.5 1.5 0.5\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\nusemtl skin\nf 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\nf 1/1/3 2/2/3 6/3/3 5/1/3\ng side\nf 1//5 5//5 8//5 4//5\nf 2//6 3//6 7//6 6//6\nf -6 -5 -1 -2 -9\n";

const HEIGHT: f32 = 10.0;

fn load(text: &str) -> (tempfile::TempDir, Result<Mesh, GpuError>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.obj");
    std::fs::write(&path, text).unwrap();
    let m = Mesh::from_obj(&path, HEIGHT, [0.5; 3], 1.0);
    (dir, m)
}

fn check_mesh(m: &Mesh) -> Result<(), TestCaseError> {
    prop_assert!(!m.indices.is_empty() && m.indices.len().is_multiple_of(3));
    prop_assert!(m.indices.iter().all(|&i| (i as usize) < m.vertices.len()));
    for v in &m.vertices {
        prop_assert!(
            v.pos.iter().chain(&v.normal).all(|c| c.is_finite()),
            "{v:?}"
        );
        prop_assert!(v.normal != [0.0; 3], "a zero normal shades as NaN: {v:?}");
    }
    let (lo, hi) = m.bounds();
    prop_assert!(lo.y.abs() <= 1e-3 * HEIGHT, "{lo} {hi}");
    prop_assert!((hi.y - HEIGHT).abs() <= 1e-3 * HEIGHT, "{lo} {hi}");
    Ok(())
}

fn check(text: &str) -> Result<(), TestCaseError> {
    let (_dir, m) = load(text);
    match m {
        Ok(m) => check_mesh(&m)?,
        Err(GpuError::Mesh { path, message }) => {
            prop_assert!(path.ends_with("m.obj") && !message.is_empty());
        }
        Err(e) => prop_assert!(false, "unexpected error kind: {e}"),
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn obj_survives_hostile_input(text in hostile::hostile(CUBE)) {
        check(&text)?;
    }

    /// Random faces over random vertices: indices past the end, zero, relative beyond the start.
    #[test]
    fn obj_of_random_faces(
        verts in prop::collection::vec(prop::array::uniform3(-10.0f32..10.0), 0..6),
        faces in prop::collection::vec(prop::collection::vec(-8i64..8, 0..6), 0..6),
    ) {
        let mut text = String::new();
        for v in &verts {
            text += &format!("v {} {} {}\n", v[0], v[1], v[2]);
        }
        for f in &faces {
            text += "f";
            for i in f {
                text += &format!(" {i}");
            }
            text += "\n";
        }
        check(&text)?;
    }
}

#[test]
fn the_valid_cube_loads() {
    let (_dir, m) = load(CUBE);
    let m = m.unwrap();
    check_mesh(&m).unwrap();
    assert_eq!(m.indices.len(), 3 * (5 * 2 + 3));
}

#[test]
fn every_number_replaced_by_every_hostile_value() {
    for (a, b) in hostile::numbers(CUBE) {
        for v in hostile::HOSTILE_NUMBERS {
            let text = format!("{}{v}{}", &CUBE[..a], &CUBE[b..]);
            if let Err(e) = check(&text) {
                panic!("{e}\n--- input:\n{text}");
            }
        }
    }
}

fn error_of(text: &str) -> String {
    let (_dir, m) = load(text);
    match m {
        Ok(m) => panic!("accepted {text:?}: {m:?}"),
        Err(e) => e.to_string(),
    }
}

/// Regressions: each of these was accepted as garbage, panicked or never returned.
#[test]
fn hostile_files_are_refused_with_the_reason() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (text, needle) in [
        (
            format!("{tri}vn 0 0 NaN\nf 1//1 2//1 3//1\n"),
            "non-finite vertex normal",
        ),
        (
            format!("{tri}vn 0 0 1e39\nf 1//1 2//1 3//1\n"),
            "non-finite vertex normal",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n".into(),
            "height (y) must be positive",
        ),
        (
            "v -3e38 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n".into(),
            "every side finite",
        ),
        (
            "v 0 0 0\nv 1e30 0 0\nv 0 1e-30 0\nf 1 2 3\n".into(),
            "overflows f32",
        ),
        (format!("{tri}p 1\nl 1 2\n"), "no triangles"),
        (format!("{tri}f 1 2 1000000000000000\n"), "out of bounds"),
        (format!("{tri}f -1 -2 -99\n"), "out of bounds"),
        (
            format!("{tri}f 1 2 3\nv 0 0 NaN\nf 1 2 4\n"),
            "non-finite vertex position",
        ),
    ] {
        let e = error_of(&text);
        assert!(e.contains("m.obj") && e.contains(needle), "{text:?}: {e}");
    }
}

#[test]
fn material_libraries_are_not_followed() {
    // A library that never ends (or blocks) must not be read: materials are not used.
    let (_dir, m) =
        load("mtllib /dev/zero\nmtllib /dev/stdin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    check_mesh(&m.unwrap()).unwrap();
}

#[test]
fn only_regular_files_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo.obj");
    let _ = std::process::Command::new("mkfifo").arg(&fifo).status();
    for p in [dir.path(), Path::new("/dev/zero"), &fifo] {
        if !p.exists() {
            continue;
        }
        let e = Mesh::from_obj(p, HEIGHT, [0.5; 3], 1.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&p.display().to_string()) && e.contains("not a regular file"),
            "{e}"
        );
    }
    let e = Mesh::from_obj(&dir.path().join("missing.obj"), HEIGHT, [0.5; 3], 1.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing.obj"), "{e}");
    let (cube_dir, _) = load(CUBE);
    let path = cube_dir.path().join("m.obj");
    for h in [f32::NAN, 0.0, -1.0, f32::INFINITY] {
        let e = Mesh::from_obj(&path, h, [0.5; 3], 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("height"), "{h}: {e}");
    }
}
