//! Profiles and kernels (`fit`): `sss.profile` (analytic models), `sss.fit` and `sss.kernel`
//! (shader-ready separable kernels, [`Kernel`]), `sss.export` (shader text), `sss.evaluate`
//! (every model's errors) and `sss.engine_params`.

use fit::KernelModel;
use fit::analytic::Model;
use fit::engine::Engine;
use fit::engine_report::EngineReport;
use fit::export::{OffsetUnit, ShaderFormat};
use fit::select::{Budget, Judge};
use fit::taps::ShaderKernel;
use mc::SimConfig;
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::simulate::{Run, thread_pool};
use crate::{args, error};

/// A shader-ready separable kernel: per pass (one rank-1 term, run as a horizontal then a
/// vertical 1D pass) its taps' offsets [cm], RGB weights [-] and a sign per channel.
#[pyclass(module = "sss", frozen)]
pub struct Kernel {
    pub(crate) inner: ShaderKernel,
}

#[pymethods]
impl Kernel {
    /// The model, as `sss fit --model` names it (e.g. "preint", "svd2-renorm").
    #[getter]
    fn model(&self) -> String {
        self.inner.model.to_string()
    }

    /// The material the kernel was fitted for.
    #[getter]
    fn material(&self) -> &str {
        &self.inner.material
    }

    /// Taps per 1D pass.
    #[getter]
    fn taps(&self) -> usize {
        self.inner.taps
    }

    /// The range R of the offsets' quadratic mapping [cm].
    #[getter]
    fn range_cm(&self) -> f64 {
        self.inner.range
    }

    /// Tap offsets, passes × taps [cm].
    #[getter]
    fn offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let k = &self.inner;
        Array2::from_shape_fn((k.pass.len(), k.taps), |(p, t)| k.pass[p].tap[t].offset)
            .into_pyarray(py)
    }

    /// Tap weights, passes × taps × 3 (R, G, B) [-].
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let k = &self.inner;
        Array3::from_shape_fn((k.pass.len(), k.taps, 3), |(p, t, c)| {
            k.pass[p].tap[t].weight[c]
        })
        .into_pyarray(py)
    }

    /// Each pass's sign per channel, passes × 3 (±1): the vertical pass adds sign × its result.
    #[getter]
    fn signs<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let k = &self.inner;
        Array2::from_shape_fn((k.pass.len(), 3), |(p, c)| k.pass[p].sign[c]).into_pyarray(py)
    }

    /// The kernel file `sss fit` writes (TOML), which `sss render --kernel` reads.
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// A kernel from the text of a kernel file (`sss fit --out`).
    #[staticmethod]
    fn from_toml(text: &str) -> PyResult<Kernel> {
        ShaderKernel::from_toml(text, "kernel text")
            .map(|inner| Kernel { inner })
            .map_err(error)
    }

    fn __repr__(&self) -> String {
        let k = &self.inner;
        format!(
            "<sss.Kernel {} for {}: {} pass(es) × {} taps, range {:.4} cm>",
            k.model,
            k.material,
            k.pass.len(),
            k.taps,
            k.range
        )
    }
}

fn parse<T: std::str::FromStr<Err = String>>(name: &str, text: &str) -> PyResult<T> {
    text.parse()
        .map_err(|e: String| error(format!("invalid {name} {text:?}: {e}")))
}

