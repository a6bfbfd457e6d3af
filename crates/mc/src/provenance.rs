//! A Monte Carlo profile's provenance (`NAME.profile.json` beside `NAME.profile.csv`): what `mc`
//! simulated for it (each channel's layer and grid, the ambient indices, photons per channel and
//! seed), and whether a cached profile can stand for the one asked.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::batch::{BatchSpec, ChannelSpec};
use crate::error::{McError, Result};
use crate::material::CHANNELS;

/// The `format` of provenance files.
const FORMAT: &str = "sss-profile-1";

/// Where a profile came from: what `mc` simulated for it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// Always [`FORMAT`].
    pub format: String,
    /// The material's short name (informative: matching compares the coefficients).
    pub material: String,
    /// Refractive index of the medium above [-].
    pub n_above: f64,
    /// Refractive index of the medium below [-].
    pub n_below: f64,
    /// The R, G, B channels: layer (cm, cm⁻¹) and tally grid (cm).
    pub channels: Vec<ChannelSpec>,
    /// Photon packets per channel (the cap of an error-targeted run).
    pub photons: u64,
    /// Seed of every random stream.
    pub seed: u64,
    /// The relative standard error the run stopped at, if it was error-targeted.
    pub target_error: Option<f64>,
}

impl Provenance {
    /// The provenance of material `m` (channels `3m..3m+3`) of a batch.
    pub fn of(spec: &BatchSpec, m: usize, slug: &str, target_error: Option<f64>) -> Self {
        Provenance {
            format: FORMAT.into(),
            material: slug.into(),
            n_above: spec.n_above,
            n_below: spec.n_below,
            channels: spec.channels[3 * m..3 * m + 3].to_vec(),
            photons: spec.photons,
            seed: spec.seed,
            target_error,
        }
    }

    /// The provenance file's text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serializes") + "\n"
    }

    /// Reads a provenance file; `name` is used in errors.
    pub fn from_json(text: &str, name: &str) -> Result<Self> {
        let p: Provenance = serde_json::from_str(text).map_err(|e| {
            McError::parse(
                name,
                e.line(),
                format!(
                    "invalid profile provenance: {e} (delete it, or the profile with it, to simulate again)"
                ),
            )
        })?;
        if p.format != FORMAT || p.channels.len() != 3 {
            return Err(McError::parse(
                name,
                0,
                format!(
                    "invalid profile provenance: format {:?} with {} channels, expected {FORMAT:?} with 3",
                    p.format,
                    p.channels.len()
                ),
            ));
        }
        Ok(p)
    }

    /// "3e4 photons" or "≤ 1e7 photons to error 0.01".
    fn photons_text(&self) -> String {
        match self.target_error {
            Some(e) => format!("≤ {} photons to error {e}", count(self.photons)),
            None => format!("{} photons", count(self.photons)),
        }
    }

    /// "3e4 photons, seed 2, dr 0.0112 cm" (for messages).
    pub fn describe(&self) -> String {
        format!(
            "{}, seed {}, dr {:.4} cm",
            self.photons_text(),
            self.seed,
            self.channels[0].grid.dr
        )
    }

    /// How this differs from `asked`: always the physics; photons, seed and grid only where
    /// `explicit` says they were asked for. Empty when the profile can stand for the one asked.
    pub fn mismatches(&self, asked: &Provenance, explicit: Explicit) -> Vec<String> {
        let close = |a: f64, b: f64| a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
        let mut v = Vec::new();
        if !(close(self.n_above, asked.n_above) && close(self.n_below, asked.n_below)) {
            v.push(format!(
                "ambient η {}/{} ≠ {}/{}",
                self.n_above, self.n_below, asked.n_above, asked.n_below
            ));
        }
        for (c, (have, want)) in self.channels.iter().zip(&asked.channels).enumerate() {
            let (h, w) = (have.layer, want.layer);
            let same = [
                (h.mu_a, w.mu_a),
                (h.mu_s, w.mu_s),
                (h.g, w.g),
                (h.n, w.n),
                (h.thickness, w.thickness),
            ]
            .iter()
            .all(|&(a, b)| close(a, b));
            if !same {
                v.push(format!(
                    "channel {} (σa, σs, g, η, thickness) ({}, {}, {}, {}, {}) ≠ ({}, {}, {}, {}, {})",
                    CHANNELS[c],
                    h.mu_a,
                    h.mu_s,
                    h.g,
                    h.n,
                    h.thickness,
                    w.mu_a,
                    w.mu_s,
                    w.g,
                    w.n,
                    w.thickness
                ));
            }
            if explicit.grid && !(close(have.grid.dr, want.grid.dr) && have.grid.nr == want.grid.nr)
            {
                v.push(format!(
                    "channel {} grid dr {} cm × {} ≠ {} cm × {}",
                    CHANNELS[c], have.grid.dr, have.grid.nr, want.grid.dr, want.grid.nr
                ));
            }
        }
        if explicit.photons && (self.photons != asked.photons || self.target_error.is_some()) {
            v.push(format!(
                "{} ≠ {}",
                self.photons_text(),
                count(asked.photons)
            ));
        }
        if explicit.seed && self.seed != asked.seed {
            v.push(format!("seed {} ≠ {}", self.seed, asked.seed));
        }
        v
    }
}

/// Which run settings the user asked for explicitly (and a cached profile must then have).
#[derive(Clone, Copy, Debug, Default)]
pub struct Explicit {
    /// Photons per channel.
    pub photons: bool,
    /// The seed.
    pub seed: bool,
    /// The grid (a run-settings file).
    pub grid: bool,
}

