//! What every command shares: count parsing, the default output folder, the worker pool and
//! progress bars (on stderr, hidden when stderr is not a terminal, e.g. in CI or pipes).

use std::path::PathBuf;

use anyhow::{Result, bail};
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
