//! The curvature a body has at the scale light travels in it: what a real-time pass reads the
//! shape table ([`crate::ShapeTable`]) at, baked per vertex.
//!
//! The shape-aware surface gather reads E at the curvature of each chord from an entry x to an
//! exit y, κ(x, y) = (n_y − n_x)·(y − x)/|y − x|²: 1/R between any two points of a sphere of
//! radius R, −1/R around a cavity, 0 on a plane; on any surface the normal curvature along the
//! chord at the chord's own length. A real-time pass has one entry per pixel and no exits to pair
//! it with, and the curvature its screen-space derivatives give is the surface's at the pixel's
//! scale, not the light's: across a ridge whose sides are flat (a nose's), the sides' pixels read
//! 0 where the light entering them leaves around the ridge. So each vertex keeps its chord
//! curvature averaged over where the light entering there leaves,
//!
//! κ̄(x) = Σ_y a_y p(|y − x|) κ(x, y) / Σ_y a_y p(|y − x|),  p(r) = e^{−r/s}/max(r, ρ_x),
//!
//! over the other vertices y of its body (a_y: a third of the area of y's triangles): exits whose
//! distance from the entry is exponentially distributed (p per unit area, so p·2πr per unit
//! radius) with the mean s = ⟨s⟩ of the half-space's exits (the shape table's width at κ = 0,
//! θ = 0), per channel. Within ρ_x = √(a_x/π), the radius of x's own share of the surface, p is
//! held at its value there (a close neighbour weighs as a neighbour, not as 1/r), and a vertex
//! within 10⁻³ρ_x of x is x's twin across a seam, not an exit. Exact identities: on a sphere every chord's κ is 1/R, so κ̄ = 1/R at any
//! scale and mesh density; on a plane 0. Vertices facing away from x (n_y·n_x ≤ 0: the other face
//! of a thin part, whose light the slab rows account for) and vertices of other bodies (not joined
//! to x by triangles) are not x's exits. Distances beyond [`REACH`]·s are not summed.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::error::{Result, ShadingError};

/// Exits farther than this many mean distances s are not summed (p·2πr = 2π e^{−r/s}: e⁻⁸ =
/// 3·10⁻⁴ of the exits lie beyond).
pub const REACH: f32 = 8.0;

/// A triangle mesh as plain data: positions [cm], unit normals, triangles as vertex indices.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceMesh<'a> {
    /// Vertex positions [cm].
    pub positions: &'a [[f32; 3]],
    /// Unit vertex normals, pointing out of the body.
    pub normals: &'a [[f32; 3]],
    /// Triangles, three vertex indices each.
    pub triangles: &'a [[u32; 3]],
}

