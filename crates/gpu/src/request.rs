//! What a render asks for, checked as a whole before any table is simulated or any device asked
//! for: the image, the kernel's sampling, the method, the lights, the camera and the scene's
//! materials. [`RenderRequest::scene`] checks it and returns the scene with its overrides applied;
//! every refusal is a [`GpuError::Invalid`] naming the request's field (callers map the field to
//! their own names for it, e.g. a command-line flag).

use glam::Vec3;

use crate::error::{GpuError, Result};
use crate::gathers::disc_gather::{DISC_LIGHTS, area_slots};
use crate::light::{AREA_CELLS, Light, MAX_EMITTERS, emitters};
use crate::mesh::Mesh;
use crate::scene::Scene;

/// The largest image side [px].
pub const MAX_SIDE: u32 = 16384;

/// The most taps per 1D pass.
pub const MAX_TAPS: usize = 1025;

/// How light travels under the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Separable screen-space kernels ([`crate::passes::blur`]).
    Separable,
    /// The directional dipole over the lit surface ([`crate::gathers::dipole`]).
    DirectionalDipole,
    /// Maisch & Ropinski's area gather ([`crate::gathers::area_gather`]).
    AreaGather,
    /// The Monte Carlo BSSRDF over the lit surface ([`crate::gathers::surface_gather`]).
    SurfaceGather,
}

impl Method {
    /// Whether the method gathers over the lit surface through the lights' maps (directional
    /// dipole, surface gather): those take at most [`DISC_LIGHTS`] lights, an area light drawn as
    /// points in the slots the others leave.
    pub fn gathers_lit_surface(self) -> bool {
        matches!(self, Method::DirectionalDipole | Method::SurfaceGather)
    }
}

/// A render as asked for. Optional fields keep the scene's own value when `None` (or empty).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderRequest {
    /// A built-in scene (`sphere`, `fin`, `pair`) or a Wavefront OBJ path.
    pub scene: String,
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// Taps per 1D pass of a fitted kernel.
    pub taps: usize,
    /// Image RMS a fitted kernel's rank must meet, if any.
    pub error_target: Option<f64>,
    /// Fraction of taps jittered per pixel, in [0, 1].
    pub jitter: Option<f32>,
    /// Kernel scale (SSSS's sssWidth), ≥ 0.
    pub sss_width: f32,
    /// Exposure of the tone mapping, > 0.
    pub exposure: f32,
    /// Depth-test tolerance [cm], > 0.
    pub tolerance_cm: Option<f32>,
    /// How light travels under the surface.
    pub method: Method,
    /// How many materials were named: one per SSS material of the scene.
    pub materials: usize,
    /// Whether the fast blur path is asked for (one material only: its samples carry no
    /// material).
    pub fast_blur: bool,
    /// The lights, replacing the scene's when not empty.
    pub lights: Vec<Light>,
    /// Camera position [cm].
    pub camera: Option<Vec3>,
    /// The point the camera looks at [cm].
    pub target: Option<Vec3>,
    /// Vertical field of view [degrees], in (1, 170).
    pub fov_deg: Option<f32>,
    /// Diffuse albedo of the SSS objects: once for all, or once per material.
    pub object_albedo: Vec<Vec3>,
    /// Diffuse albedo of the floor.
    pub floor_albedo: Option<Vec3>,
    /// Black boxes added to the scene, each by its two opposite corners [cm].
    pub boxes: Vec<(Vec3, Vec3)>,
    /// Specular intensity, ≥ 0.
    pub specular: Option<f32>,
    /// Ambient light, ≥ 0.
    pub ambient: Option<f32>,
}

impl Default for RenderRequest {
    /// The built-in sphere at 1920×1080 with its own camera, lights and albedos, one material,
    /// 17 taps, the separable method.
    fn default() -> Self {
        RenderRequest {
            scene: "sphere".into(),
            width: 1920,
            height: 1080,
            taps: 17,
            error_target: None,
            jitter: None,
            sss_width: 1.0,
            exposure: 1.0,
            tolerance_cm: None,
            method: Method::Separable,
            materials: 1,
            fast_blur: false,
            lights: Vec::new(),
            camera: None,
            target: None,
            fov_deg: None,
            object_albedo: Vec::new(),
            floor_albedo: None,
            boxes: Vec::new(),
            specular: None,
            ambient: None,
        }
    }
}

