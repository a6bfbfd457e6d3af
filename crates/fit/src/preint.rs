//! Pre-integration (thesis §5.2, eq. 5.17–5.18): a_p(x) = ∫ R_d(x, y) dy, a = a_p / √‖R_d‖₁.
//!
//! On the grid a_p is the row sum of the discrete 2D kernel, so for any additively separable
//! signal E(x, y) = E₁(x) + E₂(y) the separable convolution with a equals the full 2D convolution
//! with R_d exactly (up to rounding), and ‖a aᵀ‖₁ = ‖R_d‖₁ by construction.

use crate::kernel2d::Kernel2;
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
