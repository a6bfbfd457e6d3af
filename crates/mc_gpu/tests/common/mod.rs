//! Shared by the GPU tracer's tests: the device (or a skip outside CI when there is none) and the
//! statistics that compare a GPU run with the CPU's. (Not every test file uses each item.)
#![allow(dead_code)]

use gpu::Gpu;
use mc::{Estimate, Output};

/// The adapter wgpu finds; None (test skipped) without one, except under CI=true, where a
/// missing adapter is a failure.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => panic!("CI=true and {e}"),
        Err(e) => {
            use std::io::Write;
            let name = std::thread::current()
                .name()
                .unwrap_or("a GPU test")
                .to_string();
            let _ = writeln!(std::io::stderr().lock(), "SKIPPED {name}: {e}");
            None
        }
    }
}

/// χ² of two independent estimates of the same profile over the bins both resolve, with its
/// degrees of freedom: Σ (a − b)² / (σa² + σb²) over the bins whose mean (a + b)/2 is at least
/// three combined standard errors (a dozen photons or more in each), so the Gaussian limit holds.
pub fn chi2(a: &[Estimate], b: &[Estimate]) -> (f64, usize) {
    let mut chi2 = 0.0;
    let mut dof = 0;
    for (x, y) in a.iter().zip(b) {
        let var = x.se * x.se + y.se * y.se;
        if var > 0.0 && 0.5 * (x.value + y.value) >= 3.0 * var.sqrt() {
            chi2 += (x.value - y.value).powi(2) / var;
            dof += 1;
        }
    }
    (chi2, dof)
}

/// Whether two estimates agree within `k` combined standard errors, plus `abs` for what is
/// deterministic but rounded in f32 on the GPU (a weight of 1 − Rsp has no noise).
pub fn within(a: Estimate, b: Estimate, k: f64, abs: f64) -> bool {
    (a.value - b.value).abs() <= k * (a.se.powi(2) + b.se.powi(2)).sqrt() + abs
}

/// The GPU run agrees with the CPU run: χ²/dof ≤ 1.5 over Rd(r), Rd, A and Tt within three
/// combined standard errors. Returns a line describing the comparison, or the failure.
pub fn agree(label: &str, g: &Output, c: &Output) -> Result<String, String> {
    let (x2, dof) = chi2(&g.rd_r, &c.rd_r);
    let per = if dof > 0 { x2 / dof as f64 } else { 0.0 };
    let line = format!(
        "{label}: chi2/dof {per:.3} over {dof} bins; Rd {:.5}±{:.5} vs {:.5}±{:.5}; A {:.5} vs {:.5}; Tt {:.5} vs {:.5}; interactions/photon {:.1} vs {:.1}",
        g.rd.value,
        g.rd.se,
        c.rd.value,
        c.rd.se,
        g.a.value,
        c.a.value,
        g.tt.value,
        c.tt.value,
        g.interactions as f64 / g.photons as f64,
        c.interactions as f64 / c.photons as f64,
    );
    let totals = [(g.rd, c.rd), (g.a, c.a), (g.tt, c.tt)]
        .iter()
        .all(|&(a, b)| within(a, b, 3.0, 1e-6));
    if per <= 1.5 && totals && g.rsp == c.rsp {
        Ok(line)
    } else {
        Err(line)
    }
}
