//! `mc` throughput on one core: photons/s (criterion's throughput, elements = photon packets) of
//! a single-channel run of Skin1 R and Wholemilk R, half-spaces on the thesis grid (Table 6.1),
//! profile-only, with MCML's full tallies (A(r, z) summed, as `.mci` runs keep it) and with
//! per-photon standard errors of A(r, z) as well, as `sss bench mc` measures them. Each run
//! also counts its interaction events (drops, one per interaction site); the bench prints
//! events/photon and events/s [M/s] over the timed runs. One core: every run is traced on a
//! one-thread rayon pool.

use std::cell::Cell;
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use mc::{RunSpec, TallySet};
use sss_benches::{material, single_channel};

/// (material, photon packets per timed run): about a tenth of a second each on one core.
/// Wholemilk's albedo is near 1, so its photons take ten times as many steps.
const CASES: [(&str, u64); 2] = [("skin1", 50_000), ("wholemilk", 5_000)];

/// (label, tallies): profile-only; MCML's full set with absorption on the (r, z) grid, summed as
/// MCML sums it (as `.mci` runs keep it); and the full set with per-photon standard errors of
/// A(r, z).
const TALLIES: [(&str, TallySet); 3] = [
    (
        "profile-only",
        TallySet {
            absorption_rz: false,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    ),
    (
        "full",
        TallySet {
            absorption_rz: true,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    ),
    (
        "full-rz-se",
        TallySet {
            absorption_rz: true,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    ),
];

fn throughput(c: &mut Criterion) {
    let one_core = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let mut group = c.benchmark_group("mc");
    group.sampling_mode(SamplingMode::Flat);
    for (slug, photons) in CASES {
        let m = material(slug);
        for (label, tallies) in TALLIES {
            let spec = single_channel(&m, 0, photons, tallies);
            group.throughput(Throughput::Elements(photons));
            // Runs, events and seconds of every timed run (warm-up included), for events/s.
            let counted = Cell::new((0u64, 0u64, Duration::ZERO));
            group.bench_function(BenchmarkId::new(format!("{slug}-R"), label), |b| {
                b.iter_custom(|iters| {
                    let t = Instant::now();
                    let events: u64 = (0..iters).map(|_| trace(&one_core, &spec)).sum();
                    let elapsed = t.elapsed();
                    let (r, e, s) = counted.get();
                    counted.set((r + iters, e + events, s + elapsed));
                    elapsed
                })
            });
            let (runs, events, seconds) = counted.get();
            if runs == 0 {
                continue; // filtered out
            }
            println!(
                "mc/{slug}-R/{label}: {:.1} events/photon, {:.1} M events/s (mean over {runs} timed runs)\n",
                events as f64 / (runs * photons) as f64,
                events as f64 / seconds.as_secs_f64() / 1e6,
            );
        }
    }
    group.finish();
}

/// One run on `pool`; its interaction events.
fn trace(pool: &rayon::ThreadPool, spec: &RunSpec) -> u64 {
    let out = pool
        .install(|| mc::run(spec, &|_| {}))
        .unwrap_or_else(|e| panic!("{e}"));
    black_box(out).interactions
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = throughput
}
criterion_main!(benches);
