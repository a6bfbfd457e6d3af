//! The Python module `sss`: the `mc`, `fit`, `shading` and `render` libraries with NumPy arrays in and out. Every
//! number comes from a library call; this crate only converts arguments (refusing what does not
//! fit, naming the argument) and results (dicts of arrays), releases the GIL while the libraries
//! work, and lets Ctrl-C stop a long run.
//!
//! Units as in the CLI: lengths in cm, coefficients in cm⁻¹, Rd(r) in cm⁻².

use pyo3::prelude::*;

mod args;
mod curvature;
mod kernels;
mod mcml;
mod package;
mod render;
mod simulate;

pyo3::create_exception!(
    sss,
    SssError,
    pyo3::exceptions::PyValueError,
    "Bad input to `sss` (the message names the argument and its value) or a failed run."
);

/// Any library error as [`SssError`], with the library's message.
pub(crate) fn error(e: impl std::fmt::Display) -> PyErr {
    SssError::new_err(e.to_string())
}

/// Measured optical coefficients to subsurface-scattering kernels: Monte Carlo profiles (an
/// MCML-style tracer), analytic profiles, separable kernel fits, shader export and engine
/// parameters. Lengths in cm, coefficients in cm⁻¹, Rd(r) in cm⁻².
#[pymodule]
fn sss(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // SAFETY: at import, with the GIL held and before this module has started any thread or
    // opened the Vulkan loader; the CLI does the same first thing in `main`.
    unsafe { gpu::quiet_headless_vulkan() };
    m.add("SssError", m.py().get_type::<SssError>())?;
    m.add_class::<kernels::Kernel>()?;
    m.add_function(wrap_pyfunction!(simulate::materials, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(mcml::read_mco, m)?)?;
    m.add_function(wrap_pyfunction!(mcml::run_mci, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::profile, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::fit_kernel, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::export, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::kernel, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(kernels::engine_params, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(package::package, m)?)?;
    m.add_function(wrap_pyfunction!(curvature::light_scale_curvature, m)?)?;
    Ok(())
}
