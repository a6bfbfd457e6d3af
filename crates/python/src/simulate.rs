//! `sss.materials()` and `sss.simulate(...)`: the built-in library and the photon tracer (`mc`),
//! with the GIL released while it traces and Ctrl-C checked between slices of chunks.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use mc::{Accumulator, Material, Output, RunSpec, Sample, SimConfig, TallySet};
use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::args::Medium;
use crate::{args, error};

/// How long one slice of chunks runs between two checks for Ctrl-C [s]: the first slice takes
/// one chunk per thread, the next ones as many as this time holds (each group of a slice ends
/// with its threads waiting for the last chunk, so slices much shorter than this cost speed).
const SLICE_SECONDS: f64 = 0.4;

/// Packets per channel and angle for `incidence_angles`, as `sss simulate --incidence-photons`.
const INCIDENCE_PHOTONS: u64 = 100_000;

/// The built-in materials as dicts: `name`, `source`, `sigma_a` and `sigma_s` [cm⁻¹] and `g` [-]
/// per channel R, G, B, `eta` [-].
#[pyfunction]
pub fn materials(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for name in mc::builtin::names() {
        let m = Material::builtin(name).map_err(error)?;
        let d = PyDict::new(py);
        d.set_item("name", name)?;
        d.set_item("source", &m.source)?;
        d.set_item("sigma_a", m.sigma_a.to_vec())?;
        d.set_item("sigma_s", m.sigma_s.to_vec())?;
        d.set_item("g", m.g.to_vec())?;
        d.set_item("eta", m.eta)?;
        list.append(d)?;
    }
    Ok(list)
}

/// Simulates a material's diffuse reflectance profile Rd(r) with the MCML-style tracer, at the
/// thesis's settings unless told otherwise (its grid rule, a half-space).
///
/// material: a built-in name, a material .toml path, a dict (`sigma_a`, `sigma_s` [cm⁻¹],
/// `g`, `eta`; one value or three), or a dict of `layers` (a list of such dicts from the top,
/// each with `thickness` [cm] but the last, which may be a half-space): one MCML run per
/// channel on the grid the thesis's rule gives the top layer; `a_layers` (3 × layers) [-] is
/// the absorption per layer. photons: packets per channel [default 1e7]; seed [default
/// 1]: the same seed gives bit-identical results for any `threads` and the same numbers as
/// `sss simulate`. full: also tally the absorption A(r, z) (`a_rz`, channels × nr × nz [cm⁻³]).
/// incidence_angles: also total Rd at these beam angles [degrees] (`incidence`), with
/// incidence_photons packets per channel and angle [default 1e5, as `sss simulate`].
/// target_error: stop once the relative standard error of total Rd and of r·Rd(r) within 3
/// transport mean free paths is at most this (photons is then the cap). progress: a callable
/// `progress(done, total)` [photons], called from this thread about every 0.4 s.
///
/// Returns a dict: `r_cm` (nr), `rd` and `rd_se` (nr × 3) [cm⁻²] (the last bin is MCML's
/// overflow bin: everything beyond the grid, spread over its annulus), `rd_total`,
/// `rd_total_se`, `a_total`, `a_total_se`, `tt_total`, `tt_total_se`, `rsp` (3 each) [-], the
/// grid (`dr_cm`, `nr`, `dz_cm`, `nz`), `photons`, `seed`, `threads`, `seconds`.
#[pyfunction]
#[pyo3(signature = (material, photons=None, seed=None, threads=None, full=false, incidence_angles=None, incidence_photons=None, target_error=None, progress=None))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments
pub fn simulate<'py>(
    py: Python<'py>,
    material: &Bound<'py, PyAny>,
    photons: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    threads: Option<&Bound<'py, PyAny>>,
    full: bool,
    incidence_angles: Option<&Bound<'py, PyAny>>,
    incidence_photons: Option<&Bound<'py, PyAny>>,
    target_error: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let medium = args::medium(material)?;
    let config = SimConfig::thesis().map_err(error)?;
    let seed = match seed {
        Some(s) => s
            .extract::<u64>()
            .map_err(|_| error(format!("invalid seed {s}: must be a whole number ≥ 0")))?,
        None => config.seed,
    };
    let pool = thread_pool(threads)?;
    let angles = incidence_angles
        .map(|a| args::array("incidence_angles", a))
        .transpose()?;
    let incidence_photons = incidence_photons
        .map(|p| args::count("incidence_photons", p))
        .transpose()?
        .unwrap_or(INCIDENCE_PHOTONS);
    let target = target_error
        .map(|e| args::number("target_error", e))
        .transpose()?;
    if let Some(p) = progress
        && !p.is_callable()
    {
        return Err(error(
            "invalid progress: must be callable as progress(done, total)",
        ));
    }
    let run = Run {
        photons: photons.map(|p| args::count("photons", p)).transpose()?,
        seed,
        full,
        target_error: target,
    };
    let start = Instant::now();
    let traced = run.trace(py, &medium, &pool, progress)?;
    let seconds = start.elapsed().as_secs_f64();
    let d = output_dict(py, &traced)?;
    d.set_item(
        "material",
        match &medium {
            Medium::Homogeneous(m) => &m.name,
            Medium::Layered { name, .. } => name,
        },
    )?;
    d.set_item("seed", seed)?;
    d.set_item("threads", pool.current_num_threads())?;
    d.set_item("seconds", seconds)?;
    if let Some(angles) = angles {
        let Medium::Homogeneous(m) = &medium else {
            return Err(error(
                "invalid incidence_angles: they take a homogeneous material, not layers",
            ));
        };
        let incidence_spec = config
            .batch(&[m], incidence_photons, seed, true)
            .map_err(error)?;
        let rows = py
            .detach(|| pool.install(|| mc::incidence::rd_table(&incidence_spec, &angles, &|_| {})))
            .map_err(error)?;
        let inc = PyDict::new(py);
        inc.set_item("theta_deg", angles.clone().into_pyarray(py))?;
        let per = |f: &dyn Fn(&mc::incidence::IncidenceRow, usize) -> f64| {
            Array2::from_shape_fn((rows.len(), 3), |(i, c)| f(&rows[i], c)).into_pyarray(py)
        };
        inc.set_item("rd", per(&|r, c| r.rd[c].value))?;
        inc.set_item("rd_se", per(&|r, c| r.rd[c].se))?;
        inc.set_item("rsp", per(&|r, c| r.rsp[c]))?;
        inc.set_item("photons", incidence_photons)?;
        d.set_item("incidence", inc)?;
    }
    Ok(d)
}

