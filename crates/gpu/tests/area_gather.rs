//! The area gather (Maisch & Ropinski 2020) against what it must equal: the GPU's table lookup
//! against `fit`'s table, the pixels' footprint areas against the surface's area, the dense
//! gather against the CPU 2D convolution of the same irradiance with R′, and the layered pattern
//! against energy conservation on an evenly lit plane. Under CI=true a missing adapter fails.

use glam::Vec3;
use gpu::{
    AlbedoMode, AreaGatherSetup, AreaKernel, Camera, Frame, GatherPattern, Light, Mesh,
    RenderParams, Renderer, Scatter, Scene, Vertex,
};

mod common;
use common::gpu;

/// A medium whose kernel reaches r_max ≈ 0.93 cm (Q(r) = 10⁻⁷ cm⁻¹ there).
fn kernel(n: usize) -> (AreaKernel, fit::area_table::AreaTable) {
    let m = fit::analytic::Medium {
        sigma_a: 0.5,
        sigma_s: 20.0,
        g: 0.0,
        eta: 1.3,
    };
    let p = fit::analytic::Model::Pbd.radial(&m).unwrap();
    let rd = |x: f64| p.rd(x.max(1e-12));
    let r_max = fit::area_table::cutoff_radius(&m, 1e-7);
    let table = fit::area_table::AreaTable::build([&rd, &rd, &rd], r_max, n, n);
    (AreaKernel::new(&table).unwrap(), table)
}

/// A square of half-width `half` [cm] in the plane y = 0, facing +y, with SSS: the floor mesh
/// given a strength.
fn square(half: f32) -> Mesh {
    let mut m = Mesh::plane(0.0, half, [1.0; 3]);
    for v in &mut m.vertices {
        v.strength = 1.0;
    }
    m
}

