//! Batch tracing against independent per-channel MCML runs, determinism and shards.

mod common;

use mc::{BatchSpec, ChannelSpec, Grid, Layer, Output, RunSpec, Sample, TallySet};

/// Channels with very different albedos sharing g = 0 and η = 1.3: Ketchup G and B
/// (a ≈ 0.07, 0.02) and Wholemilk R (a ≈ 0.9996), thesis Table 6.2 [cm⁻¹], and Ketchup G at twice
/// the density (the same walk as channel 0, lengths halved).
fn channels() -> Vec<ChannelSpec> {
    [
        (9.7, 0.7),
        (14.5, 0.3),
        (0.011, 25.5),
        (2.0 * 9.7, 2.0 * 0.7),
    ]
    .iter()
    .map(|&(mu_a, mu_s)| {
        let layer = Layer {
            n: 1.3,
            mu_a,
            mu_s,
            g: 0.0,
            thickness: 1.0e8,
        };
        let mfp = 1.0 / layer.mu_t();
        ChannelSpec {
            layer,
            grid: Grid {
                dr: mfp / 20.0,
                dz: mfp / 2.0,
                nr: 80,
                nz: 20,
                na: 10,
            },
        }
    })
    .collect()
}

fn assert_agree(name: &str, batch: &Output, single: &Output) {
    common::assert_agree(name, batch, single, 15);
    assert_eq!(batch.rsp, single.rsp);
}

#[test]
fn batch_equals_independent_runs_within_statistics() {
    let chans = channels();
    let photons = 60_000;
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: chans.clone(),
        photons,
        seed: 1,
        tallies: TallySet {
            absorption_rz: true,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    };
    assert_eq!(
        spec.groups(),
        vec![vec![0, 3], vec![1], vec![2]],
        "one walk for the channels of equal albedo, one for each other"
    );
    let batch = mc::run_batch(&spec, &|_| {}).unwrap();
    for (i, c) in chans.iter().enumerate() {
        let single = RunSpec {
            sample: Sample::single(c.layer),
            grid: c.grid,
            photons,
            seed: 99 + i as u64,
            tallies: TallySet::default(),
        };
        let single = mc::run(&single, &|_| {}).unwrap();
        assert_agree(&format!("channel {i}"), &batch[i], &single);
        // The batch's A(r,z) is on the channel's own grid too: its total matches A.
        let a_rz: f64 = (0..c.grid.nr)
            .flat_map(|ir| (0..c.grid.nz).map(move |iz| (ir, iz)))
            .map(|(ir, iz)| {
                batch[i].a_rz[ir * c.grid.nz + iz].value
                    * 2.0
                    * std::f64::consts::PI
                    * (ir as f64 + 0.5)
                    * c.grid.dr
                    * c.grid.dr
                    * c.grid.dz
            })
            .sum();
        assert!(
            (a_rz - batch[i].a.value).abs() < 1e-9,
            "channel {i}: ΣA(r,z) = {a_rz}, A = {}",
            batch[i].a.value
        );
    }
}

#[test]
fn grouping_respects_albedo_g_eta_and_thickness() {
    let mut chans = channels();
    chans[1].layer.g = 0.5; // different g
    chans.push(ChannelSpec {
        layer: Layer {
            n: 1.5,
            ..chans[0].layer
        },
        grid: chans[0].grid,
    }); // different η
    chans.push(ChannelSpec {
        layer: Layer {
            thickness: 0.01,
            ..chans[0].layer
        },
        grid: chans[0].grid,
    }); // finite slab
    chans.push(ChannelSpec {
        layer: Layer {
            mu_a: 0.0,
            mu_s: 0.0,
            ..chans[0].layer
        },
        grid: chans[0].grid,
    }); // glass
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: chans,
        photons: 1000,
        seed: 1,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    };
    assert_eq!(
        spec.groups(),
        vec![vec![0, 3], vec![1], vec![2], vec![4], vec![5], vec![6]]
    );
    let out = mc::run_batch(&spec, &|_| {}).unwrap();
    // Channel 3 is channel 0 at twice the density on a grid of half the spacing: one walk, so the
    // same totals, and Rd(r) four times higher bin by bin (Rd(r) = μt²·R*(μt·r)).
    let (a, b) = (&out[0], &out[3]);
    assert!(
        (a.rd.value - b.rd.value).abs() < 1e-12,
        "{:?} {:?}",
        a.rd,
        b.rd
    );
    assert!((a.a.value - b.a.value).abs() < 1e-12, "{:?} {:?}", a.a, b.a);
    for (x, y) in a.rd_r.iter().zip(&b.rd_r).take(40) {
        assert!(
            (4.0 * x.value - y.value).abs() <= 1e-9 * y.value,
            "{x:?} {y:?}"
        );
    }
    // A glass half-space absorbs nothing: what is not reflected is transmitted (the bottom
    // surface reflects some light back up, which leaves as Rd).
    assert_eq!(out[6].a.value, 0.0);
    assert!((out[6].rsp + out[6].rd.value + out[6].tt.value - 1.0).abs() < 1e-12);
}

