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
use mc::provenance::{self, Explicit, Provenance, Reuse, provenance_path};

use crate::common::{self, parse_count};
use crate::files::Outputs;
use crate::library::{self, Named};
use render::RenderError;
use serde_json::{Value, json};

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

    /// Monte Carlo profile tables (a file, or a folder of *.table.json, from `sss table`):
    /// profiles are interpolated from them instead of simulated, and nothing is cached; each
    /// channel's g and η must lie within the tables' grid and its albedo within their albedos
    #[arg(long, value_name = "FILE|DIR", conflicts_with_all = ["photons", "seed"])]
    pub table: Option<PathBuf>,
}

impl ProfileSource {
    /// The profile folder: `--profiles`, or `out`.
    pub fn folder(&self) -> PathBuf {
        self.profiles
            .clone()
            .unwrap_or_else(crate::common::default_out)
    }

    /// The seed of every run: `--seed`, else the run settings' (`--config`, default the
    /// thesis's), already read.
    pub fn seed_in(&self, config: &mc::SimConfig) -> u64 {
        self.seed.unwrap_or(config.seed)
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
        if let Some(path) = &self.table {
            let config = library::config(self.config.as_deref())?;
            return table_profile(path, n, &config).map(|t| t.profile);
        }
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
        if csv.exists() {
            let sidecar = provenance_path(&csv);
            let have = sidecar
                .exists()
                .then(|| read_provenance(&sidecar))
                .transpose()?;
            match provenance::reuse(&name, &sidecar, have.as_ref(), &asked, self.explicit()) {
                Reuse::Use(why) => {
                    eprintln!("{why}");
                    let text = crate::files::read_text(&csv)
                        .with_context(|| format!("cannot read {name}"))?;
                    return Ok(Profile::from_csv(&text, &name)?);
                }
                Reuse::Replace(why) => eprintln!("{why}: simulating again"),
            }
        }
        let bar = common::photons(
            photons * spec.groups().len() as u64,
            &format!("simulating {}", n.slug),
        );
        let simulated = crate::common::thread_pool(self.threads)?
            .install(|| shading::profile::simulate(&spec, &name, &|k| bar.inc(k)))?;
        bar.finish_and_clear();
        eprintln!(
            "simulated {} ({}) → {name} (written when the command has finished)",
            n.slug,
            asked.describe()
        );
        out.add(provenance_path(&csv), asked.to_json());
        out.add(csv, simulated.csv);
        Ok(simulated.profile)
    }
}

/// A material's profile interpolated from `--table` on its grid under `config`.
pub fn table_profile(
    path: &std::path::Path,
    n: &Named,
    config: &mc::SimConfig,
) -> Result<fit::table_profile::TableProfile> {
    let tables = load_tables(path)?;
    let grid = config.grid_for(&n.material)?;
    let thickness = n.material.thickness.unwrap_or(config.thickness_cm);
    let t = tables.profile(&n.material, &grid, config.n_above, thickness)?;
    t.profile.validate()?;
    eprintln!(
        "{}: profile interpolated from the tables in {}",
        n.slug,
        path.display()
    );
    Ok(t)
}

/// The provenance file of a cached profile.
pub fn read_provenance(sidecar: &std::path::Path) -> Result<Provenance> {
    let text = crate::files::read_text(sidecar)
        .with_context(|| format!("cannot read {}", sidecar.display()))?;
    Ok(Provenance::from_json(
        &text,
        &sidecar.display().to_string(),
    )?)
}

/// Reads `--table`: one table file, or every `*.table.json` in a folder.
fn load_tables(path: &Path) -> Result<fit::table_profile::Tables> {
    let files: Vec<PathBuf> = if path.is_dir() {
        let mut v: Vec<PathBuf> = std::fs::read_dir(path)
            .with_context(|| format!("cannot read table folder {}", path.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.to_string_lossy().ends_with(".table.json"))
            .collect();
        v.sort();
        if v.is_empty() {
            bail!(
                "no table in {} (expected files *.table.json from `sss table`)",
                path.display()
            );
        }
        v
    } else {
        vec![path.to_path_buf()]
    };
    let tables = crate::files::read_named(&files, "table")?
        .into_iter()
        .map(|(name, text)| Ok((name.clone(), mc::table::Table::from_json(&text, &name)?)))
        .collect::<Result<Vec<_>>>()?;
    Ok(fit::table_profile::Tables::new(tables)?)
}

/// Profiles from the profile cache (`--profiles`), simulated ones added to the command's outputs.
pub struct Cached<'a> {
    /// The cache's folder and run settings.
    pub source: &'a ProfileSource,
    /// The command's outputs, which simulated profiles and tables join.
    pub files: &'a mut Outputs,
}

impl render::Profiles for Cached<'_> {
    fn profile(&mut self, m: &render::NamedMaterial) -> render::Result<fit::Profile> {
        let named = library::Named {
            slug: m.slug.clone(),
            material: m.material.clone(),
        };
        self.source
            .profile(&named, self.files)
            .map_err(|e| RenderError::Profile {
                material: m.slug.clone(),
                reason: format!("{e:#}"),
            })
    }

    /// Tables kept in the profile folder as NAME.tables.json beside the profiles, with the key
    /// they were made for: reused when it matches (announced), else built and added to the
    /// command's outputs. Nothing is kept with `--table` or when no table was asked for.
    fn tables(
        &mut self,
        m: &render::NamedMaterial,
        key: &str,
        build: &mut dyn FnMut() -> render::Result<render::MaterialTables>,
    ) -> render::Result<render::MaterialTables> {
        let path = self.source.folder().join(format!("{}.tables.json", m.slug));
        if self.source.table.is_none()
            && let Some(kept) = kept_tables(&path, key)
        {
            eprintln!("{}: reusing its tables from {}", m.slug, path.display());
            return Ok(kept);
        }
        let t = build()?;
        let any =
            t.simulated != (false, false) || t.entry_shift.is_some() || t.translucency.is_some();
        if self.source.table.is_none() && any {
            let file = json!({ "key": key, "tables": t });
            self.files.add(&path, file.to_string());
        }
        Ok(t)
    }
}

/// The tables kept in `path` if they were made for `key` (anything unreadable counts as none).
fn kept_tables(path: &std::path::Path, key: &str) -> Option<render::MaterialTables> {
    let text = crate::files::read_text(path).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    if v.get("key")?.as_str()? != key {
        return None;
    }
    serde_json::from_value(v.get("tables")?.clone()).ok()
}
