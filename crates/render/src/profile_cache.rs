//! The profile cache: Monte Carlo profiles `NAME.profile.csv` in a folder, each beside its
//! provenance `NAME.profile.json` (the material's coefficients per channel, the ambient indices,
//! the grid, photons per channel and seed), and a material's shading tables `NAME.tables.json`
//! with the key they were made for. `sss simulate`, `sss merge`, `sss reproduce` and every
//! profile simulated on demand write both profile files.
//!
//! A cached profile is reused only when it matches what was asked: always the physics (each
//! channel's σa, σs, g, η and thickness, and the ambient indices, under the run settings), and
//! the photons, seed and grid when they were given explicitly ([`mc::provenance::Explicit`]).
//! Otherwise it is simulated again and replaced. A profile without provenance (an older run, or
//! an analytic profile) is reused only when none of those three was given. Every reuse and
//! every new simulation is reported as a note ([`Progress::note`]); what is simulated joins the
//! caller's [`Outputs`], written when the caller commits them.

use std::path::{Path, PathBuf};

use fit::Profile;
use fit::table_profile::{TableProfile, Tables};
use mc::outputs::Outputs;
use mc::provenance::{self, Explicit, Provenance, Reuse, provenance_path};
use mc::{McError, SimConfig};
use serde_json::{Value, json};

use crate::error::{RenderError, Result};
use crate::plan::Profiles;
use crate::progress::Progress;
use crate::request::NamedMaterial;
use crate::tables::MaterialTables;

/// Where Monte Carlo profiles come from: a folder, with missing or mismatching ones simulated
/// and added to the caller's outputs; or tables they are interpolated from.
#[derive(Clone, Debug, Default)]
pub struct ProfileCache {
    /// The folder of profiles (and kept tables).
    pub folder: PathBuf,
    /// A run-settings file (its grid then counts as asked for); `None`: the thesis's.
    pub config: Option<PathBuf>,
    /// Photons per channel asked for; `None`: the settings'.
    pub photons: Option<u64>,
    /// The seed asked for; `None`: the settings'.
    pub seed: Option<u64>,
    /// Worker threads of a simulation; `None`: all cores.
    pub threads: Option<usize>,
    /// Monte Carlo profile tables (a file, or a folder of `*.table.json`): profiles are
    /// interpolated from them instead, and nothing is cached.
    pub table: Option<PathBuf>,
}

impl ProfileCache {
    fn explicit(&self) -> Explicit {
        Explicit {
            photons: self.photons.is_some(),
            seed: self.seed.is_some(),
            grid: self.config.is_some(),
        }
    }

    /// The profile of `n`: interpolated from [`ProfileCache::table`] when given; else reused from
    /// the folder if it matches (see the module documentation), else simulated (a profile-only
    /// batch run, reported to `progress`) and added, CSV and provenance, to `out`. A profile
    /// simulated earlier into the same `out` is taken from there.
    pub fn profile(
        &self,
        n: &NamedMaterial,
        out: &mut Outputs,
        progress: &dyn Progress,
    ) -> Result<Profile> {
        if self.threads == Some(0) {
            return Err(RenderError::invalid("threads", 0, "must be at least 1"));
        }
        if let Some(path) = &self.table {
            let config = SimConfig::read(self.config.as_deref())?;
            return table_profile(path, n, &config, progress).map(|t| t.profile);
        }
        let csv = self.folder.join(format!("{}.profile.csv", n.slug));
        let name = csv.display().to_string();
        if let Some(bytes) = out.get(&csv) {
            return Ok(Profile::from_csv(&String::from_utf8_lossy(bytes), &name)?);
        }
        let config = SimConfig::read(self.config.as_deref())?;
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
                .then(|| provenance::read(&sidecar))
                .transpose()?;
            match provenance::reuse(&name, &sidecar, have.as_ref(), &asked, self.explicit()) {
                Reuse::Use(why) => {
                    progress.note(&why);
                    let text = mc::input::read_text(&csv)
                        .map_err(|e| McError::file(format!("cannot read {name}"), e))?;
                    return Ok(Profile::from_csv(&text, &name)?);
                }
                Reuse::Replace(why) => progress.note(&format!("{why}: simulating again")),
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0))
            .build()
            .map_err(|e| {
                RenderError::invalid("threads", format!("{:?}", self.threads), e.to_string())
            })?;
        progress.begin(
            &format!("simulating {}", n.slug),
            photons * spec.groups().len() as u64,
        );
        let simulated =
            pool.install(|| shading::profile::simulate(&spec, &name, &|k| progress.advance(k)));
        progress.end();
        let simulated = simulated?;
        progress.note(&format!(
            "simulated {} ({}) → {name} (written when the command has finished)",
            n.slug,
            asked.describe()
        ));
        out.add(provenance_path(&csv), asked.to_json());
        out.add(csv, simulated.csv);
        Ok(simulated.profile)
    }
}

/// A material's profile interpolated from the tables at `path` (see [`load_tables`]) on its
/// grid under `config`, reported as a note.
pub fn table_profile(
    path: &Path,
    n: &NamedMaterial,
    config: &SimConfig,
    progress: &dyn Progress,
) -> Result<TableProfile> {
    let tables = load_tables(path)?;
    let grid = config.grid_for(&n.material)?;
    let thickness = n.material.thickness.unwrap_or(config.thickness_cm);
    let t = tables.profile(&n.material, &grid, config.n_above, thickness)?;
    t.profile.validate()?;
    progress.note(&format!(
        "{}: profile interpolated from the tables in {}",
        n.slug,
        path.display()
    ));
    Ok(t)
}

