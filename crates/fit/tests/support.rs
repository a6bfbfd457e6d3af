//! The eigensolver works on the support that holds all but ε = 10⁻⁶ of a kernel's sum
//! (`fit::SUPPORT_EPSILON`): the metrics `sss eval` reports for the SVD models must move by less
//! than ε on the scale of each metric when it does. And the quadrant form of the kernel-space metrics equals the sums over
//! the whole grid.

use fit::metrics::{ImageEval, KernelMetrics, kernel_rms, l1_error};
use fit::{Kernel2, Profile, SUPPORT_EPSILON, Separable, ground_truth, top_eigen_to};

/// Three channels of very different reach on one grid (as Ketchup's: the grid follows the widest):
/// Rd ∝ e^{−r/ℓ}/(r + ℓ/4) with ℓ = 0.2, 0.03, 0.012 cm, dr = 0.005 cm, 240 bins.
fn disparate() -> Profile {
    Profile::from_fn(0.005, 240, |c, r| {
        let l = [0.2, 0.03, 0.012][c];
        (-r / l).exp() / (r + 0.25 * l)
    })
}

fn svd_with(k: &Kernel2, rank: usize, epsilon: f64) -> Separable {
    let e = top_eigen_to(k, rank, 1e-12, 2000, epsilon);
    Separable {
        h: k.h,
        terms: e
            .values
            .iter()
            .zip(&e.vectors)
            .map(|(l, u)| fit::Term {
                sign: l.signum(),
                a: u.iter().map(|x| x * l.abs().sqrt()).collect(),
            })
            .collect(),
    }
}

fn mean_image_rms(eval: &ImageEval, a: &Separable) -> f64 {
    let e = eval.rms(a);
    e.iter().map(|(_, x)| x).sum::<f64>() / e.len() as f64
}

#[test]
fn metrics_move_less_than_the_support_epsilon() {
    let p = disparate();
    for c in 0..3 {
        let k = ground_truth(&p, c, None);
        let n = k.v.len() as f64;
        // The scale of each metric: kernel RMS against the kernel's own RMS, image RMS against the
        // signals' range (1), L1 error against the kernel's sum (1).
        let k_rms = (k.v.iter().map(|x| x * x).sum::<f64>() / n).sqrt();
        let eval = ImageEval::new(&k, 128, 64);
        let models: Vec<(String, Separable, Separable)> = (1..=4)
            .map(|r| {
                (
                    format!("svd{r}"),
                    svd_with(&k, r, 0.0),
                    svd_with(&k, r, SUPPORT_EPSILON),
                )
            })
            .collect();
        let mut cut = false;
        for (name, whole, support) in &models {
            let zeros = |a: &Separable| a.terms[0].a.iter().filter(|x| **x == 0.0).count();
            cut |= zeros(support) > zeros(whole) + 20;
            let d_kernel = (kernel_rms(&k, whole) - kernel_rms(&k, support)).abs() / k_rms;
            let d_image = (mean_image_rms(&eval, whole) - mean_image_rms(&eval, support)).abs();
            let d_l1 = (l1_error(&k, whole) - l1_error(&k, support)).abs();
            for (what, d) in [
                ("kernel RMS", d_kernel),
                ("image RMS", d_image),
                ("L1", d_l1),
            ] {
                assert!(
                    d < SUPPORT_EPSILON,
                    "channel {c} {name}: {what} moved by {d:e}"
                );
            }
        }
        if c > 0 {
            assert!(
                cut,
                "channel {c}: the narrow channels are cut to their support"
            );
        }
    }
}

/// The quadrant sums of `KernelMetrics` equal the whole-grid definitions, for even models (the
/// quadrant path) and for a model that is not even (the fallback).
#[test]
fn quadrant_metrics_equal_the_whole_grid_sums() {
    let k = ground_truth(&disparate(), 0, None);
    let metrics = KernelMetrics::new(&k);
    let even = svd_with(&k, 3, 0.0);
    let mut odd = even.clone();
    odd.terms[1].a[3] *= 1.5;
    for a in [&even, &odd] {
        let rms = kernel_rms(&k, a);
        assert!((metrics.rms(&k, a) - rms).abs() <= 1e-10 * rms);
        let l1 = l1_error(&k, a);
        assert!((metrics.l1_error(a) - l1).abs() <= 1e-10 * l1.max(1e-6));
        let normalized = kernel_rms(&k, &a.clone().renormalized(k.l1()));
        assert!((metrics.rms_normalized(&k, a) - normalized).abs() <= 1e-10 * normalized);
    }
}
