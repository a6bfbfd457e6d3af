//! Where a frame's scattering passes draw: the frame's scene, camera, size and mesh, the
//! G-buffer they read and the scattered light they write (the passes' side of
//! [`crate::frame::recording`]).

use glam::Mat4;

use crate::mesh::MeshBuffers;
use crate::passes::gbuffer::GBuffer;
use crate::scene::Scene;

/// What the scattering passes of a frame read and write: the scene, the camera's projection,
/// the image size, the mesh, the G-buffer and the scattered light they produce.
#[derive(Clone, Copy)]
pub(crate) struct Target<'a> {
    pub scene: &'a Scene,
    pub camera_view_proj: Mat4,
    pub size: (u32, u32),
    pub mesh: &'a MeshBuffers,
    pub gbuffer: &'a GBuffer,
    pub scattered: &'a wgpu::Buffer,
}
