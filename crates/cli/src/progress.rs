//! Progress bars on stderr (hidden when stderr is not a terminal, e.g. in CI or pipes).

use indicatif::{ProgressBar, ProgressStyle};

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
