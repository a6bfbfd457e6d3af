//! Shared by the GPU tests: the device, or a skip outside CI when there is none; the thick or
//! thin slab scene of the disc gathers' tests and its central mean; Skin1's surface gather. (Not every test uses each.)
#![allow(dead_code)]

use glam::Vec3;
use gpu::{Camera, Gpu, Light, Mesh, Scene, SurfaceGatherSetup};
use shading::Bssrdf;

/// The adapter wgpu finds; None (test skipped) without one, except under CI=true, where a
/// missing adapter is a failure.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => panic!("CI=true and {e}"),
        Err(e) => {
            report_skip(&e.to_string());
            None
        }
    }
}

/// Says that the running test was skipped, on the process's own stderr: libtest captures only
/// `print!` and `eprint!`, so the line shows in `cargo test`'s output (a skip is never a silent
/// pass).
pub fn report_skip(reason: &str) {
    use std::io::Write;
    let name = std::thread::current()
        .name()
        .unwrap_or("a GPU test")
        .to_string();
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED {name}: {reason}");
}

/// A 40 × 40 cm slab y ∈ [−thickness, 0] of SSS material, seen from (0, camera_y, 0) through a
/// 4° field of view (from above or, with camera_y < 0, from below), lit by a directional light
/// of unit irradiance from `towards`.
pub fn slab_scene(thickness: f32, camera_y: f32, towards: Vec3) -> Scene {
    Scene {
        mesh: Mesh::cuboid(
            Vec3::new(-20.0, -thickness, -20.0),
            Vec3::new(20.0, 0.0, 20.0),
            [1.0; 3],
            1.0,
        ),
        camera: Camera {
            position: Vec3::new(0.0, camera_y, 0.0),
            target: Vec3::new(0.0, -0.5 * thickness, 0.0),
            fov_y_deg: 4.0,
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

/// A straight shadow edge across a thick slab of SSS material (y ∈ [−4, 0], x ∈ [−60, 40] cm)
/// under a distant light of unit irradiance from −x at 60°, whose propagation runs towards +x: a
/// black box 10–10.5 cm above the slab over x < −10.5·tan 60° puts the edge (cast by its upper
/// corner) at x = 0, the shadow on its −x side. The camera looks straight down from 100 cm at
/// ±`half_view_cm` around the edge (the box outside its view).
pub fn shadow_edge_scene(half_view_cm: f32) -> Scene {
    let (sin, cos) = 60f32.to_radians().sin_cos();
    let reach = 10.5 * sin / cos;
    let mut scene = slab_scene(4.0, 100.0, Vec3::new(-sin, cos, 0.0));
    scene.mesh = Mesh::cuboid(
        Vec3::new(-60.0, -4.0, -40.0),
        Vec3::new(40.0, 0.0, 40.0),
        [1.0; 3],
        1.0,
    );
    scene.mesh.append(&Mesh::cuboid(
        Vec3::new(-60.0, 10.0, -40.0),
        Vec3::new(-reach, 10.5, 40.0),
        [0.0; 3],
        0.0,
    ));
    scene.camera = Camera {
        position: Vec3::new(0.0, 100.0, 0.0),
        target: Vec3::new(0.0, 0.0, 0.0),
        fov_y_deg: 2.0 * (half_view_cm / 100.0).atan().to_degrees(),
    };
    scene
}

/// The mean of the scattered light over the central 16×16 pixels of a `size`² frame.
pub fn centre_mean(frame: &gpu::Frame, size: u32) -> [f64; 3] {
    std::array::from_fn(|c| {
        let v = centre_values(frame, size, c);
        v.iter().sum::<f64>() / v.len() as f64
    })
}

/// Channel `c` of the central 16 × 16 pixels of a `size`² frame's scattered light.
pub fn centre_values(frame: &gpu::Frame, size: u32, c: usize) -> Vec<f64> {
    let (s, half) = (size as usize, size as usize / 2);
    (half - 8..half + 8)
        .flat_map(|y| (half - 8..half + 8).map(move |x| y * s + x))
        .map(|i| frame.scattered[i][c] as f64)
        .collect()
}

/// How a shadow-edge test's `size`² image maps onto x: each line (a column, or a row with
/// `along_rows`) spans `px` cm of x.
pub struct EdgeView {
    pub size: u32,
    pub px: f64,
    pub along_rows: bool,
}

impl EdgeView {
    /// The mean of channel `c` of per-pixel values `v` over line `i`.
    pub fn line_mean(&self, v: &[[f32; 4]], i: usize, c: usize) -> f64 {
        let w = self.size as usize;
        (0..w)
            .map(|j| {
                v[if self.along_rows {
                    i * w + j
                } else {
                    j * w + i
                }][c] as f64
            })
            .sum::<f64>()
            / w as f64
    }
}

/// Skin1 (the thesis's coefficients) with isotropic scattering, η = 1.3.
pub fn skin1() -> shading::Material {
    shading::Material {
        name: "Skin1".into(),
        source: String::new(),
        sigma_a: [0.32, 1.7, 4.8],
        sigma_s: [7.4, 8.8, 10.1],
        g: [0.0; 3],
        eta: 1.3,
        thickness: None,
    }
}

/// A batch of Skin1 at the thesis's settings.
pub fn spec(photons: u64, seed: u64) -> shading::BatchSpec {
    let config = shading::SimConfig::thesis().unwrap();
    config.batch(&[&skin1()], photons, seed, true).unwrap()
}

/// Skin1's Monte Carlo profile, 4·10⁵ photons (independent of the tables' runs: another seed).
pub fn profile() -> fit::Profile {
    shading::profile::simulate(&spec(400_000, 101), "mc", &|_| {})
        .unwrap()
        .profile
}

/// The gather of `bssrdf` with the tables of `spec` (`shading::gather_tables`) and `profile`.
pub fn setup(
    spec: &shading::BatchSpec,
    profile: &fit::Profile,
    bssrdf: Bssrdf,
) -> SurfaceGatherSetup {
    let r_max = SurfaceGatherSetup::table_radius_cm(profile);
    let t = shading::gather_tables(spec, bssrdf, r_max, &|_| {}).unwrap();
    let mut setup = SurfaceGatherSetup::new(profile, t.angles, t.directional).unwrap();
    setup.shape = t.shape;
    setup.bssrdf = bssrdf;
    setup
}
