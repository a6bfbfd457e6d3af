//! What `sss bench mc` shows of [`mc::bench`]'s measurements: photon-tracer throughput, run time
//! against error and batched against channel-by-channel tracing, as lines and as JSON.

use mc::bench::{Batching, Throughput, TimeVsError};
use mc::progress::Progress;
use mc::{Material, SimConfig};
use serde_json::{Value, json};

use crate::error::Result;

/// The three measurements of `sss bench mc`, at the thesis's settings, each section's lines
/// passed to `progress.note` as it finishes; returns them as JSON.
///
/// 1. One channel on one core: the MCML yardstick (full tallies, summed as `.mci` runs keep
///    them, with per-photon standard errors of A(r, z)) and profile-only, for Skin1 (2·10⁵
///    photons), whole milk and marble (2·10⁴).
/// 2. Run time against error on `threads` workers (all cores: `None`): the three channels of
///    Skin1 and whole milk in one walk, profile-only, 10⁴ … `max_photons` photons.
/// 3. The whole library at `library_photons` per channel: one batch (walks shared by
///    similarity) against one walk per channel.
pub fn run(
    max_photons: u64,
    library_photons: u64,
    threads: Option<usize>,
    progress: &dyn Progress,
) -> Result<Value> {
    let config = SimConfig::thesis()?;
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| crate::ReportError::Invalid {
                field: "threads".into(),
                value: format!("{threads:?}"),
                reason: e.to_string(),
            })
    };
    let (single, pool) = (pool(1)?, pool(threads.unwrap_or(0))?);
    let note = |lines: Vec<String>| lines.iter().for_each(|l| progress.note(l));
    let named: Vec<(&str, Material)> = ["skin1", "wholemilk", "marble"]
        .into_iter()
        .map(|n| Ok((n, Material::builtin(n)?)))
        .collect::<Result<_>>()?;
    let cases: Vec<(&str, &Material, u64)> = (named.iter().zip([200_000, 20_000, 20_000]))
        .map(|((n, m), photons)| (*n, m, photons))
        .collect();
    progress.note("== single channel, 1 thread, thesis grid ==");
    let throughput = single.install(|| mc::bench::throughput(&cases, &config))?;
    note(throughput_lines(&throughput));

    let threads = pool.current_num_threads();
    progress.note(&format!(
        "\n== run time against error ({threads} threads, profile-only, thesis grid) =="
    ));
    let two: Vec<(&str, &Material)> = named[..2].iter().map(|(n, m)| (*n, m)).collect();
    let errors = pool.install(|| mc::bench::time_vs_error(&two, &config, max_photons))?;
    note(error_lines(&errors));

    // The library as it was measured (docs/measurements.md): the reproduced sixteen, not every
    // built-in medium.
    let all: Vec<Material> = (mc::builtin::REPRODUCED.into_iter())
        .map(Material::builtin)
        .collect::<mc::Result<_>>()?;
    progress.note(&format!(
        "\n== whole library ({} materials × 3 channels, {library_photons} photons each, profile-only) ==",
        all.len()
    ));
    let materials: Vec<&Material> = all.iter().collect();
    let b = pool.install(|| mc::bench::batching(&materials, &config, library_photons))?;
    note(batching_lines(&b));
    Ok(json(&throughput, &errors, &b, threads))
}

/// One line per material and tally set: photons/s, events/s and events per photon.
pub fn throughput_lines(rows: &[Throughput]) -> Vec<String> {
    rows.iter()
        .map(|r| {
            format!(
                "{:<10} R  {:<17} {:>10.0} photons/s  {:>6.1} M events/s  ({:.0} events/photon)",
                r.material,
                r.tallies,
                r.photons_per_s,
                r.events_per_s / 1e6,
                r.events_per_photon
            )
        })
        .collect()
}

/// The run-time-against-error table: relative standard errors of total Rd and of Rd at 1 and 3
/// mean free paths against photons and seconds.
pub fn error_lines(rows: &[TimeVsError]) -> Vec<String> {
    let mut out = vec![format!(
        "{:<10} {:>10} {:>9}  {:<3} {:>11} {:>13} {:>13}",
        "material", "photons", "seconds", "ch", "relSE(Rd)", "relSE Rd(1ℓ)", "relSE Rd(3ℓ)"
    )];
    out.extend(rows.iter().map(|r| {
        format!(
            "{:<10} {:>10} {:>9.2}  {:<3} {:>11.2e} {:>13.2e} {:>13.2e}",
            r.material,
            r.photons,
            r.seconds,
            r.channel,
            r.rel_se_rd,
            r.rel_se_rd_r_1mfp,
            r.rel_se_rd_r_3mfp
        )
    }));
    out
}

/// The whole library batched against channel by channel, and the batched time extrapolated to
/// 10⁷ photons per channel.
pub fn batching_lines(b: &Batching) -> Vec<String> {
    vec![
        format!(
            "batched ({} walk groups): {:.2} s   channel by channel ({} walks): {:.2} s   speed-up {:.1}×",
            b.groups,
            b.batched_seconds,
            b.channels,
            b.separate_seconds,
            b.separate_seconds / b.batched_seconds
        ),
        format!(
            "extrapolated to 10⁷ photons per channel: batched {:.0} s",
            b.batched_seconds * 1e7 / b.photons as f64
        ),
    ]
}

/// All three measurements as JSON, with the threads of the multi-threaded parts.
pub fn json(
    throughput: &[Throughput],
    errors: &[TimeVsError],
    b: &Batching,
    threads: usize,
) -> Value {
    json!({
        "single_channel_one_thread": throughput,
        "time_vs_error": errors,
        "library": {
            "photons": b.photons, "groups": b.groups, "batched_seconds": b.batched_seconds,
            "separate_seconds": b.separate_seconds, "threads": threads,
        },
    })
}
