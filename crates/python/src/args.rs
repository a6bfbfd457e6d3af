//! Arguments from Python: counts, numbers, RGB triples, arrays, materials and profiles, each
//! refused with [`crate::SssError`] naming the argument and its value (as the CLI's exit-2
//! messages do) rather than with a bare `TypeError`.

use mc::Material;
use numpy::PyReadonlyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::{SssError, error};

fn refuse<T>(name: &str, v: &Bound<'_, PyAny>, why: &str) -> PyResult<T> {
    let shown = v
        .repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".into());
    Err(SssError::new_err(format!("invalid {name} {shown}: {why}")))
}

/// A positive whole number of something (photons, taps), as an int or a whole float (`1e6`).
pub fn count(name: &str, v: &Bound<'_, PyAny>) -> PyResult<u64> {
    if v.is_instance_of::<pyo3::types::PyBool>() {
        return refuse(name, v, "must be a positive whole number, not a bool");
    }
    if let Ok(n) = v.extract::<u64>() {
        if n >= 1 {
            return Ok(n);
        }
    } else if let Ok(x) = v.extract::<f64>()
        && x.is_finite()
        && x >= 1.0
        && x.fract() == 0.0
        && x < u64::MAX as f64
    {
        return Ok(x as u64);
    }
    refuse(name, v, "must be a positive whole number")
}

/// A finite number.
pub fn number(name: &str, v: &Bound<'_, PyAny>) -> PyResult<f64> {
    match v.extract::<f64>() {
        Ok(x) if x.is_finite() && !v.is_instance_of::<pyo3::types::PyBool>() => Ok(x),
        _ => refuse(name, v, "must be a finite number"),
    }
}

/// One number for R, G and B, or three.
pub fn rgb(name: &str, v: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    if let Ok(x) = number(name, v) {
        return Ok([x; 3]);
    }
    let a = array(name, v)?;
    match a.as_slice() {
        [r, g, b] => Ok([*r, *g, *b]),
        _ => refuse(name, v, "give one number or three (R, G, B)"),
    }
}

/// A sequence of finite numbers, flattened.
pub fn array(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    Ok(array_shaped(name, v)?.1)
}

/// An array of finite numbers (anything `numpy.asarray` takes) as (shape, row-major values).
pub fn array_shaped(name: &str, v: &Bound<'_, PyAny>) -> PyResult<(Vec<usize>, Vec<f64>)> {
    if v.is_instance_of::<PyString>() {
        return refuse(name, v, "must be numbers, not a string");
    }
    let np = v.py().import("numpy")?;
    let Ok(a) = np.call_method1("asarray", (v, "float64")) else {
        return refuse(name, v, "must be numbers");
    };
    let Ok(a) = a.extract::<PyReadonlyArrayDyn<'_, f64>>() else {
        return refuse(name, v, "must be numbers");
    };
    let shape = a.as_array().shape().to_vec();
    let values: Vec<f64> = a.as_array().iter().copied().collect();
    if values.iter().any(|x| !x.is_finite()) {
        return refuse(name, v, "must be finite numbers (no NaN or infinity)");
    }
    Ok((shape, values))
}

/// What `simulate` traces: a homogeneous material, or layers.
pub enum Medium {
    /// A built-in name, a material file or a coefficient dict ([`material`]).
    Homogeneous(Material),
    /// A layered sample, per channel R, G, B its layers from the top.
    Layered {
        /// The sample's name (`name`, else "layered").
        name: String,
        /// Per channel, the layers from the top (thickness [cm], coefficients [cm⁻¹]).
        layers: [Vec<mc::Layer>; 3],
    },
}

/// A medium: a dict with `layers` (a list of dicts, each with `sigma_a` and `sigma_s` [cm⁻¹],
/// `g` (default 0), `eta` and `thickness` [cm], which the last layer may leave out: a
/// half-space), else a material ([`material`]).
pub fn medium(v: &Bound<'_, PyAny>) -> PyResult<Medium> {
    let Ok(d) = v.cast::<PyDict>() else {
        return Ok(Medium::Homogeneous(material(v)?));
    };
    let Some(list) = d.get_item("layers")? else {
        return Ok(Medium::Homogeneous(material(v)?));
    };
    for (k, _) in d.iter() {
        let key = k.extract::<String>().unwrap_or_default();
        if key != "layers" && key != "name" {
            return refuse("layered material key", &k, "expected layers, name");
        }
    }
    let name = match d.get_item("name")? {
        Some(n) => n
            .extract::<String>()
            .or_else(|_| refuse("material name", &n, "must be a string"))?,
        None => "layered".into(),
    };
    let items: Vec<Bound<'_, PyAny>> = match list.try_iter() {
        Ok(it) => it.collect::<PyResult<_>>()?,
        Err(_) => return refuse("layers", &list, "must be a list of layer dicts"),
    };
    if items.is_empty() {
        return refuse("layers", &list, "must hold at least one layer");
    }
    let mut layers: [Vec<mc::Layer>; 3] = Default::default();
    for (i, item) in items.iter().enumerate() {
        let field = |f: &str| format!("layer {} {f}", i + 1);
        let Ok(l) = item.cast::<PyDict>() else {
            return refuse(&format!("layer {}", i + 1), item, "must be a dict");
        };
        for (k, _) in l.iter() {
            let key = k.extract::<String>().unwrap_or_default();
            if !["sigma_a", "sigma_s", "g", "eta", "thickness"].contains(&key.as_str()) {
                return refuse(
                    &field("key"),
                    &k,
                    "expected sigma_a, sigma_s, g, eta, thickness",
                );
            }
        }
        let required = |key: &str| -> PyResult<Bound<'_, PyAny>> {
            l.get_item(key)?
                .ok_or_else(|| SssError::new_err(format!("{}: missing", field(key))))
        };
        let sigma_a = rgb(&field("sigma_a"), &required("sigma_a")?)?;
        let sigma_s = rgb(&field("sigma_s"), &required("sigma_s")?)?;
        let g = match l.get_item("g")? {
            Some(g) => rgb(&field("g"), &g)?,
            None => [0.0; 3],
        };
        let eta = number(&field("eta"), &required("eta")?)?;
        let thickness = match l.get_item("thickness")? {
            Some(t) => number(&field("thickness"), &t)?,
            None if i + 1 == items.len() => mc::SimConfig::thesis().map_err(error)?.thickness_cm,
            None => {
                return Err(SssError::new_err(format!(
                    "{}: missing",
                    field("thickness")
                )));
            }
        };
        for (c, channel) in layers.iter_mut().enumerate() {
            channel.push(mc::Layer {
                n: eta,
                mu_a: sigma_a[c],
                mu_s: sigma_s[c],
                g: g[c],
                thickness,
            });
        }
    }
    Ok(Medium::Layered { name, layers })
}

