//! Triangle meshes in cm: the built-in shapes (sphere, ground plane, a thin fin) and Wavefront OBJ
//! files. Each vertex carries its albedo and SSS strength (0: no scattering, e.g. the floor).
//! Drawing them: their buffers on the GPU and the render pipeline every mesh pass uses.

use std::path::Path;

use glam::Vec3;

use crate::error::{GpuError, Result};

/// One vertex as the scene shader reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Position [cm].
    pub pos: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Diffuse albedo, RGB.
    pub albedo: [f32; 3],
    /// SSS strength (scales the kernel's width; 0 = none).
    pub strength: f32,
    /// Index of the SSS material (its kernel and shading tables), below
    /// [`crate::MAX_MATERIALS`]; a triangle takes its first vertex's, so vertices without SSS
    /// (strength 0) need a material with a kernel too (0, the default).
    pub material: u32,
    /// The surface's curvature at the scale light travels in its material, per channel [cm⁻¹]
    /// (`shading::light_scale_curvature`: the chord curvatures averaged over where the light
    /// leaves): what the scene pass reads the shape table at. 0 until
    /// [`Mesh::bake_shape_curvature`] sets it.
    pub curvature: [f32; 3],
}

impl Vertex {
    const ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32, 4 => Uint32, 5 => Float32x3
    ];

    /// The vertex buffer layout every pass that draws meshes uses.
    pub(crate) fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// A mesh uploaded for drawing.
pub(crate) struct MeshBuffers {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub count: u32,
}

impl MeshBuffers {
    /// Uploads `mesh` (or takes the buffers of an identical one from the renderer's pool).
    pub(crate) fn upload(alloc: crate::frame::pool::Alloc, mesh: &Mesh) -> MeshBuffers {
        MeshBuffers {
            vertices: alloc.constant(
                "vertices",
                wgpu::BufferUsages::VERTEX,
                bytemuck::cast_slice(&mesh.vertices),
            ),
            indices: alloc.constant(
                "indices",
                wgpu::BufferUsages::INDEX,
                bytemuck::cast_slice(&mesh.indices),
            ),
            count: mesh.indices.len() as u32,
        }
    }

    /// Draws every triangle (the pass's pipeline and bind groups set).
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.count, 0, 0..1);
    }
}

/// A render pipeline that draws meshes ([`crate::Vertex`]) with the depth test: `vs`, and `fs`
/// into colour targets of `formats` (none: depth only, no fragment stage).
pub(crate) fn pipeline(
    dev: &wgpu::Device,
    module: &wgpu::ShaderModule,
    label: &str,
    formats: &[wgpu::TextureFormat],
) -> wgpu::RenderPipeline {
    let targets: Vec<Option<wgpu::ColorTargetState>> =
        formats.iter().map(|&f| Some(f.into())).collect();
    pipeline_with(
        dev,
        module,
        label,
        &targets,
        (!formats.is_empty()).then_some("fs"),
    )
}