/// What a simulation asks for beyond the material: photons per channel (None: the thesis's
/// 10⁷), the seed, whether A(r, z) is tallied, an error target.
pub struct Run {
    pub photons: Option<u64>,
    pub seed: u64,
    pub full: bool,
    pub target_error: Option<f64>,
}

impl Run {
    /// The thesis's settings with the default seed.
    pub fn thesis(photons: Option<u64>) -> PyResult<Run> {
        Ok(Run {
            photons,
            seed: SimConfig::thesis().map_err(error)?.seed,
            full: false,
            target_error: None,
        })
    }

    /// Traces `medium` on `pool` at the thesis's settings with these changes (a layered sample
    /// on the grid the thesis's rule gives its top layer, one MCML run per channel).
    pub fn trace(
        &self,
        py: Python<'_>,
        medium: &Medium,
        pool: &rayon::ThreadPool,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Traced> {
        let config = SimConfig::thesis().map_err(error)?;
        let photons = self.photons.unwrap_or(config.photons);
        match medium {
            Medium::Homogeneous(m) => {
                let spec = config
                    .batch(&[m], photons, self.seed, !self.full)
                    .map_err(error)?;
                let outputs = match self.target_error {
                    Some(e) => py
                        .detach(|| {
                            pool.install(|| {
                                mc::run_batch_to_error(&spec, e, &spec.error_radii(), &|_| {})
                            })
                        })
                        .map_err(error)?,
                    None => {
                        let groups = spec.groups().len() as u64;
                        let sums = sliced(
                            py,
                            pool,
                            (mc::chunk_count(spec.photons), spec.photons * groups),
                            |chunks, done| mc::accumulate_batch(&spec, chunks, done),
                            |a: &mut Vec<Accumulator>, b| {
                                a.iter_mut().zip(&b).for_each(|(x, y)| x.merge(y))
                            },
                            progress,
                        )?;
                        mc::batch_outputs(&spec, &sums)
                    }
                };
                Ok(Traced {
                    outputs,
                    eta: m.eta,
                    absorption_rz: spec.tallies.absorption_rz,
                })
            }
            Medium::Layered { name, layers } => {
                if self.target_error.is_some() {
                    return Err(error(
                        "invalid target_error: it takes a homogeneous material, not layers",
                    ));
                }
                let top = Material {
                    name: name.clone(),
                    source: String::new(),
                    sigma_a: [0, 1, 2].map(|c| layers[c][0].mu_a),
                    sigma_s: [0, 1, 2].map(|c| layers[c][0].mu_s),
                    g: [0, 1, 2].map(|c| layers[c][0].g),
                    eta: layers[0][0].n,
                    thickness: None,
                };
                let grid = config.grid_for(&top).map_err(error)?;
                let mut outputs = Vec::new();
                for channel in layers {
                    let spec = RunSpec {
                        sample: Sample {
                            n_above: config.n_above,
                            n_below: config.n_below,
                            layers: channel.clone(),
                        },
                        grid,
                        photons,
                        seed: self.seed,
                        tallies: TallySet {
                            absorption_rz: self.full,
                            absorption_rz_se: false,
                            surface_xy: 0,
                        },
                    };
                    spec.validate().map_err(error)?;
                    let sum = sliced(
                        py,
                        pool,
                        (mc::chunk_count(photons), photons),
                        |chunks, done| mc::accumulate(&spec, chunks, done),
                        |a: &mut Accumulator, b| a.merge(&b),
                        progress,
                    )?;
                    outputs.push(Output::from_accumulator(&sum, 0, grid, spec.rsp()));
                }
                Ok(Traced {
                    outputs,
                    eta: top.eta,
                    absorption_rz: self.full,
                })
            }
        }
    }
}

/// A traced medium: its three channel outputs (R, G, B), the top boundary's η and whether
/// A(r, z) was tallied.
pub struct Traced {
    pub outputs: Vec<Output>,
    pub eta: f64,
    pub absorption_rz: bool,
}

/// Traces `chunks` chunks (of `photons` photon walks in all) by `work` in slices: exact sums, so
/// the same numbers as one call over every chunk. Between slices it checks for Ctrl-C and
/// reports progress; the GIL is released while a slice traces.
fn sliced<A: Send>(
    py: Python<'_>,
    pool: &rayon::ThreadPool,
    (chunks, photons): (u64, u64),
    work: impl Fn(std::ops::Range<u64>, &(dyn Fn(u64) + Sync)) -> mc::Result<A> + Sync,
    merge: impl Fn(&mut A, A),
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<A> {
    let threads = pool.current_num_threads() as u64;
    let done = AtomicU64::new(0);
    let count = |n: u64| {
        done.fetch_add(n, Ordering::Relaxed);
    };
    let mut sum: Option<A> = None;
    let (mut next, mut step) = (0, threads);
    while next < chunks {
        let end = (next + step).min(chunks);
        let start = Instant::now();
        let part = py
            .detach(|| pool.install(|| work(next..end, &count)))
            .map_err(error)?;
        // As many chunks as SLICE_SECONDS holds at this slice's pace, at most 4× more.
        let pace = start.elapsed().as_secs_f64() / (end - next) as f64;
        step = ((SLICE_SECONDS / pace.max(1e-9)) as u64).clamp(threads, 4 * step);
        match &mut sum {
            None => sum = Some(part),
            Some(s) => merge(s, part),
        }
        next = end;
        py.check_signals()?;
        if let Some(p) = progress {
            p.call1((done.load(Ordering::Relaxed), photons))?;
        }
    }
    sum.ok_or_else(|| error("photons: nothing to trace"))
}

pub fn thread_pool(threads: Option<&Bound<'_, PyAny>>) -> PyResult<rayon::ThreadPool> {
    let n = threads.map(|t| args::count("threads", t)).transpose()?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(n.unwrap_or(0) as usize)
        .build()
        .map_err(error)
}

/// A traced medium's three channel outputs as the dict `simulate` documents.
pub fn output_dict<'py>(py: Python<'py>, traced: &Traced) -> PyResult<Bound<'py, PyDict>> {
    let outputs = &traced.outputs;
    let g = outputs[0].grid;
    let d = PyDict::new(py);
    let r: Vec<f64> = (0..g.nr).map(|i| g.r_optimal(i)).collect();
    d.set_item("r_cm", r.into_pyarray(py))?;
    let per_bin = |f: &dyn Fn(&mc::Estimate) -> f64| {
        Array2::from_shape_fn((g.nr, 3), |(i, c)| f(&outputs[c].rd_r[i])).into_pyarray(py)
    };
    d.set_item("rd", per_bin(&|e| e.value))?;
    d.set_item("rd_se", per_bin(&|e| e.se))?;
    let totals = |f: &dyn Fn(&Output) -> f64| outputs.iter().map(f).collect::<Vec<f64>>();
    d.set_item("rd_total", totals(&|o| o.rd.value))?;
    d.set_item("rd_total_se", totals(&|o| o.rd.se))?;
    d.set_item("a_total", totals(&|o| o.a.value))?;
    d.set_item("a_total_se", totals(&|o| o.a.se))?;
    d.set_item("tt_total", totals(&|o| o.tt.value))?;
    d.set_item("tt_total_se", totals(&|o| o.tt.se))?;
    d.set_item("rsp", totals(&|o| o.rsp))?;
    let layers = outputs[0].a_l.len();
    let a_l = Array2::from_shape_fn((3, layers), |(c, l)| outputs[c].a_l[l].value);
    d.set_item("a_layers", a_l.into_pyarray(py))?;
    d.set_item("dr_cm", g.dr)?;
    d.set_item("nr", g.nr)?;
    d.set_item("dz_cm", g.dz)?;
    d.set_item("nz", g.nz)?;
    d.set_item("photons", outputs[0].photons)?;
    d.set_item("eta", traced.eta)?;
    if traced.absorption_rz {
        let a: Vec<f64> = outputs
            .iter()
            .flat_map(|o| o.a_rz.iter().map(|e| e.value))
            .collect();
        let a = numpy::ndarray::Array3::from_shape_vec((3, g.nr, g.nz), a).map_err(error)?;
        d.set_item("a_rz", a.into_pyarray(py))?;
    }
    Ok(d)
}
