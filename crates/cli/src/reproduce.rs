//! `sss reproduce`: the thesis's tables and figures regenerated from scratch, written as a
//! self-contained HTML report (tables inline, PNG plots beside it) and a JSON file with every
//! number. Each result sits beside the published one; the "what agrees" section is generated
//! from the numbers.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use fit::evaluate::{Evaluation, ImageSize, RANK1, Row, evaluate};
use fit::{KernelModel, Profile};
use serde::Deserialize;
use serde_json::{Value, json};

use crate::cache::{Explicit, Provenance, count, provenance_path};
use crate::files::Outputs;
use crate::{eval, library, parse_count, progress, simulate};

#[derive(Args)]
pub struct ReproduceArgs {
    /// Output folder (index.html, report.json, PNG plots, profiles/ with their provenance),
    /// written once the whole report is done
    #[arg(long, value_name = "DIR", default_value = "report")]
    out: PathBuf,

    /// CI-sized run: 2·10⁴ photons per channel, a coarser grid (dr = min MFP/6, 10 max MFP) and
    /// 128-pixel test images; minutes on 2 cores
    #[arg(long)]
    quick: bool,

    /// Photons per channel [default: 1e7, or 2e4 with --quick]
    #[arg(long, value_parser = parse_count)]
    photons: Option<u64>,

    /// Worker threads [default: all cores]
    #[arg(long)]
    threads: Option<usize>,

    /// Read the 16 profiles from this folder (NAME.profile.csv, e.g. a previous report's
    /// profiles/) instead of simulating them. Where a profile has its provenance
    /// (NAME.profile.json) it must be of the built-in material, and of --photons when given; a
    /// profile without one is refused when --photons is given
    #[arg(long, value_name = "DIR")]
    profiles: Option<PathBuf>,

    /// Include the rendered-scene comparisons against Mitsuba 3: an images.json that
    /// `python3 scripts/references/images.py` wrote, or the summary.json of `run.py` (every scene
    /// and material it ran, the long-mean-free-path ones included); repeatable
    #[arg(long, value_name = "JSON")]
    references: Vec<PathBuf>,

    /// Also print the report's numbers (report.json) on stdout
    #[arg(long)]
    json: bool,
}

/// The image comparisons against Mitsuba: `images.py`'s JSON (one scene and material) or
/// `run.py`'s summary (its `images` list), checked for the fields the report shows.
fn read_references(path: &std::path::Path) -> Result<Vec<Value>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read --references {}", path.display()))?;
    let v: Value = serde_json::from_str(&text)
        .with_context(|| format!("--references {}: not JSON", path.display()))?;
    let all = match v["images"].as_array() {
        Some(images) => images.clone(),
        None => vec![v],
    };
    for v in &all {
        let models = v["models"].as_array().with_context(|| {
            format!(
                "--references {}: no \"models\" list (expected images.py's images.json or run.py's summary.json)",
                path.display()
            )
        })?;
        for m in models {
            if m["model"].as_str().is_none()
                || m["rmse_noise_corrected"].as_f64().is_none()
                || m["energy_ratio"].as_array().is_none_or(|e| e.len() != 3)
            {
                bail!(
                    "--references {}: a model entry lacks model, rmse_noise_corrected or energy_ratio (rerun images.py)",
                    path.display()
                );
            }
        }
    }
    Ok(all)
}

/// The five materials of the thesis's main results.
const MAIN: [&str; 5] = ["apple", "marble", "ketchup", "skin1", "wholemilk"];

#[derive(Deserialize)]
struct Published {
    table_6_3: std::collections::BTreeMap<String, Published63>,
    table_6_5: Published65,
}

#[derive(Deserialize)]
struct Published63 {
    svd1: [f64; 3],
    preint: [f64; 3],
    guided_k1: [f64; 3],
    manual: [f64; 3],
}

impl Published63 {
    /// The published row of one of the rank-1 models ([`RANK1`]).
    fn of(&self, model: KernelModel) -> [f64; 3] {
        match model {
            KernelModel::Svd {
                rank: 1,
                renormalize: false,
            } => self.svd1,
            KernelModel::Preint => self.preint,
            KernelModel::Guided { k: 1.0, b: 0.0 } => self.guided_k1,
            KernelModel::Manual(_) => self.manual,
            _ => unreachable!("Table 6.3 has the rank-1 models of RANK1 only, not {model}"),
        }
    }
}

