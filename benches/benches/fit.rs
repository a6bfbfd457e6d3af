//! Fit time of every kernel model of `sss eval` ([`fit::evaluate::MODELS`]) on the thesis grid:
//! the three channels of Skin1's analytic profile (photon beam diffusion, 1236 bins of 34 µm; a
//! 2473 × 2473 ground truth per channel), fitted as `KernelModel::fit_truths` fits them, in
//! seconds per fit of all three channels. The radial Burley kernel is not separable: its fit is
//! `Burley::fit` and the dense kernel, as `fit::evaluate` builds it. Runs on rayon's global pool
//! (every core), as `sss eval` does. Criterion needs ten samples, so the slowest fits (guided
//! optimization, several seconds each) take about a minute each.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use fit::evaluate::MODELS;
use fit::{Burley, Kernel2, KernelModel};
use sss_benches::skin1_profile;

fn fits(c: &mut Criterion) {
    let truths = fit::ground_truths(&skin1_profile(None));
    let mut group = c.benchmark_group("fit");
    group.sampling_mode(SamplingMode::Flat);
    for model in MODELS {
        group.bench_function(model.to_string(), |b| b.iter(|| fit(model, &truths)));
    }
    group.finish();
}

/// `model` fitted to every channel's ground truth (Table A.1's Skin1 row for `manual`).
fn fit(model: KernelModel, truths: &[Kernel2]) {
    match model {
        KernelModel::Burley { radial: true } => {
            for k in truths {
                black_box(Burley::fit(k).kernel(k.half, k.h));
            }
        }
        _ => {
            black_box(
                model
                    .fit_truths(truths, "skin1")
                    .unwrap_or_else(|e| panic!("{model}: {e}")),
            );
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = fits
}
criterion_main!(benches);
