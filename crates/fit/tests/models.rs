//! Kernel models against identities from mathematics (never against this code's own output).

use fit::convolve::{Image, convolve_2d, convolve_separable};
use fit::metrics::kernel_rms;
use fit::{Gaussians, Guided, Kernel2, Profile, ground_truth, preint, svd};

/// The classical dipole (Jensen et al. 2001) for Skin1's red channel (σa = 0.32, σs = 7.4 cm⁻¹,
/// η = 1.3), sampled on `n` bins of width `dr` [cm].
fn dipole(dr: f64, n: usize) -> Profile {
    let (sa, ss, eta): (f64, f64, f64) = (0.32, 7.4, 1.3);
    let st = sa + ss;
    let alpha = ss / st;
    let str_ = (3.0 * sa * st).sqrt();
    let fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    let a = (1.0 + fdr) / (1.0 - fdr);
    let (zr, zv) = (1.0 / st, 1.0 / st * (1.0 + 4.0 / 3.0 * a));
    Profile::from_fn(dr, n, |c, r| {
        let s = [1.0, 0.7, 0.5][c]; // channels of different widths
        let r = r / s;
        let (d_r, d_v) = ((r * r + zr * zr).sqrt(), (r * r + zv * zv).sqrt());
        alpha / (4.0 * std::f64::consts::PI)
            * (zr * (1.0 + str_ * d_r) * (-str_ * d_r).exp() / d_r.powi(3)
                + zv * (1.0 + str_ * d_v) * (-str_ * d_v).exp() / d_v.powi(3))
    })
}

fn kernel() -> Kernel2 {
    ground_truth(&dipole(0.01, 80), 0, None)
}

fn frobenius2(k: &Kernel2) -> f64 {
    k.v.iter().map(|x| x * x).sum()
}

