//! Statistical agreement of two independent Monte Carlo runs, shared by the test files.

use mc::{Estimate, Output};

/// χ² of two estimates per bin over the bins both sample well (relative standard error below
/// 0.2: bins with a handful of scores have non-Gaussian errors), and the number of such bins.
pub fn chi2(a: &[Estimate], b: &[Estimate]) -> (f64, usize) {
    let mut chi = 0.0;
    let mut dof = 0;
    for (x, y) in a.iter().zip(b) {
        let v = x.se * x.se + y.se * y.se;
        if v > 0.0 && x.se < 0.2 * x.value && y.se < 0.2 * y.value {
            chi += (x.value - y.value).powi(2) / v;
            dof += 1;
        }
    }
    (chi, dof)
}

/// Two runs agree: χ²/dof of Rd(r) over at least `min_bins` well-sampled bins within the
/// project's one χ² judgement (`testkit::chi2::reduced_limit`: the 10⁻⁴ quantile of a true
/// agreement, and never below 1.5), and total Rd and A within 4 standard errors.
pub fn assert_agree(name: &str, x: &Output, y: &Output, min_bins: usize) {
    assert_profiles_agree(name, &x.rd_r, &y.rd_r, min_bins);
    for (what, p, q) in [("Rd", x.rd, y.rd), ("A", x.a, y.a)] {
        let z = (p.value - q.value) / (p.se * p.se + q.se * q.se).sqrt();
        assert!(z.abs() < 4.0, "{name} {what}: {p:?} vs {q:?} (z = {z:.2})");
    }
}

/// Two profiles agree: χ²/dof over at least `min_bins` well-sampled bins within
/// `testkit::chi2::reduced_limit(dof, 1.5)` (as in [`assert_agree`]).
pub fn assert_profiles_agree(name: &str, a: &[Estimate], b: &[Estimate], min_bins: usize) {
    let (chi, dof) = chi2(a, b);
    assert!(dof >= min_bins, "{name}: only {dof} bins to compare");
    let limit = testkit::chi2::reduced_limit(dof, 1.5);
    assert!(
        chi / dof as f64 <= limit,
        "{name}: χ²/dof = {:.2} over {dof} bins (limit {limit:.2})",
        chi / dof as f64
    );
}
