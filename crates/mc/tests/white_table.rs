//! White tables (every albedo from the largest albedo's walk, reweighted by (α/α_max)ⁿ) against
//! the per-albedo build, one walk per albedo:
//! - the largest albedo's row is that albedo's own walk, bit for bit (nothing is cut);
//! - every other albedo agrees with its own, independent walk within the noise of both: the
//!   annuli between the table's edges give χ²/dof ≤ 1.5 (or, over fewer annuli than that can
//!   judge, the 10⁻⁴ quantile: `testkit::chi2::reduced_limit`), the totals agree within 3
//!   standard errors, for g = 0 and g = 0.9 (η = 1.4: total internal reflection returns photons);
//!   the seeds are fixed and the runs deterministic, so the test does not flicker;
//! - α = 0 reflects nothing (no photon scatters back), exactly;
//! - sharded white builds merge bit-identical to the one-machine build.

#[path = "common/table_agreement.rs"]
mod table_agreement;

use mc::table::{self, Table, TableShard, TableSpec, default_albedos};
use table_agreement::spec;

fn build(s: TableSpec) -> Table {
    table::build(&[s], &|_| {}).unwrap().remove(0)
}

#[test]
fn the_largest_albedo_is_its_own_walk_bit_for_bit() {
    let white = build(spec(0.5, true, 11, 40_000));
    let each = build(spec(0.5, false, 11, 40_000));
    let last = white.albedo.len() - 1;
    assert!(white.white && !each.white);
    assert_eq!(white.cumulative[last], each.cumulative[last]);
    assert_eq!(white.cumulative_sq[last], each.cumulative_sq[last]);
    assert_eq!(white.rd[last], each.rd[last]);
    assert_eq!(white.rd_sq[last], each.rd_sq[last]);
    // The others are reweighted, not traced again: not the same numbers.
    assert_ne!(white.rd[last - 1], each.rd[last - 1]);
}

fn agree(g: f64) {
    let photons = 100_000;
    let white = build(spec(g, true, 21, photons));
    let each = build(spec(g, false, 22, photons));
    table_agreement::agree(&format!("g = {g}"), &white, &each);
}

#[test]
fn every_albedo_agrees_with_its_own_walk_at_g_0() {
    agree(0.0);
}

#[test]
fn every_albedo_agrees_with_its_own_walk_at_g_0_9() {
    agree(0.9);
}

#[test]
fn sharded_white_builds_merge_bit_identical() {
    let s = spec(0.0, true, 5, 70_000);
    let whole = build(s.clone());
    let shards: Vec<(String, TableShard)> = (1..=3)
        .map(|i| {
            let shard = TableShard::trace(std::slice::from_ref(&s), i, 3, &|_| {}).unwrap();
            // Through the file, as `sss merge` reads it.
            let text = shard.to_json();
            (
                format!("shard {i}"),
                TableShard::from_json(&text, "shard").unwrap(),
            )
        })
        .collect();
    assert_eq!(table::merge_tables(&shards).unwrap(), vec![whole.clone()]);
    // A table file keeps how it was built.
    let back = Table::from_json(&whole.to_json(), "t").unwrap();
    assert!(back.white);
}

/// `Table::agreement`, what the comparisons above rest on: a table agrees with itself exactly,
/// a bias of one albedo's reflectance shows at that albedo only, and other tables are refused.
#[test]
fn the_agreement_sees_a_bias_at_its_albedo() {
    let t = build(spec(0.5, true, 3, 40_000));
    for n in t.agreement(&t).unwrap() {
        assert_eq!((n.chi2, n.rd_z), (0.0, 0.0));
    }
    let mut biased = t.clone();
    let i = 8;
    for k in 0..t.radius.len() {
        biased.cumulative[i][k] *= 1.2;
        biased.cumulative_sq[i][k] *= 1.44;
    }
    biased.rd[i] *= 1.2;
    biased.rd_sq[i] *= 1.44;
    let a = t.agreement(&biased).unwrap();
    assert!(
        a[i].dof >= 20 && a[i].chi2 / a[i].dof as f64 > 5.0,
        "{:?}",
        a[i]
    );
    assert!(a[i].rd_z > 10.0, "{:?}", a[i]);
    assert_eq!(a[i - 1].chi2, 0.0);
    let other = build(TableSpec {
        albedos: default_albedos(12, 0.99),
        ..spec(0.5, true, 3, 1_000)
    });
    assert!(t.agreement(&other).is_err());
}
