//! Error metrics (thesis §5.1, §6.2): kernel-space RMS, L1 error, and image-space RMS of test
//! signal convolutions against the full 2D convolution with the ground truth.
//!
//! Image-space evaluation runs on a coarser grid when the kernel is large: both the ground truth
//! and each model are block-summed by an odd factor f around the centre, which keeps every
//! separable model separable (a block sum of a(x)a(y) is A(X)A(Y)) and every L1 norm unchanged.
//! Models are applied scaled to conserve energy, Σ A = Σ R_d, as SSSS normalizes its weights
//! before use (the same as eq. 5.12's ‖A‖₁ = ‖R_d‖₁ for non-negative kernels; for kernels with
//! negative lobes, e.g. SVD rank ≥ 2, the sum is what conserves energy).

use rayon::prelude::*;

use crate::convolve::{Image, Spectrum, convolve_separable};
use crate::kernel2d::{Folded, Kernel2};
use crate::separable::{Separable, Term};
use crate::signals::Signal;

/// Kernel-space RMS: √(mean over the grid of (K − A)²), row by row without forming A.
pub fn kernel_rms(k: &Kernel2, a: &Separable) -> f64 {
    let m = k.side();
    let s: f64 =
        k.v.par_chunks(m)
            .enumerate()
            .map(|(i, row)| {
                let scaled: Vec<(f64, &[f64])> = a
                    .terms
                    .iter()
                    .map(|t| (t.sign * t.a[i], &t.a[..]))
                    .collect();
                row.iter()
                    .enumerate()
                    .map(|(j, x)| (x - scaled.iter().map(|(s, a)| s * a[j]).sum::<f64>()).powi(2))
                    .sum::<f64>()
            })
            .sum();
    (s / k.v.len() as f64).sqrt()
}

/// |‖A‖₁ − ‖K‖₁| / ‖K‖₁, before any renormalization.
pub fn l1_error(k: &Kernel2, a: &Separable) -> f64 {
    let kl = k.l1();
    (a.l1() - kl).abs() / kl
}

/// Block-summing by an odd factor `f` about the centre.
pub fn bin_kernel(k: &Kernel2, f: usize) -> Kernel2 {
    let (half, map) = bin_map(k.half, f);
    let m = 2 * half + 1;
    let mut v = vec![0.0; m * m];
    let side = k.side();
    for i in 0..side {
        for j in 0..side {
            v[map[i] * m + map[j]] += k.v[i * side + j];
        }
    }
    Kernel2 {
        half,
        h: k.h * f as f64,
        v,
    }
}

/// Block-summing every term's 1D function by an odd factor `f` about the centre, as
/// [`bin_kernel`] does the 2D kernel (a block sum of a(x)a(y) is A(X)A(Y)).
pub fn bin_separable(s: &Separable, f: usize) -> Separable {
    let (half, map) = bin_map(s.half(), f);
    let terms = s
        .terms
        .iter()
        .map(|t| {
            let mut a = vec![0.0; 2 * half + 1];
            for (i, x) in t.a.iter().enumerate() {
                a[map[i]] += x;
            }
            Term { sign: t.sign, a }
        })
        .collect();
    Separable {
        h: s.h * f as f64,
        terms,
    }
}

/// New half-width and the coarse index of every fine index for odd factor f.
fn bin_map(half: usize, f: usize) -> (usize, Vec<usize>) {
    let f = f.max(1) | 1;
    let r = (f / 2) as isize;
    let new_half = (half as isize + r) / f as isize;
    let map = (0..2 * half + 1)
        .map(|i| {
            let d = i as isize - half as isize;
            ((d + r).div_euclid(f as isize) + new_half) as usize
        })
        .collect();
    (new_half as usize, map)
}

/// The binning factor that brings a kernel of half-width `half` to at most `max_half`.
pub fn eval_factor(half: usize, max_half: usize) -> usize {
    let f = half.div_ceil(max_half.max(1)).max(1);
    f | 1
}

/// Image-space evaluation of models on the test signals at a common coarse grid. Each signal's
/// padded transform is computed once and shared by every model (one inverse transform per model
/// and signal).
pub struct ImageEval {
    /// Odd factor by which kernels are block-summed onto the evaluation grid.
    pub factor: usize,
    /// Side of the square test signals [px].
    pub size: usize,
    ground_truth: Kernel2,
    /// (signal, its image, its transform padded by the binned kernel's half-width, the ground
    /// truth's convolution).
    references: Vec<(Signal, Image, Spectrum, Image)>,
}

