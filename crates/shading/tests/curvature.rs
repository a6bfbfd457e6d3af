//! The curvature at the scale light travels (`shading::curvature`), against the identities of
//! chord curvature: every chord of a sphere of radius R has κ = 1/R (so the average is 1/R at any
//! scale and mesh density), around a cavity −1/R, on a plane 0, on a cylinder of radius r at a
//! scale well below r its mean curvature 1/(2r) (Euler: the normal curvatures' average over
//! directions); two bodies and the far face of a thin part are not a vertex's exits.

use glam::Vec3;
use shading::{SurfaceMesh, light_scale_curvature};

/// A triangulated surface: positions, normals, triangles.
#[derive(Default)]
struct Surface {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl Surface {
    fn mesh(&self) -> SurfaceMesh<'_> {
        SurfaceMesh {
            positions: &self.positions,
            normals: &self.normals,
            triangles: &self.triangles,
        }
    }

    /// A grid of (rows + 1) × (cols + 1) vertices at `point(u, v)`, u, v ∈ [0, 1], normals
    /// `normal(u, v)`.
    fn grid(
        &mut self,
        (rows, cols): (u32, u32),
        point: impl Fn(f32, f32) -> Vec3,
        normal: impl Fn(f32, f32) -> Vec3,
    ) {
        let base = self.positions.len() as u32;
        for i in 0..=rows {
            for j in 0..=cols {
                let (u, v) = (i as f32 / rows as f32, j as f32 / cols as f32);
                self.positions.push(point(u, v).into());
                self.normals.push(normal(u, v).normalize().into());
            }
        }
        let row = cols + 1;
        for i in 0..rows {
            for j in 0..cols {
                let (a, b) = (base + i * row + j, base + (i + 1) * row + j);
                self.triangles.push([a, a + 1, b]);
                self.triangles.push([a + 1, b + 1, b]);
            }
        }
    }

    /// A UV sphere of radius `radius` at `centre`; normals pointing out (`sign` 1) or in (−1).
    fn sphere(&mut self, centre: Vec3, radius: f32, sign: f32) {
        let dir = |u: f32, v: f32| {
            let (t, p) = (std::f32::consts::PI * u, std::f32::consts::TAU * v);
            Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin())
        };
        self.grid(
            (96, 192),
            |u, v| centre + radius * dir(u, v),
            |u, v| sign * dir(u, v),
        );
    }
}

const SCALES: [f32; 3] = [0.3, 0.1, 0.05];

#[test]
fn a_sphere_is_one_over_its_radius_at_every_scale_and_a_cavity_minus_that() {
    for (radius, sign) in [(5.0f32, 1.0f32), (1.0, 1.0), (0.2, 1.0), (5.0, -1.0)] {
        let mut s = Surface::default();
        s.sphere(Vec3::ZERO, radius, sign);
        let k = light_scale_curvature(s.mesh(), SCALES).unwrap();
        for (i, v) in k.iter().enumerate() {
            for (c, got) in v.iter().enumerate() {
                let want = sign / radius;
                assert!(
                    (got - want).abs() < 2e-3 * want.abs(),
                    "R = {radius}, sign {sign}, vertex {i}, channel {c}: {got} against {want}"
                );
            }
        }
    }
}

#[test]
fn a_plane_is_flat_and_a_cylinder_is_its_mean_curvature() {
    let mut plane = Surface::default();
    plane.grid(
        (60, 60),
        |u, v| Vec3::new(6.0 * u, 0.0, 6.0 * v),
        |_, _| Vec3::Y,
    );
    for v in light_scale_curvature(plane.mesh(), SCALES).unwrap() {
        assert_eq!(v, [0.0; 3]);
    }
    // A cylinder of radius 2 cm, 4 cm long, read at its middle at 0.05 and 0.1 cm.
    let r = 2.0f32;
    let mut cylinder = Surface::default();
    let around = |v: f32| {
        let p = std::f32::consts::TAU * v;
        Vec3::new(p.cos(), 0.0, p.sin())
    };
    cylinder.grid(
        (160, 500),
        |u, v| r * around(v) + Vec3::Y * 4.0 * u,
        |_, v| around(v),
    );
    let k = light_scale_curvature(cylinder.mesh(), [0.05, 0.1, 0.0]).unwrap();
    for (i, p) in cylinder.positions.iter().enumerate() {
        if (p[1] - 2.0).abs() < 0.5 {
            for (c, got) in k[i][..2].iter().enumerate() {
                let want = 0.5 / r;
                assert!(
                    (got - want).abs() < 0.03 * want,
                    "vertex {i} channel {c}: {got} against 1/(2r) = {want}"
                );
            }
            assert_eq!(
                k[i][2], 0.0,
                "a channel that does not scatter is the half-space"
            );
        }
    }
}