/// Regression: `sss simulate skin1` and `sss simulate --all` gave Skin1 different numbers for one
/// seed, because a walk's streams were seeded by its group's position and shared with whichever
/// channels it was batched with. Same seed ⇒ a channel's results are bit-identical alone and in a
/// bigger batch (other albedos, another g, its own rescaled twin, another order), with every
/// tally, at normal and oblique incidence.
#[test]
fn a_channel_alone_and_in_a_bigger_batch_gives_the_same_bits() {
    let mut chans = channels();
    let mut other_g = chans[1];
    other_g.layer.g = 0.8;
    chans.push(other_g);
    chans.reverse();
    let spec = |channels: Vec<ChannelSpec>| BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels,
        photons: 20_000,
        seed: 11,
        tallies: TallySet {
            absorption_rz: true,
            absorption_rz_se: true,
            surface_xy: 8,
        },
    };
    let batch = spec(chans.clone());
    for theta_deg in [0.0, 40.0] {
        let theta = mc::incidence::Incidence { theta_deg };
        let together = mc::run_batch_at(&batch, theta, &|_| {}).unwrap();
        for (i, c) in chans.iter().enumerate() {
            let alone = mc::run_batch_at(&spec(vec![*c]), theta, &|_| {}).unwrap();
            assert!(
                alone[0] == together[i],
                "θ = {theta_deg}°, channel {i}: Rd {:?} alone, {:?} in the batch",
                alone[0].rd,
                together[i].rd
            );
        }
    }
}

/// Same seed ⇒ bit-identical tallies with 1 and 2 threads (and any chunk order).
#[test]
fn same_seed_same_bits_whatever_the_thread_count() {
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: channels(),
        photons: 100_000,
        seed: 42,
        tallies: TallySet::default(),
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            mc::accumulate_batch(&spec, 0..mc::chunk_count(spec.photons), &|_| {}).unwrap()
        })
    };
    assert_eq!(run(1), run(2));
    let mcml = RunSpec {
        sample: Sample::single(channels()[2].layer),
        grid: channels()[2].grid,
        photons: 50_000,
        seed: 3,
        tallies: TallySet::default(),
    };
    let run1 = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| mc::accumulate(&mcml, 0..mc::chunk_count(mcml.photons), &|_| {}).unwrap())
    };
    assert_eq!(run1(1), run1(2));
}

/// Shards (disjoint chunk ranges) merge into exactly the unsharded run.
#[test]
fn shards_merge_bit_identically() {
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: channels(),
        photons: 70_000,
        seed: 5,
        tallies: TallySet::default(),
    };
    let n = mc::chunk_count(spec.photons);
    let whole = mc::accumulate_batch(&spec, 0..n, &|_| {}).unwrap();
    let mut merged = mc::accumulate_batch(&spec, 0..2, &|_| {}).unwrap();
    for (m, s) in merged
        .iter_mut()
        .zip(mc::accumulate_batch(&spec, 2..n, &|_| {}).unwrap())
    {
        m.merge(&s);
    }
    assert_eq!(merged, whole);
}

/// An error-targeted run stops once every channel meets the target, and not before.
#[test]
fn error_target_is_met() {
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: channels(),
        photons: 2_000_000,
        seed: 8,
        tallies: TallySet {
            absorption_rz: false,
            absorption_rz_se: true,
            surface_xy: 0,
        },
    };
    let r_max: Vec<f64> = spec.channels.iter().map(|c| 3.0 / c.layer.mu_t()).collect();
    let target = 0.01;
    let out = mc::run_batch_to_error(&spec, target, &r_max, &|_| {}).unwrap();
    let worst = out
        .iter()
        .zip(&r_max)
        .map(|(o, &r)| mc::relative_error(o, r))
        .fold(0.0, f64::max);
    assert!(worst <= target, "{worst}");
    assert!(
        out[0].photons < spec.photons,
        "stopped before the photon cap"
    );
    // It stopped at the first round that met the target: one round fewer does not meet it.
    let round = mc::ROUND_CHUNKS * mc::CHUNK_PHOTONS;
    let fewer = BatchSpec {
        photons: out[0].photons - round,
        ..spec.clone()
    };
    let before = mc::run_batch(&fewer, &|_| {}).unwrap();
    let worst = before
        .iter()
        .zip(&r_max)
        .map(|(o, &r)| mc::relative_error(o, r))
        .fold(0.0, f64::max);
    assert!(worst > target, "{worst}");
}

/// At oblique incidence the batch walk scores every channel's surface grid Rd(x, y) on that
/// channel's own grid: χ² against independent runs, and the same Rsp.
#[test]
fn oblique_batch_surface_grids_equal_independent_runs() {
    let chans: Vec<ChannelSpec> = channels()
        .into_iter()
        .map(|mut c| {
            c.layer.n = 1.4;
            c
        })
        .collect();
    let (photons, theta) = (60_000, mc::incidence::Incidence { theta_deg: 60.0 });
    let tallies = TallySet {
        absorption_rz: false,
        absorption_rz_se: true,
        surface_xy: 20,
    };
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: chans.clone(),
        photons,
        seed: 3,
        tallies,
    };
    let batch = mc::run_batch_at(&spec, theta, &|_| {}).unwrap();
    for (i, c) in chans.iter().enumerate() {
        let single = RunSpec {
            sample: Sample::single(c.layer),
            grid: c.grid,
            photons,
            seed: 77 + i as u64,
            tallies,
        };
        let single = mc::run_at(&single, theta, &|_| {}).unwrap();
        assert_eq!(batch[i].rsp, single.rsp);
        common::assert_profiles_agree(
            &format!("channel {i} Rd(x, y)"),
            &batch[i].rd_xy,
            &single.rd_xy,
            15,
        );
    }
}
