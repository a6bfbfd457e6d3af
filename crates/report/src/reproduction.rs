//! The whole reproduction as `sss reproduce` runs it: the library's profiles (simulated in one
//! batch, or read from a folder the user named, each checked against its provenance), every
//! model on the five main materials, Tables 6.4 and 6.5 rendered (skipped, saying why, without
//! an adapter), chapter 5's figures, and the report with its files.

use std::path::{Path, PathBuf};
use std::time::Instant;

use fit::Profile;
use fit::evaluate::{ImageSize, evaluate};
use mc::outputs::Outputs;
use mc::progress::Progress;
use mc::provenance::{self, Explicit, Provenance, Reuse, provenance_path};
use mc::{Material, McError, SimConfig};

use crate::error::{ReportError, Result};
use crate::reproduce::{MAIN, MitsubaImages, Published, RenderedTables, Report};

/// What a reproduction is asked for.
#[derive(Clone, Debug, Default)]
pub struct Asked {
    /// CI size: 2·10⁴ photons per channel, a coarser grid (dr = min MFP/6, 10 max MFP) and
    /// 128-pixel test images.
    pub quick: bool,
    /// Photons per channel [default: the thesis settings', or 2·10⁴ when quick].
    pub photons: Option<u64>,
    /// A folder of the library's profiles `NAME.profile.csv` to read instead of simulating.
    pub profiles: Option<PathBuf>,
    /// The rendered-scene comparisons against Mitsuba 3 to include.
    pub references: Vec<MitsubaImages>,
}

/// The whole report in `out`: `index.html`, `report.json`, the plots and `profiles/` with their
/// provenance, as files to write; and `report.json`'s text. Runs and steps are reported to
/// `progress`; the Monte Carlo runs and fits use the current rayon pool.
pub fn reproduce(asked: Asked, out: &Path, progress: &dyn Progress) -> Result<(Outputs, String)> {
    let published = Published::thesis();
    let mut config = SimConfig::thesis()?;
    let extent_mfp = config.grid.r_max_mfp;
    let image = if asked.quick {
        config.grid.dr_per_min_mfp = 6.0;
        config.grid.r_max_mfp = 10.0;
        ImageSize {
            size: 128,
            max_half: 48,
        }
    } else {
        ImageSize::default()
    };
    let photons = asked
        .photons
        .unwrap_or(if asked.quick { 20_000 } else { config.photons });
    let mut files = Outputs::default();

    // 1. Profiles of the thesis's library (Table 6.2 and the draft's liquids), one batch: the
    // media added to the library since are not part of the reproduction.
    let all = mc::builtin::REPRODUCED
        .into_iter()
        .map(|n| Ok((n.to_lowercase(), Material::builtin(n)?)))
        .collect::<mc::Result<Vec<_>>>()?;
    let t = Instant::now();
    let (csvs, provenance) = library_profiles(&asked, &config, photons, &all, progress)?;
    let simulate_seconds = t.elapsed().as_secs_f64();
    // The photons behind the report: those asked, or those every profile read says it has.
    let counts: Vec<Option<u64>> = provenance
        .iter()
        .map(|p| {
            p.as_ref()
                .filter(|p| p.target_error.is_none())
                .map(|p| p.photons)
        })
        .collect();
    let photons = match &counts[..] {
        [Some(first), rest @ ..] if rest.iter().all(|c| *c == Some(*first)) => Some(*first),
        _ => None,
    };
    let mut profiles = Vec::new();
    for (((slug, _), csv), prov) in all.iter().zip(&csvs).zip(&provenance) {
        let path = out.join("profiles").join(format!("{slug}.profile.csv"));
        let p = Profile::parse_csv(csv, &path.display().to_string())?;
        if let Some(prov) = prov {
            files.add(provenance_path(&path), prov.to_json());
        }
        files.add(path, csv.as_str());
        profiles.push(p);
    }
    let index = |slug: &str| {
        all.iter()
            .position(|(s, _)| s == slug)
            .expect("the report's materials are built in")
    };

    // 2. Every model on the five main materials, with their plots.
    let mut evals = Vec::new();
    for name in MAIN {
        let p = &profiles[index(name)];
        progress.note(&format!("fitting and evaluating every model for {name} …"));
        let ev = evaluate(p, name, image)?;
        files.add_in(out, crate::plot::evaluation(p, &ev, name)?);
        evals.push(ev);
    }
    for ((slug, _), p) in all.iter().zip(&profiles) {
        if !MAIN.contains(&slug.as_str()) {
            let png = crate::plot::profile(p, slug)?;
            files.add(out.join(format!("{slug}.profile.png")), png);
        }
    }
    let slugs: Vec<(&str, &Material)> = all.iter().map(|(s, m)| (s.as_str(), m)).collect();
    let tables = crate::reproduce::tables(&slugs, &evals, &published);

    // 3. Tables 6.4 and 6.5 rendered on our scenes (skipped, saying why, without an adapter).
    let rendered_tables = rendered(&all, &profiles, asked.quick, &published, progress)?;

    // 4. Fig. 5.15 and 5.17 on Skin1: their plots, numbers and claims.
    progress
        .note("guided k = 1.55, b = 50 against pre-integration, and the manual w sweep (skin1) …");
    let i = index(crate::reproduce::CHAPTER5_MATERIAL);
    let chapter5 = crate::reproduce::chapter5(&all[i].1, &profiles[i], image, extent_mfp)?;
    for (name, png) in chapter5.plots()? {
        files.add(out.join(name), png);
    }
    let report = Report::new(
        asked.quick,
        photons,
        simulate_seconds,
        tables,
        &chapter5,
        rendered_tables,
        asked.references,
    );
    let json = serde_json::to_string_pretty(&report)
        .map_err(|e| ReportError::invalid("report.json", "the report", e.to_string()))?;
    files.add(out.join("report.json"), json.as_str());
    files.add(out.join("index.html"), report.html());
    Ok((files, json))
}

