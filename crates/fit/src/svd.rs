//! SVD rank-N (thesis §5.1): the best rank-N approximation of the symmetric 2D kernel in the
//! Frobenius norm (Eckart–Young), A_N = Σ_{i≤N} λᵢ uᵢ uᵢᵀ with the N eigenvalues of largest |λ|;
//! the singular values are σᵢ = |λᵢ| and the 1D functions aᵢ = uᵢ √σᵢ with sign(λᵢ).
//!
//! Eigenpairs come from block subspace iteration with Rayleigh–Ritz (a few dense matrix products of
//! the m×m kernel, parallel over rows), which converges fast because the spectra of these kernels
//! decay quickly (thesis Fig. 5.1). Each eigenvector's sign is chosen so its sum is non-negative.
//!
//! A kernel that is mirror-symmetric in x and y (every rotated profile) maps every odd function to
//! zero (each row is even), so its eigenvectors with λ ≠ 0 are even and are those of the quadrant
//! Q (n+1 samples per side) in symmetric form M_pq = √c_p Q_pq √c_q, c = 1 on the centre line and
//! 2 elsewhere, with u_{n±p} = v_p/√c_p: the same eigenpairs from a quarter of the samples.

use nalgebra::{DMatrix, SymmetricEigen};
use rayon::prelude::*;

use crate::kernel2d::{Folded, Kernel2, SUPPORT_EPSILON};
use crate::separable::{Separable, Term};

/// Why the eigensolver stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Every requested Ritz pair's residual ‖Ku − λu‖ fell below 10⁻¹⁰·|λ₁|.
    Converged,
    /// The iteration limit was reached first.
    MaxIterations,
}

/// Eigenpairs of a symmetric kernel, sorted by |λ| descending.
#[derive(Clone, Debug)]
pub struct Eigen {
    /// Eigenvalues λᵢ, signed.
    pub values: Vec<f64>,
    /// Unit eigenvectors, each of length `side`.
    pub vectors: Vec<Vec<f64>>,
    /// Subspace iterations run.
    pub iterations: usize,
    /// Why the iteration stopped.
    pub stop: Stop,
}

/// The `count` eigenpairs of largest |λ| of the symmetric matrix `k` (the kernel's samples as an
/// m×m matrix), converged to residuals ‖Ku − λu‖ ≤ 10⁻¹⁰·|λ₁| (at most 1000 iterations), on the
/// support that holds all but [`SUPPORT_EPSILON`] of Σ|K| (eigenvectors are zero beyond it; by
/// Weyl's inequality each eigenvalue moves by at most the Frobenius norm of what is left out).
pub fn top_eigen(k: &Kernel2, count: usize) -> Eigen {
    top_eigen_to(k, count, 1e-10, 1000, SUPPORT_EPSILON)
}