#[derive(Deserialize)]
struct Published65 {
    svd: Vec<[f64; 3]>,
    deon: Vec<[f64; 3]>,
}

const PUBLISHED: &str = include_str!("../../../configs/thesis_published.toml");

fn find(ev: &Evaluation, model: KernelModel, c: usize) -> &Row {
    ev.row(model, c)
        .expect("evaluate measures every model of fit::evaluate::MODELS on every channel")
}

/// RMS over the five test signals of a row's image-space errors.
fn image_rms(r: &Row) -> f64 {
    (r.image_rms.iter().map(|(_, e)| e * e).sum::<f64>() / r.image_rms.len() as f64).sqrt()
}

/// A profile of `--profiles` and its provenance, if it has one: one that is not of the built-in
/// material, or not of the --photons given, is refused (the user named these files), as is one
/// without provenance when --photons is given.
fn read_profile(
    csv: &std::path::Path,
    asked: &Provenance,
    explicit: Explicit,
) -> Result<(String, Option<Provenance>)> {
    let text =
        std::fs::read_to_string(csv).with_context(|| format!("cannot read {}", csv.display()))?;
    let sidecar = provenance_path(csv);
    if !sidecar.exists() {
        if explicit.photons {
            bail!(
                "{} has no provenance ({} is missing): its photon count is unknown, so it cannot stand for --photons {}",
                csv.display(),
                sidecar.display(),
                asked.photons
            );
        }
        return Ok((text, None));
    }
    let json = std::fs::read_to_string(&sidecar)
        .with_context(|| format!("cannot read {}", sidecar.display()))?;
    let have = Provenance::from_json(&json, &sidecar.display().to_string())?;
    let differ = have.mismatches(asked, explicit);
    if !differ.is_empty() {
        bail!(
            "{} does not match what was asked: {}",
            csv.display(),
            differ.join("; ")
        );
    }
    Ok((text, Some(have)))
}

