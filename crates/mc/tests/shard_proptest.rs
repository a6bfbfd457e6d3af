//! Hostile shard files for `sss merge` ([`Shard::from_json`], [`mc::shard::merge`]): random
//! mutations of a valid shard and every number replaced by every hostile value.
//!
//! Requirement: no panic and no abort (a size in the file never sizes an allocation before it is
//! checked against the specification), every refusal names the file, and whatever is accepted
//! merges and normalizes without panicking.

use testkit::hostile;

use std::sync::LazyLock;

use mc::shard::{self, Shard};
use mc::{BatchSpec, ChannelSpec, Grid, Layer, McError, TallySet};
use proptest::prelude::*;

const NAME: &str = "shard-1-of-1.json";

/// A whole run in one shard: a walk shared by two channels on different grids (Ketchup G and
/// its twin at twice the density) and a walk of its own (Skin1 R), with every tally, in one
/// chunk.
static VALID: LazyLock<String> = LazyLock::new(|| {
    let channel = |mu_a: f64, mu_s: f64, nr: usize| ChannelSpec {
        layer: Layer {
            n: 1.3,
            mu_a,
            mu_s,
            g: 0.0,
            thickness: 1.0e8,
        },
        grid: Grid {
            dr: 0.2 / (mu_a + mu_s),
            dz: 0.5 / (mu_a + mu_s),
            nr,
            nz: 3,
            na: 2,
        },
    };
    let spec = BatchSpec {
        n_above: 1.0,
        n_below: 1.0,
        channels: vec![
            channel(9.7, 0.7, 6),
            channel(0.32, 7.4, 5),
            channel(19.4, 1.4, 4),
        ],
        photons: 200,
        seed: 3,
        tallies: TallySet {
            absorption_rz: true,
            absorption_rz_se: true,
            surface_xy: 1,
        },
    };
    let chunks = 0..mc::chunk_count(spec.photons);
    let groups = mc::accumulate_batch(&spec, chunks.clone(), &|_| {}).unwrap();
    let labels = ["a:R", "a:G", "a:B"].map(String::from).to_vec();
    Shard {
        spec,
        labels,
        chunks,
        groups,
    }
    .to_json()
});

/// Parses, merges and normalizes `text` as far as it is accepted; a refusal must name the file.
fn check_shard(text: &str) -> Result<(), TestCaseError> {
    let named = |e: McError| -> Result<(), TestCaseError> {
        let msg = e.to_string();
        prop_assert!(
            msg.contains(NAME),
            "the error does not name the file: {msg}"
        );
        Ok(())
    };
    let s = match Shard::from_json(text, NAME) {
        Ok(s) => s,
        Err(e) => return named(e),
    };
    match shard::merge(&[(NAME.to_string(), s)]) {
        Ok((spec, _, accs)) => {
            let out = mc::batch_outputs(&spec, &accs);
            prop_assert_eq!(out.len(), spec.channels.len());
        }
        Err(e) => named(e)?,
    }
    Ok(())
}

#[test]
fn the_valid_shard_merges() {
    check_shard(&VALID).unwrap();
    let s = Shard::from_json(&VALID, NAME).unwrap();
    assert_eq!(s.spec.groups(), vec![vec![0, 2], vec![1]]);
}

/// Every number of the file, replaced in turn by every hostile value (a deterministic sweep
/// complementing the random mutations below).
#[test]
fn every_number_replaced_by_every_hostile_value() {
    let valid = VALID.as_str();
    for (a, b) in hostile::numbers(valid) {
        for v in hostile::HOSTILE_NUMBERS {
            let text = format!("{}{v}{}", &valid[..a], &valid[b..]);
            if let Err(e) = check_shard(&text) {
                panic!("{e}\n--- input:\n{text}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn shard_json_survives_hostile_input(text in hostile::hostile(VALID.as_str())) {
        check_shard(&text)?;
    }
}
