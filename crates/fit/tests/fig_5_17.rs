//! Thesis Fig. 5.17: the manual model's w "seamlessly" moves the kernel from emphasised far
//! scattering, "which offers a more pronounced falloff", to predominant near scattering, "which
//! preserves sharper features". Checked through the light across a shadow edge, whose exact form
//! for a separable kernel is the tail of its 1D function (eq. 5.15).

use fit::evaluate::ImageSize;
use fit::metrics::{edge_response, edge_width};
use fit::{Kernel2, Manual, WSweep, table_a1};

mod common;

const IMAGE: ImageSize = ImageSize {
    size: 96,
    max_half: 32,
};

/// A Gaussian of standard deviation σ crosses an edge with 10–90 % width 2·Φ⁻¹(0.9)·σ =
/// 2.5631·σ, M(0) = ½ and M(x) + M(−x) = 1.
#[test]
fn the_edge_of_a_gaussian_is_its_cumulative_distribution() {
    let (h, sigma) = (0.01, 0.1);
    let a = Manual {
        w: 1.0,
        tau_near: sigma * sigma,
        tau_far: 1.0,
    }
    .separable(200, h)
    .terms
    .remove(0)
    .a;
    let m = edge_response(&a);
    assert!((m[200] - 0.5).abs() < 1e-12);
    for d in [1, 7, 30, 150] {
        assert!((m[200 + d] + m[200 - d] - 1.0).abs() < 1e-12);
    }
    let width = edge_width(&m, h);
    let expected = 2.0 * 1.281_551_565_545 * sigma;
    // Linear interpolation between samples 0.1 σ apart.
    assert!(
        (width - expected).abs() < 0.002 * expected,
        "{width} vs {expected}"
    );
}

/// Skin1 with Table A.1's τ_n, τ_f: the edge narrows as w grows (near scattering, sharper) and
/// widens as it falls (far scattering, more light into the shadow), in every channel.
#[test]
fn raising_w_moves_skin1_from_far_to_near_scattering() {
    let (p, mfp) = common::skin1_quick();
    let truths: Vec<Kernel2> = fit::ground_truths(&p);
    let w: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    let s = WSweep::measure(&truths, table_a1("skin1").unwrap(), &w, &[0.1, 0.9], IMAGE).unwrap();
    for c in 0..3 {
        for pair in s.edge_width.windows(2) {
            assert!(pair[1][c] < pair[0][c], "channel {c}: {:?}", s.edge_width);
        }
        // More light a mean free path into the shadow with the far-weighted kernel.
        let x = s.truth_edge[c].len() / 2 + (mfp[c] / s.h).round() as usize;
        let (far, near) = (&s.edges[0].1[c], &s.edges[1].1[c]);
        assert!(far[x] > near[x], "channel {c}: {} vs {}", far[x], near[x]);
    }
}

/// A kernel that is itself a manual kernel, a_m(x)a_m(y) with w = 0.3, is matched exactly by the
/// sweep at w = 0.3 (zero image error, the same edge) and by no other w.
#[test]
fn the_sweep_finds_the_w_of_a_manual_kernel() {
    let (half, h) = (60, 0.01);
    let params = [0.02, 0.03, 0.05].map(|s: f64| Manual {
        w: 0.3,
        tau_near: (0.2 * s).powi(2),
        tau_far: s * s,
    });
    let truths: Vec<Kernel2> = params
        .iter()
        .map(|m| {
            let k = m.separable(half, h).to_dense();
            Kernel2 { half, h, v: k.v }
        })
        .collect();
    let w: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    let s = WSweep::measure(&truths, params, &w, &[0.3], IMAGE).unwrap();
    assert_eq!(s.best_w(), [0.3; 3]);
    let at = w.iter().position(|&x| x == 0.3).unwrap();
    for c in 0..3 {
        assert!(s.image_rms[at][c] < 1e-12, "{:?}", s.image_rms[at]);
        assert!((s.edge_width[at][c] - s.truth_edge_width[c]).abs() < 1e-12);
        assert!(
            s.image_rms
                .iter()
                .enumerate()
                .all(|(i, e)| i == at || e[c] > 1e-6)
        );
    }
}
