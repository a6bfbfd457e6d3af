//! Materials: RGB optical coefficients of a homogeneous medium, read from TOML.
//!
//! ```toml
//! name = "Skin1"
//! source = "Jensen et al. 2001, via Freude 2014 Table 6.2"
//! unit = "cm"                 # lengths in cm or mm; coefficients in unit⁻¹
//! sigma_a = [0.32, 1.7, 4.8]  # absorption, R G B
//! sigma_s = [7.4, 8.8, 10.1]  # scattering, R G B
//! g = 0.0                     # HG anisotropy, one value or [R, G, B]
//! eta = 1.3                   # refractive index
//! # thickness = 1e8           # optional, in `unit`; default: the run config's
//! ```
//! Instead of `sigma_a` and `sigma_s`, an artist's `color` (multiple-scattering albedo, R G B)
//! and `radius` (mean free path 1/σt per channel, in `unit`) may be given; they are inverted to
//! coefficients by [`crate::artist`]. Values are converted to cm / cm⁻¹ on load.

use serde::Deserialize;

use crate::artist::Artist;
use crate::error::{McError, Result};

pub use crate::channel::CHANNELS;

/// A named homogeneous material, coefficients in cm⁻¹.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Display name.
    pub name: String,
    /// Where the coefficients come from.
    pub source: String,
    /// Absorption coefficient σa per channel [cm⁻¹].
    pub sigma_a: [f64; 3],
    /// Scattering coefficient σs per channel [cm⁻¹].
    pub sigma_s: [f64; 3],
    /// HG anisotropy g per channel [-].
    pub g: [f64; 3],
    /// Refractive index η [-].
    pub eta: f64,
    /// Thickness [cm], if the material fixes one.
    pub thickness: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    name: String,
    #[serde(default)]
    source: String,
    unit: String,
    sigma_a: Option<[f64; 3]>,
    sigma_s: Option<[f64; 3]>,
    color: Option<[f64; 3]>,
    radius: Option<[f64; 3]>,
    g: OneOrThree,
    eta: OneOrThree,
    thickness: Option<f64>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum OneOrThree {
    One(f64),
    Three([f64; 3]),
}