pub fn run(a: ReproduceArgs) -> Result<()> {
    let start = Instant::now();
    let published: Published = toml::from_str(PUBLISHED).expect("published tables parse");
    let pool = simulate::thread_pool(a.threads)?;
    let mut config = library::config(None)?;
    let image = if a.quick {
        config.grid.dr_per_min_mfp = 6.0;
        config.grid.r_max_mfp = 10.0;
        ImageSize {
            size: 128,
            max_half: 48,
        }
    } else {
        ImageSize::default()
    };
    let photons = a
        .photons
        .unwrap_or(if a.quick { 20_000 } else { config.photons });
    let references = a
        .references
        .iter()
        .map(|p| read_references(p))
        .collect::<Result<Vec<_>>>()?
        .concat();
    let mut files = Outputs::default();

    // 1. Profiles of the whole library, one batch.
    let all = library::all()?;
    let t = Instant::now();
    let materials: Vec<&mc::Material> = all.iter().map(|n| &n.material).collect();
    let spec = config.batch(&materials, photons, config.seed, true)?;
    let (csvs, provenance): (Vec<String>, Vec<Option<Provenance>>) = match &a.profiles {
        Some(dir) => {
            let explicit = Explicit {
                photons: a.photons.is_some(),
                ..Explicit::default()
            };
            all.iter()
                .enumerate()
                .map(|(i, n)| {
                    let asked = Provenance::of(&spec, i, &n.slug, None);
                    read_profile(
                        &dir.join(format!("{}.profile.csv", n.slug)),
                        &asked,
                        explicit,
                    )
                })
                .collect::<Result<Vec<_>>>()?
                .into_iter()
                .unzip()
        }
        None => {
            let bar = progress::photons(
                photons * spec.groups().len() as u64,
                "simulating the library",
            );
            let outputs = pool.install(|| mc::run_batch(&spec, &|k| bar.inc(k)))?;
            bar.finish_and_clear();
            all.iter()
                .enumerate()
                .map(|(i, n)| {
                    let chans: Vec<_> = outputs[3 * i..3 * i + 3].iter().collect();
                    (
                        simulate::profile_csv(&chans),
                        Some(Provenance::of(&spec, i, &n.slug, None)),
                    )
                })
                .unzip()
        }
    };
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
    for ((n, csv), prov) in all.iter().zip(&csvs).zip(&provenance) {
        let path = a
            .out
            .join("profiles")
            .join(format!("{}.profile.csv", n.slug));
        let p = Profile::parse_csv(csv, &path.display().to_string())?;
        if let Some(prov) = prov {
            files.add(provenance_path(&path), prov.to_json());
        }
        files.add(path, csv.as_str());
        files.add(
            a.out.join(format!("{}.profile.png", n.slug)),
            fit::plot::profile(&p, &n.slug)?,
        );
        profiles.push(p);
    }

    // 2. Every model on the five main materials, with their plots.
    let mut evals = Vec::new();
    for name in MAIN {
        let i = all
            .iter()
            .position(|n| n.slug == name)
            .expect("main materials are built in");
        eprintln!("fitting and evaluating every model for {name} …");
        let ev = pool.install(|| evaluate(&profiles[i], name, image))?;
        eval::plots(&profiles[i], &ev, name, &a.out, &mut files)?;
        evals.push(ev);
    }

    let mut report = build(&all, &evals, &published, photons, simulate_seconds, a.quick);
    // 3. Tables 6.4 and 6.5 rendered on our scenes (skipped, saying why, without an adapter).
    crate::reproduce_rendered::add(&mut report, &all, &profiles, a.quick)?;
    // 4. Fig. 5.15 and 5.17 on Skin1: their plots, numbers and claims.
    crate::reproduce_chapter5::add(&mut report, &all, &profiles, image, &a.out, &mut files)?;
    if !references.is_empty() {
        report["rendered"] = Value::Array(references);
    }
    files.add(
        a.out.join("report.json"),
        serde_json::to_string_pretty(&report)?,
    );
    files.add(a.out.join("index.html"), html(&report, &all));
    files.commit()?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    eprintln!(
        "wrote {} in {:.0} s",
        a.out.join("index.html").display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn build(
    all: &[library::Named],
    evals: &[Evaluation],
    published: &Published,
    photons: Option<u64>,
    simulate_seconds: f64,
    quick: bool,
) -> Value {
    // Table 6.2.
    let t62: Vec<Value> = all
        .iter()
        .map(|n| {
            let m = &n.material;
            json!({ "material": n.slug, "name": m.name, "eta": m.eta, "sigma_a": m.sigma_a, "sigma_s": m.sigma_s, "g": m.g,
                    "albedo": ([0, 1, 2].map(|c| m.albedo(c))), "mfp_cm": ([0, 1, 2].map(|c| m.mfp(c))), "source": m.source })
        })
        .collect();

    // Table 6.3: raw kernel RMS, and normalized by the table's largest entry (the thesis's way).
    let raw: Vec<Vec<[f64; 3]>> = evals
        .iter()
        .map(|ev| {
            RANK1
                .iter()
                .map(|&m| [0, 1, 2].map(|c| find(ev, m, c).kernel_rms))
                .collect()
        })
        .collect();
    let max = raw
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b));
    let t63: Vec<Value> = MAIN
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let p = &published.table_6_3[*m];
            json!({ "material": m, "models": RANK1.iter().enumerate().map(|(j, &model)| json!({
                "model": model, "name": model.title(), "raw": raw[i][j], "normalized": raw[i][j].map(|x| x / max), "published": p.of(model),
            })).collect::<Vec<_>>() })
        })
        .collect();

    // Table 6.5: SVD rank-N vs d'Eon N, Skin1, image-space RMS over the five test signals.
    let skin = &evals[MAIN
        .iter()
        .position(|m| *m == "skin1")
        .expect("skin1 is a main material")];
    let svd_n = |rank| KernelModel::Svd {
        rank,
        renormalize: false,
    };
    let deon_n = |n| KernelModel::Deon { n };
    let ours = |model: &dyn Fn(usize) -> KernelModel| -> Vec<[f64; 3]> {
        (1..=6)
            .map(|n| [0, 1, 2].map(|c| image_rms(find(skin, model(n), c))))
            .collect()
    };
    let (svd, deon) = (ours(&svd_n), ours(&deon_n));
    let kernel_wins = (1..=6)
        .flat_map(|n| (0..3).map(move |c| (n, c)))
        .filter(|&(n, c)| find(skin, svd_n(n), c).kernel_rms < find(skin, deon_n(n), c).kernel_rms)
        .count();
    let max65 = svd
        .iter()
        .chain(&deon)
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b));
    let norm =
        |v: &[[f64; 3]]| -> Vec<[f64; 3]> { v.iter().map(|r| r.map(|x| x / max65)).collect() };
    let t65 = json!({ "svd": norm(&svd), "deon": norm(&deon), "svd_raw": svd, "deon_raw": deon, "published_svd": published.table_6_5.svd, "published_deon": published.table_6_5.deon });

    // Table 5.1: properties, and our mean fit time per channel over the five materials.
    let fit_time = |model: KernelModel| {
        let v: Vec<f64> = evals
            .iter()
            .flat_map(|ev| (0..3).map(move |c| find(ev, model, c).fit_seconds))
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    // The thesis's rows name families; each is timed on the model given beside it.
    let [svd1, preint, guided_k1, manual] = RANK1;
    let t51: Vec<Value> = [
        ("d'Eon 1 Gaussian", deon_n(1), "low", "2", true, false),
        ("d'Eon 2+ Gaussians", deon_n(6), "high", "2 per Gaussian", false, false),
        ("SVD rank-1", svd1, "low", "2", true, true),
        ("SVD rank-2+", svd_n(6), "excellent", "2 per rank", false, true),
        ("Kernel pre-integration", preint, "high", "2", true, true),
        ("Guided optimization", guided_k1, "controllable", "2", true, false),
        ("Manual approximation", manual, "controllable", "2", true, true),
    ]
    .iter()
    .map(|&(name, model, q, passes, sep, closed)| json!({ "model": name, "timed": model, "visual_quality": q, "convolutions_1d": passes, "separable": sep, "closed_form": closed, "fit_seconds_per_channel": fit_time(model) }))
    .collect();

    json!({
        "mode": if quick { "quick" } else { "full" },
        "photons_per_channel": photons,
        "simulate_seconds": simulate_seconds,
        "table_6_2": t62,
        "table_6_3": t63,
        "table_6_5": t65,
        "table_5_1": t51,
        "claims": claims(&raw, &svd, &deon, kernel_wins, published),
    })
}