/// κ̄ per vertex and channel [cm⁻¹] (module docs) at the exits' mean distances `mean_cm` [cm] per
/// channel (`ShapeTable::light_scale`); a channel whose mean distance is 0 (it does not scatter)
/// and a vertex with no exits in reach get 0, the half-space. Deterministic (each vertex's sum in
/// a fixed order), in parallel over vertices. Errors name the field: positions and normals of
/// different lengths, a triangle's index out of range, a non-finite position or normal, a mean
/// distance negative or not finite.
pub fn light_scale_curvature(mesh: SurfaceMesh, mean_cm: [f32; 3]) -> Result<Vec<[f32; 3]>> {
    check(mesh, mean_cm)?;
    let n = mesh.positions.len();
    let reach = REACH * mean_cm.iter().fold(0.0f32, |a, &b| a.max(b));
    if n == 0 || reach <= 0.0 {
        return Ok(vec![[0.0; 3]; n]);
    }
    let area = vertex_areas(mesh);
    let own: Vec<f32> = area
        .iter()
        .map(|a| (a / std::f32::consts::PI).sqrt())
        .collect();
    let body = bodies(n, mesh.triangles);
    // Vertices by cell of side reach/2: every exit in reach lies in the 5³ cells around.
    let cell = |p: [f32; 3]| p.map(|c| (2.0 * c / reach).floor() as i32);
    let mut grid: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
    for (i, &p) in mesh.positions.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i as u32);
    }
    let inv_mean = mean_cm.map(|s| if s > 0.0 { 1.0 / s } else { 0.0 });
    let of_vertex = |x: usize| -> [f32; 3] {
        let (px, nx) = (
            glam::Vec3::from(mesh.positions[x]),
            glam::Vec3::from(mesh.normals[x]),
        );
        let (mut num, mut den) = ([0.0f64; 3], [0.0f64; 3]);
        let c = cell(mesh.positions[x]);
        for dx in -2..=2 {
            for dy in -2..=2 {
                for dz in -2..=2 {
                    let Some(ys) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &y in ys {
                        let y = y as usize;
                        let ny = glam::Vec3::from(mesh.normals[y]);
                        if y == x || body[y] != body[x] || ny.dot(nx) <= 0.0 {
                            continue;
                        }
                        let d = glam::Vec3::from(mesh.positions[y]) - px;
                        let r2 = d.length_squared();
                        if r2 >= reach * reach {
                            continue;
                        }
                        let r = r2.sqrt();
                        if r <= 1e-3 * own[x] {
                            continue;
                        }
                        let near = r.max(own[x]);
                        let kappa = f64::from((ny - nx).dot(d) / r2);
                        for ch in 0..3 {
                            if inv_mean[ch] > 0.0 && r * inv_mean[ch] < REACH {
                                let w = f64::from(area[y] * (-r * inv_mean[ch]).exp() / near);
                                num[ch] += w * kappa;
                                den[ch] += w;
                            }
                        }
                    }
                }
            }
        }
        [0, 1, 2].map(|ch| {
            if den[ch] > 0.0 {
                (num[ch] / den[ch]) as f32
            } else {
                0.0
            }
        })
    };
    Ok((0..n).into_par_iter().map(of_vertex).collect())
}

/// Checks the mesh and the mean distances; errors name the field.
fn check(mesh: SurfaceMesh, mean_cm: [f32; 3]) -> Result<()> {
    if mesh.normals.len() != mesh.positions.len() {
        return Err(ShadingError::invalid(
            "curvature: normals",
            mesh.normals.len(),
            format!("must be one per position ({})", mesh.positions.len()),
        ));
    }
    for (field, values) in [("positions", mesh.positions), ("normals", mesh.normals)] {
        if let Some(i) = values.iter().position(|v| v.iter().any(|c| !c.is_finite())) {
            return Err(ShadingError::invalid(
                format!("curvature: {field}[{i}]"),
                format!("{:?}", values[i]),
                "must be finite",
            ));
        }
    }
    let n = mesh.positions.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i as usize >= n))
    {
        return Err(ShadingError::invalid(
            format!("curvature: triangles[{t}]"),
            format!("{:?}", mesh.triangles[t]),
            format!("indices must be below the vertex count {n}"),
        ));
    }
    for (c, s) in mean_cm.iter().enumerate() {
        if !(s.is_finite() && *s >= 0.0) {
            return Err(ShadingError::invalid(
                format!("curvature: mean exit distance of channel {c} [cm]"),
                s,
                "must be finite and ≥ 0",
            ));
        }
    }
    Ok(())
}

/// A third of the area of each vertex's triangles [cm²].
fn vertex_areas(mesh: SurfaceMesh) -> Vec<f32> {
    let mut area = vec![0.0f32; mesh.positions.len()];
    for t in mesh.triangles {
        let [a, b, c] = t.map(|i| glam::Vec3::from(mesh.positions[i as usize]));
        let third = (b - a).cross(c - a).length() / 6.0;
        for &i in t {
            area[i as usize] += third;
        }
    }
    area
}

/// The body of each vertex: vertices joined by triangles share one (union–find, each labelled by
/// its smallest vertex).
fn bodies(n: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let up = parent[parent[i as usize] as usize];
            parent[i as usize] = up;
            i = up;
        }
        i
    }
    for t in triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            let (lo, hi) = (a.min(b), a.max(b));
            parent[hi as usize] = lo;
        }
    }
    (0..n as u32).map(|i| root(&mut parent, i)).collect()
}
