//! What `sss simulate` and `sss merge` write for a finished batch of materials (simulated, or
//! merged from shards): per material its profile CSV with its provenance, its JSON summary,
//! with A(r, z) tallied its MCML `.mco` files, and with Rd(θ) measured its table and plot; and
//! the summaries as text. Also an MCML input's runs as JSON and text.

use std::path::Path;

use fit::analytic::Medium;
use mc::incidence::IncidenceRow;
use mc::outputs::Outputs;
use mc::provenance::{Provenance, provenance_path};
use mc::{BatchSpec, CHANNELS, ChannelSpec, Output};
use rayon::prelude::*;
use serde_json::{Value, json};

use crate::error::Result;
use crate::incidence::IncidenceComparison;

/// A finished batch (simulated or merged from shards), ready to be written.
pub struct Finished<'a> {
    /// The batch.
    pub spec: &'a BatchSpec,
    /// `SLUG:R`, `SLUG:G`, `SLUG:B` per material ([`mc::shard::check_labels`]).
    pub labels: &'a [String],
    /// The results, one per channel.
    pub outputs: &'a [Output],
    /// Rd(θ) per material, or empty.
    pub incidence: &'a [Vec<IncidenceRow>],
    /// The profile run's wall time [s].
    pub seconds: f64,
    /// Worker threads of the run.
    pub threads: usize,
    /// The relative standard error the run stopped at, if it ran to one.
    pub target_error: Option<f64>,
}

impl Finished<'_> {
    /// Each material's files in `out`: `SLUG.profile.csv` and its provenance, `SLUG.summary.json`,
    /// with A(r, z) tallied `SLUG.R/G/B.mco`, and with Rd(θ) `SLUG.incidence.csv` and `.png`;
    /// and each material's summary (the JSON file's contents).
    pub fn files(&self, out: &Path) -> Result<(Outputs, Vec<Value>)> {
        let &Finished {
            spec,
            labels,
            outputs,
            incidence,
            seconds,
            threads,
            target_error,
        } = self;
        let mut files = Outputs::default();
        let mut summaries = Vec::new();
        for m in 0..outputs.len() / 3 {
            let slug = labels[3 * m].split(':').next().unwrap_or("material");
            let chans: Vec<&Output> = outputs[3 * m..3 * m + 3].iter().collect();
            let specs = &spec.channels[3 * m..3 * m + 3];
            let csv = out.join(format!("{slug}.profile.csv"));
            let provenance = Provenance::of(spec, m, slug, target_error);
            files.add(provenance_path(&csv), provenance.to_json());
            files.add(
                csv,
                fit::Profile::csv_from_mc([chans[0], chans[1], chans[2]]),
            );
            let mut mco_files = Vec::new();
            if spec.tallies.absorption_rz {
                // The three .mco texts (each a few MB of formatted numbers) in parallel.
                let texts: Vec<(String, String)> = CHANNELS
                    .par_iter()
                    .enumerate()
                    .map(|(c, ch)| {
                        let name = format!("{slug}.{ch}.mco");
                        let run = mc::RunSpec::of_channel(spec, 3 * m + c, chans[c].photons);
                        let text = mc::mco::write(&name, &run, chans[c], seconds)?;
                        Ok((name, text))
                    })
                    .collect::<mc::Result<_>>()?;
                for (name, text) in texts {
                    files.add(out.join(&name), text);
                    mco_files.push(name);
                }
            }
            let run = (spec, seconds, threads);
            let mut summary = summary_json(slug, run, specs, &chans, &mco_files);
            if let Some(rows) = incidence.get(m) {
                let (csv, png) = (
                    format!("{slug}.incidence.csv"),
                    format!("{slug}.incidence.png"),
                );
                let media = [0, 1, 2].map(|c| Medium::of_layer(&specs[c].layer, spec.n_above));
                let table = IncidenceComparison::new(&media, rows.clone());
                files.add(out.join(&csv), table.csv());
                files.add(out.join(&png), table.png(slug)?);
                summary["incidence"] = table.json();
                summary["files"]["incidence"] = json!(csv);
                summary["files"]["incidence_plot"] = json!(png);
            }
            files.add(
                out.join(format!("{slug}.summary.json")),
                format!("{:#}\n", summary),
            );
            summaries.push(summary);
        }
        Ok((files, summaries))
    }
}

/// One material's summary: per channel its totals with standard errors and coefficients, the
/// run's photons, seed, time, threads and grid, and the files written.
fn summary_json(
    slug: &str,
    (spec, seconds, threads): (&BatchSpec, f64, usize),
    specs: &[ChannelSpec],
    chans: &[&Output],
    mco: &[String],
) -> Value {
    let g = chans[0].grid;
    let channels: serde_json::Map<String, Value> = CHANNELS
        .iter()
        .enumerate()
        .map(|(c, ch)| {
            let (o, l) = (chans[c], specs[c].layer);
            let v = json!({
                "rsp": o.rsp, "rd": o.rd.value, "rd_se": o.rd.se, "a": o.a.value, "a_se": o.a.se, "tt": o.tt.value, "tt_se": o.tt.se,
                "photons": o.photons, "interactions": o.interactions,
                "sigma_a_per_cm": l.mu_a, "sigma_s_per_cm": l.mu_s, "g": l.g, "eta": l.n, "thickness_cm": l.thickness,
                "albedo": l.albedo(), "mfp_cm": l.transport_mfp(),
            });
            (ch.to_string(), v)
        })
        .collect();
    json!({
        "material": slug,
        "photons": chans[0].photons,
        "seed": spec.seed,
        "seconds": seconds,
        "threads": threads,
        "grid": { "dr_cm": g.dr, "nr": g.nr, "dz_cm": g.dz, "nz": g.nz, "na": g.na, "da_rad": g.da() },
        "channels": channels,
        "walk_groups": spec.groups().len(),
        "files": { "profile": format!("{slug}.profile.csv"), "provenance": format!("{slug}.profile.json"), "mco": mco },
    })
}