impl RenderRequest {
    /// Checks what needs no scene: image size, taps, targets, scales and lights.
    pub fn validate(&self) -> Result<()> {
        for (field, side) in [("width", self.width), ("height", self.height)] {
            if side == 0 || side > MAX_SIDE {
                return Err(GpuError::invalid(
                    field,
                    side,
                    format!("must lie in 1..={MAX_SIDE} px"),
                ));
            }
        }
        if self.taps == 0 || self.taps > MAX_TAPS {
            return Err(GpuError::invalid(
                "taps",
                self.taps,
                format!("must lie in 1..={MAX_TAPS}"),
            ));
        }
        if let Some(t) = self.error_target
            && !(t.is_finite() && t > 0.0)
        {
            return Err(GpuError::invalid(
                "error_target",
                t,
                "must be a positive image RMS",
            ));
        }
        if let Some(j) = self.jitter
            && !(0.0..=1.0).contains(&j)
        {
            return Err(GpuError::invalid("jitter", j, "must lie in [0, 1]"));
        }
        let finite_at_least =
            |v: f32, zero_ok: bool| v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0));
        for (field, v, zero_ok) in [
            ("sss_width", Some(self.sss_width), true),
            ("exposure", Some(self.exposure), false),
            ("tolerance_cm", self.tolerance_cm, false),
            ("specular", self.specular, true),
            ("ambient", self.ambient, true),
        ] {
            if let Some(v) = v
                && !finite_at_least(v, zero_ok)
            {
                let reason = if zero_ok {
                    "must be finite and ≥ 0"
                } else {
                    "must be finite and > 0"
                };
                return Err(GpuError::invalid(field, v, reason));
            }
        }
        if let Some(f) = self.fov_deg
            && !(f > 1.0 && f < 170.0)
        {
            return Err(GpuError::invalid(
                "fov_deg",
                f,
                "must lie in (1, 170) degrees",
            ));
        }
        for (field, v) in self
            .object_albedo
            .iter()
            .map(|v| ("object_albedo", v))
            .chain(self.floor_albedo.iter().map(|v| ("floor_albedo", v)))
        {
            if !(v.min_element() >= 0.0 && v.max_element() <= 1.0) {
                return Err(GpuError::invalid(
                    field,
                    v,
                    "each channel must lie in [0, 1]",
                ));
            }
        }
        check_lights(&self.lights, self.method.gathers_lit_surface())?;
        Ok(())
    }

    /// Checks the request ([`RenderRequest::validate`]), loads its scene and applies the
    /// overrides, then checks what needs the scene: one material per SSS material, one when the
    /// method or the fast blur needs it, the albedos' count, a camera that does not sit on its
    /// target.
    pub fn scene(&self) -> Result<Scene> {
        self.validate()?;
        let mut scene = Scene::named(&self.scene)?;
        let materials = scene.material_count().max(1);
        if self.materials != materials {
            return Err(GpuError::invalid(
                "materials",
                self.materials,
                format!(
                    "scene {} has {materials} SSS material(s): give one per material",
                    self.scene
                ),
            ));
        }
        if materials > 1 && self.fast_blur {
            return Err(GpuError::invalid(
                "fast_blur",
                materials,
                "the fast blur takes one SSS material: its samples do not know their material",
            ));
        }
        if materials > 1 && self.method != Method::Separable {
            return Err(GpuError::invalid(
                "method",
                format!("{:?}", self.method),
                "the directional dipole, the area gather and the surface gather render one SSS material per frame",
            ));
        }
        if ![0, 1, materials].contains(&self.object_albedo.len()) {
            return Err(GpuError::invalid(
                "object_albedo",
                format!("{} values", self.object_albedo.len()),
                format!("give one, or one per material ({materials})"),
            ));
        }
        if let Some(c) = self.camera {
            scene.camera.position = c;
        }
        if let Some(t) = self.target {
            scene.camera.target = t;
        }
        if let Some(f) = self.fov_deg {
            scene.camera.fov_y_deg = f;
        }
        if (scene.camera.position - scene.camera.target).length() <= 0.0 {
            return Err(GpuError::invalid(
                "camera",
                scene.camera.position,
                "coincides with the target",
            ));
        }
        if !self.lights.is_empty() {
            scene.lights = self.lights.clone();
        }
        for vert in &mut scene.mesh.vertices {
            let albedo = if vert.strength > 0.0 {
                self.object_albedo
                    .get(vert.material as usize)
                    .or(self.object_albedo.first())
                    .copied()
            } else {
                self.floor_albedo
            };
            if let Some(v) = albedo {
                vert.albedo = v.into();
            }
        }
        for &(lo, hi) in &self.boxes {
            scene.mesh.append(&Mesh::cuboid(lo, hi, [0.0; 3], 0.0));
        }
        if let Some(v) = self.specular {
            scene.specular = v;
        }
        if let Some(v) = self.ambient {
            scene.ambient = Vec3::splat(v);
        }
        Ok(scene)
    }
}

