//! The browser page (`web/` in the repository) with what it draws: one material's package, each
//! scene's frame as `gpu::WebFrame` writes it (the renderer's own buffers, so the page draws the
//! frame `sss render` draws) and the material's table variants the page switches between.
//! [`Site::build`] plans each scene as `sss render` would; [`Site::files`] are the files to write
//! into one folder, served as it is (`sss view`).

use shading::{PackedShading, Shading};

use crate::error::{RenderError, Result};
use crate::package::Package;
use crate::plan::{Plan, Profiles};
use crate::progress::Progress;
use crate::request::Request;

/// The page, as in the repository.
const INDEX_HTML: &str = include_str!("../../../web/index.html");
/// Its script.
const SSS_JS: &str = include_str!("../../../web/sss.js");

/// The page with one material's scenes, ready to be written.
#[derive(Clone, Debug)]
pub struct Site {
    /// The material's package (also under `package/`).
    pub package: Package,
    files: Vec<(String, Vec<u8>)>,
}

/// A scene of the site: its name in `?scene=` and the request's scene (a built-in name or an
/// .obj path).
#[derive(Clone, Debug, PartialEq)]
pub struct SiteScene {
    /// The name the page shows and `?scene=` selects.
    pub name: String,
    /// What `Request::frame.scene` takes.
    pub scene: String,
    /// A path-traced reference image to show beside it (PNG bytes), e.g. `mitsuba.png` of
    /// `scripts/references/images.py` (its view is the reference scene's).
    pub reference: Option<Vec<u8>>,
    /// The reference's view (camera, lights, image size, albedos), replacing the request's for
    /// this scene ([`crate::Reference`]); `None`: the request's.
    pub view: Option<crate::SceneView>,
}

impl SiteScene {
    /// The page's scenes from their names or .obj paths (each named after its file stem), the
    /// first being the default; none given: the sphere and the fin.
    pub fn list(scenes: &[String]) -> Vec<SiteScene> {
        let default = ["sphere".to_string(), "fin".to_string()];
        let scenes = if scenes.is_empty() {
            &default[..]
        } else {
            scenes
        };
        scenes
            .iter()
            .map(|scene| SiteScene {
                name: std::path::Path::new(scene)
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("scene")
                    .to_string(),
                scene: scene.clone(),
                reference: None,
                view: None,
            })
            .collect()
    }

    /// Sets the reference image (PNG bytes) of the scene named `name` in `scenes`; a scene the
    /// page does not have, or bytes that are not a PNG, are refused (field `reference`).
    pub fn set_reference(scenes: &mut [SiteScene], name: &str, png: Vec<u8>) -> Result<()> {
        if !png.starts_with(b"\x89PNG") {
            return Err(RenderError::invalid("reference", name, "not a PNG"));
        }
        let names: Vec<String> = scenes.iter().map(|s| s.name.clone()).collect();
        match scenes.iter_mut().find(|s| s.name == name) {
            Some(s) => {
                s.reference = Some(png);
                Ok(())
            }
            None => {
                let reason = format!("no such scene (the page has {})", names.join(", "));
                Err(RenderError::invalid("reference", name, reason))
            }
        }
    }
}

impl Site {
    /// Plans `request` (one SSS material, the separable method at full resolution) on each of
    /// `scenes`, the first being the page's default, with profiles and tables from `profiles`.
    pub fn build(
        request: &Request,
        scenes: &[SiteScene],
        profiles: &mut dyn Profiles,
        progress: &dyn Progress,
    ) -> Result<Site> {
        let Some(first) = scenes.first() else {
            return Err(RenderError::invalid("scenes", 0, "the page needs a scene"));
        };
        let mut files = vec![
            ("index.html".to_string(), INDEX_HTML.as_bytes().to_vec()),
            ("sss.js".to_string(), SSS_JS.as_bytes().to_vec()),
        ];
        let mut package = None;
        for s in scenes {
            let mut r = request.clone();
            r.frame.scene = s.scene.clone();
            if let Some(v) = &s.view {
                v.apply(&mut r.frame);
            }
            if r.half_res || r.frame.fast_blur {
                return Err(RenderError::invalid(
                    "resolution",
                    "half or fast",
                    "the page runs the full-resolution exact blur",
                ));
            }
            let plan = Plan::build(&r, profiles, progress)?;
            if package.is_none() {
                package = Some(Package::from_plan(&r, &plan)?);
            }
            let frame = gpu::WebFrame::new(&plan.scene, &plan.gpu_kernels, &plan.params)?;
            let mut json = serde_json::to_value(&frame).expect("a frame serializes");
            json["files"] = frame.binaries().iter().map(|(n, _)| n.clone()).collect();
            json["scene"] = s.scene.clone().into();
            let dir = format!("frames/{}", s.name);
            files.push((format!("{dir}/frame.json"), json.to_string().into_bytes()));
            for (name, bytes) in frame.binaries() {
                files.push((format!("{dir}/{name}"), bytes.clone()));
            }
            if let Some(png) = &s.reference {
                files.push((format!("{dir}/reference.png"), png.clone()));
            }
        }
        let package = package.expect("at least one scene");
        files.push((
            "frames/methods.bin".to_string(),
            variants(&package.rendered)
                .iter()
                .flat_map(|v| bytemuck::bytes_of(v).to_vec())
                .collect(),
        ));
        let site = serde_json::json!({
            "material": package.slug,
            "default_scene": first.name,
            "scenes": scenes.iter().map(|s| serde_json::json!({
                "name": s.name,
                "reference": s.reference.as_ref().map(|_| format!("frames/{}/reference.png", s.name)),
            })).collect::<Vec<_>>(),
            "material_bytes": shading::PACKED_SHADING_SIZE,
            "methods": ["kernel only", "+ incidence and thin-part light", "+ exit law", "+ entry shift"],
        });
        files.push(("site.json".to_string(), site.to_string().into_bytes()));
        for (name, bytes) in package.files() {
            files.push((format!("package/{name}"), bytes));
        }
        Ok(Site { package, files })
    }

    /// The files, names relative to the site's folder.
    pub fn files(&self) -> &[(String, Vec<u8>)] {
        &self.files
    }
}

/// The page's methods, each the tables of the one before it plus some: the kernel alone (every
/// table off, as `sss render --incidence-aware off --exit-aware off --entry-shift off
/// --translucency off`), + the incidence table and light through thin parts, + the exit law at
/// the entry angle, + the entry shift (`full`: what `sss render` draws by default).
fn variants(full: &Shading) -> [PackedShading; 4] {
    let kernel = Shading {
        eta: full.eta,
        ..Shading::default()
    };
    let incidence = Shading {
        incidence: full.incidence,
        translucency: full.translucency,
        ..kernel
    };
    let exit = Shading {
        exit: full.exit,
        ..incidence
    };
    [kernel, incidence, exit, *full].map(|s| PackedShading::new(&s))
}
