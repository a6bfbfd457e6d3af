//! The same seed gives the same bits on the same adapter, whatever the rounds, the photons in
//! flight and the steps per dispatch; and typed errors for what the GPU tracer refuses.

mod common;

use mc::{Layer, Material, SimConfig, TallySet};
use mc_gpu::{Dispatch, McGpuError, Tracer};

/// Also the regression test of the photons lavapipe lost: one slot asked for 100,000 steps per
/// dispatch ran into Mesa 22's silent end of shader loops after 65,535 iterations before the
/// steps were capped by the loop budget.
#[test]
fn the_same_seed_gives_the_same_bits_whatever_the_dispatch() {
    let Some(gpu) = common::gpu() else { return };
    let m = Material::builtin("skin1").unwrap();
    let spec = SimConfig::thesis()
        .unwrap()
        .batch(&[&m], 100_000, 5, true)
        .unwrap();
    let run = |d: Dispatch| {
        Tracer::new(&gpu)
            .unwrap()
            .with_dispatch(d)
            .run_batch(&gpu, &spec, &|_| {})
            .unwrap()
    };
    let reference = run(Dispatch::for_device(&gpu.device));
    assert_eq!(
        run(Dispatch::for_device(&gpu.device)),
        reference,
        "two runs"
    );
    let cuts = [
        Dispatch {
            slots: 1_000,
            steps: Some(3),
            round: 7_777,
        },
        Dispatch {
            slots: 100_000,
            steps: Some(5_000),
            round: 1 << 22,
        },
        Dispatch {
            slots: 1,
            steps: Some(100_000),
            round: 40_000,
        },
    ];
    for d in cuts {
        assert_eq!(run(d), reference, "{d:?}");
    }
    let mut other = spec.clone();
    other.seed += 1;
    let o = Tracer::new(&gpu)
        .unwrap()
        .run_batch(&gpu, &other, &|_| {})
        .unwrap();
    assert_ne!(o[0].rd.value, reference[0].rd.value);
}

/// A channel's numbers depend on the batch's seed and on the channel alone, not on the other
/// channels of the batch (as on the CPU).
#[test]
fn a_channel_does_not_depend_on_the_others_in_its_batch() {
    let Some(gpu) = common::gpu() else { return };
    let config = SimConfig::thesis().unwrap();
    let (a, b) = (
        Material::builtin("skin1").unwrap(),
        Material::builtin("marble").unwrap(),
    );
    let both = config.batch(&[&a, &b], 20_000, 9, true).unwrap();
    let alone = config.batch(&[&b], 20_000, 9, true).unwrap();
    let tracer = Tracer::new(&gpu).unwrap();
    let both = tracer.run_batch(&gpu, &both, &|_| {}).unwrap();
    let alone = tracer.run_batch(&gpu, &alone, &|_| {}).unwrap();
    assert_eq!(both[3..], alone[..]);
}

#[test]
fn progress_counts_every_photon_of_every_channel() {
    let Some(gpu) = common::gpu() else { return };
    let m = Material::builtin("skin1").unwrap();
    let spec = SimConfig::thesis()
        .unwrap()
        .batch(&[&m], 30_000, 1, true)
        .unwrap();
    let count = std::sync::atomic::AtomicU64::new(0);
    mc_gpu::run_batch(&gpu, &spec, &|n| {
        count.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    })
    .unwrap();
    assert_eq!(count.into_inner(), 90_000);
}

#[test]
fn what_the_gpu_does_not_tally_is_refused_by_name() {
    let Some(gpu) = common::gpu() else { return };
    let m = Material::builtin("skin1").unwrap();
    let config = SimConfig::thesis().unwrap();
    let full = config.batch(&[&m], 1000, 1, false).unwrap();
    let e = mc_gpu::run_batch(&gpu, &full, &|_| {}).unwrap_err();
    assert!(
        matches!(&e, McGpuError::Unsupported { what, .. } if what.contains("A_rz")),
        "{e}"
    );
    let mut xy = config.batch(&[&m], 1000, 1, true).unwrap();
    xy.tallies = TallySet {
        surface_xy: 4,
        ..xy.tallies
    };
    assert!(matches!(
        mc_gpu::run_batch(&gpu, &xy, &|_| {}),
        Err(McGpuError::Unsupported { .. })
    ));
    let mut none = config.batch(&[&m], 1000, 1, true).unwrap();
    none.photons = 0;
    assert!(matches!(
        mc_gpu::run_batch(&gpu, &none, &|_| {}),
        Err(McGpuError::Spec(_))
    ));
    let layer = Layer {
        n: 1.3,
        mu_a: 1.0,
        mu_s: 10.0,
        g: 0.0,
        thickness: 0.1,
    };
    let deep = mc::RunSpec {
        sample: mc::Sample {
            n_above: 1.0,
            n_below: 1.0,
            layers: vec![layer; mc_gpu::MAX_LAYERS + 1],
        },
        grid: mc::Grid {
            dr: 0.01,
            dz: 0.01,
            nr: 10,
            nz: 1,
            na: 1,
        },
        photons: 10,
        seed: 1,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: false,
            surface_xy: 0,
        },
    };
    let e = mc_gpu::run(&gpu, &deep, &|_| {}).unwrap_err();
    assert!(e.to_string().contains("17 layers"), "{e}");
}