/// Refuses lights the renderer cannot draw, naming the field `lights`: an invalid light, more
/// emitters than [`MAX_EMITTERS`] (an area light counts [`AREA_CELLS`]²), and, for the methods
/// that gather over the lit surface, more than [`DISC_LIGHTS`] directional and point lights, or
/// area lights with no slot left among them (each is drawn as the slots' share of points per
/// frame).
pub(crate) fn check_lights(lights: &[Light], gathers_lit_surface: bool) -> Result<()> {
    for light in lights {
        light.validate()?;
    }
    let count = emitters(lights).len();
    let areas = lights.iter().any(|l| matches!(l, Light::Area { .. }));
    if gathers_lit_surface && (areas && area_slots(lights) == 0 || !areas && count > DISC_LIGHTS) {
        return Err(GpuError::invalid(
            "lights",
            lights.len(),
            format!(
                "the directional dipole and the surface gather take at most {DISC_LIGHTS} lights, each area light counting at least 1"
            ),
        ));
    }
    if count > MAX_EMITTERS {
        return Err(GpuError::invalid(
            "lights",
            lights.len(),
            format!(
                "{count} point lights once each area light is split into its {} cells; at most {MAX_EMITTERS}",
                AREA_CELLS * AREA_CELLS
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request() -> RenderRequest {
        RenderRequest {
            scene: "sphere".into(),
            width: 64,
            height: 36,
            taps: 17,
            error_target: None,
            jitter: None,
            sss_width: 1.0,
            exposure: 1.0,
            tolerance_cm: None,
            method: Method::Separable,
            materials: 1,
            fast_blur: false,
            lights: Vec::new(),
            camera: None,
            target: None,
            fov_deg: None,
            object_albedo: Vec::new(),
            floor_albedo: None,
            boxes: Vec::new(),
            specular: None,
            ambient: None,
        }
    }

    fn field(r: RenderRequest) -> String {
        match r.scene().unwrap_err() {
            GpuError::Invalid { field, .. } => field,
            e => panic!("{e}"),
        }
    }

    #[test]
    fn a_plain_request_gives_the_scene_with_its_overrides() {
        let s = RenderRequest {
            fov_deg: Some(30.0),
            ambient: Some(0.25),
            object_albedo: vec![Vec3::new(0.5, 0.4, 0.3)],
            ..request()
        }
        .scene()
        .unwrap();
        assert_eq!(s.camera.fov_y_deg, 30.0);
        assert_eq!(s.ambient, Vec3::splat(0.25));
        let sss = s.mesh.vertices.iter().find(|v| v.strength > 0.0).unwrap();
        assert_eq!(Vec3::from(sss.albedo), Vec3::new(0.5, 0.4, 0.3));
    }

    #[test]
    fn each_refusal_names_its_field() {
        let dir = Light::Directional {
            towards: Vec3::Y,
            irradiance: Vec3::ONE,
            shadow: true,
        };
        for (r, f) in [
            (
                RenderRequest {
                    width: 0,
                    ..request()
                },
                "width",
            ),
            (
                RenderRequest {
                    height: MAX_SIDE + 1,
                    ..request()
                },
                "height",
            ),
            (
                RenderRequest {
                    taps: 0,
                    ..request()
                },
                "taps",
            ),
            (
                RenderRequest {
                    error_target: Some(-1.0),
                    ..request()
                },
                "error_target",
            ),
            (
                RenderRequest {
                    jitter: Some(2.0),
                    ..request()
                },
                "jitter",
            ),
            (
                RenderRequest {
                    exposure: 0.0,
                    ..request()
                },
                "exposure",
            ),
            (
                RenderRequest {
                    sss_width: f32::NAN,
                    ..request()
                },
                "sss_width",
            ),
            (
                RenderRequest {
                    tolerance_cm: Some(0.0),
                    ..request()
                },
                "tolerance_cm",
            ),
            (
                RenderRequest {
                    ambient: Some(-1.0),
                    ..request()
                },
                "ambient",
            ),
            (
                RenderRequest {
                    fov_deg: Some(180.0),
                    ..request()
                },
                "fov_deg",
            ),
            (
                RenderRequest {
                    floor_albedo: Some(Vec3::splat(1.5)),
                    ..request()
                },
                "floor_albedo",
            ),
            (
                RenderRequest {
                    method: Method::SurfaceGather,
                    lights: vec![dir; DISC_LIGHTS + 1],
                    ..request()
                },
                "lights",
            ),
            (
                RenderRequest {
                    lights: vec![dir; MAX_EMITTERS + 1],
                    ..request()
                },
                "lights",
            ),
            (
                RenderRequest {
                    materials: 2,
                    ..request()
                },
                "materials",
            ),
            (
                RenderRequest {
                    scene: "pair".into(),
                    materials: 2,
                    fast_blur: true,
                    ..request()
                },
                "fast_blur",
            ),
            (
                RenderRequest {
                    scene: "pair".into(),
                    materials: 2,
                    method: Method::AreaGather,
                    ..request()
                },
                "method",
            ),
            (
                RenderRequest {
                    object_albedo: vec![Vec3::ONE; 2],
                    ..request()
                },
                "object_albedo",
            ),
            (
                RenderRequest {
                    camera: Some(Vec3::ONE),
                    target: Some(Vec3::ONE),
                    ..request()
                },
                "camera",
            ),
        ] {
            assert_eq!(field(r), f);
        }
    }
}
