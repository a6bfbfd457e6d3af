//! What `sss bench mc` shows of [`mc::bench`]'s measurements: photon-tracer throughput, run time
//! against error and batched against channel-by-channel tracing, as lines and as JSON.

use mc::bench::{Batching, Throughput, TimeVsError};
use serde_json::{Value, json};

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
