//! MCML's files: `sss.read_mco(path)` (an `.mco` written by MCML or by `sss`) and
//! `sss.run_mci(path)` (every run of an `.mci` input file, traced as MCML traces it).

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::{args, error};

/// Reads an MCML output file (`.mco`): a dict of its totals (`photons`, `rsp`, `rd`, `a`, `tt`
/// [-]), bin widths (`dr_cm`, `dz_cm`) and 1D arrays (`rd_r`, `tt_r` [cm⁻²], `rd_a`, `tt_a`
/// [sr⁻¹], `a_z` [cm⁻¹], `a_l` [-]).
#[pyfunction]
pub fn read_mco<'py>(py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyDict>> {
    let text = args::read_text(path)?;
    let m = mc::mco::read(&text, path).map_err(error)?;
    let d = PyDict::new(py);
    d.set_item("photons", m.photons)?;
    d.set_item("dr_cm", m.dr)?;
    d.set_item("dz_cm", m.dz)?;
    d.set_item("rsp", m.rsp)?;
    d.set_item("rd", m.rd)?;
    d.set_item("a", m.a)?;
    d.set_item("tt", m.tt)?;
    for (key, v) in [
        ("a_l", m.a_l),
        ("a_z", m.a_z),
        ("rd_r", m.rd_r),
        ("rd_a", m.rd_a),
        ("tt_r", m.tt_r),
        ("tt_a", m.tt_a),
    ] {
        d.set_item(key, v.into_pyarray(py))?;
    }
    Ok(d)
}

/// Runs every run of an MCML input file (`.mci`) as MCML does (A(r, z) tallied), without
/// writing files: a list with one dict per run: `out_name` (the `.mco` the file names),
/// `photons`, `seconds`, totals `rsp`, `rd`, `a`, `tt` [-] with `rd_se`, `a_se`, `tt_se`, bin
/// widths `dr_cm`, `dz_cm`, and arrays `rd_r`, `tt_r` [cm⁻²], `a_z` [cm⁻¹], `a_rz` (nr × nz)
/// [cm⁻³]. photons overrides the file's counts; seed [default 1] seeds every run.
#[pyfunction]
#[pyo3(signature = (path, photons=None, seed=None))]
pub fn run_mci<'py>(
    py: Python<'py>,
    path: &str,
    photons: Option<&Bound<'py, PyAny>>,
    seed: Option<u64>,
) -> PyResult<Bound<'py, PyList>> {
    let text = args::read_text(path)?;
    let photons = photons.map(|p| args::count("photons", p)).transpose()?;
    let mut runs = mc::mci::parse(&text, path, seed.unwrap_or(1)).map_err(error)?;
    let list = PyList::empty(py);
    for r in &mut runs {
        if let Some(n) = photons {
            r.spec.photons = n;
        }
        r.spec.tallies.absorption_rz = true;
        let start = std::time::Instant::now();
        let spec = &r.spec;
        let o = py.detach(|| mc::run(spec, &|_| {})).map_err(error)?;
        py.check_signals()?;
        let g = o.grid;
        let d = PyDict::new(py);
        d.set_item("out_name", &r.out_name)?;
        d.set_item("photons", o.photons)?;
        d.set_item("seconds", start.elapsed().as_secs_f64())?;
        d.set_item("rsp", o.rsp)?;
        for (key, e) in [("rd", o.rd), ("a", o.a), ("tt", o.tt)] {
            d.set_item(key, e.value)?;
            d.set_item(format!("{key}_se"), e.se)?;
        }
        d.set_item("dr_cm", g.dr)?;
        d.set_item("dz_cm", g.dz)?;
        let values = |v: &[mc::Estimate]| v.iter().map(|e| e.value).collect::<Vec<f64>>();
        d.set_item("rd_r", values(&o.rd_r).into_pyarray(py))?;
        d.set_item("tt_r", values(&o.tt_r).into_pyarray(py))?;
        d.set_item("a_z", values(&o.a_z).into_pyarray(py))?;
        let a_rz = Array2::from_shape_vec((g.nr, g.nz), values(&o.a_rz)).map_err(error)?;
        d.set_item("a_rz", a_rz.into_pyarray(py))?;
        list.append(d)?;
    }
    Ok(list)
}
