//! Pre-integration (thesis §5.2, eq. 5.17–5.18): a_p(x) = ∫ R_d(x, y) dy, a = a_p / √‖R_d‖₁.
//!
//! On the grid a_p is the row sum of the discrete 2D kernel, so for any additively separable
//! signal E(x, y) = E₁(x) + E₂(y) the separable convolution with a equals the full 2D convolution
//! with R_d exactly (up to rounding), and ‖a aᵀ‖₁ = ‖R_d‖₁ by construction.
//! For shader taps at arbitrary offsets, [`projection`] integrates the continuous profile
//! (an Abel projection) instead.

use crate::kernel2d::Kernel2;
use crate::profile::Profile;
use crate::separable::Separable;

/// The rank-1 pre-integrated kernel of a discrete ground truth.
pub fn preint(k: &Kernel2) -> Separable {
    let m = k.side();
    // Column sums, accumulated row by row (memory order; the same order of terms as per column).
    let mut a_p = vec![0.0; m];
    for row in k.v.chunks(m) {
        a_p.iter_mut().zip(row).for_each(|(a, x)| *a += x);
    }
    let norm = k.l1().sqrt();
    Separable::rank1(k.h, a_p.into_iter().map(|x| x / norm).collect())
}

/// Pre-integration from the continuous profile: on a grid of half-width `half` and spacing `h`
/// [cm], sample i holds ∫ P(x) dx over its cell (4-point Gauss–Legendre per cell on the Abel
/// projection [`projection`]), scaled so the 2D kernel a(x)a(y) sums to 1. Used for shader taps,
/// where cell integrals of the continuous projection are more accurate near r = 0 than row sums of
/// the sampled 2D kernel.
pub fn preint_continuous(p: &Profile, c: usize, half: usize, h: f64) -> Separable {
    let (x, w) = (
        [
            -0.861_136_311_594_053,
            -0.339_981_043_584_856,
            0.339_981_043_584_856,
            0.861_136_311_594_053,
        ],
        [
            0.347_854_845_137_454,
            0.652_145_154_862_546,
            0.652_145_154_862_546,
            0.347_854_845_137_454,
        ],
    );
    let cell = |i: usize| -> f64 {
        let centre = i as f64 * h;
        x.iter()
            .zip(&w)
            .map(|(t, wt)| 0.5 * h * wt * projection(p, c, centre + 0.5 * h * t))
            .sum()
    };
    let right: Vec<f64> = (0..=half).map(cell).collect();
    let a: Vec<f64> = (0..2 * half + 1)
        .map(|i| right[(i as isize - half as isize).unsigned_abs()])
        .collect();
    let total: f64 = a.iter().sum();
    Separable::rank1(h, a.into_iter().map(|v| v / total).collect())
}

/// The Abel projection P(x) = ∫ Rd(√(x²+y²)) dy of channel `c` [cm⁻¹] at |x| [cm], by the
/// substitution y = √(r² − x²) over each linear segment of the interpolated profile, which removes
/// the 1/√(r²−x²) singularity: P(x) = 2 ∫_{|x|}^{∞} Rd(r) r / √(r² − x²) dr, evaluated with
/// Gauss–Legendre in u = √(r² − x²) on each segment.
pub fn projection(p: &Profile, c: usize, x: f64) -> f64 {
    let x = x.abs();
    let r_end = *p.r.last().expect("validated");
    if x >= r_end {
        return 0.0;
    }
    // Breakpoints of the piecewise-linear profile beyond |x|, mapped to u = √(r² − x²).
    let mut rs: Vec<f64> = vec![x];
    rs.extend(p.r.iter().copied().filter(|&r| r > x));
    let (nodes, weights) = gauss_legendre_8();
    let mut total = 0.0;
    for w in rs.windows(2) {
        let (u0, u1) = (
            (w[0] * w[0] - x * x).max(0.0).sqrt(),
            (w[1] * w[1] - x * x).sqrt(),
        );
        let half = 0.5 * (u1 - u0);
        for (t, wt) in nodes.iter().zip(weights.iter()) {
            let u = u0 + half * (t + 1.0);
            total += wt * half * p.at(c, (u * u + x * x).sqrt());
        }
    }
    2.0 * total
}

fn gauss_legendre_8() -> ([f64; 8], [f64; 8]) {
    let x = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_2,
    ];
    let w = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    (
        [-x[3], -x[2], -x[1], -x[0], x[0], x[1], x[2], x[3]],
        [w[3], w[2], w[1], w[0], w[0], w[1], w[2], w[3]],
    )
}
