//! A path-traced reference that `scripts/references/images.py --arrays` left in a folder, as the
//! browser page shows it beside its own frame: the scene as `sss render` drew it there
//! (`view.json`: geometry, image size, camera, lights, occluders, albedos and the material's
//! file), and Mitsuba's image (`arrays.npz`'s `reference`, linear radiance) tone-mapped as the
//! renderer's recombination does, so the two stand side by side in the same view.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;
use mc::McError;
use serde::Deserialize;

use crate::error::{RenderError, Result};
use crate::parse;
use crate::request::NamedMaterial;
use crate::view::SiteScene;

/// `view.json` as `images.py` writes it.
#[derive(Deserialize)]
struct ViewFile {
    name: String,
    scene: String,
    width: u32,
    height: u32,
    camera: [f32; 3],
    target: [f32; 3],
    fov_deg: f32,
    boxes: Vec<String>,
    lights: Vec<String>,
    floor_albedo: [f32; 3],
    specular: f32,
    ambient: f32,
    object_albedo: [f32; 3],
    material_toml: String,
}

/// The frame settings of a reference's scene, which replace the page's for that scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneView {
    /// Image width and height [px].
    pub size: (u32, u32),
    /// Camera position, target [cm] and vertical field of view [degrees].
    pub camera: (Vec3, Vec3, f32),
    /// The lights.
    pub lights: Vec<gpu::Light>,
    /// Black occluders (min and max corner [cm]).
    pub boxes: Vec<(Vec3, Vec3)>,
    /// Diffuse albedo of the SSS object and of the floor [-].
    pub albedo: (Vec3, Vec3),
    /// Specular intensity and ambient irradiance.
    pub specular_ambient: (f32, f32),
}

impl SceneView {
    /// `frame` with these settings.
    pub fn apply(&self, frame: &mut gpu::RenderRequest) {
        (frame.width, frame.height) = self.size;
        let (eye, target, fov) = self.camera;
        (frame.camera, frame.target, frame.fov_deg) = (Some(eye), Some(target), Some(fov));
        frame.lights = self.lights.clone();
        frame.boxes = self.boxes.clone();
        frame.object_albedo = vec![self.albedo.0];
        frame.floor_albedo = Some(self.albedo.1);
        (frame.specular, frame.ambient) =
            (Some(self.specular_ambient.0), Some(self.specular_ambient.1));
    }
}

/// A reference run read from its folder.
#[derive(Clone, Debug)]
pub struct Reference {
    /// The page's scene: named after the reference's scene, with its view and image.
    pub scene: SiteScene,
    /// The material the reference was rendered with (e.g. index-matched, η = 1), its slug the
    /// material's name in lower case with every run of other characters than a–z, 0–9 a `-`
    /// (`skin1 (eta 1.0)` → `skin1-eta-1-0`).
    pub material: NamedMaterial,
}

/// A refusal naming the folder.
fn refuse(dir: &Path, reason: impl Into<String>) -> RenderError {
    RenderError::invalid("reference", dir.display(), reason)
}

