//! What `sss eval` shows of [`fit::evaluate`]: the table of every model's kernel- and image-space
//! errors and the Pareto front of GPU cost against image error, as lines of text, and both as
//! JSON.

use fit::evaluate::{Evaluation, Row};
use fit::pareto::{Pareto, Point};
use fit::signals::Signal;
use serde_json::{Value, json};

/// The table of every model and channel: kernel-space RMS (raw and L1-normalized), L1 error,
/// image RMS on the edge and shaded signals, fit time [s].
pub fn table_lines(slug: &str, rows: &[Row]) -> Vec<String> {
    let mut out = vec![
        format!(
            "{slug}: kernel-space RMS (raw / L1-normalized), image RMS (edge, shaded), fit time"
        ),
        format!(
            "  {:<24} {:>3} {:>11} {:>11} {:>9} {:>10} {:>10} {:>8}",
            "model", "ch", "kernel", "kernel(N)", "L1 err", "edge", "shaded", "fit [s]"
        ),
    ];
    for r in rows {
        let img = |s: Signal| {
            r.image_rms
                .iter()
                .find(|(x, _)| *x == s)
                .map_or(f64::NAN, |(_, e)| *e)
        };
        out.push(format!(
            "  {:<24} {:>3} {:>11.3e} {:>11.3e} {:>9.2e} {:>10.3e} {:>10.3e} {:>8.3}",
            r.label(),
            mc::CHANNELS[r.channel],
            r.kernel_rms,
            r.kernel_rms_normalized,
            r.l1_error,
            img(Signal::Edge),
            img(Signal::Shaded),
            r.fit_seconds
        ));
    }
    out
}

/// The Pareto front of GPU cost against mean image RMS, the best separable model per pass budget,
/// and dense kernels on lines of their own.
pub fn pareto_lines(slug: &str, p: &Pareto) -> Vec<String> {
    let t = p.taps_per_pass;
    let mut out = vec![
        format!(
            "{slug}: Pareto front of GPU cost (T = {t} taps per 1D pass) against image RMS (mean \
             over signals and channels; worst channel)"
        ),
        format!(
            "  {:<24} {:>6} {:>8} {:>10} {:>10}",
            "model", "passes", "taps/px", "mean RMS", "worst ch."
        ),
    ];
    out.extend(p.front.iter().map(|q| {
        format!(
            "  {:<24} {:>6} {:>8} {:>10.3e} {:>10.3e}",
            q.label, q.cost.passes, q.cost.taps, q.mean_image_rms, q.worst_channel_rms
        )
    }));
    let error = |q: &Point| {
        format!(
            "mean image RMS {:.3e}, worst channel {:.3e}",
            q.mean_image_rms, q.worst_channel_rms
        )
    };
    for r in &p.recommended {
        out.push(match &r.best {
            Some(q) => format!(
                "  recommended for {} passes: {} ({} passes, {} taps/px; {})",
                r.budget,
                q.label,
                q.cost.passes,
                q.cost.taps,
                error(q)
            ),
            None => format!("  recommended for {} passes: none fits", r.budget),
        });
    }
    out.extend(p.dense.iter().map(|q| {
        format!(
            "  dense: {} (1 pass of {t}×{t} = {} taps/px; {})",
            q.label,
            q.cost.taps,
            error(q)
        )
    }));
    out
}

/// One material's evaluation and front as JSON: `{"name", "models": [...], "pareto"}`.
pub fn json(slug: &str, ev: &Evaluation, pareto: &Pareto) -> Value {
    json!({
        "name": slug,
        "models": ev.rows.iter().map(Row::json).collect::<Vec<_>>(),
        "pareto": pareto,
    })
}