#[test]
fn ground_truth_is_normalized_and_radially_symmetric() {
    let k = kernel();
    assert!((k.v.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    let n = k.half;
    for d in [1, 5, 20] {
        let (a, b, c, e) = (
            k.at(n, n + d),
            k.at(n, n - d),
            k.at(n + d, n),
            k.at(n - d, n),
        );
        assert!(a == b && b == c && c == e, "4-fold symmetry at offset {d}");
    }
}

/// Eckart–Young: ‖K − A_N‖²_F = Σ_{i>N} σᵢ² = ‖K‖²_F − Σ_{i≤N} σᵢ².
#[test]
fn svd_rank_n_error_is_the_discarded_spectrum() {
    let k = kernel();
    let f2 = frobenius2(&k);
    for rank in 1..=6 {
        let (a, e) = svd(&k, rank);
        assert_eq!(e.stop, fit::Stop::Converged, "rank {rank}");
        let err2 = kernel_rms(&k, &a).powi(2) * k.v.len() as f64;
        let discarded = f2 - e.values.iter().map(|l| l * l).sum::<f64>();
        assert!(
            (err2 - discarded).abs() <= 1e-8 * f2,
            "rank {rank}: ‖K−A‖² = {err2:e}, Σσ² discarded = {discarded:e}"
        );
    }
}

#[test]
fn svd_agrees_with_a_dense_eigensolver() {
    let k = ground_truth(&dipole(0.02, 30), 1, None);
    let m = k.side();
    let dense = nalgebra::SymmetricEigen::new(nalgebra::DMatrix::from_row_slice(m, m, &k.v));
    let mut ev: Vec<f64> = dense.eigenvalues.iter().copied().collect();
    ev.sort_by(|a, b| b.abs().total_cmp(&a.abs()));
    let e = fit::top_eigen(&k, 8);
    for (a, b) in e.values.iter().zip(&ev) {
        assert!((a - b).abs() <= 1e-10 * ev[0].abs(), "{a} vs {b}");
    }
}

fn random_image(w: usize, seed: u64, f: impl Fn(usize, usize, f64, f64) -> f64) -> Image {
    // Two deterministic pseudo-random 1D signals.
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let e1: Vec<f64> = (0..w).map(|_| next()).collect();
    let e2: Vec<f64> = (0..w).map(|_| next()).collect();
    let mut img = Image::new(w, w);
    for (y, &b) in e2.iter().enumerate() {
        for (x, &a) in e1.iter().enumerate() {
            img.v[y * w + x] = f(x, y, a, b);
        }
    }
    img
}

/// Pre-integration is exact on additively separable signals E₁(x) + E₂(y) (thesis eq. 5.15).
#[test]
fn preint_is_exact_on_additively_separable_signals() {
    let k = ground_truth(&dipole(0.02, 40), 2, None);
    let a = preint(&k);
    assert!(
        (a.l1() - k.l1()).abs() < 1e-12,
        "energy conserving by construction"
    );
    for (name, img) in [
        ("edge", random_image(96, 1, |x, _, _, _| f64::from(x < 48))),
        ("E1(x)+E2(y)", random_image(96, 2, |_, _, e1, e2| e1 + e2)),
    ] {
        let full = convolve_2d(&img, &k);
        let sep = convolve_separable(&img, &a);
        let scale = full.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = full
            .v
            .iter()
            .zip(&sep.v)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-9 * scale,
            "{name}: max |Δ| = {worst:e} of {scale:e}"
        );
    }
    // And it is not exact on a signal that is not additively separable (the test can fail).
    let img = random_image(96, 3, |_, _, e1, e2| e1 * e2);
    let d = convolve_2d(&img, &k).rms_diff(&convolve_separable(&img, &a));
    assert!(d > 1e-6, "{d}");
}

/// With Γ ≡ 1 and no constraint, the guided optimization is the weighted rank-1 problem with
/// uniform weights: its minimizer is SVD rank-1.
#[test]
fn guided_without_weights_or_constraint_is_svd_rank_1() {
    let k = kernel();
    let g = Guided {
        k: 0.0,
        b: 0.0,
        constrained: false,
        ..Guided::default()
    }
    .fit(&k);
    assert_eq!(g.stop, fit::GuidedStop::Converged);
    let (s, _) = svd(&k, 1);
    let (dg, ds) = (g.kernel.to_dense(), s.to_dense());
    let scale = ds.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst =
        dg.v.iter()
            .zip(&ds.v)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
    assert!(worst <= 1e-6 * scale, "max |Δ| = {worst:e}");
}

#[test]
fn guided_meets_the_l1_constraint() {
    let k = kernel();
    for (kk, b) in [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (1.0, 50.0)] {
        let g = Guided {
            k: kk,
            b,
            ..Guided::default()
        }
        .fit(&k);
        assert!(
            g.constraint_error < 1e-6,
            "k={kk} b={b}: {:e}",
            g.constraint_error
        );
        assert!(
            g.kernel.terms[0]
                .a
                .iter()
                .all(|x| x.is_finite() && *x >= 0.0)
        );
        // The unconstrained SVD rank-1 is the best rank-1 kernel in Frobenius norm; the
        // constrained fit with uniform weights cannot beat it.
        if kk == 0.0 {
            assert!(kernel_rms(&k, &svd(&k, 1).0) <= kernel_rms(&k, &g.kernel));
        }
    }
}

/// Errors fall with N for both multi-pass models, and SVD rank-N beats d'Eon's N Gaussians at
/// equal pass count (Eckart–Young: a sum of N separable Gaussians is a rank-N kernel).
#[test]
fn multi_pass_models_converge_and_svd_wins_at_equal_passes() {
    let k = kernel();
    let deon = Gaussians::fit_up_to(&k, 6);
    let mut prev = (f64::INFINITY, f64::INFINITY);
    for n in 1..=6 {
        let e_svd = kernel_rms(&k, &svd(&k, n).0);
        let g = &deon[n - 1];
        assert!(
            (g.weights.iter().sum::<f64>() - 1.0).abs() < 1e-9,
            "d'Eon L1 constraint, N={n}"
        );
        let e_deon = kernel_rms(&k, &g.to_separable(k.half, k.h));
        assert!(e_svd < prev.0, "SVD not decreasing at N={n}");
        assert!(
            e_deon <= prev.1 * (1.0 + 1e-9),
            "d'Eon not decreasing at N={n}: {e_deon} > {}",
            prev.1
        );
        assert!(e_svd < e_deon, "N={n}: SVD {e_svd:e} ≥ d'Eon {e_deon:e}");
        prev = (e_svd, e_deon);
    }
}

#[test]
fn unusable_profiles_are_refused() {
    let ok = "r_cm,R,G,B,R_se,G_se,B_se\n";
    let row = |r: f64, v: &str| format!("{r},{v},{v},{v},0,0,0\n");
    let cases = [
        (
            "single bin",
            format!("{ok}{}{}", row(0.01, "1"), row(0.03, "1")),
        ),
        (
            "zeros",
            format!(
                "{ok}{}{}{}{}",
                row(0.01, "0"),
                row(0.03, "0"),
                row(0.05, "0"),
                row(0.07, "0")
            ),
        ),
        (
            "nan",
            format!(
                "{ok}{}{}{}{}",
                row(0.01, "NaN"),
                row(0.03, "1"),
                row(0.05, "1"),
                row(0.07, "1")
            ),
        ),
        (
            "negative",
            format!(
                "{ok}{}{}{}{}",
                row(0.01, "1"),
                row(0.03, "-1"),
                row(0.05, "1"),
                row(0.07, "1")
            ),
        ),
        ("header", "r,R,G,B\n0.1,1,1,1\n".to_string()),
    ];
    for (name, csv) in cases {
        let e = Profile::from_csv(&csv, "p.csv");
        assert!(e.is_err(), "{name} accepted");
    }
    let good = format!(
        "{ok}{}{}{}{}",
        row(0.01, "3"),
        row(0.03, "2"),
        row(0.05, "1"),
        row(0.07, "9")
    );
    let p = Profile::from_csv(&good, "p.csv").unwrap();
    assert_eq!(p.len(), 3, "the overflow bin is dropped");
    assert!((p.dr - 0.01 / (0.5 + 1.0 / 6.0)).abs() < 1e-15);
}

/// The manual model's automatic fit minimizes the image-space error: it never ends worse than
/// where it started, and from a deliberately poor start it improves a lot.
#[test]
fn manual_image_space_fit_improves_on_its_start() {
    let k = ground_truth(&dipole(0.02, 40), 0, None);
    let eval = fit::metrics::ImageEval::new(&k, 128, 48);
    let cost = |m: &fit::Manual| {
        eval.rms(&m.separable(k.half, k.h))
            .iter()
            .map(|(_, e)| e * e)
            .sum::<f64>()
    };
    let start = fit::Manual {
        w: 0.9,
        tau_near: (0.5 * k.h).powi(2),
        tau_far: (0.3 * k.h).powi(2).max((4.0 * k.h).powi(2)),
    };
    let fitted = fit::Manual::fit_image_space(&k, start);
    assert!(cost(&fitted) <= cost(&start));
    assert!(
        cost(&fitted) < 0.5 * cost(&start),
        "{} vs {}",
        cost(&fitted),
        cost(&start)
    );
    assert!(fitted.tau_near <= fitted.tau_far && (0.0..=1.0).contains(&fitted.w));
}

/// The solvers work on the quadrant of a mirror-symmetric kernel (an exact reformulation, every
/// eigenvector with λ ≠ 0 is even): breaking the mirror symmetry by one part in 10¹⁴ at a corner
/// sends them down the full-matrix path, and both must give the same eigenpairs and guided fits.
#[test]
fn quadrant_solvers_equal_the_full_matrix_solvers() {
    let k = kernel();
    let mut broken = k.clone();
    let m = k.side();
    // Symmetric (i ↔ j) but no longer mirror-symmetric.
    broken.v[1] *= 1.0 + 1e-14;
    broken.v[m] = broken.v[1];
    let (folded, full) = (fit::top_eigen(&k, 4), fit::top_eigen(&broken, 4));
    for (i, (a, b)) in folded.values.iter().zip(&full.values).enumerate() {
        assert!(
            (a - b).abs() <= 1e-10 * folded.values[0].abs(),
            "λ{i}: {a} vs {b}"
        );
    }
    for (u, v) in folded.vectors.iter().zip(&full.vectors).take(2) {
        let d = u
            .iter()
            .zip(v)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(d < 1e-7, "eigenvector differs by {d:e}");
        assert_eq!(u.len(), m);
        assert!(u.iter().zip(u.iter().rev()).all(|(p, q)| p == q), "even");
    }
    for g in [0.0, 1.0, 2.0] {
        let solver = Guided {
            k: g,
            b: if g == 1.0 { 50.0 } else { 0.0 },
            ..Guided::default()
        };
        let (a, b) = (solver.fit(&k), solver.fit(&broken));
        let (a, b) = (&a.kernel.terms[0].a, &b.kernel.terms[0].a);
        let scale = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let d = a
            .iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(d <= 1e-6 * scale, "guided k = {g}: {d:e} of {scale:e}");
    }
}

/// The guided fit is a KKT point of eq. 5.19–5.20 on the full grid: with G = ∂F/∂a,
/// F(a) = Σ Γᵢⱼ(Kᵢⱼ − aᵢaⱼ)², every aᵢ > 0 has the same Gᵢ = −λ (the multiplier of Σa = √‖K‖₁)
/// and every aᵢ = 0 has Gᵢ ≥ −λ. Checked on a narrow kernel in a wide grid (Ketchup's green and
/// blue: the floor the multiplier spreads over the empty grid is what the iteration converges
/// slowly on), where the solver must also converge in a few dozen passes, not hundreds.
#[test]
fn guided_fit_is_a_kkt_point_and_converges_fast_on_a_wide_grid() {
    let p = Profile::from_fn(0.01, 600, |_, r| (-r / 0.01).exp() / (r + 0.005));
    let k = ground_truth(&p, 0, None);
    let (m, n) = (k.side(), k.half as f64);
    let scaled = |i: usize| (i as f64 - n) / n;
    for (kk, b) in [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (1.55, 50.0)] {
        let guided = Guided {
            k: kk,
            b,
            ..Guided::default()
        };
        let fit = guided.fit(&k);
        assert_eq!(fit.stop, fit::GuidedStop::Converged, "k={kk} b={b}");
        assert!(
            fit.iterations <= 60,
            "k={kk} b={b}: {} passes",
            fit.iterations
        );
        assert_eq!(fit.kernel.terms[0].sign, 1.0);
        let a = &fit.kernel.terms[0].a;
        // Gᵢ = −4 Σⱼ Γᵢⱼ (Kᵢⱼ − aᵢaⱼ) aⱼ (Γ and K symmetric), and its scale 4 Σⱼ Γᵢⱼ |Kᵢⱼ| aⱼ.
        let (mut grad, mut scale) = (vec![0.0; m], 0.0f64);
        for i in 0..m {
            let (mut g, mut sc) = (0.0, 0.0);
            for j in 0..m {
                let w = guided.weight(scaled(j), scaled(i));
                g += -4.0 * w * (k.at(i, j) - a[i] * a[j]) * a[j];
                sc += 4.0 * w * k.at(i, j).abs() * a[j];
            }
            grad[i] = g;
            scale = scale.max(sc);
        }
        // Indices whose weight row vanishes (the centre line when b > 0) do not enter F.
        let live: Vec<usize> = (0..m).filter(|&i| b == 0.0 || i as f64 != n).collect();
        let on: Vec<f64> = live
            .iter()
            .filter(|&&i| a[i] > 0.0)
            .map(|&i| grad[i])
            .collect();
        assert!(
            on.len() > m / 2,
            "k={kk} b={b}: support {} of {m}",
            on.len()
        );
        let lambda = -on.iter().sum::<f64>() / on.len() as f64;
        let spread = on.iter().map(|g| (g + lambda).abs()).fold(0.0, f64::max);
        assert!(
            spread <= 1e-6 * scale,
            "k={kk} b={b}: spread {spread:e} of {scale:e}"
        );
        for &i in live.iter().filter(|&&i| a[i] == 0.0) {
            assert!(grad[i] >= -lambda - 1e-6 * scale, "k={kk} b={b}: index {i}");
        }
        assert!(fit.constraint_error < 1e-12, "k={kk} b={b}");
    }
}