impl Reference {
    /// Reads `dir`'s `view.json` and `arrays.npz` (written by `images.py --arrays`).
    pub fn read(dir: &Path) -> Result<Reference> {
        let path = dir.join("view.json");
        let text = mc::input::read_text(&path)
            .map_err(|e| McError::file(format!("cannot read {}", path.display()), e))?;
        let v: ViewFile = serde_json::from_str(&text)
            .map_err(|e| refuse(dir, format!("view.json is not images.py's: {e}")))?;
        let material =
            mc::Material::from_toml(&v.material_toml, &format!("{}/view.json", dir.display()))?;
        let npz = dir.join("arrays.npz");
        let bytes = std::fs::read(&npz)
            .map_err(|e| McError::file(format!("cannot read {}", npz.display()), e))?;
        let png = reference_png(&bytes, v.width, v.height).map_err(|e| refuse(dir, e))?;
        let bad =
            |what: &'static str| move |e: String| refuse(dir, format!("view.json {what}: {e}"));
        let lights = (v.lights.iter()).map(|l| parse::light(l).map_err(bad("lights")));
        let lights = lights.collect::<Result<_>>()?;
        let boxes = (v.boxes.iter()).map(|b| parse::cuboid(b).map_err(bad("boxes")));
        let boxes = boxes.collect::<Result<_>>()?;
        let scene = if v.scene.ends_with(".obj") {
            dir.join(&v.scene).display().to_string()
        } else {
            v.scene.clone()
        };
        let view = SceneView {
            size: (v.width, v.height),
            camera: (v.camera.into(), v.target.into(), v.fov_deg),
            lights,
            boxes,
            albedo: (v.object_albedo.into(), v.floor_albedo.into()),
            specular_ambient: (v.specular, v.ambient),
        };
        // File names are made of the slug: the material's name, lower case, [a-z0-9-] only.
        let slug = (material.name.to_lowercase())
            .split(|c: char| !c.is_ascii_alphanumeric())
            .filter(|w| !w.is_empty())
            .collect::<Vec<_>>()
            .join("-");
        Ok(Reference {
            scene: SiteScene {
                name: v.name,
                scene,
                reference: Some(png),
                view: Some(view),
            },
            material: NamedMaterial { slug, material },
        })
    }
}

/// `arrays.npz`'s `reference` (linear radiance, height × width × 3) as the page shows a frame:
/// × π (the renderer's linear output is π × radiance), ACES and sRGB at exposure 1
/// ([`gpu::eval::compare::tone_map`]), as PNG bytes.
fn reference_png(npz: &[u8], width: u32, height: u32) -> std::result::Result<Vec<u8>, String> {
    let mut archive =
        npyz::npz::NpzArchive::new(Cursor::new(npz)).map_err(|e| format!("arrays.npz: {e}"))?;
    let array = archive
        .by_name("reference")
        .map_err(|e| format!("arrays.npz: {e}"))?
        .ok_or("arrays.npz has no `reference`")?;
    let shape = array.shape().to_vec();
    if shape != [height as u64, width as u64, 3] {
        return Err(format!(
            "arrays.npz's reference is {shape:?}, view.json says {height} × {width} × 3"
        ));
    }
    let values: Vec<f64> = match array.dtype().descr().as_str() {
        "<f4" => array
            .into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect()),
        _ => array.into_vec::<f64>(),
    }
    .map_err(|e| format!("arrays.npz's reference: {e}"))?;
    let mut rgba = Vec::with_capacity(values.len() / 3 * 4);
    for px in values.chunks_exact(3) {
        let linear = [0, 1, 2].map(|c| (std::f64::consts::PI * px[c]) as f32);
        rgba.extend(gpu::eval::compare::tone_map(linear, 1.0));
        rgba.push(255);
    }
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(&rgba).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(png)
}

impl Reference {
    /// The page's material and scenes with reference runs `runs`: the material given, else the
    /// runs' (they must share one), else Skin1; the scenes listed (none: the sphere and the fin,
    /// or with runs none), each run's scene replacing a listed one of its name. A run rendered
    /// with another material than the one given is refused: the two images would not show the
    /// same medium.
    pub fn page(
        given: Option<NamedMaterial>,
        listed: &[String],
        runs: Vec<Reference>,
    ) -> Result<(NamedMaterial, Vec<SiteScene>)> {
        let material = match (given, runs.first()) {
            (Some(m), _) => m,
            (None, Some(r)) => r.material.clone(),
            (None, None) => NamedMaterial {
                slug: "skin1".into(),
                material: mc::Material::builtin("skin1")?,
            },
        };
        let mut scenes = if listed.is_empty() && !runs.is_empty() {
            Vec::new()
        } else {
            SiteScene::list(listed)
        };
        for r in runs {
            if r.material.material != material.material {
                let reason = format!(
                    "scene {} was rendered with {} (η = {}), the page draws {} (η = {}): leave the material out to draw the reference's",
                    r.scene.name,
                    r.material.slug,
                    r.material.material.eta,
                    material.slug,
                    material.material.eta
                );
                return Err(RenderError::invalid("reference", &r.scene.name, reason));
            }
            scenes.retain(|s| s.name != r.scene.name);
            scenes.push(r.scene);
        }
        Ok((material, scenes))
    }
}
