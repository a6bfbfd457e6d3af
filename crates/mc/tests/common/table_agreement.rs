//! The tables both test files build (`spec`: 12 albedos up to 0.999 at η = 1.4), and two builds
//! of one profile table agree within noise (shared by mc's white tables and
//! mc_gpu's tables): per albedo node above α = 0, χ²/dof over the rings both resolve, where there
//! are at least 20 of them (albedos whose light is spread over fewer, g = 0.9 below α ≈ 0.9 with
//! Rd < 1 %, are judged by their totals alone), at most 1.5 or, over fewer rings than 1.5 can
//! judge, the value a true agreement exceeds with probability 10⁻⁴ ([`reduced_limit`]); the totals
//! within 3 combined standard errors; at least 8 albedos judged by their rings, and χ²/dof ≤ 1.2
//! pooled over them (or the 10⁻⁴ quantile over fewer rings than 1.2 can judge): with ~500 rings a
//! true agreement lies within 1 ± 0.07 (one standard deviation; a white table's albedos share a
//! walk, which correlates their terms, not their means), so a bias of a few percent of the noise
//! would show. α = 0 reflects nothing, exactly, in `a`.

use mc::table::{Table, TableSpec, default_albedos};
use testkit::chi2::reduced_limit;

/// A small table of anisotropy `g` at η = 1.4 (total internal reflection returns photons).
pub fn spec(g: f64, white: bool, seed: u64, photons: u64) -> TableSpec {
    TableSpec {
        g,
        eta: 1.4,
        albedos: default_albedos(12, 0.999),
        photons,
        seed,
        white,
    }
}

pub fn agree(what: &str, a: &Table, b: &Table) {
    assert_eq!(a.rd[0], 0.0, "{what}: α = 0 scatters nothing back");
    let (mut judged, mut pooled, mut pooled_dof) = (0, 0.0, 0);
    for (i, n) in a.agreement(b).unwrap().iter().enumerate().skip(1) {
        let alpha = a.albedo[i];
        if n.dof >= 20 {
            let reduced = n.chi2 / n.dof as f64;
            let limit = reduced_limit(n.dof, 1.5);
            assert!(
                reduced <= limit,
                "{what}, α = {alpha}: χ²/dof = {reduced:.2} over {} rings (limit {limit:.2})",
                n.dof
            );
            judged += 1;
            (pooled, pooled_dof) = (pooled + n.chi2, pooled_dof + n.dof);
        }
        assert!(
            n.rd_z <= 3.0,
            "{what}, α = {alpha}: Rd {:?} against {:?}",
            a.rd_node(i),
            b.rd_node(i)
        );
    }
    assert!(
        judged >= 8,
        "{what}: {judged} albedos judged by their annuli"
    );
    let reduced = pooled / pooled_dof as f64;
    eprintln!("{what}: pooled χ²/dof {reduced:.3} over {pooled_dof} annuli, {judged} albedos");
    let limit = reduced_limit(pooled_dof, 1.2);
    assert!(
        reduced <= limit,
        "{what}: pooled χ²/dof = {reduced:.3} (limit {limit:.3})"
    );
}