impl ImageEval {
    /// Prepares signals of `size` pixels and their ground-truth convolutions; kernels are binned
    /// to half-width ≤ `max_half`.
    pub fn new(k: &Kernel2, size: usize, max_half: usize) -> Self {
        Self::with_factor(k, size, eval_factor(k.half, max_half))
    }

    /// As [`ImageEval::new`], kernels block-summed by a given odd `factor` (one pixel is `factor`
    /// samples).
    pub fn with_factor(k: &Kernel2, size: usize, factor: usize) -> Self {
        let factor = factor.max(1) | 1;
        let ground_truth = bin_kernel(k, factor);
        let references = Signal::ALL
            .iter()
            .map(|&s| {
                let e = s.image(size);
                let spectrum = Spectrum::new(&e, ground_truth.half);
                let m = spectrum.convolve_dense(&ground_truth);
                (s, e, spectrum, m)
            })
            .collect();
        ImageEval {
            factor,
            size,
            ground_truth,
            references,
        }
    }

    /// The model binned like the ground truth and scaled to its sum (energy conservation).
    fn binned(&self, model: &Separable) -> Separable {
        bin_separable(model, self.factor).rescaled_to_sum(self.ground_truth.v.iter().sum())
    }

    /// E * A through the signal's shared transform when A fits in its padding.
    fn apply(e: &Image, spectrum: &Spectrum, a: &Separable) -> Image {
        if a.half() <= spectrum.pad() {
            spectrum.convolve_separable(a)
        } else {
            convolve_separable(e, a)
        }
    }

    /// Image RMS per signal of a model (renormalized to the ground truth's L1 norm). Signals go
    /// through the inverse transform in pairs ([`Spectrum::convolve_separable_pair`]).
    pub fn rms(&self, model: &Separable) -> Vec<(Signal, f64)> {
        let binned = self.binned(model);
        self.references
            .chunks(2)
            .flat_map(|pair| match pair {
                [(s1, _, sp1, m1), (s2, _, sp2, m2)] if binned.half() <= sp1.pad() => {
                    let (c1, c2) = sp1.convolve_separable_pair(sp2, &binned);
                    vec![(*s1, c1.rms_diff(m1)), (*s2, c2.rms_diff(m2))]
                }
                _ => pair
                    .iter()
                    .map(|(s, e, spectrum, m)| (*s, Self::apply(e, spectrum, &binned).rms_diff(m)))
                    .collect(),
            })
            .collect()
    }

    /// Image RMS per signal of a dense (non-separable) kernel on the ground truth's grid, binned
    /// like the ground truth and convolved in 2D (a radial kernel as engines apply it).
    pub fn rms_dense(&self, k: &Kernel2) -> Vec<(Signal, f64)> {
        let binned = bin_kernel(k, self.factor);
        self.references
            .iter()
            .map(|(s, e, spectrum, m)| {
                let c = if binned.half <= spectrum.pad() {
                    spectrum.convolve_dense(&binned)
                } else {
                    crate::convolve::convolve_2d(e, &binned)
                };
                (*s, c.rms_diff(m))
            })
            .collect()
    }

    /// The convolution of a signal with a model and the ground-truth reference (for plots).
    pub fn images(&self, signal: Signal, model: &Separable) -> (Image, Image, Image) {
        let binned = self.binned(model);
        let (_, e, spectrum, m) = self
            .references
            .iter()
            .find(|(s, ..)| *s == signal)
            .expect("every signal is prepared");
        (e.clone(), m.clone(), Self::apply(e, spectrum, &binned))
    }
}

/// The kernel-space metrics of many models against one ground truth. On a mirror-symmetric truth
/// (every rotated profile) and a model whose 1D functions are even, the sums run over the quadrant
/// with each sample's multiplicity: a quarter of the work, the same sums up to rounding.
pub struct KernelMetrics {
    folded: Folded,
    /// ‖K‖₁.
    l1: f64,
    /// Samples on the grid.
    count: f64,
}

impl KernelMetrics {
    /// Prepares the metrics against the ground truth `k`.
    pub fn new(k: &Kernel2) -> Self {
        KernelMetrics {
            folded: Folded::new(k),
            l1: k.l1(),
            count: k.v.len() as f64,
        }
    }

