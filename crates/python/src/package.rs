//! `sss.package(...)`: a material's whole shading model as `sss export --format package` writes
//! it (`render::Package`): its files as bytes, and its tables as NumPy arrays with their standard
//! errors and grids, for a Python program or an engine's build script. No GPU is needed.

use numpy::IntoPyArray;
use numpy::ndarray::{Array1, Array2, Array3};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::SssError;
use crate::render::{materials, refused, tables};

/// A (rows × 3) array of RGB rows.
fn rgb_rows<'py>(py: Python<'py>, rows: &[[f32; 3]]) -> Bound<'py, numpy::PyArray2<f32>> {
    let flat: Vec<f32> = rows.iter().flatten().copied().collect();
    Array2::from_shape_vec((rows.len(), 3), flat)
        .expect("rows of three")
        .into_pyarray(py)
}

/// A (rows × 9 × 3) array of angle tables.
fn rgb_tables<'py>(py: Python<'py>, tables: &[[[f32; 3]; 9]]) -> Bound<'py, numpy::PyArray3<f32>> {
    let flat: Vec<f32> = tables.iter().flatten().flatten().copied().collect();
    Array3::from_shape_vec((tables.len(), 9, 3), flat)
        .expect("tables of 9 × 3")
        .into_pyarray(py)
}

/// The shading model of one material as `sss export MATERIAL --format package` writes it: a dict
/// with `files` (file name → bytes: README.md, tables.json, tables.bin, kernel.{json,wgsl,glsl,
/// hlsl}, sss_lookups.{wgsl,glsl,hlsl}; write them into a folder as they are) and the tables as
/// float32 arrays: `angles_deg` (9,), `incidence` and `incidence_se` (9 × 3: ρ(θ)/ρ(0) per
/// channel), `exit` and `exit_se` (9 × 9 × 3: h(θ_o; θ_i), [θ_i][θ_o]), `entry_shift_cm` and
/// `entry_shift_se_cm` (9 × 3, δ(θ) [cm]), `translucency` (a dict with `thickness_cm` (16,),
/// `tt_over_rho` (16 × 3), `exit` (16 × 9 × 3), `rho` and `rho_se` (3,)), `eta`, `notes`.
/// Profiles simulated at the thesis's settings (1e7 photons per channel unless `photons`), seed 1
/// unless `seed`; the tables 1e5 photons per channel and angle (`incidence_photons`) and 2e4 per
/// thickness (`translucency_photons`), as `sss render`'s defaults.
#[pyfunction]
#[pyo3(signature = (
    material = None, *, taps = 17, photons = None, seed = None, incidence_photons = None,
    translucency_photons = None
))]
pub fn package<'py>(
    py: Python<'py>,
    material: Option<&Bound<'py, PyAny>>,
    taps: usize,
    photons: Option<&Bound<'py, PyAny>>,
    seed: Option<u64>,
    incidence_photons: Option<&Bound<'py, PyAny>>,
    translucency_photons: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let materials = match material {
        Some(m) if !m.is_none() => materials(m)?,
        _ => vec![::render::NamedMaterial::builtin("skin1").map_err(refused)?],
    };
    if materials.len() != 1 {
        return Err(SssError::new_err(format!(
            "invalid material: a package holds one material, not {}",
            materials.len()
        )));
    }
    let mut request = ::render::Request {
        materials,
        tables: tables(photons, seed, incidence_photons, translucency_photons)?,
        ..Default::default()
    };
    request.frame.taps = taps;
    let p = py
        .detach(|| {
            let mut profiles = ::render::Simulated {
                tables: &request.tables,
                progress: &(),
            };
            ::render::Package::build(&request, &mut profiles, &())
        })
        .map_err(refused)?;
    let out = PyDict::new(py);
    let files = PyDict::new(py);
    for (name, bytes) in p.files() {
        files.set_item(name, PyBytes::new(py, &bytes))?;
    }
    out.set_item("files", files)?;
    let t = &p.tables;
    let angles: Vec<f32> = (0..9).map(|k| 10.0 * k as f32).collect();
    out.set_item("angles_deg", Array1::from(angles).into_pyarray(py))?;
    out.set_item("incidence", rgb_rows(py, &t.angles.incidence))?;
    out.set_item("incidence_se", rgb_rows(py, &t.angles.incidence_se))?;
    out.set_item("exit", rgb_tables(py, &t.angles.exit))?;
    out.set_item("exit_se", rgb_tables(py, &t.angles.exit_se))?;
    let shift = t.entry_shift.unwrap_or(shading::EntryShift::NONE);
    out.set_item("entry_shift_cm", rgb_rows(py, &shift.shift_cm))?;
    out.set_item("entry_shift_se_cm", rgb_rows(py, &shift.shift_se_cm))?;
    let translucency = match &t.translucency {
        None => None,
        Some((tr, rho)) => {
            let d = PyDict::new(py);
            let thickness: Vec<f32> = (0..shading::TRANSLUCENCY_STEPS)
                .map(|k| tr.thickness_cm(k) as f32)
                .collect();
            d.set_item("thickness_cm", Array1::from(thickness).into_pyarray(py))?;
            d.set_item("tt_over_rho", rgb_rows(py, &tr.table))?;
            d.set_item("exit", rgb_tables(py, &tr.exit))?;
            let v = |f: fn(&shading::Estimate) -> f64| {
                Array1::from(rho.iter().map(|r| f(r) as f32).collect::<Vec<_>>()).into_pyarray(py)
            };
            d.set_item("rho", v(|r| r.value))?;
            d.set_item("rho_se", v(|r| r.se))?;
            Some(d)
        }
    };
    out.set_item("translucency", translucency)?;
    out.set_item("eta", p.rendered.eta)?;
    out.set_item("notes", p.notes.clone())?;
    Ok(out)
}
