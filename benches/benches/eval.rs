//! Image-space evaluation, in seconds per call. On the thesis grid (Skin1's analytic profile,
//! photon beam diffusion, channel R): preparing the evaluator (`ImageEval::new`: the ground
//! truth binned to a half-width ≤ 128 and convolved in 2D with the five 256-pixel test signals)
//! and one rank-1 kernel's image RMS on them (`ImageEval::rms` of pre-integration: binned,
//! rescaled, two 1D passes per signal). And the whole `fit::evaluate::evaluate` (every model
//! fitted and measured on three channels) on a smaller problem, [`EVALUATE`]: at the size `sss
//! eval` runs it, about a minute and a half a call on 2 cores, criterion's ten samples would take
//! a quarter of an hour. Runs on rayon's global pool (every core), as `sss eval` does.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use fit::evaluate::{ImageSize, evaluate};
use fit::metrics::ImageEval;
use fit::{ground_truth, preint};
use sss_benches::skin1_profile;

/// The problem of the whole-`evaluate` bench: Skin1's profile out to this many of its largest
/// MFP (the thesis grid reaches 32), and test signals of this size.
const EVALUATE: (f64, ImageSize) = (
    8.0,
    ImageSize {
        size: 128,
        max_half: 64,
    },
);

fn image_eval(c: &mut Criterion) {
    let k = ground_truth(&skin1_profile(None), 0, None);
    let size = ImageSize::default();
    let mut group = c.benchmark_group("eval");
    group.sampling_mode(SamplingMode::Flat);
    group.bench_function("image-eval-new", |b| {
        b.iter(|| ImageEval::new(&k, size.size, size.max_half))
    });
    let eval = ImageEval::new(&k, size.size, size.max_half);
    let a = preint(&k);
    group.bench_function("image-rms-preint", |b| b.iter(|| eval.rms(&a)));

    let (reach, image) = EVALUATE;
    let p = skin1_profile(Some(reach));
    group.bench_function("evaluate", |b| {
        b.iter(|| {
            black_box(evaluate(&p, "skin1", image).unwrap_or_else(|e| panic!("{e}")));
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = image_eval
}
criterion_main!(benches);