    /// Σ over the grid of g(K, A) for a model with even functions, on the quadrant; `None` when
    /// the model is not even (or the grids differ) and the full sum is needed.
    fn folded_sum(&self, a: &Separable, g: impl Fn(f64, f64) -> f64 + Sync) -> Option<f64> {
        let f = &self.folded;
        let even = a
            .terms
            .iter()
            .all(|t| t.a.len() == 2 * f.half + 1 && t.a.iter().eq(t.a.iter().rev()));
        if !even {
            return None;
        }
        let terms: Vec<(f64, Vec<f64>)> = a.terms.iter().map(|t| (t.sign, f.fold(&t.a))).collect();
        let len = f.len;
        Some(
            f.v.par_chunks(len)
                .enumerate()
                .map(|(p, row)| {
                    let scaled: Vec<(f64, &[f64])> =
                        terms.iter().map(|(s, a)| (s * a[p], &a[..])).collect();
                    f.c[p]
                        * row
                            .iter()
                            .enumerate()
                            .map(|(q, x)| {
                                f.c[q] * g(*x, scaled.iter().map(|(s, a)| s * a[q]).sum::<f64>())
                            })
                            .sum::<f64>()
                })
                .sum(),
        )
    }

    /// Kernel-space RMS, as [`kernel_rms`].
    pub fn rms(&self, k: &Kernel2, a: &Separable) -> f64 {
        match self.folded_sum(a, |x, y| (x - y).powi(2)) {
            Some(s) => (s / self.count).sqrt(),
            None => kernel_rms(k, a),
        }
    }

    /// ‖A‖₁ of the model on the grid.
    fn model_l1(&self, a: &Separable) -> f64 {
        if a.terms.len() == 1 {
            return a.l1();
        }
        self.folded_sum(a, |_, y| y.abs()).unwrap_or_else(|| a.l1())
    }

    /// Kernel-space RMS after scaling the model to ‖A‖₁ = ‖K‖₁ (eq. 5.12).
    pub fn rms_normalized(&self, k: &Kernel2, a: &Separable) -> f64 {
        let s = (self.l1 / self.model_l1(a)).sqrt();
        let mut scaled = a.clone();
        for t in &mut scaled.terms {
            t.a.iter_mut().for_each(|x| *x *= s);
        }
        self.rms(k, &scaled)
    }

    /// |‖A‖₁ − ‖K‖₁| / ‖K‖₁, as [`l1_error`].
    pub fn l1_error(&self, a: &Separable) -> f64 {
        (self.model_l1(a) - self.l1).abs() / self.l1
    }
}

/// The exitance across a shadow edge of a rank-1 kernel a(x)a(y) (thesis §5.2): the irradiance
/// E = 1 for x < 0 and 0 beyond, so M(x) = ∫_{−∞}^{0} a(x − x′) dx′ = ∫_x^∞ a(u) du with a
/// normalized to Σa = 1 (the y pass sums to 1). Sample i holds Σ_{j>i} a_j + a_i/2: each sample is
/// its cell's mass, the cell through x_i counted half, so M(x) + M(−x) = 1 and M(0) = ½.
///
/// For the pre-integrated a_p this is the ground truth's own edge exactly (eq. 5.15; the draft's
/// eq. 5.17 writes a_p(x) = ∫R_d(x, y) dx, but a function of x integrates out y: ∫R_d(x, y) dy).
/// Dimensionless, per unit irradiance; one value per sample of `a`.
pub fn edge_response(a: &[f64]) -> Vec<f64> {
    let total: f64 = a.iter().sum();
    let mut m = vec![0.0; a.len()];
    let mut beyond = 0.0;
    for (i, x) in a.iter().enumerate().rev() {
        let x = x / total;
        m[i] = beyond + 0.5 * x;
        beyond += x;
    }
    m
}

/// The 10–90 % width [cm] of an [`edge_response`] `m` sampled every `h` cm and centred (length
/// 2n+1): twice the distance into the shadow where M falls to 0.1 (M is point-symmetric about
/// the edge), by linear interpolation between samples.
pub fn edge_width(m: &[f64], h: f64) -> f64 {
    let n = m.len() / 2;
    let side = &m[n..];
    match side.iter().position(|&v| v <= 0.1) {
        // Less than 10 % crosses the edge itself: a kernel narrower than a sample.
        Some(0) => 0.0,
        // The grid ends before M falls to 0.1: wider than the grid can tell.
        None => f64::INFINITY,
        Some(i) => {
            let (m0, m1) = (side[i - 1], side[i]);
            2.0 * h * ((i - 1) as f64 + (m0 - 0.1) / (m0 - m1))
        }
    }
}

/// Size of the image-space evaluation: test signals of `size` pixels, kernels binned to a
/// half-width of at most `max_half` pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    /// Side of the square test signals [px].
    pub size: usize,
    /// Largest half-width of the binned kernels [px].
    pub max_half: usize,
}

impl Default for ImageSize {
    fn default() -> Self {
        ImageSize {
            size: 256,
            max_half: 128,
        }
    }
}