impl Material {
    /// An artist's material from `KEY=VALUE` items: `color=R,G,B` (multiple-scattering albedo in
    /// [0, 1]; one value for all three), `radius=R,G,B[:cm|mm]` (mean free path 1/σt, default cm),
    /// optionally `g=G` (default 0) and `eta=N` (default 1.3); inverted to σa, σs by van de Hulst's
    /// fit ([`crate::artist::Artist::coefficients`]). Returns the material with a name made from its parameters
    /// (`artist-XXXXXXXX`, so that profiles of different artist materials never share a file).
    pub fn from_artist(kv: &[String]) -> Result<(String, Material)> {
        let refuse = |m: String| McError::Artist(format!("invalid --from-artist {m}"));
        let (mut color, mut radius, mut g, mut eta) = (None, None, 0.0, 1.3);
        for item in kv {
            let (key, value) = item
                .split_once('=')
                .ok_or_else(|| refuse(format!("{item:?}: expected KEY=VALUE")))?;
            let number = |v: &str| {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| refuse(format!("{key}={v:?}: not a number")))
            };
            let rgb = |v: &str| match v.split(',').map(number).collect::<Result<Vec<_>>>() {
                Ok(x) if x.len() == 1 => Ok([x[0]; 3]),
                Ok(x) if x.len() == 3 => Ok([x[0], x[1], x[2]]),
                Ok(_) => Err(refuse(format!(
                    "{key}: {v:?}: give one value or three (R,G,B)"
                ))),
                Err(_) => {
                    let bad = v.split(',').find(|x| x.trim().parse::<f64>().is_err());
                    Err(refuse(format!(
                        "{key}: {:?} is not a number",
                        bad.unwrap_or(v)
                    )))
                }
            };
            match key.trim() {
                "color" => color = Some(rgb(value)?),
                "radius" => {
                    let (v, unit) = value.split_once(':').unwrap_or((value, "cm"));
                    let to_cm = match unit {
                        "cm" => 1.0,
                        "mm" => 0.1,
                        u => return Err(refuse(format!("radius unit {u:?}: cm or mm"))),
                    };
                    radius = Some(rgb(v)?.map(|r| r * to_cm));
                }
                "g" => g = number(value)?,
                "eta" => eta = number(value)?,
                k => return Err(refuse(format!("key {k:?}: color, radius, g or eta"))),
            }
        }
        let (Some(color), Some(radius)) = (color, radius) else {
            return Err(McError::Artist(
                "--from-artist needs color=R,G,B and radius=R,G,B[:unit]".into(),
            ));
        };
        let (sigma_a, sigma_s) = crate::artist::Artist { color, radius }.coefficients([g; 3])?;
        let id = format!("{color:?}{radius:?}{g}{eta}")
            .bytes()
            .fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
            });
        let material = Material {
            name: "artist".into(),
            source: format!("artist color {color:?}, radius {radius:?} cm, g {g}, eta {eta}"),
            sigma_a,
            sigma_s,
            g: [g; 3],
            eta,
            thickness: None,
        };
        material.validate()?;
        Ok((format!("artist-{:08x}", id as u32), material))
    }

    /// Parses and validates a material TOML; `source_name` is used in error messages.
    pub fn from_toml(text: &str, source_name: &str) -> Result<Self> {
        let f: MaterialFile =
            toml::from_str(text).map_err(|e| McError::toml(text, source_name, e))?;
        if f.name.trim().is_empty() {
            return Err(McError::invalid(
                "name",
                format!("{:?}", f.name),
                "must not be empty",
            ));
        }
        let to_cm = match f.unit.as_str() {
            "cm" => 1.0,
            "mm" => 0.1,
            other => {
                return Err(McError::invalid(
                    "unit",
                    format!("{other:?}"),
                    "must be \"cm\" or \"mm\"",
                ));
            }
        };
        let g = match f.g {
            OneOrThree::One(g) => [g; 3],
            OneOrThree::Three(g) => g,
        };
        let eta = match f.eta {
            OneOrThree::One(eta) => eta,
            OneOrThree::Three([r, g, b]) if r == g && g == b => r,
            OneOrThree::Three(e) => {
                return Err(McError::invalid(
                    "eta",
                    format!("{e:?}"),
                    "give one refractive index: the three channels share each photon's walk \
                     through one boundary (a batch), and tissue's dispersion across R, G, B is \
                     about 1 %",
                ));
            }
        };
        let missing = |field: &str, reason| McError::invalid(field, "missing", reason);
        let (sigma_a, sigma_s) = match (f.sigma_a, f.sigma_s, f.color, f.radius) {
            (Some(a), Some(s), None, None) => (a.map(|x| x / to_cm), s.map(|x| x / to_cm)),
            (None, None, Some(color), Some(radius)) => Artist {
                color,
                radius: radius.map(|r| r * to_cm),
            }
            .coefficients(g)?,
            (Some(_), None, None, None) => {
                return Err(missing(
                    "sigma_s",
                    "sigma_a is given: give sigma_s beside it",
                ));
            }
            (None, Some(_), None, None) => {
                return Err(missing(
                    "sigma_a",
                    "sigma_s is given: give sigma_a beside it",
                ));
            }
            (None, None, Some(_), None) => {
                return Err(missing("radius", "color is given: give radius beside it"));
            }
            (None, None, None, Some(_)) => {
                return Err(missing("color", "radius is given: give color beside it"));
            }
            (None, None, None, None) => {
                return Err(McError::invalid(
                    "sigma_a, sigma_s",
                    "missing",
                    "give the coefficients sigma_a and sigma_s [1/unit], or an artist's color \
                     and radius",
                ));
            }
            _ => {
                return Err(McError::invalid(
                    "sigma_a/sigma_s/color/radius",
                    "a mixed set",
                    "give either sigma_a and sigma_s, or an artist's color and radius",
                ));
            }
        };
        let m = Material {
            name: f.name,
            source: f.source,
            sigma_a,
            sigma_s,
            g,
            eta,
            thickness: f.thickness.map(|t| t * to_cm),
        };
        m.validate()?;
        Ok(m)
    }

    /// Checks every coefficient; the error names the field and channel.
    pub fn validate(&self) -> Result<()> {
        for (c, ch) in CHANNELS.iter().enumerate() {
            for (field, v) in [("sigma_a", self.sigma_a[c]), ("sigma_s", self.sigma_s[c])] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(McError::invalid(
                        format!("{field}[{ch}]"),
                        McError::number(v),
                        "must be non-negative and finite",
                    ));
                }
            }
            // g = 1: every scattering keeps the photon's direction, so σs(1 − g) = 0 and the
            // medium never turns light back (Rd = 0, transmission as if it did not scatter):
            // nothing a kernel can be fitted to. g = −1 (straight back) is a real limit.
            if !(self.g[c].is_finite() && (-1.0..1.0).contains(&self.g[c])) {
                return Err(McError::invalid(
                    format!("g[{ch}]"),
                    McError::number(self.g[c]),
                    "must lie in [-1, 1): at g = 1 light scattered keeps its direction and never \
                     returns (Rd = 0); for a channel that does not scatter give sigma_s = 0",
                ));
            }
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(McError::invalid(
                "eta",
                McError::number(self.eta),
                "refractive index must be positive and finite",
            ));
        }
        if let Some(t) = self.thickness
            && !(t.is_finite() && t > 0.0)
        {
            return Err(McError::invalid(
                "thickness",
                McError::number(t),
                "must be positive and finite",
            ));
        }
        Ok(())
    }

    /// What a user should know about this material that is not an error, one line each: η < 1
    /// (a medium of lower index than the air above it) is simulated as given.
    pub fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if self.eta < 1.0 {
            notes.push(format!(
                "{}: eta = {} < 1, a medium of lower refractive index than the air above it: \
                 light from outside beyond {:.1}° of the normal is totally reflected at its \
                 surface; simulated as given",
                self.name,
                self.eta,
                self.eta.asin().to_degrees()
            ));
        }
        notes
    }

    /// Single-scattering albedo σs/(σa+σs) of channel `c` [-]; 0 when nothing interacts.
    pub fn albedo(&self, c: usize) -> f64 {
        let t = self.sigma_a[c] + self.sigma_s[c];
        if t > 0.0 { self.sigma_s[c] / t } else { 0.0 }
    }

    /// Transport mean free path 1/(σa + σs(1−g)) of channel `c` [cm] (thesis Table 6.1);
    /// infinite for a non-interacting channel.
    pub fn mfp(&self, c: usize) -> f64 {
        self.layer(c, f64::INFINITY).transport_mfp()
    }

    /// The artist parameters of the material ([`Artist::of_coefficients`]).
    pub fn artist(&self) -> Artist {
        Artist::of_coefficients(self.sigma_a, self.sigma_s, self.g)
    }

    /// The layer of channel `c` with the given thickness [cm].
    pub fn layer(&self, c: usize, thickness: f64) -> crate::Layer {
        crate::Layer {
            n: self.eta,
            mu_a: self.sigma_a[c],
            mu_s: self.sigma_s[c],
            g: self.g[c],
            thickness,
        }
    }
}
