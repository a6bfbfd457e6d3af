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

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use fit::Profile;
use mc::provenance::{Explicit, Provenance, provenance_path};

use crate::files::Outputs;
use crate::library::{self, Named};
use crate::{parse_count, progress, simulate};

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
        let text = Profile::csv_from_mc([&outputs[0], &outputs[1], &outputs[2]]);
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
