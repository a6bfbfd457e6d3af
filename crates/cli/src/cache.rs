//! The profile cache: Monte Carlo profiles `NAME.profile.csv` in a folder, each beside its
//! provenance `NAME.profile.json` (the material's coefficients per channel, the ambient indices,
//! the grid, photons per channel and seed). `sss simulate`, `sss merge`, `sss reproduce` and
//! every profile simulated on demand write both.
//!
//! A cached profile is reused only when it matches what was asked: always the physics (each
//! channel's σa, σs, g, η and thickness, and the ambient indices, under the thesis settings or
//! `--config`), and the photons, seed and grid when `--photons`, `--seed` or `--config` is given.
//! Otherwise it is simulated again and replaced. A profile without provenance (an older run, or
//! `sss profile`'s analytic output) is reused only when none of those three was given. Every
//! reuse and every new simulation is announced on stderr.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use fit::Profile;
use mc::{BatchSpec, ChannelSpec};
use serde::{Deserialize, Serialize};

use crate::files::Outputs;
use crate::library::{self, Named};
use crate::{parse_count, progress, simulate};

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

    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serializes") + "\n"
    }

    /// Reads a provenance file; `name` is used in errors.
    pub fn from_json(text: &str, name: &str) -> Result<Self> {
        let p: Provenance = serde_json::from_str(text)
            .with_context(|| format!("invalid profile provenance {name} (delete it, or the profile with it, to simulate again)"))?;
        if p.format != FORMAT || p.channels.len() != 3 {
            bail!(
                "invalid profile provenance {name}: format {:?} with {} channels, expected {FORMAT:?} with 3",
                p.format,
                p.channels.len()
            );
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
                    mc::CHANNELS[c],
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
                    mc::CHANNELS[c],
                    have.grid.dr,
                    have.grid.nr,
                    want.grid.dr,
                    want.grid.nr
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
    pub photons: bool,
    pub seed: bool,
    pub grid: bool,
}

impl Explicit {
    fn any(self) -> bool {
        self.photons || self.seed || self.grid
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

/// The provenance file beside a profile CSV: `NAME.profile.csv` → `NAME.profile.json`.
pub fn provenance_path(csv: &Path) -> PathBuf {
    csv.with_extension("json")
}

/// Where Monte Carlo profiles come from: a folder, with missing or mismatching ones simulated
/// and written there.
#[derive(Args)]
pub struct ProfileSource {
    /// Folder of Monte Carlo profiles NAME.profile.csv with their provenance NAME.profile.json. A
    /// profile there is reused (announced on stderr) when it was simulated for the material's
    /// coefficients and for any --photons, --seed and --config given; otherwise it is simulated
    /// and written there, with the command's other outputs [default: out; for render, its --out]
    #[arg(long, value_name = "DIR")]
    pub profiles: Option<PathBuf>,

    /// Photons per channel for profiles simulated here; when given, a cached profile must have
    /// been simulated with exactly this many [default: from the settings, 1e7]
    #[arg(long, value_parser = parse_count)]
    pub photons: Option<u64>,

    /// Seed for profiles simulated here; when given, a cached profile must have this seed
    /// [default: from the settings, 1]
    #[arg(long)]
    pub seed: Option<u64>,

    /// Run settings TOML for profiles simulated here (grid rule, thickness, ambient η); when
    /// given, a cached profile must have its grid [default: built-in configs/thesis.toml]
    #[arg(long = "config", value_name = "FILE")]
    pub config: Option<PathBuf>,

    /// Worker threads [default: all cores]
    #[arg(long)]
    pub threads: Option<usize>,
}

impl ProfileSource {
    /// The profile folder: `--profiles`, or `out`.
    pub fn folder(&self) -> PathBuf {
        self.profiles.clone().unwrap_or_else(crate::default_out)
    }

    /// The seed asked for, or the thesis's 1 (also the seed of render's own `mc` tables).
    pub fn seed(&self) -> u64 {
        self.seed.unwrap_or(1)
    }

    fn explicit(&self) -> Explicit {
        Explicit {
            photons: self.photons.is_some(),
            seed: self.seed.is_some(),
            grid: self.config.is_some(),
        }
    }

    /// The profile of a material: reused from the folder if it matches (see the module
    /// documentation), else simulated (a profile-only batch run) and added, CSV and provenance,
    /// to `out` to be written with the command's other outputs. A profile simulated earlier in
    /// the same command is taken from `out`.
    pub fn profile(&self, n: &Named, out: &mut Outputs) -> Result<Profile> {
        let csv = self.folder().join(format!("{}.profile.csv", n.slug));
        let name = csv.display().to_string();
        if let Some(bytes) = out.get(&csv) {
            return Ok(Profile::from_csv(&String::from_utf8_lossy(bytes), &name)?);
        }
        let config = library::config(self.config.as_deref())?;
        let (photons, seed) = (
            self.photons.unwrap_or(config.photons),
            self.seed.unwrap_or(config.seed),
        );
        let spec = config.batch(&[&n.material], photons, seed, true)?;
        let asked = Provenance::of(&spec, 0, &n.slug, None);
        let explicit = self.explicit();
        if csv.exists() {
            let sidecar = provenance_path(&csv);
            let reuse = if sidecar.exists() {
                let text = std::fs::read_to_string(&sidecar)
                    .with_context(|| format!("cannot read {}", sidecar.display()))?;
                let have = Provenance::from_json(&text, &sidecar.display().to_string())?;
                let differ = have.mismatches(&asked, explicit);
                if differ.is_empty() {
                    eprintln!("reusing {name} ({})", have.describe());
                } else {
                    eprintln!(
                        "{name} does not match what was asked ({}): simulating again",
                        differ.join("; ")
                    );
                }
                differ.is_empty()
            } else if explicit.any() {
                eprintln!(
                    "{name} has no provenance ({} is missing), and --photons, --seed or --config was given: simulating again",
                    sidecar.display()
                );
                false
            } else {
                eprintln!(
                    "reusing {name} without provenance (no {}): its material, photons and seed are unknown; give --photons or --seed to simulate again",
                    sidecar.display()
                );
                true
            };
            if reuse {
                let text =
                    std::fs::read_to_string(&csv).with_context(|| format!("cannot read {name}"))?;
                return Ok(Profile::from_csv(&text, &name)?);
            }
        }
        let bar = progress::photons(
            photons * spec.groups().len() as u64,
            &format!("simulating {}", n.slug),
        );
        let outputs = simulate::thread_pool(self.threads)?
            .install(|| mc::run_batch(&spec, &|k| bar.inc(k)))?;
        bar.finish_and_clear();
        let text = simulate::profile_csv(&outputs.iter().collect::<Vec<_>>());
        eprintln!(
            "simulated {} ({}) → {name} (written when the command has finished)",
            n.slug,
            asked.describe()
        );
        let p = Profile::from_csv(&text, &name)?;
        out.add(provenance_path(&csv), asked.to_json());
        out.add(csv, text);
        Ok(p)
    }
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

    #[test]
    fn only_asked_settings_must_match() {
        let n = library::material("skin1").unwrap();
        let config = library::config(None).unwrap();
        let spec = |photons, seed| config.batch(&[&n.material], photons, seed, true).unwrap();
        let asked = Provenance::of(&spec(1000, 1), 0, "skin1", None);
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
    }
}
