//! The profile cache's flags (`--profiles`, `--photons`, `--seed`, `--config`, `--threads`,
//! `--table`) as a `render::ProfileCache`: profiles reused from a folder when they match what was
//! asked (`--photons`, `--seed` or `--config` given must match too), else simulated and written
//! there; every reuse and simulation announced on stderr.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use fit::Profile;

use crate::common::{Bars, parse_count};
use crate::files::Outputs;
use crate::library::Named;

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

/// The kernel and tables a package or the page is built with (`sss export --format package`,
/// `sss view`).
#[derive(Args)]
pub struct TableFlags {
    /// package and page: taps per 1D pass of the kernel
    #[arg(long, default_value_t = 17)]
    pub taps: usize,

    /// package and page: photons per channel and angle of the incidence, exit and entry-shift
    /// tables
    #[arg(long, value_parser = parse_count, default_value = "100000")]
    pub incidence_photons: u64,

    /// package and page: photons per channel and thickness of the translucency table
    #[arg(long, value_parser = parse_count, default_value = "20000")]
    pub translucency_photons: u64,
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

    /// `sss render`'s default request for `named` with these flags' run settings and seed, and
    /// the kernel's taps and the tables' photons of `t` (`sss export --format package`, `sss view`).
    pub fn request(&self, named: Named, t: &TableFlags) -> Result<render::Request> {
        let config = crate::library::config(self.config.as_deref())?;
        let mut request = render::Request {
            materials: vec![render::NamedMaterial {
                slug: named.slug,
                material: named.material,
            }],
            tables: render::TableSettings {
                seed: self.seed_in(&config),
                config,
                incidence_photons: t.incidence_photons,
                translucency_photons: t.translucency_photons,
            },
            ..render::Request::default()
        };
        request.frame.taps = t.taps;
        Ok(request)
    }

    /// `build(profiles, progress)` with profiles and tables from this cache (simulated ones join
    /// `files`) and bars on stderr: a plan, a package or a site.
    pub fn build<T>(
        &self,
        files: &mut Outputs,
        build: impl FnOnce(&mut dyn render::Profiles, &Bars) -> render::Result<T>,
    ) -> render::Result<T> {
        let mut profiles = Cached {
            source: self,
            files,
        };
        build(&mut profiles, &Bars::default())
    }

    /// The cache these flags describe.
    pub fn cache(&self) -> render::ProfileCache {
        render::ProfileCache {
            folder: self.folder(),
            config: self.config.clone(),
            photons: self.photons,
            seed: self.seed,
            threads: self.threads,
            table: self.table.clone(),
        }
    }

    /// The profile of a material (`render::ProfileCache::profile`), a simulated one added to
    /// `out`; bars and notes on stderr.
    pub fn profile(&self, n: &Named, out: &mut Outputs) -> Result<Profile> {
        let p = self.cache().profile(n, out, &Bars::default());
        Ok(p.map_err(|e| e.renamed(|f| (f == "threads").then(|| "--threads".into())))?)
    }
}

/// Profiles and tables from the cache (`render::Cached`), simulated ones added to the command's
/// outputs; bars and notes on stderr.
pub struct Cached<'a> {
    /// The cache's folder and run settings.
    pub source: &'a ProfileSource,
    /// The command's outputs, which simulated profiles and tables join.
    pub files: &'a mut Outputs,
}

impl Cached<'_> {
    /// `f` on the library's cache with these flags, outputs and bars.
    fn with<T>(
        &mut self,
        f: impl FnOnce(&mut render::Cached) -> render::Result<T>,
    ) -> render::Result<T> {
        let cache = self.source.cache();
        let progress = &Bars::default();
        let files = &mut *self.files;
        f(&mut render::Cached {
            cache: &cache,
            files,
            progress,
        })
    }
}

impl render::Profiles for Cached<'_> {
    fn profile(&mut self, m: &Named) -> render::Result<Profile> {
        self.with(|c| c.profile(m))
    }

    fn tables(
        &mut self,
        m: &Named,
        key: &str,
        build: &mut dyn FnMut() -> render::Result<render::MaterialTables>,
    ) -> render::Result<render::MaterialTables> {
        self.with(|c| c.tables(m, key, build))
    }
}