/// A material: a built-in name (`sss.materials()`), a path to a material `.toml` file, or a dict
/// with `sigma_a` and `sigma_s` [cm⁻¹], `g` [-] (default 0) and `eta` [-], each one value or
/// three (R, G, B), optionally `name` and `thickness` [cm].
pub fn material(v: &Bound<'_, PyAny>) -> PyResult<Material> {
    if let Ok(d) = v.cast::<PyDict>() {
        return material_of_dict(d);
    }
    let Ok(s) = v.extract::<String>() else {
        return refuse(
            "material",
            v,
            "give a built-in name, a .toml path or a dict of coefficients",
        );
    };
    mc::builtin::resolve(&s).map(|(_, m)| m).map_err(error)
}

fn material_of_dict(d: &Bound<'_, PyDict>) -> PyResult<Material> {
    const KEYS: [&str; 6] = ["name", "sigma_a", "sigma_s", "g", "eta", "thickness"];
    for (k, _) in d.iter() {
        let key = k.extract::<String>().unwrap_or_default();
        if !KEYS.contains(&key.as_str()) {
            return refuse("material key", &k, &format!("expected {}", KEYS.join(", ")));
        }
    }
    let get = |key: &str| d.get_item(key);
    let required = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        get(key)?.ok_or_else(|| SssError::new_err(format!("material dict: missing {key:?}")))
    };
    let m = Material {
        name: match get("name")? {
            Some(n) => n
                .extract::<String>()
                .or_else(|_| refuse("material name", &n, "must be a string"))?,
            None => "material".into(),
        },
        source: "Python dict".into(),
        sigma_a: rgb("sigma_a", &required("sigma_a")?)?,
        sigma_s: rgb("sigma_s", &required("sigma_s")?)?,
        g: match get("g")? {
            Some(g) => rgb("g", &g)?,
            None => [0.0; 3],
        },
        eta: number("eta", &required("eta")?)?,
        thickness: get("thickness")?
            .map(|t| number("thickness", &t))
            .transpose()?,
    };
    m.validate().map_err(error)?;
    Ok(m)
}

/// A profile: the dict `simulate` or `profile` returns (`dr_cm`, `r_cm` (n), `rd` (n × 3),
/// optionally `rd_se` (n × 3); the last bin is MCML's overflow bin and is left out), checked as
/// the fits need it.
pub fn profile(v: &Bound<'_, PyAny>) -> PyResult<fit::Profile> {
    let Ok(d) = v.cast::<PyDict>() else {
        return refuse(
            "profile",
            v,
            "give the dict sss.simulate or sss.profile returns",
        );
    };
    let item = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        d.get_item(key)?
            .ok_or_else(|| SssError::new_err(format!("profile dict: missing {key:?}")))
    };
    let dr = number("dr_cm", &item("dr_cm")?)?;
    let r = array("r_cm", &item("r_cm")?)?;
    let n = r.len();
    let columns = |key: &str, v: &Bound<'_, PyAny>| -> PyResult<[Vec<f64>; 3]> {
        let (shape, values) = array_shaped(key, v)?;
        if shape != [n, 3] {
            return refuse(key, v, &format!("must have shape ({n}, 3), like r_cm"));
        }
        Ok(std::array::from_fn(|c| {
            (0..n.saturating_sub(1))
                .map(|i| values[3 * i + c])
                .collect()
        }))
    };
    let rd = columns("rd", &item("rd")?)?;
    let se = match d.get_item("rd_se")? {
        Some(s) => columns("rd_se", &s)?,
        None => std::array::from_fn(|_| vec![0.0; n.saturating_sub(1)]),
    };
    let p = fit::Profile {
        dr,
        r: r[..n.saturating_sub(1)].to_vec(),
        rd,
        se,
    };
    p.validate().map_err(error)?;
    Ok(p)
}

/// The text of a file the caller named, through `mc`'s input cap.
pub fn read_text(path: &str) -> PyResult<String> {
    mc::input::read_text(path).map_err(|e| error(format!("cannot read {path}: {e}")))
}
