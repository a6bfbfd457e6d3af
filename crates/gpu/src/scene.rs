//! Scenes: meshes, a camera and lights. Units are cm; y is up.

use std::path::Path;

use glam::{Mat4, Vec3};

use crate::error::{GpuError, Result};
use crate::light::{Emitter, Light};
use crate::mesh::Mesh;

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position [cm].
    pub position: Vec3,
    /// Point looked at [cm].
    pub target: Vec3,
    /// Vertical field of view [degrees].
    pub fov_y_deg: f32,
}

impl Camera {
    /// View matrix (right-handed, looking down −z), with +y up unless the camera looks (nearly)
    /// straight up or down, where +z is up instead.
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(
            self.position,
            self.target,
            up_for(self.target - self.position),
        )
    }

    /// Projection with wgpu's [0, 1] depth.
    pub fn projection(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_y_deg.to_radians(), aspect, near, far)
    }

    /// Pixels per cm on a surface facing the camera at view depth 1 cm: height/(2·tan(fov_y/2)).
    pub fn px_per_cm_at_unit_depth(&self, height: u32) -> f32 {
        height as f32 / (2.0 * (0.5 * self.fov_y_deg.to_radians()).tan())
    }
}

/// How the albedo is split around the scattering (thesis §4.4): before, after, or √ on both sides.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlbedoMode {
    /// All of the albedo before the scattering: the blur spreads irradiance × albedo.
    Pre,
    /// All of the albedo after the scattering: the blur spreads the irradiance, and its result is
    /// multiplied by the albedo.
    Post,
    /// √albedo before and √albedo after the scattering.
    PrePost,
}

/// What the scene pass draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// All geometry: the SSS objects (strength > 0) and the floor.
    pub mesh: Mesh,
    /// The view.
    pub camera: Camera,
    /// The lights: at most [`crate::MAX_EMITTERS`] emitters in all, an area light counting
    /// [`crate::AREA_CELLS`]².
    pub lights: Vec<Light>,
    /// Constant ambient irradiance, RGB.
    pub ambient: Vec3,
    /// Blinn–Phong specular intensity and exponent.
    pub specular: f32,
    /// Blinn–Phong exponent of the specular highlight.
    pub shininess: f32,
}

/// The skin-like albedo of the built-in SSS objects and the grey of the floor.
const OBJECT_ALBEDO: [f32; 3] = [0.9, 0.75, 0.65];
const FLOOR_ALBEDO: [f32; 3] = [0.5, 0.5, 0.5];

impl Scene {
    fn around(mut mesh: Mesh, camera: Camera) -> Scene {
        mesh.append(&Mesh::plane(0.0, 60.0, FLOOR_ALBEDO));
        Scene {
            mesh,
            camera,
            lights: vec![Light::Directional {
                towards: Vec3::new(-0.6, 1.0, 0.5).normalize(),
                irradiance: Vec3::splat(1.2),
                shadow: true,
            }],
            ambient: Vec3::splat(0.03),
            specular: 0.15,
            shininess: 60.0,
        }
    }

    /// A 5 cm sphere on a floor.
    pub fn sphere() -> Scene {
        Scene::around(
            Mesh::sphere(Vec3::new(0.0, 5.0, 0.0), 5.0, OBJECT_ALBEDO, 1.0),
            Camera {
                position: Vec3::new(0.0, 9.0, 24.0),
                target: Vec3::new(0.0, 4.0, 0.0),
                fov_y_deg: 35.0,
            },
        )
    }

    /// Thin parts: a sphere with a 3 mm fin and a 1 mm fin standing beside it (light bleeds
    /// through and around thin geometry; depth discontinuities all along the fins' edges).
    pub fn fin() -> Scene {
        let mut m = Mesh::sphere(Vec3::new(-4.0, 4.0, 0.0), 4.0, OBJECT_ALBEDO, 1.0);
        m.append(&Mesh::cuboid(
            Vec3::new(1.5, 0.0, -3.0),
            Vec3::new(1.8, 9.0, 3.0),
            OBJECT_ALBEDO,
            1.0,
        ));
        m.append(&Mesh::cuboid(
            Vec3::new(4.5, 0.0, -2.0),
            Vec3::new(4.6, 6.0, 2.0),
            OBJECT_ALBEDO,
            1.0,
        ));
        Scene::around(
            m,
            Camera {
                position: Vec3::new(4.0, 8.0, 22.0),
                target: Vec3::new(0.5, 4.0, 0.0),
                fov_y_deg: 35.0,
            },
        )
    }

