//! Profile tables on the GPU (`mc_gpu::table`, `sss table --device gpu`) against the CPU's, never
//! against themselves:
//! - a white table (every albedo from the largest albedo's walk, reweighted by (α/α_max)ⁿ) equals
//!   the CPU's per-albedo table (one independent walk per albedo) within the noise of both, for
//!   g = 0 and g = 0.9 (η = 1.4: total internal reflection returns photons): the annuli between
//!   the table's edges give χ²/dof ≤ 1.5 per albedo (the 10⁻⁴ quantile over fewer annuli) and
//!   ≤ 1.2 pooled over the albedos, the totals agree within 3 standard errors (the statistic of `crates/mc/tests/white_table.rs`; measured
//!   over four seed pairs here, pooled χ²/dof 0.81–1.17);
//! - the per-albedo build (`--white off`) agrees with the CPU's white table the same way, and its
//!   largest albedo is the white table's walk bit for bit (the same walk and streams);
//! - α = 0 reflects nothing, exactly; the same seed gives the same table whatever the dispatch.

mod common;
#[path = "../../mc/tests/common/table_agreement.rs"]
mod table_agreement;

use mc::table::{self, Table, TableSpec};
use table_agreement::spec;

/// One table on the GPU.
fn one(
    gpu: &gpu::Gpu,
    s: &TableSpec,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(Table, u64), mc_gpu::McGpuError> {
    mc_gpu::tables(gpu, std::slice::from_ref(s), progress).map(|(mut t, n)| (t.remove(0), n))
}

fn cpu(s: &TableSpec) -> Table {
    table::build(std::slice::from_ref(s), &|_| {})
        .unwrap()
        .remove(0)
}

fn white_agrees(g: f64) {
    let Some(gpu) = common::gpu() else { return };
    let (t, interactions) = one(&gpu, &spec(g, true, 31, 100_000), &|_| {}).unwrap();
    assert!(t.white && t.tracer.as_deref().is_some_and(|s| s.starts_with("gpu: ")));
    assert!(interactions > 100_000);
    table_agreement::agree(
        &format!("white, g = {g}"),
        &t,
        &cpu(&spec(g, false, 32, 100_000)),
    );
}

#[test]
fn a_white_table_equals_the_cpus_at_g_0() {
    white_agrees(0.0);
}

#[test]
fn a_white_table_equals_the_cpus_at_g_0_9() {
    white_agrees(0.9);
}

#[test]
fn per_albedo_walks_equal_the_cpu_and_end_in_the_white_walk() {
    let Some(gpu) = common::gpu() else { return };
    let photons = 40_000;
    let (each, _) = one(&gpu, &spec(0.5, false, 41, photons), &|_| {}).unwrap();
    assert!(!each.white);
    table_agreement::agree(
        "per albedo, g = 0.5",
        &each,
        &cpu(&spec(0.5, true, 42, photons)),
    );
    // The white table traces the largest albedo's own walk.
    let (white, _) = one(&gpu, &spec(0.5, true, 41, photons), &|_| {}).unwrap();
    let last = white.albedo.len() - 1;
    assert_eq!(white.cumulative[last], each.cumulative[last]);
    assert_eq!(white.rd_sq[last], each.rd_sq[last]);
    assert_ne!(white.rd[last - 1], each.rd[last - 1]);
}

#[test]
fn the_same_seed_gives_the_same_table_whatever_the_dispatch() {
    let Some(gpu) = common::gpu() else { return };
    let s = spec(0.0, true, 7, 5_000);
    let (a, _) = one(&gpu, &s, &|_| {}).unwrap();
    let tracer = mc_gpu::Tracer::new(&gpu)
        .unwrap()
        .with_dispatch(mc_gpu::Dispatch {
            slots: 100,
            steps: Some(7),
            round: 1_000,
        });
    let (b, _) = tracer.table(&gpu, &s, &|_| {}).unwrap();
    assert_eq!(a, b);
    // Through the file, as `sss profile --model table` reads it.
    assert_eq!(Table::from_json(&a.to_json(), "t").unwrap(), a);
}