#[test]
fn other_bodies_and_the_far_face_of_a_thin_part_are_not_exits() {
    // Two spheres 1 mm apart: each is its own 1/R.
    let mut s = Surface::default();
    s.sphere(Vec3::ZERO, 1.0, 1.0);
    let first = s.positions.len();
    s.sphere(Vec3::new(2.1, 0.0, 0.0), 0.5, 1.0);
    let k = light_scale_curvature(s.mesh(), SCALES).unwrap();
    for (i, v) in k.iter().enumerate() {
        let want = if i < first { 1.0 } else { 2.0 };
        assert!(
            (v[0] - want).abs() < 2e-3 * want,
            "vertex {i}: {} against {want}",
            v[0]
        );
    }
    // A 2 mm plate whose faces share its rim: each face is flat, the other face is no exit
    // (with it, κ = (n_y − n_x)·d/|d|² would read 2/t).
    let mut plate = Surface::default();
    plate.grid(
        (40, 40),
        |u, v| Vec3::new(4.0 * u, 0.1, 4.0 * v),
        |_, _| Vec3::Y,
    );
    plate.grid(
        (40, 40),
        |u, v| Vec3::new(4.0 * u, -0.1, 4.0 * v),
        |_, _| -Vec3::Y,
    );
    // Join the faces into one body through a triangle at a corner.
    plate.triangles.push([0, 1, 41 * 41]);
    for v in light_scale_curvature(plate.mesh(), SCALES).unwrap() {
        assert_eq!(v, [0.0; 3]);
    }
}

#[test]
fn the_bake_is_the_same_on_any_thread_count() {
    let mut s = Surface::default();
    let bump = |u: f32, v: f32| 0.5 * (-((u - 0.5).powi(2) + (v - 0.5).powi(2)) * 20.0).exp();
    s.grid(
        (50, 50),
        |u, v| Vec3::new(3.0 * u, bump(u, v), 3.0 * v),
        |u, v| {
            let h = 1e-3;
            let du = (bump(u + h, v) - bump(u - h, v)) / (2.0 * h * 3.0);
            let dv = (bump(u, v + h) - bump(u, v - h)) / (2.0 * h * 3.0);
            Vec3::new(-du, 1.0, -dv)
        },
    );
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| light_scale_curvature(s.mesh(), SCALES).unwrap())
    };
    let one = run(1);
    assert_eq!(one, run(2));
    // The bump's top is convex, its foot concave.
    let top = 25 * 51 + 25;
    assert!(one[top][1] > 0.5, "the bump's top: {:?}", one[top]);
    assert!(one.iter().any(|v| v[1] < -0.05), "no concave foot");
}

#[test]
fn bad_meshes_and_scales_are_refused_by_name() {
    let positions = [[0.0f32; 3], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    let normals = [[0.0f32, 1.0, 0.0]; 3];
    let mesh =
        |positions: &'static [[f32; 3]], normals: &'static [[f32; 3]], triangles| SurfaceMesh {
            positions,
            normals,
            triangles,
        };
    let positions: &'static [[f32; 3]] = Box::leak(Box::new(positions));
    let normals: &'static [[f32; 3]] = Box::leak(Box::new(normals));
    let cases: Vec<(SurfaceMesh, [f32; 3], &str)> = vec![
        (mesh(positions, &normals[..2], &[]), SCALES, "normals"),
        (
            mesh(positions, normals, &[[0, 1, 3]]),
            SCALES,
            "triangles[0]",
        ),
        (
            mesh(&[[f32::NAN, 0.0, 0.0]], &[[0.0, 1.0, 0.0]], &[]),
            SCALES,
            "positions[0]",
        ),
        (
            mesh(positions, normals, &[[0, 1, 2]]),
            [0.1, -1.0, 0.1],
            "channel 1",
        ),
        (
            mesh(positions, normals, &[[0, 1, 2]]),
            [0.1, 0.1, f32::INFINITY],
            "channel 2",
        ),
    ];
    for (m, scales, field) in cases {
        let e = light_scale_curvature(m, scales).unwrap_err().to_string();
        assert!(e.contains(field), "{e} does not name {field}");
    }
    // A triangle alone has no exits in reach of its vertices but each other: still finite.
    let k = light_scale_curvature(mesh(positions, normals, &[[0, 1, 2]]), SCALES).unwrap();
    assert_eq!(k, vec![[0.0; 3]; 3]);
}
