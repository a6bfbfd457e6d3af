//! The 2D ground-truth kernel R_d(x, y) built from a radial profile by rotation (thesis §6.1).
//!
//! Grid: a square of side m = 2n+1 samples with the profile's own spacing h = dr [cm], the centre
//! at index n, so sample (i, j) sits at (x, y) = ((j−n)h, (i−n)h). Each sample takes Rd at its
//! radius ρ = √(x²+y²) by linear interpolation between the profile's sample radii (constant below
//! the first, zero beyond the last). "Normalized" means the samples of a channel sum to 1.

use rayon::prelude::*;

use crate::profile::Profile;

/// A dense, square, centred 2D kernel (row-major, `side × side`).
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel2 {
    /// Half-width n in samples; side = 2n+1.
    pub half: usize,
    /// Sample spacing h [cm].
    pub h: f64,
    /// Values, row-major.
    pub v: Vec<f64>,
}

impl Kernel2 {
    /// Side m = 2n+1 in samples.
    pub fn side(&self) -> usize {
        2 * self.half + 1
    }

    /// Value at row `i`, column `j`.
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.v[i * self.side() + j]
    }

    /// ‖K‖₁ = Σ|k_ij|.
    pub fn l1(&self) -> f64 {
        self.v.iter().map(|x| x.abs()).sum()
    }

    /// The kernel scaled so its samples sum to 1.
    pub fn normalized(mut self) -> Self {
        let s: f64 = self.v.iter().sum();
        if s != 0.0 {
            self.v.iter_mut().for_each(|x| *x /= s);
        }
        self
    }

    /// The identity kernel: a unit sample at the centre, half-width `half`, spacing `h` [cm].
    pub fn delta(half: usize, h: f64) -> Self {
        let m = 2 * half + 1;
        let mut v = vec![0.0; m * m];
        v[half * m + half] = 1.0;
        Kernel2 { half, h, v }
    }

    /// Whether this is the identity kernel ([`Kernel2::delta`]): the normalized kernel of a
    /// channel that returns no light.
    pub fn is_delta(&self) -> bool {
        let c = self.half * self.side() + self.half;
        self.v
            .iter()
            .enumerate()
            .all(|(i, &x)| x == if i == c { 1.0 } else { 0.0 })
    }

    /// Coordinate of index `i` along an axis [cm].
    pub fn coord(&self, i: usize) -> f64 {
        (i as f64 - self.half as f64) * self.h
    }
}

/// The normalized ground truths of `p`'s three channels ([`ground_truth`] at the profile's
/// length).
pub fn ground_truths(p: &Profile) -> Vec<Kernel2> {
    (0..3).map(|c| ground_truth(p, c, None)).collect()
}

/// The normalized ground truth of channel `c`, half-width `half` samples (default: the profile's
/// length, so the axes reach its last radius).
pub fn ground_truth(p: &Profile, c: usize, half: Option<usize>) -> Kernel2 {
    cell_ground_truth(p, c, p.dr, half.unwrap_or(p.len()), 1)
}

/// Channel `c`'s normalized ground truth on a grid of the caller's choosing: samples `h` [cm]
/// apart, half-width `half`, each the mean of Rd over its h × h cell from `sub` × `sub` midpoint
/// subsamples. Block sums of these cells are the pixel integrals that [`ground_truth`] forms from
/// the profile's own spacing, by another quadrature of the same integrals; with `h` = dr and
/// `sub` = 1 it is [`ground_truth`] at half-width `half`. The samples are computed on one octant
/// (the rotated profile is symmetric in x, in y and under x ↔ y).
pub fn cell_ground_truth(p: &Profile, c: usize, h: f64, half: usize, sub: usize) -> Kernel2 {
    let (n, m, sub) = (half, 2 * half + 1, sub.max(1));
    // Subsample offsets from a cell's centre [cm].
    let offsets: Vec<f64> = (0..sub)
        .map(|k| ((k as f64 + 0.5) / sub as f64 - 0.5) * h)
        .collect();
    let cell = |i: usize, j: usize| {
        let (y, x) = (i as f64 * h, j as f64 * h);
        let mut sum = 0.0;
        for dy in &offsets {
            for dx in &offsets {
                sum += p.at(c, ((x + dx).powi(2) + (y + dy).powi(2)).sqrt());
            }
        }
        sum / (sub * sub) as f64
    };
    // Row i of the octant holds the cells j ≤ i.
    let octant: Vec<Vec<f64>> = (0..=n)
        .into_par_iter()
        .map(|i| (0..=i).map(|j| cell(i, j)).collect())
        .collect();
    let mut v = vec![0.0; m * m];
    for i in 0..=n {
        for j in 0..=n {
            let value = if j <= i { octant[i][j] } else { octant[j][i] };
            for row in [n + i, n - i] {
                v[row * m + n + j] = value;
                v[row * m + n - j] = value;
            }
        }
    }
    // A channel that returns no light (Rd ≡ 0: it does not scatter, as wine's green and blue)
    // spreads nothing: its normalized kernel is the identity; its weight, the channel's total
    // reflectance, is 0.
    if v.iter().all(|&x| x == 0.0) {
        return Kernel2::delta(n, h);
    }
    Kernel2 { half: n, h, v }.normalized()
}