/// As [`top_eigen`] with a chosen relative residual, iteration cap and support (`epsilon` = 0:
/// the whole kernel): eigenvalues converge with the square of the residual, so plots of a
/// spectrum need far less than eigenvectors do.
pub fn top_eigen_to(
    k: &Kernel2,
    count: usize,
    relative_residual: f64,
    max_iterations: usize,
    epsilon: f64,
) -> Eigen {
    let f = Folded::within(k, epsilon);
    let m = f.len;
    let root: Vec<f64> = f.c.iter().map(|c| c.sqrt()).collect();
    let matrix: Vec<f64> =
        f.v.iter()
            .enumerate()
            .map(|(i, x)| root[i / m] * x * root[i % m])
            .collect();
    let count = count.min(m);
    let p = (count + 6).min(m);
    // Deterministic start: smooth, linearly independent functions of the coordinate.
    let mut q = DMatrix::<f64>::from_fn(m, p, |i, j| {
        let x = (i as f64 + 0.5) / m as f64;
        ((j + 1) as f64 * std::f64::consts::PI * x).cos() + 1.0 / (1.0 + j as f64 + x)
    });
    orthonormalize(&mut q);
    let scale = matrix
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()))
        .max(f64::MIN_POSITIVE);
    let (mut values, mut vectors) = (Vec::new(), DMatrix::zeros(m, count));
    let mut stop = Stop::MaxIterations;
    let mut iterations = 0;
    for it in 1..=max_iterations {
        iterations = it;
        let kq = multiply(&matrix, m, &q);
        // Rayleigh–Ritz on the subspace.
        let h = q.transpose() * &kq;
        let h = (&h + h.transpose()) * 0.5;
        let eig = SymmetricEigen::new(h);
        let mut order: Vec<usize> = (0..p).collect();
        order.sort_by(|&a, &b| {
            eig.eigenvalues[b]
                .abs()
                .total_cmp(&eig.eigenvalues[a].abs())
        });
        let ritz = &q * &eig.eigenvectors;
        let k_ritz = &kq * &eig.eigenvectors;
        values = order[..count].iter().map(|&o| eig.eigenvalues[o]).collect();
        let lead = values.first().map(|v: &f64| v.abs()).unwrap_or(scale);
        let mut worst: f64 = 0.0;
        for (c, &o) in order[..count].iter().enumerate() {
            let u = ritz.column(o);
            let r = k_ritz.column(o) - u * eig.eigenvalues[o];
            worst = worst.max(r.norm());
            vectors.set_column(c, &u);
        }
        if worst <= relative_residual * lead {
            stop = Stop::Converged;
            break;
        }
        // Next subspace: K·(Ritz vectors), ordered, orthonormalized.
        q = DMatrix::from_fn(m, p, |i, j| k_ritz[(i, order[j])]);
        orthonormalize(&mut q);
    }
    let vectors = (0..count)
        .map(|c| {
            let v: Vec<f64> = vectors
                .column(c)
                .iter()
                .zip(&root)
                .map(|(x, r)| x / r)
                .collect();
            let mut u = f.unfold(&v);
            if u.iter().sum::<f64>() < 0.0 {
                u.iter_mut().for_each(|x| *x = -*x);
            }
            u
        })
        .collect();
    Eigen {
        values,
        vectors,
        iterations,
        stop,
    }
}

/// The rank-N SVD approximation: terms sᵢ aᵢ aᵢᵀ with aᵢ = uᵢ√|λᵢ|, sᵢ = sign λᵢ.
pub fn svd(k: &Kernel2, rank: usize) -> (Separable, Eigen) {
    let e = top_eigen(k, rank);
    let terms = e
        .values
        .iter()
        .zip(&e.vectors)
        .map(|(&l, u)| Term {
            sign: if l < 0.0 { -1.0 } else { 1.0 },
            a: u.iter().map(|x| x * l.abs().sqrt()).collect(),
        })
        .collect();
    (Separable { h: k.h, terms }, e)
}

/// K·Q for a dense matrix K (m×m, row-major) and Q (m×p), parallel over rows of K.
fn multiply(k: &[f64], m: usize, q: &DMatrix<f64>) -> DMatrix<f64> {
    let p = q.ncols();
    // Column-major Q: gather columns once for contiguous dot products.
    let cols: Vec<&[f64]> = (0..p).map(|j| &q.as_slice()[j * m..(j + 1) * m]).collect();
    let rows: Vec<Vec<f64>> = (0..m)
        .into_par_iter()
        .map(|i| {
            let row = &k[i * m..(i + 1) * m];
            cols.iter()
                .map(|c| row.iter().zip(c.iter()).map(|(a, b)| a * b).sum())
                .collect()
        })
        .collect();
    DMatrix::from_fn(m, p, |i, j| rows[i][j])
}

/// Modified Gram–Schmidt (twice, for stability) on the columns.
fn orthonormalize(q: &mut DMatrix<f64>) {
    for _ in 0..2 {
        for j in 0..q.ncols() {
            for i in 0..j {
                let d = q.column(i).dot(&q.column(j));
                let ci = q.column(i).clone_owned();
                let mut cj = q.column_mut(j);
                cj -= ci * d;
            }
            let n = q.column(j).norm();
            if n > 0.0 {
                q.column_mut(j).scale_mut(1.0 / n);
            }
        }
    }
}