/// An analytic profile on the material's thesis grid, as the dict `simulate` returns (`r_cm`,
/// `rd` (nr × 3, the last bin everything beyond the grid), `rd_se` zeros, `dr_cm`, `nr`).
/// model: "dipole", "better-dipole", "directional-dipole", "pbd" or "burley".
#[pyfunction]
#[pyo3(signature = (material, model="pbd"))]
pub fn profile<'py>(
    py: Python<'py>,
    material: &Bound<'py, PyAny>,
    model: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let m = args::material(material)?;
    let model = Model::parse(model).map_err(error)?;
    let grid = SimConfig::thesis()
        .and_then(|c| c.grid_for(&m))
        .map_err(error)?;
    let nr = grid.nr - 1;
    let (p, overflow) = py
        .detach(|| {
            Ok::<_, fit::FitError>((
                fit::analytic::profile(model, &m, grid.dr, nr)?,
                fit::analytic::overflow(model, &m, grid.dr, nr)?,
            ))
        })
        .map_err(error)?;
    let mut r = p.r.clone();
    r.push(grid.r_optimal(nr));
    let d = PyDict::new(py);
    d.set_item("r_cm", r.into_pyarray(py))?;
    let rd = Array2::from_shape_fn(
        (nr + 1, 3),
        |(i, c)| {
            if i < nr { p.rd[c][i] } else { overflow[c] }
        },
    );
    d.set_item("rd", rd.into_pyarray(py))?;
    d.set_item("rd_se", Array2::<f64>::zeros((nr + 1, 3)).into_pyarray(py))?;
    d.set_item("dr_cm", grid.dr)?;
    d.set_item("nr", nr + 1)?;
    d.set_item("model", model.name())?;
    d.set_item("material", &m.name)?;
    Ok(d)
}

/// Fits a kernel model to a profile and samples it into `taps` taps per pass [default 17].
/// source: the dict `simulate` or `profile` returns, or a material simulated at the thesis's
/// settings (`photons` per channel [default 1e7]). model: as `sss fit --model` takes it ("preint", "svd", "svd2",
/// "svd2-renorm", "guided", "guided-k1.55-b50", "manual", "deon3", "skin", "skin-fit",
/// "burley").
#[pyfunction(name = "fit")]
#[pyo3(signature = (source, model="preint", taps=None, material=None, photons=None))]
pub fn fit_kernel(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    model: &str,
    taps: Option<&Bound<'_, PyAny>>,
    material: Option<&str>,
    photons: Option<&Bound<'_, PyAny>>,
) -> PyResult<Kernel> {
    let (p, name) = source_profile(py, source, material, photons)?;
    let material = name.as_str();
    let model: KernelModel = parse("model", model)?;
    let taps = match taps {
        Some(t) => args::count("taps", t)? as usize,
        None => fit::taps::TapSpec::default().taps,
    };
    let inner = py
        .detach(|| Judge::new(&p).kernel(model, material, taps))
        .map_err(error)?;
    Ok(Kernel { inner })
}

/// The kernel as shader source: format "hlsl", "glsl", "wgsl" or "json" (SSSS's layout), the
/// offsets in unit "cm" or "mm".
#[pyfunction]
#[pyo3(signature = (kernel, format="hlsl", unit="cm"))]
pub fn export(kernel: &Kernel, format: &str, unit: &str) -> PyResult<String> {
    let format: ShaderFormat = parse("format", format)?;
    let unit: OffsetUnit = parse("unit", unit)?;
    Ok(fit::export::export(&kernel.inner, format, unit))
}

/// Fits every model that fits the budget "PASSESxTAPS" (1D passes × taps per pass) to the
/// profile (source: as `fit` takes it), ranks them by their mean image RMS on the test signals and returns the best kernel
/// and the ranking (a list of dicts: `model`, `passes`, `image_rms` per channel,
/// `mean_image_rms`).
#[pyfunction]
#[pyo3(signature = (source, budget="2x17", material=None, photons=None))]
pub fn kernel<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    budget: &str,
    material: Option<&str>,
    photons: Option<&Bound<'py, PyAny>>,
) -> PyResult<(Kernel, Bound<'py, PyList>)> {
    let (p, name) = source_profile(py, source, material, photons)?;
    let material = name.as_str();
    let budget: Budget = parse("budget", budget)?;
    let mut ranked = py
        .detach(|| Judge::new(&p).rank(budget, material))
        .map_err(error)?;
    let list = PyList::empty(py);
    for s in &ranked {
        let d = PyDict::new(py);
        d.set_item("model", s.model.to_string())?;
        d.set_item("passes", 2 * s.kernel.pass.len())?;
        d.set_item("image_rms", s.image_rms.to_vec())?;
        d.set_item("mean_image_rms", s.error())?;
        list.append(d)?;
    }
    let best = ranked.swap_remove(0);
    Ok((Kernel { inner: best.kernel }, list))
}