/// The share of a kernel's sum that the eigensolver may leave out (SVD models and the spectrum):
/// it works on the centred square that holds all but this fraction, and eigenvectors are zero
/// beyond it. The metrics of the SVD models move by far less than this (tests/support.rs).
pub const SUPPORT_EPSILON: f64 = 1e-6;

/// A kernel as the solvers see it: when it is mirror-symmetric in x and in y (every kernel built
/// from a radial profile is, exactly), its quadrant x, y ≥ 0 with the multiplicity of each index
/// (1 for the centre line, 2 for the others), so that for even functions a, b
/// Σᵢⱼ aᵢ Kᵢⱼ bⱼ = Σ_pq c_p a_p Q_pq c_q b_q on a quarter of the samples; otherwise the whole
/// kernel with multiplicities 1. A mirror-symmetric kernel can also be cut to its support: the
/// smallest centred square outside which |K| sums to at most ε of Σ|K|.
pub(crate) struct Folded {
    /// Samples per side of `v`.
    pub len: usize,
    /// Row-major `len × len` samples.
    pub v: Vec<f64>,
    /// Multiplicity of each index.
    pub c: Vec<f64>,
    /// Offset of each index from the centre [samples].
    pub offset: Vec<f64>,
    /// The kernel's half-width n.
    pub half: usize,
    mirrored: bool,
}

impl Folded {
    /// The quadrant of a mirror-symmetric kernel, or the kernel itself.
    pub fn new(k: &Kernel2) -> Folded {
        Folded::within(k, 0.0)
    }

    /// As [`Folded::new`], the quadrant cut to the support that holds all but `epsilon` of Σ|K|
    /// (no cut for `epsilon` = 0 or a kernel that is not mirror-symmetric).
    pub fn within(k: &Kernel2, epsilon: f64) -> Folded {
        let (n, m) = (k.half, k.side());
        let row = |i: usize| &k.v[i * m..(i + 1) * m];
        let mirrored = (0..m).all(|i| {
            let r = row(i);
            r == row(m - 1 - i) && (0..n).all(|j| r[j] == r[m - 1 - j])
        });
        if !mirrored {
            return Folded {
                len: m,
                v: k.v.clone(),
                c: vec![1.0; m],
                offset: (0..m).map(|i| i as f64 - n as f64).collect(),
                half: n,
                mirrored,
            };
        }
        let multiplicity = |p: usize| if p == 0 { 1.0 } else { 2.0 };
        let len = if epsilon > 0.0 {
            // Σ|K| per square ring max(|x|, |y|) = d, from the quadrant.
            let mut ring = vec![0.0; n + 1];
            for p in 0..=n {
                for (q, x) in row(n + p)[n..].iter().enumerate() {
                    ring[p.max(q)] += multiplicity(p) * multiplicity(q) * x.abs();
                }
            }
            let total: f64 = ring.iter().sum();
            let mut outside = 0.0;
            let mut len = n + 1;
            while len > 1 && outside + ring[len - 1] <= epsilon * total {
                outside += ring[len - 1];
                len -= 1;
            }
            len
        } else {
            n + 1
        };
        Folded {
            len,
            v: (0..len)
                .flat_map(|p| row(n + p)[n..n + len].iter().copied())
                .collect(),
            c: (0..len).map(multiplicity).collect(),
            offset: (0..len).map(|p| p as f64).collect(),
            half: n,
            mirrored,
        }
    }

    /// A function on this form's indices as the kernel's full 1D function (length 2n+1, zero
    /// beyond the support).
    pub fn unfold(&self, a: &[f64]) -> Vec<f64> {
        if !self.mirrored {
            return a.to_vec();
        }
        let n = self.half;
        (0..2 * n + 1)
            .map(|i| a.get(i.abs_diff(n)).copied().unwrap_or(0.0))
            .collect()
    }

    /// A full 1D function (length 2n+1) on this form's indices.
    pub fn fold(&self, a: &[f64]) -> Vec<f64> {
        if !self.mirrored {
            return a.to_vec();
        }
        a[self.half..self.half + self.len].to_vec()
    }
}