/// Reads Monte Carlo profile tables: one table file, or every `*.table.json` in a folder.
pub fn load_tables(path: &Path) -> Result<Tables> {
    let files: Vec<PathBuf> = if path.is_dir() {
        let mut v: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| McError::file(format!("cannot read table folder {}", path.display()), e))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.to_string_lossy().ends_with(".table.json"))
            .collect();
        v.sort();
        if v.is_empty() {
            return Err(RenderError::NoTables(path.display().to_string()));
        }
        v
    } else {
        vec![path.to_path_buf()]
    };
    let tables = mc::input::read_named(&files, "table")?
        .into_iter()
        .map(|(name, text)| Ok((name.clone(), mc::table::Table::from_json(&text, &name)?)))
        .collect::<Result<Vec<_>>>()?;
    Ok(Tables::new(tables)?)
}

/// Profiles and tables from a [`ProfileCache`] for [`crate::Plan::build`], what is simulated or
/// built added to the caller's outputs.
pub struct Cached<'a> {
    /// The cache's folder and run settings.
    pub cache: &'a ProfileCache,
    /// The caller's outputs, which simulated profiles and tables join.
    pub files: &'a mut Outputs,
    /// Where simulations and notes are reported.
    pub progress: &'a dyn Progress,
}

impl Profiles for Cached<'_> {
    fn profile(&mut self, m: &NamedMaterial) -> Result<Profile> {
        self.cache
            .profile(m, self.files, self.progress)
            .map_err(|e| {
                // The error and its sources, as `anyhow` writes a chain.
                let (mut reason, mut source) = (e.to_string(), std::error::Error::source(&e));
                while let Some(s) = source {
                    reason += &format!(": {s}");
                    source = s.source();
                }
                RenderError::Profile {
                    material: m.slug.clone(),
                    reason,
                }
            })
    }

    /// Tables kept in the profile folder as NAME.tables.json beside the profiles, with the key
    /// they were made for: reused when it matches (a note), else built and added to the
    /// caller's outputs. Nothing is kept with tables to interpolate from, or when no table was
    /// asked for.
    fn tables(
        &mut self,
        m: &NamedMaterial,
        key: &str,
        build: &mut dyn FnMut() -> Result<MaterialTables>,
    ) -> Result<MaterialTables> {
        let path = self.cache.folder.join(format!("{}.tables.json", m.slug));
        if self.cache.table.is_none()
            && let Some(kept) = kept_tables(&path, key)
        {
            self.progress.note(&format!(
                "{}: reusing its tables from {}",
                m.slug,
                path.display()
            ));
            return Ok(kept);
        }
        let t = build()?;
        let any = t.simulated != (false, false)
            || t.entry_shift.is_some()
            || t.translucency.is_some()
            || t.shape.is_some();
        if self.cache.table.is_none() && any {
            let file = json!({ "key": key, "tables": t });
            self.files.add(&path, file.to_string());
        }
        Ok(t)
    }
}

/// The tables kept in `path` if they were made for `key` (anything unreadable counts as none).
fn kept_tables(path: &Path, key: &str) -> Option<MaterialTables> {
    let text = mc::input::read_text(path).ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    if v.get("key")?.as_str()? != key {
        return None;
    }
    serde_json::from_value(v.get("tables")?.clone()).ok()
}

/// The profile `sss profile` writes: an analytic model's, or the Monte Carlo profile
/// interpolated from tables (`sss table`).
#[derive(Clone, Copy, Debug)]
pub enum ProfileModel {
    /// An analytic model's Rd(r).
    Analytic(fit::analytic::Model),
    /// The Monte Carlo profile interpolated from tables ([`table_profile`]).
    Table,
}

impl std::str::FromStr for ProfileModel {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("table") {
            return Ok(ProfileModel::Table);
        }
        fit::analytic::Model::parse(s)
            .map(ProfileModel::Analytic)
            .map_err(|e| format!("{e} (or `table`, with tables)"))
    }
}

impl ProfileModel {
    /// The model's name in file names: `pbd`, `table`, …
    pub fn name(&self) -> &'static str {
        match self {
            ProfileModel::Analytic(m) => m.name(),
            ProfileModel::Table => "table",
        }
    }

    /// The profile of `n` on its grid under `config`, as the CSV `sss simulate` writes (an
    /// analytic model's last bin holds everything beyond the grid, with a standard error of 0);
    /// `tables` (a file or a folder of them) is read for [`ProfileModel::Table`] and refused
    /// with an analytic model.
    pub fn csv(
        &self,
        n: &NamedMaterial,
        config: &SimConfig,
        tables: Option<&Path>,
        progress: &dyn Progress,
    ) -> Result<String> {
        let grid = config.grid_for(&n.material)?;
        let nr = grid.nr - 1;
        match (self, tables) {
            (ProfileModel::Table, Some(t)) => Ok(table_profile(t, n, config, progress)?.to_csv()),
            (ProfileModel::Table, None) => Err(RenderError::invalid(
                "table",
                "none",
                "model table interpolates tables: name a file or folder from `sss table`",
            )),
            (ProfileModel::Analytic(m), Some(t)) => Err(RenderError::invalid(
                "table",
                t.display(),
                format!("is read only with model table, not {}", m.name()),
            )),
            (ProfileModel::Analytic(model), None) => {
                let p = fit::analytic::profile(*model, &n.material, grid.dr, nr)?;
                let overflow = fit::analytic::overflow(*model, &n.material, grid.dr, nr)?;
                Ok(p.to_csv(overflow.map(|v| (v, 0.0))))
            }
        }
    }
}