/// The qualitative claims of Tables 6.3 and 6.5, checked on our numbers and on the published ones.
/// `raw[material][j]` is the kernel RMS of `RANK1[j]`: 0 SVD rank-1, 1 pre-integration, 2 guided
/// k = 1, 3 manual.
fn claims(
    raw: &[Vec<[f64; 3]>],
    svd: &[[f64; 3]],
    deon: &[[f64; 3]],
    kernel_wins: usize,
    published: &Published,
) -> Vec<Value> {
    let cases = |f: &dyn Fn(&[[f64; 3]]) -> [bool; 3]| -> usize {
        raw.iter()
            .map(|m| f(m).iter().filter(|&&b| b).count())
            .sum()
    };
    let pub_rows: Vec<Vec<[f64; 3]>> = MAIN
        .iter()
        .map(|m| {
            let p = &published.table_6_3[*m];
            RANK1.iter().map(|&model| p.of(model)).collect::<Vec<_>>()
        })
        .collect();
    let pub_cases = |f: &dyn Fn(&[[f64; 3]]) -> [bool; 3]| -> usize {
        pub_rows
            .iter()
            .map(|m| f(m).iter().filter(|&&b| b).count())
            .sum()
    };
    let agree = raw
        .iter()
        .zip(&pub_rows)
        .map(|(o, p)| {
            (0..3)
                .filter(|&c| (o[1][c] < o[2][c]) == (p[1][c] < p[2][c]))
                .count()
        })
        .sum::<usize>();
    let svd_lowest = |m: &[[f64; 3]]| {
        [0, 1, 2].map(|c| m[0][c] < m[1][c] && m[0][c] < m[2][c] && m[0][c] < m[3][c])
    };
    let preint_below_guided = |m: &[[f64; 3]]| [0, 1, 2].map(|c| m[1][c] < m[2][c]);
    let ratio = |rows: &[Vec<[f64; 3]>]| {
        let r: Vec<f64> = rows
            .iter()
            .flat_map(|m| (0..3).map(move |c| m[1][c] / m[0][c]))
            .collect();
        r.iter().sum::<f64>() / r.len() as f64
    };
    let n65 = |s: &[[f64; 3]], d: &[[f64; 3]], f: &dyn Fn(usize, usize) -> bool| {
        (0..6)
            .flat_map(|n| (0..3).map(move |c| (n, c)))
            .filter(|&(n, c)| f(n, c) && s[n][c].is_finite() && d[n][c].is_finite())
            .count()
    };
    let (ps, pd) = (&published.table_6_5.svd, &published.table_6_5.deon);
    let svd_wins = n65(svd, deon, &|n, c| svd[n][c] < deon[n][c]);
    let pub_svd_wins = n65(ps, pd, &|n, c| ps[n][c] < pd[n][c]);
    let saving = (0..5)
        .flat_map(|n| (0..3).map(move |c| (n, c)))
        .filter(|&(n, c)| svd[n][c] <= deon[n + 1][c])
        .count();
    let pub_saving = (0..5)
        .flat_map(|n| (0..3).map(move |c| (n, c)))
        .filter(|&(n, c)| ps[n][c] <= pd[n + 1][c])
        .count();
    let decreasing = |v: &[[f64; 3]]| {
        (0..3).all(|c| v.windows(2).all(|w| w[1][c] <= 1.01 * w[0][c]) && v[5][c] * 5.0 <= v[0][c])
    };
    vec![
        json!({ "claim": "Table 6.3: SVD rank-1 (not renormalized) has the lowest kernel-space RMS of the four rank-1 models", "ours": format!("{} of 15", cases(&svd_lowest)), "published": format!("{} of 15", pub_cases(&svd_lowest)), "holds": cases(&svd_lowest) == 15,
                "why": "Eckart–Young: the truncated SVD is the best rank-1 approximation in the Frobenius norm, whatever the profile." }),
        json!({ "claim": "Table 6.3: pre-integration's kernel RMS is roughly twice SVD rank-1's", "ours": format!("mean ratio {:.2}", ratio(raw)), "published": format!("mean ratio {:.2}", ratio(&pub_rows)), "holds": (1.5..3.0).contains(&ratio(raw)),
                "why": "Pre-integration matches projections, not point values: it spreads the peak, which costs kernel-space error but not edge fidelity." }),
        json!({ "claim": "Table 6.3: which of pre-integration and guided k = 1 has the lower kernel RMS, case by case", "ours": format!("same as the thesis in {agree} of 15"), "published": format!("pre-integration lower in {} of 15", pub_cases(&preint_below_guided)), "holds": agree >= 12,
                "why": "Guided k = 1 weights errors by radius, trading the centre for the falloff; which wins in plain kernel RMS depends on the profile (the thesis's Ketchup G/B are exceptions). Our guided fit meets its L1 constraint exactly; the thesis's was off by up to 25%." }),
        json!({ "claim": "Table 6.5 (kernel space): at equal pass count SVD rank-N has lower kernel-space RMS than d'Eon with N Gaussians", "ours": format!("{kernel_wins} of 18"), "published": "not tabulated", "holds": kernel_wins == 18,
                "why": "Eckart–Young: a sum of N separable Gaussians is a rank-N kernel, and the truncated SVD is the best rank-N kernel in the Frobenius norm." }),
        json!({ "claim": "Table 6.5 (image space): at equal pass count SVD rank-N has lower image-space RMS than d'Eon with N Gaussians", "ours": format!("{svd_wins} of 18"), "published": format!("{pub_svd_wins} of 18"), "holds": svd_wins == 18,
                "why": "A sum of N separable Gaussians is itself a rank-N kernel, and SVD's rank-N is the best one in kernel space. Image space need not follow: every SVD term of a radially symmetric kernel is even, and some have Σa = 0, so their pass adds nothing to an edge's image and little to other near-symmetric signals; SVD then plateaus for one rank while d'Eon keeps improving." }),
        json!({ "claim": "Table 6.5: SVD saves about one rank: SVD rank-N is at least as good as d'Eon N+1", "ours": format!("{saving} of 15"), "published": format!("{pub_saving} of 15"), "holds": saving >= 10, "why": "Same argument, with a margin." }),
        json!({ "claim": "Table 6.5: both converge to the ground truth as N grows (no step increases the error by more than 1%, and N = 6 is at least 5× better than N = 1)", "ours": format!("SVD {}, d'Eon {}", decreasing(svd), decreasing(deon)), "published": format!("SVD {}, d'Eon {}", decreasing(ps), decreasing(pd)), "holds": decreasing(svd) && decreasing(deon),
                "why": "Each added term can only reduce the best achievable kernel-space error (nested fits); image-space error follows up to plateaus (see above)." }),
    ]
}

