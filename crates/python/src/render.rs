//! `sss.render(...)`: a scene drawn with the material's subsurface scattering by the `render`
//! library, the same request `sss render` builds from its flags, so the same arguments give the
//! same image (bit-identical on the same adapter). The GIL is released while the tables are
//! simulated and the frame is drawn.

use ::render::{Choice, Plan, RenderError, Request};
use numpy::IntoPyArray;
use numpy::ndarray::Array3;
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::kernels::Kernel;
use crate::{SssError, args};

/// The request's fields by the keyword arguments that set them, so that a refusal names the
/// argument.
const ARGUMENTS: [(&str, &str); 17] = [
    ("fov_deg", "fov"),
    ("tolerance_cm", "tolerance"),
    ("lights", "light"),
    ("materials", "material"),
    ("incidence", "incidence_aware"),
    ("exit", "exit_aware"),
    ("exit_law", "exit_aware"),
    ("disc radius", "radius"),
    ("light map size", "light_map"),
    ("gather_pattern", "gather_inner/gather_layers"),
    ("camera", "camera/target"),
    ("fast_blur", "blur"),
    ("depth_test", "depth_test"),
    ("albedo", "albedo"),
    ("dipole_energy", "dipole_energy"),
    ("bssrdf", "bssrdf"),
    ("no_sss", "no_sss"),
];

/// A library error as [`SssError`], a refused field named by its keyword argument.
pub(crate) fn refused(e: RenderError) -> PyErr {
    let name = |field: &str| {
        ARGUMENTS
            .iter()
            .find(|(f, _)| *f == field)
            .map(|(_, a)| a.to_string())
    };
    SssError::new_err(e.renamed(name).to_string())
}

/// `on`/`off`, a bool or None (the method's default).
fn switch(name: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<bool>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if let Ok(b) = v.extract::<bool>() {
        return Ok(Some(b));
    }
    match v.extract::<String>().as_deref() {
        Ok("on") => Ok(Some(true)),
        Ok("off") => Ok(Some(false)),
        _ => Err(SssError::new_err(format!(
            "invalid {name} {}: expected True, False, \"on\" or \"off\"",
            v.repr().map(|r| r.to_string()).unwrap_or_default()
        ))),
    }
}

/// A named choice ([`::render::Choice`]) by its name.
fn choice<T: Choice>(name: &str, v: &str) -> PyResult<T> {
    T::parse(v)
        .map_err(|e| refused(e.renamed(|field| (field == T::WHAT).then(|| name.to_string()))))
}