/// A summary as text: the material's photons and grid, then per channel Rd, A, Tt and Rsp with
/// standard errors and the transport mean free path (one line each).
pub fn summary_text(s: &Value) -> String {
    let mut text = format!(
        "{}  ({} photons/channel, dr = {:.4e} cm, nr = {})\n",
        s["material"].as_str().unwrap_or("?"),
        s["photons"],
        s["grid"]["dr_cm"].as_f64().unwrap_or(0.0),
        s["grid"]["nr"]
    );
    for ch in CHANNELS {
        let c = &s["channels"][ch];
        let f = |k: &str| c[k].as_f64().unwrap_or(f64::NAN);
        text += &format!(
            "  {ch}: Rd = {:.5} ± {:.5}  A = {:.5} ± {:.5}  Tt = {:.5}  Rsp = {:.5}  MFP = {:.4} cm\n",
            f("rd"),
            f("rd_se"),
            f("a"),
            f("a_se"),
            f("tt"),
            f("rsp"),
            f("mfp_cm")
        );
    }
    text
}

/// A summary's Rd(θ) table as text, with the ratio to normal incidence when 0° was run; empty
/// without one.
pub fn incidence_text(s: &Value) -> String {
    let Some(rows) = s["incidence"].as_array() else {
        return String::new();
    };
    let rd = |r: &Value, ch: &str| r["rd"][ch].as_f64().unwrap_or(f64::NAN);
    let normal = rows.iter().find(|r| r["theta_deg"].as_f64() == Some(0.0));
    let (title, header) = match normal {
        Some(_) => (", and Rd(θ)/Rd(0°)", "     ratio R  ratio G  ratio B"),
        None => (" (no 0° angle: no ratio)", ""),
    };
    let material = s["material"].as_str().unwrap_or("?");
    let mut text = format!("{material}: Rd(θ) per unit incident power{title}\n");
    text += &format!("  θ [deg]   Rd R     Rd G     Rd B{header}\n");
    for r in rows {
        text += &format!(
            "  {:>7.2}  {:.5}  {:.5}  {:.5}",
            r["theta_deg"].as_f64().unwrap_or(f64::NAN),
            rd(r, "R"),
            rd(r, "G"),
            rd(r, "B")
        );
        if let Some(n) = normal {
            for ch in CHANNELS {
                text += &format!("  {:>7.4}", rd(r, ch) / rd(n, ch));
            }
        }
        text += "\n";
    }
    text
}

/// One run of an MCML input as JSON: its output file, photons, time and totals with standard
/// errors.
pub fn mci_run_json(output: &Path, out: &Output, seconds: f64) -> Value {
    json!({
        "output": output, "photons": out.photons, "seconds": seconds,
        "rsp": out.rsp, "rd": out.rd.value, "rd_se": out.rd.se, "a": out.a.value, "a_se": out.a.se, "tt": out.tt.value, "tt_se": out.tt.se,
    })
}

/// One run of [`mci_run_json`] as a line of text.
pub fn mci_run_text(r: &Value) -> String {
    let f = |k: &str| r[k].as_f64().unwrap_or(0.0);
    format!(
        "{}: Rsp = {:.5}  Rd = {:.5} ± {:.5}  A = {:.5} ± {:.5}  Tt = {:.5} ± {:.5}",
        r["output"].as_str().unwrap_or("?"),
        r["rsp"],
        f("rd"),
        f("rd_se"),
        f("a"),
        f("a_se"),
        f("tt"),
        f("tt_se")
    )
}

/// Runs every run of an MCML input (A(r, z) tallied, as MCML does; `photons` packets each where
/// given, else the file's) and returns its `.mco` files in `out` (each named as the `.mci` names
/// it, without its folder) and each run as [`mci_run_json`]. Progress per run goes to `progress`.
pub fn run_mci(
    mut runs: Vec<mc::mci::MciRun>,
    photons: Option<u64>,
    out: &Path,
    progress: &dyn mc::progress::Progress,
) -> Result<(Outputs, Vec<Value>)> {
    let mut files = Outputs::default();
    let mut report = Vec::new();
    for r in &mut runs {
        r.spec.photons = photons.unwrap_or(r.spec.photons);
        r.spec.tallies.absorption_rz = true;
    }
    for (k, r) in runs.iter().enumerate() {
        let start = std::time::Instant::now();
        progress.begin(&format!("run {}/{}", k + 1, runs.len()), r.spec.photons);
        let result = mc::run(&r.spec, &|n| progress.advance(n));
        progress.end();
        let result = result?;
        let seconds = start.elapsed().as_secs_f64();
        let name = Path::new(&r.out_name)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| format!("run{}.mco", k + 1));
        let path = out.join(&name);
        files.add(
            &path,
            mc::mco::write(&r.out_name, &r.spec, &result, seconds)?,
        );
        report.push(mci_run_json(&path, &result, seconds));
    }
    Ok((files, report))
}