fn scene(mesh: Mesh, camera: Camera, towards: Vec3) -> Scene {
    Scene {
        mesh,
        camera,
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

fn params(size: u32) -> RenderParams {
    RenderParams {
        width: size,
        height: size,
        albedo: AlbedoMode::Post,
        ..RenderParams::default()
    }
}

#[test]
fn the_gpu_lookup_equals_the_table() {
    let Some(gpu) = gpu() else { return };
    let (k, table) = kernel(64);
    let r_max = table.r_max as f32;
    let mut state = 7u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f32 / (1u64 << 53) as f32
    };
    // Distances up to 1.2 r_max (beyond it: 0) and disc radii up to 1.2 r_max (beyond the last
    // row: clamped), some at exact texel centres.
    let mut points: Vec<[f32; 2]> = (0..2000)
        .map(|_| {
            let (r, ra) = (1.2 * r_max * next(), 1.2 * r_max * next().powi(2));
            [r, std::f32::consts::PI * ra * ra]
        })
        .collect();
    points.extend((0..64).map(|i| [table.r_at(i) as f32, table.area_at(i) as f32]));
    // The CPU twin reads fit's table: R′/energy, with the width factor's scaling.
    for &[r, a] in &points {
        let got = k.lookup(r, a, 1.0);
        for (c, g) in got.iter().enumerate() {
            let want = if r <= r_max {
                (table.lookup(c, r as f64, a as f64) / table.energy[c]) as f32
            } else {
                0.0
            };
            assert!(
                (g - want).abs() <= 1e-4 * want + 1e-6,
                "r {r}, A {a}: {g} vs {want}"
            );
        }
        let wide = k.lookup(2.5 * r, 6.25 * a, 2.5);
        for c in 0..3 {
            assert!((wide[c] * 6.25 - got[c]).abs() <= 1e-4 * got[c] + 1e-6);
        }
    }
    let renderer = Renderer::new(&gpu);
    for scale in [1.0, 2.5] {
        let on_gpu = renderer.area_lookup(&gpu, &k, scale, &points).unwrap();
        for (&[r, a], g) in points.iter().zip(&on_gpu) {
            let want = k.lookup(r, a, scale);
            for c in 0..3 {
                assert!(
                    (g[c] - want[c]).abs() <= 2e-5 * want[c] + 1e-7,
                    "scale {scale}, r {r}, A {a}: GPU {} vs CPU {}",
                    g[c],
                    want[c]
                );
            }
        }
    }
}

/// Σ over pixels of the footprint area is the area of the surface seen: a 10 × 10 cm square seen
/// at 60° and at 75° from its normal. The pixel at the image's centre covers (d/f)²/cos θ, d the
/// distance and f the focal length in pixels; at 88° (cos θ < gpu::gathers::area_gather::GRAZING) the
/// frontal footprint over the bound instead.
#[test]
fn footprint_areas_add_up_to_the_surface_seen() {
    let Some(gpu) = gpu() else { return };
    let (k, _) = kernel(16);
    let setup = AreaGatherSetup {
        pattern: GatherPattern::dense(0),
        ..AreaGatherSetup::new(k)
    };
    let size = 256u32;
    let frame = |deg: f32| {
        let t = deg.to_radians();
        let camera = Camera {
            position: 40.0 * Vec3::new(0.0, t.cos(), t.sin()),
            target: Vec3::ZERO,
            fov_y_deg: 20.0,
        };
        let s = scene(square(5.0), camera, Vec3::Y);
        let f = gpu::render(&gpu, &s, Scatter::AreaGather(&setup), &params(size)).unwrap();
        let centre = f.surface[(size / 2 * size + size / 2) as usize][3] as f64;
        let sum = f.surface.iter().map(|v| v[3] as f64).sum::<f64>();
        let d_over_f = 40.0 / camera.px_per_cm_at_unit_depth(size) as f64;
        (sum, centre, d_over_f * d_over_f)
    };
    for deg in [60.0f32, 75.0] {
        let (sum, centre, frontal) = frame(deg);
        assert!(
            (sum / 100.0 - 1.0).abs() < 0.01,
            "{deg}°: Σ A = {sum} cm², want 100"
        );
        let want = frontal / (deg as f64).to_radians().cos();
        // The derivatives are differences across the pixel's 2×2 quad: off by up to a pixel
        // along the depth's slope (0.5 % per pixel at 75° here).
        assert!(
            (centre / want - 1.0).abs() < 0.02,
            "{deg}°: {centre} vs {want}"
        );
    }
    let cos = 88f32.to_radians().cos();
    assert!(cos < gpu::gathers::area_gather::GRAZING);
    let (_, centre, frontal) = frame(88.0);
    let want = frontal / gpu::gathers::area_gather::GRAZING as f64;
    // 28.6× the frontal depth slope at 88°: 4 % per pixel across the quad.
    assert!((centre / want - 1.0).abs() < 0.1, "88°: {centre} vs {want}");
}

/// A square lit at 40° with a box standing on it: a shadow edge, and holes without SSS where the
/// box is seen. Camera straight above, ≈ 0.1 cm per pixel, so the kernel reaches ≈ 9 px; the
/// square lies within the view, so no light enters where the camera does not see (no splats).
fn shadowed() -> Scene {
    let mut mesh = square(4.5);
    mesh.append(&Mesh::cuboid(
        Vec3::new(-1.0, 0.0, -1.0),
        Vec3::new(1.0, 1.5, 1.0),
        [0.5; 3],
        0.0,
    ));
    let t = 40f32.to_radians();
    let camera = Camera {
        position: Vec3::new(0.0, 60.0, 0.0),
        target: Vec3::ZERO,
        fov_y_deg: 9.0,
    };
    scene(mesh, camera, Vec3::new(t.sin(), t.cos(), 0.0))
}

/// The frame gathered with `pattern` and the kernel widened by `width`.
fn gather(gpu: &gpu::Gpu, scene: &Scene, pattern: GatherPattern, size: u32, width: f32) -> Frame {
    let setup = AreaGatherSetup {
        pattern,
        ..AreaGatherSetup::new(kernel(256).0)
    };
    let p = RenderParams {
        sss_width: width,
        ..params(size)
    };
    gpu::render(gpu, scene, Scatter::AreaGather(&setup), &p).unwrap()
}

/// The dense pattern is the brute-force screen-space 2D convolution: per SSS pixel
/// Σ_j E_j·A_j·R′(|x_j − x_o|, A_j) over the pixels j within the block, which the CPU sums from
/// the frame's irradiance, positions and areas.
#[test]
fn the_dense_gather_is_the_2d_convolution_with_the_area_kernel() {
    let Some(gpu) = gpu() else { return };
    let size = 96;
    let n = 11i64;
    let f = gather(&gpu, &shadowed(), GatherPattern::dense(n as u32), size, 1.0);
    let k = kernel(256).0;
    let s = size as i64;
    let max = f
        .scattered
        .iter()
        .map(|v| v[0].max(v[1]).max(v[2]))
        .fold(0.0, f32::max);
    assert!(max > 0.5, "the lit square scatters: max {max}");
    let mut checked = 0;
    for y in 0..s {
        for x in 0..s {
            let o = (y * s + x) as usize;
            if f.geometry[o][1] <= 0.0 {
                assert_eq!(f.scattered[o][..3], [0.0; 3], "pixel without SSS");
                continue;
            }
            let xo = Vec3::from_slice(&f.surface[o][..3]);
            let mut want = [0.0f32; 3];
            for dy in -n..=n {
                for dx in -n..=n {
                    let (u, v) = (x + dx, y + dy);
                    if u < 0 || v < 0 || u >= s || v >= s {
                        continue;
                    }
                    let j = (v * s + u) as usize;
                    let a = f.surface[j][3];
                    if a <= 0.0 {
                        continue;
                    }
                    let d = Vec3::from_slice(&f.surface[j][..3]).distance(xo);
                    let r = k.lookup(d, a, 1.0);
                    for (c, w) in want.iter_mut().enumerate() {
                        *w += f.irradiance[j][c] * a * r[c];
                    }
                }
            }
            for (c, w) in want.iter().enumerate() {
                let g = f.scattered[o][c];
                assert!(
                    (g - w).abs() < 1e-5 * max,
                    "pixel ({x}, {y}) channel {c}: GPU {g} vs CPU {w}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 4000, "{checked} SSS pixels");
}

/// On an evenly lit plane the layered pattern's cells tile the surface, so the gathered light is
/// the irradiance (the kernel has unit energy), to within the table's bilinear interpolation near
/// the kernel's peak (1.3 % with 64², 0.4 % with 256² texels here): for a kernel of ≈ 9 px, as
/// the dense gather, and widened 6× (≈ 56 px, most of it in the outer layers). The paper's √i
/// brightening adds energy that is not there.
#[test]
fn the_layered_pattern_conserves_energy_on_an_evenly_lit_plane() {
    let Some(gpu) = gpu() else { return };
    let camera = Camera {
        position: Vec3::new(0.0, 60.0, 0.0),
        target: Vec3::ZERO,
        fov_y_deg: 24.0,
    };
    let s = scene(square(60.0), camera, Vec3::Y);
    let size = 256u32;
    let centre = |f: &Frame| {
        let i = (size / 2 * size + size / 2) as usize;
        [0, 1, 2].map(|c| f.scattered[i][c] / f.irradiance[i][c])
    };
    for (pattern, width) in [
        (GatherPattern::default(), 1.0),
        (GatherPattern::dense(24), 1.0),
        (GatherPattern::default(), 6.0),
    ] {
        let got = centre(&gather(&gpu, &s, pattern, size, width));
        for (c, g) in got.iter().enumerate() {
            assert!(
                (g - 1.0).abs() < 0.01,
                "{pattern:?}, width {width}: channel {c}: {g}"
            );
        }
    }
    let bright = GatherPattern {
        brighten: true,
        ..GatherPattern::default()
    };
    let got = centre(&gather(&gpu, &s, bright, size, 6.0));
    assert!(got[0] > 1.1, "brightened: {got:?}");
}

/// An n×n grid of squares in the plane y = `y`, half-width `half` [cm], facing `normal_y` (±1).
fn grid(half: f32, y: f32, normal_y: f32, n: u32) -> Mesh {
    let step = 2.0 * half / n as f32;
    let mut vertices = Vec::new();
    for k in 0..=n {
        for i in 0..=n {
            vertices.push(Vertex {
                pos: [-half + i as f32 * step, y, -half + k as f32 * step],
                normal: [0.0, normal_y, 0.0],
                albedo: [1.0; 3],
                strength: 1.0,
                material: 0,
                curvature: [0.0; 3],
            });
        }
    }
    let at = |i: u32, k: u32| k * (n + 1) + i;
    let mut indices = Vec::new();
    for k in 0..n {
        for i in 0..n {
            // Counter-clockwise seen from the side the normal points to.
            let quad = [at(i, k), at(i, k + 1), at(i + 1, k + 1), at(i + 1, k)];
            let q = if normal_y > 0.0 {
                quad
            } else {
                [quad[0], quad[3], quad[2], quad[1]]
            };
            indices.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
        }
    }
    Mesh { vertices, indices }
}

/// A slab `d` cm thick lit from behind, seen from the front: the front face receives no light,
/// the back face's triangles are splats (facing away from the camera, behind the face seen), and
/// the light at the front's centre is Σ E·A·R′(|x − x_o|, A) over them (summed here on the CPU),
/// with x the triangle's centre or eq. 9's point. As d → 0 the centres' sum tends to the kernel's
/// unit energy, while eq. 9 counts the kernel's peak once per nearby triangle. With the light in
/// front instead, the back face is dark and nothing is splatted.
#[test]
fn splats_carry_the_light_through_a_slab() {
    let Some(gpu) = gpu() else { return };
    let (k, _) = kernel(256);
    let camera = Camera {
        position: Vec3::new(0.0, 60.0, 0.0),
        target: Vec3::ZERO,
        fov_y_deg: 12.0,
    };
    let size = 128u32;
    let c = (size / 2 * size + size / 2) as usize;
    // The kernel widened 8× (r_max ≈ 7.4 cm) over triangles of 0.25 cm, so that the splats
    // sample it finely; the slab reaches beyond the view and the kernel.
    let width = 8.0;
    let p = RenderParams {
        sss_width: width,
        ..params(size)
    };
    // `towards`: the direction to the light.
    for (d, towards, clamp) in [
        (0.02, Vec3::NEG_Y, false),
        (0.5, Vec3::NEG_Y, false),
        (2.0, Vec3::NEG_Y, false),
        (0.02, Vec3::NEG_Y, true),
        (0.5, Vec3::Y, false),
    ] {
        let setup = AreaGatherSetup {
            splat_clamp: clamp,
            ..AreaGatherSetup::new(k.clone())
        };
        let mut mesh = grid(8.0, 0.0, 1.0, 64);
        mesh.append(&grid(8.0, -d, -1.0, 64));
        let s = scene(mesh, camera, towards);
        let f = gpu::render(&gpu, &s, Scatter::AreaGather(&setup), &p).unwrap();
        let got = f.scattered[c];
        if towards == Vec3::Y {
            // Lit in front: the gathered light only, which is the even irradiance (to the
            // table's interpolation near the peak); a splat would add a third or more.
            let ratio = got[0] / f.irradiance[c][0];
            assert!((ratio - 1.0).abs() < 0.02, "lit in front: {ratio}");
            continue;
        }
        assert_eq!(f.irradiance[c][..3], [0.0; 3], "the front face is dark");
        let back = grid(8.0, -d, -1.0, 64);
        let field = |xo: Vec3| {
            let mut sum = 0.0f64;
            for t in back.indices.chunks_exact(3) {
                let p = [0, 1, 2].map(|j| Vec3::from(back.vertices[t[j] as usize].pos));
                let a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
                let xi = (p[0] + p[1] + p[2]) / 3.0;
                let n = Vec3::NEG_Y;
                let xb = xo - n * (xo - xi).dot(n);
                let l = (xb - xi).length();
                let x = if clamp && l > 0.0 {
                    xi + (xb - xi) / l * (a / std::f32::consts::PI).sqrt().min(l)
                } else {
                    xi
                };
                sum += (a * k.lookup(x.distance(xo), a, width)[0]) as f64;
            }
            sum
        };
        // The GPU's receivers: the mean positions of 4×4-pixel blocks, brought back to the pixel
        // by cubic B-spline weights.
        let block = |bx: u32, by: u32| {
            let mut m = Vec3::ZERO;
            for y in 4 * by..4 * by + 4 {
                for x in 4 * bx..4 * bx + 4 {
                    m += Vec3::from_slice(&f.surface[(y * size + x) as usize][..3]);
                }
            }
            m / 16.0
        };
        let bspline = |t: f64| {
            [
                (1.0 - t).powi(3) / 6.0,
                (4.0 - 6.0 * t * t + 3.0 * t.powi(3)) / 6.0,
                (1.0 + 3.0 * t + 3.0 * t * t - 3.0 * t.powi(3)) / 6.0,
                t.powi(3) / 6.0,
            ]
        };
        let u = (size / 2) as f64 / 4.0 + 0.125 - 0.5;
        let (b0, w) = (u.floor() as u32, bspline(u - u.floor()));
        let mut want = 0.0;
        for (j, wy) in w.iter().enumerate() {
            for (i, wx) in w.iter().enumerate() {
                want += wx * wy * field(block(b0 + i as u32 - 1, b0 + j as u32 - 1));
            }
        }
        let rel = got[0] as f64 / want - 1.0;
        assert!(rel.abs() < 1e-4, "d = {d}: GPU {} vs CPU {want}", got[0]);
        if d < 0.05 && !clamp {
            assert!((want - 1.0).abs() < 0.02, "d = {d}: {want}");
        }
        if clamp {
            assert!(want > 1.3, "eq. 9 at d = {d}: {want}");
        }
    }
}