/// A profile of the folder the user named and its provenance, if it has one: one that is not of
/// the built-in material, or not of the photons asked for, is refused, as is one without
/// provenance when photons were asked for.
fn read_profile(
    csv: &Path,
    asked: &Provenance,
    explicit: Explicit,
) -> Result<(String, Option<Provenance>)> {
    let name = csv.display().to_string();
    let text =
        mc::input::read_text(csv).map_err(|e| McError::file(format!("cannot read {name}"), e))?;
    let sidecar = provenance_path(csv);
    let have = sidecar
        .exists()
        .then(|| provenance::read(&sidecar))
        .transpose()?;
    match provenance::reuse(&name, &sidecar, have.as_ref(), asked, explicit) {
        Reuse::Use(_) => Ok((text, have)),
        Reuse::Replace(why) if have.is_none() => Err(ReportError::Refused(format!(
            "{why}: it cannot stand for --photons {}",
            asked.photons
        ))),
        Reuse::Replace(why) => Err(ReportError::Refused(why)),
    }
}

/// Every reproduced material's profile CSV with its provenance: read from the folder asked (each
/// must match what was asked) or simulated in one batch of `photons` per channel.
fn library_profiles(
    asked: &Asked,
    config: &SimConfig,
    photons: u64,
    all: &[(String, Material)],
    progress: &dyn Progress,
) -> Result<(Vec<String>, Vec<Option<Provenance>>)> {
    let materials: Vec<&Material> = all.iter().map(|(_, m)| m).collect();
    let spec = config.batch(&materials, photons, config.seed, true)?;
    let asked_of = |i: usize| Provenance::of(&spec, i, &all[i].0, None);
    if let Some(dir) = &asked.profiles {
        let explicit = Explicit {
            photons: asked.photons.is_some(),
            ..Explicit::default()
        };
        let read = all
            .iter()
            .enumerate()
            .map(|(i, (slug, _))| {
                let csv = dir.join(format!("{slug}.profile.csv"));
                read_profile(&csv, &asked_of(i), explicit)
            })
            .collect::<Result<Vec<_>>>()?;
        return Ok(read.into_iter().unzip());
    }
    let total = photons * spec.groups().len() as u64;
    progress.begin("simulating the library", total);
    let outputs = mc::run_batch(&spec, &|k| progress.advance(k));
    progress.end();
    let outputs = outputs?;
    Ok((0..all.len())
        .map(|i| {
            let o = &outputs[3 * i..3 * i + 3];
            (
                Profile::csv_from_mc([&o[0], &o[1], &o[2]]),
                Some(asked_of(i)),
            )
        })
        .unzip())
}

/// Tables 6.4 and 6.5 rendered on our scenes with the library's profiles, or skipped (saying
/// why) without an adapter.
fn rendered(
    all: &[(String, Material)],
    profiles: &[Profile],
    quick: bool,
    published: &Published,
    progress: &dyn Progress,
) -> Result<RenderedTables> {
    Ok(match gpu::Gpu::new() {
        Err(e) => {
            progress.note(&format!("rendered Tables 6.4 and 6.5 skipped: {e}"));
            RenderedTables::Skipped {
                reason: e.to_string(),
            }
        }
        Ok(gpu) => {
            progress.note("rendering Tables 6.4 and 6.5 on our scenes …");
            let with: Vec<(&str, &Profile)> = all
                .iter()
                .zip(profiles)
                .map(|((slug, _), p)| (slug.as_str(), p))
                .collect();
            let r = crate::rendered::rendered_tables(&gpu, &with, quick, published)?;
            progress.note(&format!(
                "rendered Tables 6.4 and 6.5 in {:.1} s",
                r.seconds
            ));
            RenderedTables::Rendered(Box::new(r))
        }
    })
}