impl Explicit {
    /// Whether any setting was asked for.
    pub fn any(self) -> bool {
        self.photons || self.seed || self.grid
    }
}

/// Whether a cached profile stands for the one asked, with the line that says why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reuse {
    /// Use it.
    Use(String),
    /// Do not: a cache simulates it again; files the user named are refused.
    Replace(String),
}

/// The reuse policy of a profile folder, for the profile `name` (its CSV exists) whose
/// provenance file `sidecar` holds `have` (None: there is none): with provenance, it stands for
/// `asked` when [`Provenance::mismatches`] finds nothing; without, only when nothing was
/// asked for explicitly (its material, photons and seed are unknown).
pub fn reuse(
    name: &str,
    sidecar: &Path,
    have: Option<&Provenance>,
    asked: &Provenance,
    explicit: Explicit,
) -> Reuse {
    match have {
        Some(have) => {
            let differ = have.mismatches(asked, explicit);
            if differ.is_empty() {
                Reuse::Use(format!("reusing {name} ({})", have.describe()))
            } else {
                Reuse::Replace(format!(
                    "{name} does not match what was asked ({})",
                    differ.join("; ")
                ))
            }
        }
        None if explicit.any() => Reuse::Replace(format!(
            "{name} has no provenance ({} is missing), so its photons, seed and grid are unknown",
            sidecar.display()
        )),
        None => Reuse::Use(format!(
            "reusing {name} without provenance (no {}): its material, photons and seed are unknown",
            sidecar.display()
        )),
    }
}

/// A count as people write it: 10000000 → "1e7", 30000 → "3e4", 12345 → "12345".
pub fn count(n: u64) -> String {
    let zeros = (0..19)
        .take_while(|&k| n.is_multiple_of(10u64.pow(k + 1)))
        .count() as u32;
    if n > 0 && zeros >= 3 && n / 10u64.pow(zeros) < 10 {
        format!("{}e{zeros}", n / 10u64.pow(zeros))
    } else {
        n.to_string()
    }
}

/// Reads the provenance file `sidecar` of a cached profile.
pub fn read(sidecar: &Path) -> Result<Provenance> {
    let name = sidecar.display().to_string();
    let text = crate::input::read_text(sidecar)
        .map_err(|e| crate::McError::file(format!("cannot read {name}"), e))?;
    Provenance::from_json(&text, &name)
}

/// The provenance file beside a profile CSV: `NAME.profile.csv` → `NAME.profile.json`.
pub fn provenance_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_read_as_people_write_them() {
        assert_eq!(count(10_000_000), "1e7");
        assert_eq!(count(30_000), "3e4");
        assert_eq!(count(250_000), "250000");
        assert_eq!(count(12_345), "12345");
        assert_eq!(count(100), "100");
    }

    /// A batch of one three-channel material under the thesis settings.
    fn spec(photons: u64, seed: u64) -> BatchSpec {
        let m = crate::Material {
            name: "m".into(),
            source: String::new(),
            sigma_a: [0.1, 0.5, 2.0],
            sigma_s: [10.0, 20.0, 40.0],
            g: [0.0, 0.5, 0.9],
            eta: 1.4,
            thickness: None,
        };
        let config = crate::SimConfig::thesis().unwrap();
        config.batch(&[&m], photons, seed, true).unwrap()
    }

    #[test]
    fn only_asked_settings_must_match() {
        let asked = Provenance::of(&spec(1000, 1), 0, "m", None);
        let have = Provenance::of(&spec(3000, 2), 0, "x", None);
        assert!(have.mismatches(&asked, Explicit::default()).is_empty());
        let all = Explicit {
            photons: true,
            seed: true,
            grid: true,
        };
        assert_eq!(have.mismatches(&asked, all).len(), 2);
        let mut other = have.clone();
        other.channels[1].layer.mu_s *= 1.01;
        assert_eq!(other.mismatches(&asked, Explicit::default()).len(), 1);
        let back = Provenance::from_json(&have.to_json(), "p.json").unwrap();
        assert!(back.mismatches(&have, all).is_empty());
        assert!(Provenance::from_json("{}", "p.json").is_err());
    }

    /// The policy: provenance that matches → use; that differs → replace; none → use only when
    /// nothing was asked for.
    #[test]
    fn reuse_follows_the_provenance() {
        let asked = Provenance::of(&spec(1000, 1), 0, "m", None);
        let photons = Explicit {
            photons: true,
            ..Explicit::default()
        };
        let sidecar = Path::new("m.profile.json");
        let r = |have: Option<&Provenance>, e| reuse("m.profile.csv", sidecar, have, &asked, e);
        assert!(matches!(r(Some(&asked), photons), Reuse::Use(_)));
        let mut more = asked.clone();
        more.photons = 2000;
        assert!(matches!(r(Some(&more), Explicit::default()), Reuse::Use(_)));
        match r(Some(&more), photons) {
            Reuse::Replace(why) => assert!(why.contains("2e3 photons ≠ 1e3"), "{why}"),
            u => panic!("{u:?}"),
        }
        assert!(matches!(r(None, Explicit::default()), Reuse::Use(_)));
        match r(None, photons) {
            Reuse::Replace(why) => assert!(why.contains("m.profile.json is missing"), "{why}"),
            u => panic!("{u:?}"),
        }
    }
}