/// A table cell with our value above the published one (grey).
pub(crate) fn cell(ours: f64, published: f64) -> String {
    format!("<td>{ours:.3}<br><span class=\"pub\">{published:.3}</span></td>")
}

fn html(r: &Value, all: &[library::Named]) -> String {
    let e = |v: &Value| {
        v.as_f64()
            .map(|x| format!("{x:.3e}"))
            .unwrap_or_else(|| "–".into())
    };
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>sss reproduce</title><style>body{{font-family:sans-serif;max-width:1400px;margin:auto;padding:1em}}table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #bbb;padding:3px 7px;text-align:right}}th{{background:#eee}}.pub{{color:#777}}.ok{{color:#070}}.bad{{color:#b00}}img{{max-width:100%}}</style></head><body>"
    );
    let photons = match r["photons_per_channel"].as_u64() {
        Some(n) => format!("{} photons per channel", count(n)),
        None => "profiles of unknown or differing photon counts".into(),
    };
    let _ = write!(
        h,
        "<h1>Separable SSS for arbitrary materials — reproduction</h1><p>Mode: <b>{}</b>, {photons} (library simulated or read in {:.0} s). Published values from Freude 2014 in <span class=\"pub\">grey</span>.</p>",
        r["mode"].as_str().unwrap_or(""),
        r["simulate_seconds"].as_f64().unwrap_or(0.0)
    );

    h += "<h2>What agrees, what differs and why</h2><table><tr><th>claim</th><th>ours</th><th>published</th><th>holds</th><th>why</th></tr>";
    for c in r["claims"].as_array().into_iter().flatten() {
        let ok = c["holds"].as_bool().unwrap_or(false);
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td class=\"pub\">{}</td><td class=\"{}\">{}</td><td style=\"text-align:left\">{}</td></tr>",
            c["claim"].as_str().unwrap_or(""),
            c["ours"].as_str().unwrap_or(""),
            c["published"].as_str().unwrap_or(""),
            if ok { "ok" } else { "bad" },
            if ok { "yes" } else { "no" },
            c["why"].as_str().unwrap_or("")
        );
    }
    h += "</table>";

    h += "<h2>Table 6.2 — materials (cm⁻¹) with derived albedo and MFP</h2><table><tr><th>material</th><th>σa R G B</th><th>σs R G B</th><th>g</th><th>η</th><th>albedo R G B</th><th>MFP [cm] R G B</th></tr>";
    for m in r["table_6_2"].as_array().into_iter().flatten() {
        let v3 = |k: &str, p: usize| {
            m[k].as_array()
                .map(|a| {
                    a.iter()
                        .map(|x| format!("{:.*}", p, x.as_f64().unwrap_or(f64::NAN)))
                        .collect::<Vec<_>>()
                        .join(" ")
                })
                .unwrap_or_default()
        };
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            m["material"].as_str().unwrap_or(""),
            v3("sigma_a", 4),
            v3("sigma_s", 3),
            v3("g", 3),
            m["eta"],
            v3("albedo", 5),
            v3("mfp_cm", 4)
        );
    }
    h += "</table>";

    h += "<h2>Table 6.3 — kernel-space RMS of the rank-1 models (normalized: largest entry = 1)</h2><table><tr><th>material</th>";
    for m in RANK1 {
        let _ = write!(h, "<th colspan=3>{} R G B</th><th>Σ</th>", m.title());
    }
    h += "</tr>";
    for m in r["table_6_3"].as_array().into_iter().flatten() {
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{}</td>",
            m["material"].as_str().unwrap_or("")
        );
        for model in m["models"].as_array().into_iter().flatten() {
            let mut sum = (0.0, 0.0);
            for c in 0..3 {
                let (o, p) = (
                    model["normalized"][c].as_f64().unwrap_or(f64::NAN),
                    model["published"][c].as_f64().unwrap_or(f64::NAN),
                );
                sum = (sum.0 + o, sum.1 + p);
                h += &cell(o, p);
            }
            h += &cell(sum.0, sum.1);
        }
        h += "</tr>";
    }
    h += "</table><p>Raw (unnormalized) values:</p><table><tr><th>material</th>";
    for m in RANK1 {
        let _ = write!(h, "<th colspan=3>{}</th>", m.title());
    }
    h += "</tr>";
    for m in r["table_6_3"].as_array().into_iter().flatten() {
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{}</td>",
            m["material"].as_str().unwrap_or("")
        );
        for model in m["models"].as_array().into_iter().flatten() {
            for c in 0..3 {
                let _ = write!(h, "<td>{}</td>", e(&model["raw"][c]));
            }
        }
        h += "</tr>";
    }
    h += "</table>";

    h += "<h2>Table 6.5 — image-space RMS, Skin1, SVD rank-N vs d'Eon N Gaussians (normalized: max = 1)</h2><p>Ours: RMS over our five test signals; published: the Head scene.</p><table><tr><th>N</th><th colspan=3>SVD R G B</th><th>Σ</th><th colspan=3>d'Eon R G B</th><th>Σ</th></tr>";
    let t = &r["table_6_5"];
    for n in 0..6 {
        let _ = write!(h, "<tr><td>{}</td>", n + 1);
        for (o, p) in [("svd", "published_svd"), ("deon", "published_deon")] {
            let (mut so, mut sp) = (0.0, 0.0);
            for c in 0..3 {
                let (x, y) = (
                    t[o][n][c].as_f64().unwrap_or(f64::NAN),
                    t[p][n][c].as_f64().unwrap_or(f64::NAN),
                );
                so += x;
                sp += y;
                h += &cell(x, y);
            }
            h += &cell(so, sp);
        }
        h += "</tr>";
    }
    h += "</table>";

    h += "<h2>Table 5.1 — model properties, with our measured fit time</h2><table><tr><th>model</th><th>visual quality (thesis)</th><th>1D convolutions</th><th>separable</th><th>closed form</th><th>our fit time per channel [s]</th></tr>";
    for m in r["table_5_1"].as_array().into_iter().flatten() {
        let yn = |k: &str| {
            if m[k].as_bool().unwrap_or(false) {
                "✓"
            } else {
                "✗"
            }
        };
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td></tr>",
            m["model"].as_str().unwrap_or(""),
            m["visual_quality"].as_str().unwrap_or(""),
            m["convolutions_1d"].as_str().unwrap_or(""),
            yn("separable"),
            yn("closed_form"),
            m["fit_seconds_per_channel"].as_f64().unwrap_or(f64::NAN)
        );
    }
    h += "</table>";

    h += "<h2>Fig. 5.1 — singular values of the main materials</h2>";
    for m in MAIN {
        let _ = write!(h, "<img src=\"{m}.singular_values.png\" width=\"45%\">");
    }
    h += "<h2>Fig. 6.2 / A.12–A.64 — kernel slices (main axis, diagonal) against the ground truth</h2>";
    for m in MAIN {
        let _ = write!(
            h,
            "<h3>{m}</h3><img src=\"{m}.slices_rank1.png\"><img src=\"{m}.slices_multipass.png\">"
        );
    }
    h += "<h2>Fig. 6.3–6.10 — test-signal convolutions of the rank-1 models (every panel labelled, with colour scales)</h2>";
    for m in MAIN {
        let _ = write!(
            h,
            "<h3>{m}</h3><img src=\"{m}.conv_edge.png\" width=\"49%\"> <img src=\"{m}.conv_circle_squares.png\" width=\"49%\">"
        );
    }
    h += "<h2>Fig. 6.1 / A.1–A.11 — simulated profiles</h2>";
    for n in all {
        let _ = write!(h, "<img src=\"{}.profile.png\" width=\"49%\">", n.slug);
    }
    h += &crate::reproduce_chapter5::html(r);
    h += &crate::reproduce_rendered::html(&r["rendered_tables"]);
    h += &rendered_html(&r["rendered"]);
    h += "</body></html>\n";
    h
}