/// Every kernel model on a profile (source: as `fit` takes it): the rows of `sss eval --json` (a list of dicts: `model`,
/// `family`, `variant`, `rank`, `k`, `channel`, `kernel_rms`, `kernel_rms_normalized`,
/// `l1_error`, `image_rms` per test signal, `fit_seconds`).
#[pyfunction]
#[pyo3(signature = (source, material=None, photons=None))]
pub fn evaluate<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    material: Option<&str>,
    photons: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (p, name) = source_profile(py, source, material, photons)?;
    let material = name.as_str();
    let ev = py
        .detach(|| fit::evaluate::evaluate(&p, material, Default::default()))
        .map_err(error)?;
    let rows: Vec<serde_json::Value> = ev.rows.iter().map(fit::evaluate::Row::json).collect();
    from_json(py, &serde_json::Value::Array(rows))
}

/// A material's parameters for an engine ("unreal", "unity", "blender", "openpbr"), as `sss
/// engine-params --json` prints them: `params` (the engine's fields, units and notes),
/// `burley_fit` (the Christensen–Burley profile fitted to the Monte Carlo profile, with its
/// errors), `best_separable` under `budget`, and for "blender" `random_walk` (the Random Walk
/// fields that make Cycles trace the material's own σa, σs and g; else None). profile: the material's Monte Carlo profile
/// (`simulate`'s dict) [default: simulated here at the thesis's settings, `photons` per channel].
#[pyfunction]
#[pyo3(signature = (material, engine="unreal", profile=None, budget="2x17", photons=None))]
pub fn engine_params<'py>(
    py: Python<'py>,
    material: &Bound<'py, PyAny>,
    engine: &str,
    profile: Option<&Bound<'py, PyAny>>,
    budget: &str,
    photons: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let m = args::material(material)?;
    let (p, _) = source_profile(py, profile.unwrap_or(material), Some(&m.name), photons)?;
    let engine: Engine = parse("engine", engine)?;
    let budget: Budget = parse("budget", budget)?;
    let report = py
        .detach(|| EngineReport::new(&p, &m, &m.name, engine, budget))
        .map_err(error)?;
    let v = serde_json::to_value(&report).map_err(error)?;
    from_json(py, &v)
}

/// A profile argument and the material's name: the dict `simulate` or `profile` returns
/// (named `material`, else "material"), or a material (a built-in name, a `.toml` path or a
/// coefficient dict) traced here at the thesis's settings with `photons` per channel [default
/// 1e7] (Ctrl-C stops it).
fn source_profile(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    material: Option<&str>,
    photons: Option<&Bound<'_, PyAny>>,
) -> PyResult<(fit::Profile, String)> {
    if let Ok(d) = source.cast::<PyDict>()
        && d.contains("r_cm")?
    {
        let name = material.unwrap_or("material").to_string();
        return Ok((args::profile(source)?, name));
    }
    let medium = args::medium(source)?;
    let run = Run::thesis(photons.map(|p| args::count("photons", p)).transpose()?)?;
    let out = run.trace(py, &medium, &thread_pool(None)?, None)?.outputs;
    let name = match (material, &medium) {
        (Some(n), _) => n.to_string(),
        (None, args::Medium::Homogeneous(m)) => m.name.clone(),
        (None, args::Medium::Layered { name, .. }) => name.clone(),
    };
    Ok((fit::Profile::from_mc([&out[0], &out[1], &out[2]]), name))
}

/// Plain data (a library's `Serialize` output) as Python lists, dicts and numbers.
fn from_json<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (v.to_string(),))
}