    /// Two 4 cm spheres side by side, 0.4 cm apart: SSS material 0 on the left, 1 on the right
    /// (two materials in one frame).
    pub fn pair() -> Scene {
        let mut m = Mesh::sphere(Vec3::new(-4.2, 4.0, 0.0), 4.0, OBJECT_ALBEDO, 1.0);
        m.append(&Mesh::sphere(Vec3::new(4.2, 4.0, 0.0), 4.0, OBJECT_ALBEDO, 1.0).with_material(1));
        Scene::around(
            m,
            Camera {
                position: Vec3::new(0.0, 9.0, 26.0),
                target: Vec3::new(0.0, 4.0, 0.0),
                fov_y_deg: 35.0,
            },
        )
    }

    /// The SSS materials the scene uses: one more than the largest `material` index among its
    /// vertices (0: no SSS surfaces). Vertices without SSS count too: a triangle takes its
    /// material from its first vertex, whose strength may be 0 where an SSS part meets another.
    pub fn material_count(&self) -> usize {
        if !self.mesh.vertices.iter().any(|v| v.strength > 0.0) {
            return 0;
        }
        self.mesh
            .vertices
            .iter()
            .map(|v| v.material as usize + 1)
            .max()
            .unwrap_or(0)
    }

    /// An OBJ model scaled to 10 cm tall on the floor.
    pub fn obj(path: &Path) -> Result<Scene> {
        let mesh = Mesh::from_obj(path, 10.0, OBJECT_ALBEDO, 1.0)?;
        Ok(Scene::around(
            mesh,
            Camera {
                position: Vec3::new(0.0, 8.0, 26.0),
                target: Vec3::new(0.0, 5.0, 0.0),
                fov_y_deg: 35.0,
            },
        ))
    }

    /// A built-in scene by name (`sphere`, `fin`, `pair`) or an OBJ path.
    pub fn named(name: &str) -> Result<Scene> {
        match name {
            "sphere" => Ok(Scene::sphere()),
            "fin" => Ok(Scene::fin()),
            "pair" => Ok(Scene::pair()),
            p if p.ends_with(".obj") => Scene::obj(Path::new(p)),
            other => Err(GpuError::invalid(
                "scene",
                other,
                "expected sphere, fin, pair or a path to an .obj file",
            )),
        }
    }

    /// An emitter's view-projection for its shadow map: orthographic over the scene's bounding
    /// sphere for directional lights, perspective onto it from points (point lights, the cells
    /// of area lights).
    pub(crate) fn light_view_proj(&self, light: &Emitter) -> Mat4 {
        let (centre, radius) = self.shadow_bounds();
        let at = light.pos_or_dir.truncate();
        if light.pos_or_dir.w == 0.0 {
            let eye = centre + at * 3.0 * radius;
            Mat4::orthographic_rh(-radius, radius, -radius, radius, 0.1, 6.0 * radius)
                * Mat4::look_at_rh(eye, centre, up_for(at))
        } else {
            let d = (centre - at).length().max(1e-3);
            let fov = (2.0 * (radius / d).min(0.99).asin()).min(2.9);
            // Occluders between the point and the objects (non-scattering boxes) must lie beyond
            // the near plane: the nearest vertex of anything counts, with a margin of 10 % (a
            // large face whose interior comes closer than that to the point is still clipped).
            let nearest = self
                .mesh
                .vertices
                .iter()
                .map(|v| (Vec3::from(v.pos) - at).length())
                .fold(f32::MAX, f32::min);
            let near = (d - radius).min(0.9 * nearest).max(0.1);
            Mat4::perspective_rh(fov, 1.0, near, d + 3.0 * radius)
                * Mat4::look_at_rh(at, centre, up_for(centre - at))
        }
    }

    /// The sphere the shadow maps cover [cm]: centre and radius, 1.5 × the half-diagonal of the
    /// SSS objects' bounding box (of everything when there are none; the floor is large).
    pub(crate) fn shadow_bounds(&self) -> (Vec3, f32) {
        let (lo, hi) = self.mesh.bounds();
        // The floor is large; shadow maps cover the objects on it.
        let objects: Vec<_> = self
            .mesh
            .vertices
            .iter()
            .filter(|v| v.strength > 0.0)
            .collect();
        let (lo, hi) = if objects.is_empty() {
            (lo, hi)
        } else {
            objects.iter().fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(a, b), v| (a.min(Vec3::from(v.pos)), b.max(Vec3::from(v.pos))),
            )
        };
        (0.5 * (lo + hi), 0.5 * (hi - lo).length() * 1.5)
    }

    /// Every emitter of the scene's lights, in order.
    pub(crate) fn emitters(&self) -> Vec<Emitter> {
        crate::light::emitters(&self.lights)
    }
}

/// An up vector for a view along `direction`: +y, or +z when the view is within ~8° of vertical
/// (where +y would make the view matrix degenerate).
fn up_for(direction: Vec3) -> Vec3 {
    if direction.normalize_or_zero().y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}
