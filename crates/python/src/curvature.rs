//! `sss.light_scale_curvature(...)`: a mesh's curvature at the scale light travels in a material,
//! per vertex and channel (`shading::light_scale_curvature`), for an engine's asset build: what
//! its shader reads the shape table at (`sss_shape_energy`).

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;

use crate::args::array_shaped;
use crate::{SssError, error};

/// (rows × 3) values of argument `name`, or an error naming it.
fn rows(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; 3]>> {
    let (shape, values) = array_shaped(name, v)?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(SssError::new_err(format!(
            "invalid {name} of shape {shape:?}: must be (n, 3)"
        )));
    }
    Ok(values.chunks_exact(3).map(|r| [r[0], r[1], r[2]]).collect())
}

/// The curvature [cm⁻¹] of a triangle mesh at the scale light travels in a material, per vertex
/// and channel: each vertex's chord curvatures (n_y − n_x)·(y − x)/|y − x|² to the other
/// vertices of its body facing its way, averaged with the weight e^{−r/s}/r per unit area (exits
/// at a mean distance s from the entry): 1/R on a sphere at any scale, 0 on a plane. `positions`
/// (n × 3) [cm], `normals` (n × 3, pointing out), `triangles` (m × 3 vertex indices), `mean_cm`:
/// s per channel [cm], the half-space's mean exit distance (the shape table's ⟨s⟩ at κ = 0 and
/// θ = 0). Returns an n × 3 float32 array; raises SssError naming the argument on bad input.
#[pyfunction]
pub fn light_scale_curvature<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    normals: &Bound<'py, PyAny>,
    triangles: &Bound<'py, PyAny>,
    mean_cm: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
    let as_f32 =
        |r: Vec<[f64; 3]>| -> Vec<[f32; 3]> { r.iter().map(|v| v.map(|x| x as f32)).collect() };
    let positions = as_f32(rows("positions", positions)?);
    let normals = as_f32(rows("normals", normals)?);
    let triangles: Vec<[u32; 3]> = rows("triangles", triangles)?
        .iter()
        .map(|t| {
            t.iter()
                .all(|&i| i >= 0.0 && i.fract() == 0.0 && i <= u32::MAX as f64)
                .then(|| t.map(|i| i as u32))
                .ok_or_else(|| {
                    SssError::new_err(format!(
                        "invalid triangles row {t:?}: vertex indices must be whole numbers ≥ 0"
                    ))
                })
        })
        .collect::<PyResult<_>>()?;
    let (shape, s) = array_shaped("mean_cm", mean_cm)?;
    if shape != [3] {
        return Err(SssError::new_err(format!(
            "invalid mean_cm of shape {shape:?}: must be three numbers (R, G, B) [cm]"
        )));
    }
    let mean = [s[0] as f32, s[1] as f32, s[2] as f32];
    let baked = py
        .detach(|| {
            shading::light_scale_curvature(
                shading::SurfaceMesh {
                    positions: &positions,
                    normals: &normals,
                    triangles: &triangles,
                },
                mean,
            )
        })
        .map_err(error)?;
    let flat: Vec<f32> = baked.iter().flatten().copied().collect();
    Ok(Array2::from_shape_vec((baked.len(), 3), flat)
        .expect("rows of three")
        .into_pyarray(py))
}
