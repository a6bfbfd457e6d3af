//! `Judge` fits and scores the models on a grid of five cells per pixel, each cell the mean of Rd
//! over it, instead of the profile's own bins (a profile of 3,201 bins: 1,195² samples instead
//! of 6,403²). Two things must hold for that to be the same judge:
//! - its pixels are the same integrals of Rd: exactly the block sums of the bins' grid when a
//!   pixel holds a whole number of subsamples per bin, to quadrature accuracy otherwise;
//! - the kernel it chooses is as good, scored on the bins' own grid, as the best of the same
//!   candidates fitted and scored there.

use fit::metrics::{ImageEval, bin_kernel, eval_factor};
use fit::select::{Budget, Judge, candidates};
use fit::taps::{ShaderKernel, TapSpec};
use fit::{Profile, ground_truth, ground_truths};

/// Three channels of different reach, ∝ e^{−r/ℓ}/(r + ℓ/20) (a diffuse profile's 1/r peak,
/// rounded within the first bins) with ℓ = 0.2, 0.05, 0.01 cm, on `n` bins of 10⁻³ cm.
fn profile(n: usize) -> Profile {
    Profile::from_fn(1e-3, n, |c, r| {
        let l = [0.2, 0.05, 0.01][c];
        (-r / l).exp() / (r + 0.05 * l)
    })
}

/// The largest relative difference between the judge's pixels and the bins' grid's pixels,
/// over pixels holding at least 10⁻⁶ of the kernel.
fn worst_pixel(p: &Profile) -> f64 {
    let judge = Judge::new(p);
    let f = eval_factor(p.len(), 128);
    (0..3)
        .map(|c| {
            let fine = bin_kernel(&ground_truth(p, c, None), f);
            let k = &judge.truths()[c];
            let ours = bin_kernel(k, eval_factor(k.half, 128));
            assert_eq!(ours.half, fine.half, "the same pixels");
            assert!(
                (ours.h - fine.h).abs() < 1e-12 * fine.h,
                "the same pixel size"
            );
            fine.v
                .iter()
                .zip(&ours.v)
                .filter(|(a, _)| **a >= 1e-6)
                .map(|(a, b)| ((a - b) / a).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

#[test]
fn pixels_are_the_bins_grids_integrals() {
    // 1,900 bins: 15 bins per pixel, 5 cells of 3 subsamples each, at the bins' own radii.
    let exact = worst_pixel(&profile(1900));
    assert!(exact < 1e-9, "whole bins per cell: {exact:e}");
    // 1,400 bins: 11 bins per pixel, 5 cells of 3 × 3 subsamples 2.2/3 bins apart.
    let quadrature = worst_pixel(&profile(1400));
    assert!(quadrature < 2e-3, "another quadrature: {quadrature:e}");
}

#[test]
fn its_choice_is_as_good_on_the_bins_grid() {
    let p = profile(1400);
    let budget = Budget::default();
    let truths = ground_truths(&p);
    let evals: Vec<ImageEval> = truths.iter().map(|k| ImageEval::new(k, 256, 128)).collect();
    // Mean over channels and signals of the image RMS, on the bins' grid.
    let fine_score = |k: &ShaderKernel| {
        (0..3)
            .map(|c| {
                let e = evals[c].rms(&k.to_separable(c, truths[c].h, truths[c].half));
                (e.iter().map(|(_, x)| x * x).sum::<f64>() / e.len() as f64).sqrt()
            })
            .sum::<f64>()
            / 3.0
    };
    let spec = TapSpec {
        taps: budget.taps,
        ..TapSpec::default()
    };
    let best_fine = candidates(budget.passes)
        .iter()
        .map(|m| {
            let fitted = m.fit_truths(&truths, "test").unwrap();
            fine_score(&ShaderKernel::from_fitted(&fitted, "test", spec).unwrap())
        })
        .fold(f64::INFINITY, f64::min);
    let chosen = &Judge::new(&p).rank(budget, "test").unwrap()[0];
    let ours = fine_score(&chosen.kernel);
    assert!(
        ours <= 1.05 * best_fine,
        "{} scores {ours:.3e} on the bins' grid, the best there {best_fine:.3e}",
        chosen.model
    );
}