/// One or several of something given as a string or a list of strings.
fn strings(name: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(Vec::new());
    };
    if v.is_instance_of::<PyString>() {
        return Ok(vec![v.extract()?]);
    }
    v.extract::<Vec<String>>().map_err(|_| {
        SssError::new_err(format!(
            "invalid {name} {}: give a string or a list of strings",
            v.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

/// An (x, y, z) triple: three numbers, or `"X,Y,Z"`.
fn point(name: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<glam::Vec3>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if let Ok(s) = v.extract::<String>() {
        return ::render::parse::vec3(&s)
            .map(Some)
            .map_err(|e| SssError::new_err(format!("invalid {name}: {e}")));
    }
    let [x, y, z] = args::rgb(name, v)?;
    Ok(Some(glam::Vec3::new(x as f32, y as f32, z as f32)))
}

/// The material arguments as named materials: one, or a list (one per SSS material of the
/// scene).
pub(crate) fn materials(v: &Bound<'_, PyAny>) -> PyResult<Vec<::render::NamedMaterial>> {
    let items: Vec<Bound<'_, PyAny>> = if v.is_instance_of::<pyo3::types::PyList>() {
        v.try_iter()?.collect::<PyResult<_>>()?
    } else {
        vec![v.clone()]
    };
    items
        .iter()
        .map(|item| {
            let material = args::material(item)?;
            let slug = match item.extract::<String>() {
                Ok(s) if mc::builtin::is_path(&s) => std::path::Path::new(&s)
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("material")
                    .to_lowercase(),
                Ok(s) => s.to_lowercase(),
                Err(_) => material.name.to_lowercase(),
            };
            Ok(::render::NamedMaterial { slug, material })
        })
        .collect()
}

/// `resolution` is full or half, `blur` exact or fast.
fn two_ways(resolution: &str, blur: &str) -> PyResult<()> {
    for (name, v) in [("resolution", resolution), ("blur", blur)] {
        let allowed = if name == "blur" {
            ["exact", "fast"]
        } else {
            ["full", "half"]
        };
        if !allowed.contains(&v) {
            return Err(SssError::new_err(format!(
                "invalid {name} {v:?}: expected {} or {}",
                allowed[0], allowed[1]
            )));
        }
    }
    Ok(())
}

/// The SSS objects' albedo: one RGB, or one per material.
fn albedos(object_albedo: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<glam::Vec3>> {
    let albedos: Vec<[f64; 3]> = match object_albedo.filter(|v| !v.is_none()) {
        None => Vec::new(),
        Some(v) => match args::rgb("object_albedo", v) {
            Ok(c) => vec![c],
            Err(_) => v
                .try_iter()?
                .map(|item| args::rgb("object_albedo", &item?))
                .collect::<PyResult<_>>()?,
        },
    };
    Ok(albedos
        .into_iter()
        .map(|c| glam::Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
        .collect())
}

/// The run settings of the profiles and tables: the thesis's, with the photons and seed given.
pub(crate) fn tables(
    photons: Option<&Bound<'_, PyAny>>,
    seed: Option<u64>,
    incidence_photons: Option<&Bound<'_, PyAny>>,
    translucency_photons: Option<&Bound<'_, PyAny>>,
) -> PyResult<::render::TableSettings> {
    let mut tables = ::render::TableSettings::default();
    if let Some(p) = incidence_photons.filter(|v| !v.is_none()) {
        tables.incidence_photons = args::count("incidence_photons", p)?;
    }
    if let Some(p) = translucency_photons.filter(|v| !v.is_none()) {
        tables.translucency_photons = args::count("translucency_photons", p)?;
    }
    if let Some(p) = photons.filter(|v| !v.is_none()) {
        tables.config.photons = args::count("photons", p)?;
    }
    if let Some(s) = seed {
        tables.seed = s;
    }
    Ok(tables)
}

/// The plan of `request`, its profiles simulated, drawn on the first adapter found.
fn draw(request: &Request) -> ::render::Result<gpu::Frame> {
    let mut profiles = ::render::Simulated {
        tables: &request.tables,
        progress: &(),
    };
    let plan = Plan::build(request, &mut profiles, &())?;
    let gpu = gpu::Gpu::new()?;
    plan.render(&gpu)
}

/// Renders a scene with the material's subsurface scattering and returns its linear radiance as
/// a float32 array (height × width × 3, top row first), the image `sss render` writes as
/// render.pfm for the same arguments. The defaults are `sss render`'s: Skin1 on the built-in
/// sphere, pre-integration (17 taps) with the incidence, exit (at the entry angle) and
/// entry-shift tables and light through thin parts; profiles simulated at the thesis's settings
/// (1e7 photons per channel unless `photons`), seed 1 unless `seed`; the tables 1e5 photons per
/// channel and angle (`incidence_photons`) and 2e4 per thickness (`translucency_photons`). Needs a GPU adapter (Mesa's
/// lavapipe will do).
///
/// material: a built-in name, a material .toml path, a dict of coefficients, or a list of them
/// (one per SSS material of the scene: "pair" takes two). scene: "sphere", "fin", "pair" or a
/// Wavefront .obj path. width, height [px]. light: a light or a list of them, as `sss render
/// --light` writes them ("dir:X,Y,Z[:E]", "point:X,Y,Z[:I]", "area:X,Y,Z:AX,AY,AZ:SIDE[:L]").
/// method: "separable", "directional-dipole", "area-gather" or "surface-gather". kernel: an
/// `sss.Kernel` instead of pre-integration. incidence_aware, entry_shift, translucency, shape: True,
/// False, "on", "off" or None (the method's default); exit_aware: "entry", "on", "off" or None.
/// camera, target [cm]: three numbers; fov [degrees]. object_albedo: one RGB or one per
/// material; floor_albedo: RGB. Every other argument as the `sss render` flag of the same name.
#[pyfunction]
#[pyo3(signature = (
    material = None, *, scene = "sphere", width = 1920, height = 1080, light = None,
    method = "separable", kernel = None, taps = 17, error_target = None,
    incidence_aware = None, exit_aware = None, entry_shift = None, translucency = None,
    shape = None, albedo = "pre-post", depth_test = "lerp", tolerance = None, jitter = None,
    resolution = "full", blur = "exact", sss_width = 1.0, exposure = 1.0,
    camera = None, target = None, fov = None, object_albedo = None, floor_albedo = None,
    specular = None, ambient = None, no_sss = false,
    photons = None, seed = None, incidence_photons = None, translucency_photons = None,
    bssrdf = "directional", samples = 16, frames = 16, frame_seed = None, radius = None,
    dipole_energy = "monte-carlo", light_map = 1024, denoise = None
))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    material: Option<&Bound<'py, PyAny>>,
    scene: &str,
    width: u32,
    height: u32,
    light: Option<&Bound<'py, PyAny>>,
    method: &str,
    kernel: Option<PyRef<'py, Kernel>>,
    taps: usize,
    error_target: Option<f64>,
    incidence_aware: Option<&Bound<'py, PyAny>>,
    exit_aware: Option<&str>,
    entry_shift: Option<&Bound<'py, PyAny>>,
    translucency: Option<&Bound<'py, PyAny>>,
    shape: Option<&Bound<'py, PyAny>>,
    albedo: &str,
    depth_test: &str,
    tolerance: Option<f32>,
    jitter: Option<f32>,
    resolution: &str,
    blur: &str,
    sss_width: f32,
    exposure: f32,
    camera: Option<&Bound<'py, PyAny>>,
    target: Option<&Bound<'py, PyAny>>,
    fov: Option<f32>,
    object_albedo: Option<&Bound<'py, PyAny>>,
    floor_albedo: Option<&Bound<'py, PyAny>>,
    specular: Option<f32>,
    ambient: Option<f32>,
    no_sss: bool,
    photons: Option<&Bound<'py, PyAny>>,
    seed: Option<u64>,
    incidence_photons: Option<&Bound<'py, PyAny>>,
    translucency_photons: Option<&Bound<'py, PyAny>>,
    bssrdf: &str,
    samples: u32,
    frames: u32,
    frame_seed: Option<u32>,
    radius: Option<f32>,
    dipole_energy: &str,
    light_map: u32,
    denoise: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
    let materials = match material {
        Some(m) if !m.is_none() => materials(m)?,
        _ => vec![::render::NamedMaterial::builtin("skin1").map_err(refused)?],
    };
    let lights = strings("light", light)?
        .iter()
        .map(|s| {
            ::render::parse::light(s).map_err(|e| SssError::new_err(format!("invalid light: {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    two_ways(resolution, blur)?;
    let object_albedo = albedos(object_albedo)?;
    let tables = tables(photons, seed, incidence_photons, translucency_photons)?;
    let request = Request {
        frame: gpu::RenderRequest {
            scene: scene.to_string(),
            width,
            height,
            taps,
            error_target,
            jitter,
            sss_width,
            exposure,
            tolerance_cm: tolerance,
            method: choice("method", method)?,
            materials: materials.len(),
            fast_blur: blur == "fast",
            lights,
            camera: point("camera", camera)?,
            target: point("target", target)?,
            fov_deg: fov,
            object_albedo,
            floor_albedo: point("floor_albedo", floor_albedo)?,
            boxes: Vec::new(),
            specular,
            ambient,
        },
        materials,
        kernel: kernel.map(|k| k.inner.clone()),
        albedo: choice("albedo", albedo)?,
        depth_test: choice("depth_test", depth_test)?,
        half_res: resolution == "half",
        shading: ::render::ShadingOptions {
            incidence: switch("incidence_aware", incidence_aware)?,
            exit: exit_aware.map(|e| choice("exit_aware", e)).transpose()?,
            entry_shift: switch("entry_shift", entry_shift)?,
            translucency: switch("translucency", translucency)?,
            shape: switch("shape", shape)?,
        },
        tables,
        gather: ::render::GatherOptions {
            bssrdf: choice("bssrdf", bssrdf)?,
            samples,
            frames,
            frame_seed,
            radius_cm: radius,
            dipole_energy: choice("dipole_energy", dipole_energy)?,
            light_map,
            denoise: switch("denoise", denoise)?.unwrap_or(false),
            ..Default::default()
        },
        no_sss,
    };
    let frame = py.detach(|| draw(&request)).map_err(refused)?;
    let (w, h) = (frame.width as usize, frame.height as usize);
    let rgb: Vec<f32> = frame
        .linear
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let image = Array3::from_shape_vec((h, w, 3), rgb)
        .map_err(|e| SssError::new_err(format!("frame of {w}×{h}: {e}")))?;
    Ok(image.into_pyarray(py))
}
