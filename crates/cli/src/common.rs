//! What every command shares: count parsing, the default output folder, the worker pool and
//! progress bars (on stderr, hidden when stderr is not a terminal, e.g. in CI or pipes).

use std::path::PathBuf;
use std::sync::Mutex;

use anyhow::{Result, bail};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use indicatif::{ProgressBar, ProgressStyle};

/// Parses a positive count written as an integer or in scientific notation (`1e6`).
pub fn parse_count(s: &str) -> Result<u64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    if !(v.is_finite() && v >= 1.0 && v.fract() == 0.0 && v < u64::MAX as f64) {
        return Err(format!("{s:?} must be a positive whole number"));
    }
    Ok(v as u64)
}

/// One value or three comma-separated values (R,G,B).
pub fn parse_rgb(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| format!("{x:?} is not a number"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [a] => Ok([a; 3]),
        [a, b, c] => Ok([a, b, c]),
        _ => Err(format!("{s:?}: give one value or three (R,G,B)")),
    }
}

/// Default output folder.
pub fn default_out() -> PathBuf {
    PathBuf::from("out")
}

/// A pool of `threads` workers (`--threads`), all cores when `None`.
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    if threads == Some(0) {
        bail!("invalid --threads 0: must be at least 1");
    }
    Ok(rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()?)
}

/// A bar counting photons, with rate and ETA.
pub fn photons(total: u64, label: &str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "{msg} [{bar:30}] {human_pos}/{human_len} photons  {per_sec}  ETA {eta}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(label.to_string());
    bar
}

/// A flag's value parser for a library's named choice ([`render::Choice`]): its names, each with
/// its help line in `--help`.
pub fn choice<T: render::Choice + Clone>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        T::CHOICES
            .iter()
            .map(|(name, _, help)| PossibleValue::new(*name).help(*help)),
    )
    .map(|name| T::parse(&name).expect("clap admits only the listed names"))
}

/// A flag's value parser for `on` / `off`.
pub fn on_off() -> impl TypedValueParser<Value = bool> {
    PossibleValuesParser::new(["on", "off"]).map(|v| v == "on")
}

/// Photon bars for a library's Monte Carlo runs ([`render::Progress`]): one bar per run, cleared
/// when it ends.
#[derive(Default)]
pub struct Bars(Mutex<Option<ProgressBar>>);

impl Bars {
    fn bar(&self) -> std::sync::MutexGuard<'_, Option<ProgressBar>> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl render::Progress for Bars {
    fn begin(&self, label: &str, total: u64) {
        *self.bar() = Some(photons(total, label));
    }

    fn advance(&self, k: u64) {
        if let Some(b) = &*self.bar() {
            b.inc(k);
        }
    }

    fn end(&self) {
        if let Some(b) = self.bar().take() {
            b.finish_and_clear();
        }
    }

    fn note(&self, line: &str) {
        eprintln!("{line}");
    }
}

/// Prints `v` as indented JSON on stdout (`--json`).
pub fn print_json(v: &serde_json::Value) -> Result<()> {
    println!("{}", serde_json::to_string_pretty(v)?);
    Ok(())
}

/// Writes `text` to stdout as it is (a shader snippet when no --out is given).
pub fn print_raw(text: &str) -> Result<()> {
    use anyhow::Context;
    use std::io::Write;
    let out = std::io::stdout().write_all(text.as_bytes());
    out.context("cannot write to standard output")
}

/// Writes the shard file of slice `i` of `n` and reports it (one JSON line with --json);
/// `events`: the interactions traced, where counted.
pub fn write_shard(
    path: &std::path::Path,
    text: String,
    (i, n): (u64, u64),
    (seconds, events): (f64, Option<u64>),
    json: bool,
) -> Result<()> {
    let mut files = mc::outputs::Outputs::default();
    files.add(path, text);
    files.commit()?;
    if json {
        let v = serde_json::json!({ "shard": path, "index": i, "of": n, "seconds": seconds, "events": events });
        println!("{v}");
    } else {
        let rate = events.map_or(String::new(), |e| {
            format!(", {:.3e} events/s", e as f64 / seconds)
        });
        let path = path.display();
        eprintln!("wrote {path} ({seconds:.1} s{rate}); combine all {n} shards with `sss merge`");
    }
    Ok(())
}
