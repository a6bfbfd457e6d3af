//! What `sss compare-profiles` shows of [`fit::profile_compare`]: every analytic model against
//! the Monte Carlo profile, as a table of lines and as JSON.

use fit::profile_compare::{BANDS, ModelAgreement};
use serde_json::{Map, Value, json};

/// The band's name in transport mean free paths, e.g. `0.5-3`.
fn band_name(b: usize) -> String {
    format!("{}-{}", BANDS[b].0, BANDS[b].1)
}

/// The table: per model and channel, total Rd of Monte Carlo and of the model, their relative
/// difference, the RMS of r·Rd(r) within 3 transport MFP and the worst relative error per band.
pub fn lines(slug: &str, models: &[ModelAgreement]) -> Vec<String> {
    let mut out = vec![
        format!("{slug}: analytic models against Monte Carlo (r in transport MFP ℓ = 1/σt′)"),
        format!(
            "  {:<19} {:>2} {:>8} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}",
            "model", "ch", "Rd MC", "Rd", "ΔRd/Rd", "rms rRd", "max|e|<½ℓ", "½–3ℓ", "3–10ℓ"
        ),
    ];
    for m in models {
        for (c, ch) in m.channels.iter().enumerate() {
            let band = |b: usize| {
                ch.band_max_rel_err[b].map_or("-".to_string(), |e| format!("{:.1}%", 100.0 * e))
            };
            out.push(format!(
                "  {:<19} {:>2} {:>8.4} {:>8.4} {:>7.1}% {:>8.1}% {:>9} {:>9} {:>9}",
                m.model.name(),
                mc::CHANNELS[c],
                ch.total_mc,
                ch.total_model,
                100.0 * ch.total_rel_err,
                100.0 * ch.rms_r_rd_3mfp,
                band(0),
                band(1),
                band(2)
            ));
        }
    }
    out
}

/// One material's comparison as JSON: `{"material", "plot", "models": [{"model", "channels":
/// {"R": {...}, …}}]}`.
pub fn json(slug: &str, plot: &str, models: &[ModelAgreement]) -> Value {
    let models: Vec<Value> = models
        .iter()
        .map(|m| {
            let channel = |ch: &fit::profile_compare::ChannelAgreement| {
                let bands: Map<String, Value> = (0..3)
                    .map(|b| (band_name(b), json!(ch.band_max_rel_err[b])))
                    .collect();
                json!({
                    "total_mc": ch.total_mc, "total_mc_se": ch.total_mc_se,
                    "total_model": ch.total_model, "total_rel_err": ch.total_rel_err,
                    "rms_r_rd_3mfp": ch.rms_r_rd_3mfp, "max_rel_err_by_band_mfp": bands,
                })
            };
            let channels: Map<String, Value> = m
                .channels
                .iter()
                .enumerate()
                .map(|(c, ch)| (mc::CHANNELS[c].to_string(), channel(ch)))
                .collect();
            json!({ "model": m.model.name(), "channels": channels })
        })
        .collect();
    json!({ "material": slug, "plot": plot, "models": models })
}