/// [`pipeline`] with the fragment entry point `fragment` (None: no fragment stage) writing
/// `targets`: a depth-only pass may have one that discards, a pass may write some channels only.
pub(crate) fn pipeline_with(
    dev: &wgpu::Device,
    module: &wgpu::ShaderModule,
    label: &str,
    targets: &[Option<wgpu::ColorTargetState>],
    fragment: Option<&str>,
) -> wgpu::RenderPipeline {
    dev.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: None,
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[Some(Vertex::layout())],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(depth_test()),
        multisample: Default::default(),
        fragment: fragment.map(|entry| wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Depth32 with writes and a less-than test: what every pass that draws meshes uses.
fn depth_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: wgpu::TextureFormat::Depth32Float,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// The largest OBJ file read [bytes]: 1 GiB, some 20 million triangles.
pub const MESH_CAP: u64 = 1 << 30;

/// An indexed triangle list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The vertices.
    pub vertices: Vec<Vertex>,
    /// Triangle corners as indices into `vertices`, three per triangle.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Appends another mesh.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend_from_slice(&other.vertices);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// The same mesh with every vertex on SSS material `material`.
    pub fn with_material(mut self, material: u32) -> Mesh {
        for v in &mut self.vertices {
            v.material = material;
        }
        self
    }

    /// Sets each SSS vertex's [`Vertex::curvature`] for its material's shape table in `shading`
    /// (`shading::light_scale_curvature` at the table's [`shading::ShapeTable::light_scale`],
    /// over the vertices of that material): what `sss render --shape on` reads E at. Vertices
    /// without SSS (strength 0) or whose material has no shape table keep theirs. Errors: a
    /// vertex's material beyond `shading`, a mesh the bake refuses (named).
    pub fn bake_shape_curvature(&mut self, shading: &[shading::Shading]) -> Result<()> {
        if let Some(v) = self
            .vertices
            .iter()
            .find(|v| v.material as usize >= shading.len())
        {
            return Err(GpuError::invalid(
                "vertex material",
                v.material,
                format!("must be below the {} materials shaded", shading.len()),
            ));
        }
        for (m, s) in shading.iter().enumerate() {
            let Some(table) = &s.shape else {
                continue;
            };
            let of = |v: &Vertex| v.strength > 0.0 && v.material as usize == m;
            // The material's vertices, renumbered, and the triangles among them.
            let mut index = vec![u32::MAX; self.vertices.len()];
            let mut positions = Vec::new();
            let mut normals = Vec::new();
            for (i, v) in self.vertices.iter().enumerate().filter(|(_, v)| of(v)) {
                index[i] = positions.len() as u32;
                positions.push(v.pos);
                normals.push(glam::Vec3::from(v.normal).normalize_or_zero().into());
            }
            if positions.is_empty() {
                continue;
            }
            let triangles: Vec<[u32; 3]> = (self.indices.chunks_exact(3))
                .map(|t| [0, 1, 2].map(|k| index[t[k] as usize]))
                .filter(|t| t.iter().all(|&i| i != u32::MAX))
                .collect();
            let mesh = shading::SurfaceMesh {
                positions: &positions,
                normals: &normals,
                triangles: &triangles,
            };
            let baked = shading::light_scale_curvature(mesh, table.light_scale())?;
            for (v, &i) in self.vertices.iter_mut().zip(&index) {
                if i != u32::MAX {
                    v.curvature = baked[i as usize];
                }
            }
        }
        Ok(())
    }

    /// A UV sphere.
    pub fn sphere(centre: Vec3, radius: f32, albedo: [f32; 3], strength: f32) -> Mesh {
        let (rings, segments) = (96u32, 192u32);
        let mut m = Mesh::default();
        for i in 0..=rings {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..=segments {
                let phi = std::f32::consts::TAU * j as f32 / segments as f32;
                let n = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                m.vertices.push(Vertex {
                    pos: (centre + radius * n).into(),
                    normal: n.into(),
                    albedo,
                    strength,
                    material: 0,
                    curvature: [0.0; 3],
                });
            }
        }
        let row = segments + 1;
        for i in 0..rings {
            for j in 0..segments {
                let (a, b) = (i * row + j, (i + 1) * row + j);
                m.indices.extend([a, a + 1, b, a + 1, b + 1, b]);
            }
        }
        m
    }

    /// An axis-aligned box from `min` to `max` with flat faces.
    pub fn cuboid(min: Vec3, max: Vec3, albedo: [f32; 3], strength: f32) -> Mesh {
        let mut m = Mesh::default();
        let faces: [(Vec3, Vec3, Vec3); 6] = [
            (Vec3::X, Vec3::Y, Vec3::Z),
            (-Vec3::X, Vec3::Z, Vec3::Y),
            (Vec3::Y, Vec3::Z, Vec3::X),
            (-Vec3::Y, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y),
            (-Vec3::Z, Vec3::Y, Vec3::X),
        ];
        let centre = 0.5 * (min + max);
        let half = 0.5 * (max - min);
        for (n, u, v) in faces {
            let base = m.vertices.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = centre + half * (n + su * u + sv * v);
                m.vertices.push(Vertex {
                    pos: p.into(),
                    normal: n.into(),
                    albedo,
                    strength,
                    material: 0,
                    curvature: [0.0; 3],
                });
            }
            // Counter-clockwise seen from outside (u × v = n).
            m.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        m
    }

    /// A square ground plane at height `y`, facing up.
    pub fn plane(y: f32, half: f32, albedo: [f32; 3]) -> Mesh {
        let n = [0.0, 1.0, 0.0];
        let v = |x: f32, z: f32| Vertex {
            pos: [x, y, z],
            normal: n,
            albedo,
            strength: 0.0,
            material: 0,
            curvature: [0.0; 3],
        };
        Mesh {
            vertices: vec![
                v(-half, -half),
                v(half, -half),
                v(half, half),
                v(-half, half),
            ],
            indices: vec![0, 2, 1, 0, 3, 2],
        }
    }

    /// A Wavefront OBJ file, scaled to `height` [cm] and standing on y = 0 centred at the origin;
    /// missing normals are computed from the faces. Only triangles and polygons are read (points
    /// and lines have no surface) and `mtllib` is not followed (materials are not used, and a
    /// library path such as `/dev/zero` would never end). Refused with the reason: anything but a
    /// regular file, no faces, a non-finite position or normal, a flat or overflowing extent.
    pub fn from_obj(path: &Path, height: f32, albedo: [f32; 3], strength: f32) -> Result<Mesh> {
        if !(height.is_finite() && height > 0.0) {
            return Err(GpuError::invalid(
                "mesh height",
                height,
                "must be positive and finite",
            ));
        }
        let err = |message: String| GpuError::Mesh {
            path: path.display().to_string(),
            message,
        };
        // Checked before opening: opening a FIFO would block until someone writes to it.
        let meta = std::fs::metadata(path).map_err(|e| err(e.to_string()))?;
        if !meta.is_file() {
            return Err(err("not a regular file".into()));
        }
        if meta.len() > MESH_CAP {
            return Err(err(format!(
                "{} MiB, above the cap of {} MiB on meshes",
                meta.len() >> 20,
                MESH_CAP >> 20
            )));
        }
        let file = std::fs::File::open(path).map_err(|e| err(e.to_string()))?;
        let (models, _) = tobj::load_obj_buf(
            &mut std::io::BufReader::new(file),
            &tobj::LoadOptions {
                triangulate: true,
                single_index: true,
                ignore_points: true,
                ignore_lines: true,
            },
            |_| Err(tobj::LoadError::OpenFileFailed),
        )
        .map_err(|e| err(e.to_string()))?;
        let mut m = Mesh::default();
        for model in &models {
            let mesh = &model.mesh;
            let base = m.vertices.len() as u32;
            let count = mesh.positions.len() / 3;
            for k in 0..count {
                let p = [
                    mesh.positions[3 * k],
                    mesh.positions[3 * k + 1],
                    mesh.positions[3 * k + 2],
                ];
                let n = if mesh.normals.len() == mesh.positions.len() {
                    [
                        mesh.normals[3 * k],
                        mesh.normals[3 * k + 1],
                        mesh.normals[3 * k + 2],
                    ]
                } else {
                    [0.0; 3]
                };
                for (what, v) in [("position", p), ("normal", n)] {
                    if v.iter().any(|c| !c.is_finite()) {
                        return Err(err(format!(
                            "non-finite vertex {what} {v:?} in object {:?}",
                            model.name
                        )));
                    }
                }
                m.vertices.push(Vertex {
                    pos: p,
                    normal: n,
                    albedo,
                    strength,
                    material: 0,
                    curvature: [0.0; 3],
                });
            }
            m.indices.extend(mesh.indices.iter().map(|i| i + base));
        }
        if m.indices.is_empty() {
            return Err(err("no triangles".into()));
        }
        m.fill_missing_normals();
        let (lo, hi) = m.bounds();
        let extent = hi - lo;
        if !(extent.is_finite() && extent.y > 0.0) {
            return Err(err(format!(
                "extent {:?} cm: its height (y) must be positive and every side finite",
                extent.to_array()
            )));
        }
        let scale = height / extent.y;
        let shift = Vec3::new(-0.5 * (lo.x + hi.x), -lo.y, -0.5 * (lo.z + hi.z));
        for v in &mut m.vertices {
            v.pos = ((Vec3::from(v.pos) + shift) * scale).into();
        }
        if let Some(v) = m.vertices.iter().find(|v| !Vec3::from(v.pos).is_finite()) {
            return Err(err(format!(
                "scaling to {height} cm tall overflows f32 at {:?}",
                v.pos
            )));
        }
        Ok(m)
    }

    /// Area-weighted vertex normals for the vertices without one (a file may give normals for
    /// some faces only); a zero normal would shade as NaN.
    fn fill_missing_normals(&mut self) {
        if self.vertices.iter().all(|v| v.normal != [0.0; 3]) {
            return;
        }
        let mut acc = vec![Vec3::ZERO; self.vertices.len()];
        for t in self.indices.chunks(3) {
            let p = |i: u32| Vec3::from(self.vertices[i as usize].pos);
            let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            for &i in t {
                acc[i as usize] += n;
            }
        }
        for (v, n) in self.vertices.iter_mut().zip(acc) {
            if v.normal == [0.0; 3] {
                v.normal = n.normalize_or(Vec3::Y).into();
            }
        }
    }

    /// Axis-aligned bounds.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), v| (lo.min(Vec3::from(v.pos)), hi.max(Vec3::from(v.pos))),
        )
    }
}