/// The rendered-scene section: `images.py`'s comparisons against Mitsuba 3, one per scene and
/// material, or how to make them.
fn rendered_html(v: &Value) -> String {
    let mut h = String::from("<h2>Rendered scenes against Mitsuba 3</h2>");
    let Some(all) = v.as_array() else {
        h += "<p>Not included: run <code>python3 scripts/references/run.py --quick</code> and pass its <code>out/references/summary.json</code> (or one <code>images.json</code>) with <code>--references</code>.</p>";
        return h;
    };
    for v in all {
        h += &rendered_one(v);
    }
    h
}

/// One scene and material of `rendered_html`.
fn rendered_one(v: &Value) -> String {
    let Some(models) = v["models"].as_array() else {
        return String::new();
    };
    let mut h = format!(
        "<h3>{} / {}</h3>",
        v["scene"].as_str().unwrap_or("sphere"),
        v["material"].as_str().unwrap_or("skin1")
    );
    let _ = write!(
        h,
        "<p>The {} scene, η = 1, {}×{} pixels, Mitsuba with {} samples per pixel (mean of two seeds; its noise {:.1} % of the mean on 2×2 blocks; silhouettes, {:.1} % of the lit blocks, excluded on both sides). Errors relative to the reference's mean; noise-corrected = √(MSE − var(reference)) ± standard error; spatial = what remains once each channel is scaled by its best global factor.</p>",
        v["scene"].as_str().unwrap_or("sphere"),
        v["width"],
        v["height"],
        v["spp"],
        100.0 * v["reference_noise_rel"].as_f64().unwrap_or(f64::NAN),
        100.0 * v["silhouette_fraction"].as_f64().unwrap_or(f64::NAN)
    );
    if let Some(pass) = v["calibration_pass"].as_bool() {
        let e: Vec<String> = v["calibration_energy_ratio"]
            .as_array()
            .map(|e| {
                e.iter()
                    .map(|x| format!("{:.4}", x.as_f64().unwrap_or(f64::NAN)))
                    .collect()
            })
            .unwrap_or_default();
        let _ = write!(
            h,
            "<p>Calibration (<code>--no-sss</code> against Mitsuba's direct light on the same opaque Lambertian surfaces): noise-corrected RMSE {:.2} ± {:.2} %, energy {}: {}. A deliberately wrong render (albedo × 0.8) is {}.</p>",
            100.0 * v["calibration_rmse_rel"].as_f64().unwrap_or(f64::NAN),
            100.0 * v["calibration_rmse_se"].as_f64().unwrap_or(f64::NAN),
            e.join(" / "),
            if pass {
                "<span class=\"ok\">passes</span>"
            } else {
                "<span class=\"bad\">fails: the scene ranks nothing</span>"
            },
            if v["negative_control"]["rejected"] == true {
                "rejected"
            } else {
                "<span class=\"bad\">not rejected</span>"
            }
        );
    }
    h += "<table><tr><th>model</th><th>RMSE</th><th>noise-corrected RMSE</th><th>spatial</th><th>SSIM</th><th>DSSIM</th><th>energy R / G / B</th></tr>";
    for m in models {
        let e: Vec<String> = m["energy_ratio"]
            .as_array()
            .map(|e| {
                e.iter()
                    .map(|x| format!("{:.3}", x.as_f64().unwrap_or(f64::NAN)))
                    .collect()
            })
            .unwrap_or_default();
        let pct = |k: &str| 100.0 * m[k].as_f64().unwrap_or(f64::NAN);
        let _ = write!(
            h,
            "<tr><td style=\"text-align:left\">{}</td><td>{:.2} %</td><td>{:.2} ± {:.2} %</td><td>{:.2} %</td><td>{:.4}</td><td>{:.4}</td><td>{}</td></tr>",
            m["model"].as_str().unwrap_or("?"),
            pct("rmse_rel"),
            pct("rmse_noise_corrected"),
            pct("rmse_noise_corrected_se"),
            pct("rmse_spatial"),
            m["ssim"].as_f64().unwrap_or(f64::NAN),
            (1.0 - m["ssim"].as_f64().unwrap_or(f64::NAN)) / 2.0,
            e.join(" / ")
        );
    }
    h += "</table>";
    if let Some(ranked) = v["rankings"].as_object() {
        h += "<p>Rankings (paired over blocks, resolved at 3 standard errors):</p><ul>";
        for (k, r) in ranked {
            let verdict = match r.as_bool() {
                Some(true) => "<span class=\"ok\">yes</span>",
                Some(false) => "<span class=\"bad\">no</span>",
                None => "undecided",
            };
            let _ = write!(h, "<li>{k}: {verdict}</li>");
        }
        h += "</ul>";
    }
    h
}
