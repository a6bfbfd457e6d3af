//! CPU reference convolutions with clamp-to-edge boundaries (an edge stays additively separable up
//! to the image border), by FFT: the image is padded by the kernel's half-width with its edge
//! values, so the circular convolution of the padded image equals the clamp-to-edge linear one in
//! the image's own pixels (exact up to rounding).
//!
//! [`Spectrum`] keeps one padded image's 2D transform so that many kernels are applied to it for
//! the price of one inverse transform each: a dense kernel by its 2D transform, a separable one
//! Σ sᵢ aᵢ(x) aᵢ(y) by the outer products of its 1D transforms (the transform of aᵢ ⊗ aᵢ is
//! âᵢ(u) âᵢ(v)), never forming the 2D kernel.

use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::kernel2d::Kernel2;
use crate::separable::Separable;

/// A single-channel float image, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width [px].
    pub width: usize,
    /// Height [px].
    pub height: usize,
    /// Pixel values, row-major, `width × height`.
    pub v: Vec<f64>,
}

impl Image {
    /// An all-zero image.
    pub fn new(width: usize, height: usize) -> Self {
        Image {
            width,
            height,
            v: vec![0.0; width * height],
        }
    }

    /// The value at column `x`, row `y`.
    pub fn at(&self, x: usize, y: usize) -> f64 {
        self.v[y * self.width + x]
    }

    /// Clamp-to-edge sample at signed coordinates.
    fn clamped(&self, x: isize, y: isize) -> f64 {
        let x = x.clamp(0, self.width as isize - 1) as usize;
        let y = y.clamp(0, self.height as isize - 1) as usize;
        self.at(x, y)
    }

    /// Root-mean-square difference to another image of the same size.
    pub fn rms_diff(&self, other: &Image) -> f64 {
        let s: f64 = self
            .v
            .iter()
            .zip(&other.v)
            .map(|(a, b)| (a - b).powi(2))
            .sum();
        (s / self.v.len() as f64).sqrt()
    }
}

/// The 2D transform of an image padded (clamp-to-edge) by `pad` pixels on every side, ready to be
/// convolved with any kernel of half-width ≤ `pad`.
pub struct Spectrum {
    width: usize,
    height: usize,
    pad: usize,
    /// Padded width and height.
    pw: usize,
    ph: usize,
    data: Vec<Complex<f64>>,
    plans: Plans,
}

/// A 1D transform.
type Spectrum1 = Vec<Complex<f64>>;

/// Forward and inverse 1D plans along both axes of a padded image.
struct Plans {
    fx: Arc<dyn Fft<f64>>,
    fy: Arc<dyn Fft<f64>>,
    ix: Arc<dyn Fft<f64>>,
    iy: Arc<dyn Fft<f64>>,
}

impl Spectrum {
    /// Pads `e` by `pad` pixels (clamp-to-edge) and transforms it.
    pub fn new(e: &Image, pad: usize) -> Self {
        let (pw, ph) = (fast_len(e.width + 2 * pad), fast_len(e.height + 2 * pad));
        let mut planner = FftPlanner::<f64>::new();
        let plans = Plans {
            fx: planner.plan_fft_forward(pw),
            fy: planner.plan_fft_forward(ph),
            ix: planner.plan_fft_inverse(pw),
            iy: planner.plan_fft_inverse(ph),
        };
        let n = pad as isize;
        let data: Vec<Complex<f64>> = (0..pw * ph)
            .map(|p| Complex::new(e.clamped((p % pw) as isize - n, (p / pw) as isize - n), 0.0))
            .collect();
        let data = forward(data, pw, ph, &*plans.fx, &*plans.fy);
        Spectrum {
            width: e.width,
            height: e.height,
            pad,
            pw,
            ph,
            data,
            plans,
        }
    }

    /// The half-width of the largest kernel this spectrum can be convolved with.
    pub fn pad(&self) -> usize {
        self.pad
    }

    /// (E * K)(x, y) = Σ E(x−i, y−j) K(i, j) for a dense kernel with `k.half ≤ pad`.
    pub fn convolve_dense(&self, k: &Kernel2) -> Image {
        assert!(k.half <= self.pad, "kernel wider than the padding");
        let (pw, ph, n) = (self.pw, self.ph, k.half as isize);
        // The kernel wrapped around the origin.
        let mut b = vec![Complex::new(0.0, 0.0); pw * ph];
        let m = k.side();
        for i in 0..m {
            let y = (i as isize - n).rem_euclid(ph as isize) as usize;
            for j in 0..m {
                let x = (j as isize - n).rem_euclid(pw as isize) as usize;
                b[y * pw + x] += Complex::new(k.at(i, j), 0.0);
            }
        }
        let mut b = forward(b, pw, ph, &*self.plans.fx, &*self.plans.fy);
        b.iter_mut().zip(&self.data).for_each(|(x, y)| *x *= y);
        self.pixels(&self.inverse(b), |z| z.re)
    }

    /// Σᵢ sᵢ·((E * aᵢ)ₓ * aᵢ)ᵧ for a separable kernel with half-width ≤ `pad`: the same as the
    /// horizontal-then-vertical clamp-to-edge passes, through the 1D transforms of each aᵢ.
    pub fn convolve_separable(&self, s: &Separable) -> Image {
        let b = self.separable_product(s, self.data.clone());
        self.pixels(&self.inverse(b), |z| z.re)
    }

    /// [`Spectrum::convolve_separable`] of this image and of `other` (padded alike) with one
    /// inverse transform: both results are real, so the transform of E₁ + iE₂ carries E₁ * A in
    /// its real part and E₂ * A in its imaginary part.
    pub fn convolve_separable_pair(&self, other: &Spectrum, s: &Separable) -> (Image, Image) {
        assert!(
            (other.pw, other.ph, other.pad) == (self.pw, self.ph, self.pad)
                && (other.width, other.height) == (self.width, self.height),
            "a pair of images padded alike"
        );
        let i = Complex::new(0.0, 1.0);
        let both = self.data.iter().zip(&other.data).map(|(a, b)| a + i * b);
        let b = self.separable_product(s, both.collect());
        let rows = self.inverse(b);
        (self.pixels(&rows, |z| z.re), self.pixels(&rows, |z| z.im))
    }

    /// `data` (a spectrum stored as [`forward`] leaves it) times the transform of a separable
    /// kernel with half-width ≤ `pad`.
    fn separable_product(&self, s: &Separable, mut b: Vec<Complex<f64>>) -> Vec<Complex<f64>> {
        assert!(s.half() <= self.pad, "kernel wider than the padding");
        let (pw, ph) = (self.pw, self.ph);
        let transform = |a: &[f64], len: usize, plan: &dyn Fft<f64>| {
            let n = (a.len() / 2) as isize;
            let mut t = vec![Complex::new(0.0, 0.0); len];
            for (j, w) in a.iter().enumerate() {
                t[(j as isize - n).rem_euclid(len as isize) as usize] += Complex::new(*w, 0.0);
            }
            plan.process(&mut t);
            t
        };
        // (sign, transform along x, transform along y) of each term.
        let terms: Vec<(f64, Spectrum1, Spectrum1)> = s
            .terms
            .iter()
            .map(|t| {
                (
                    t.sign,
                    transform(&t.a, pw, &*self.plans.fx),
                    transform(&t.a, ph, &*self.plans.fy),
                )
            })
            .collect();
        // The kernel's transform along this row: Σᵢ sᵢ âᵢ(u) âᵢ(v) over v (the spectrum is
        // stored transposed: one x frequency u per row, over y frequencies v).
        let mut k = vec![Complex::new(0.0, 0.0); ph];
        for (u, column) in b.chunks_mut(ph).enumerate() {
            k.fill(Complex::new(0.0, 0.0));
            for (sign, ax, ay) in &terms {
                let su = ax[u] * *sign;
                k.iter_mut().zip(ay).for_each(|(k, a)| *k += su * a);
            }
            column.iter_mut().zip(&k).for_each(|(x, k)| *x *= k);
        }
        b
    }

    /// The inverse transform of `b` (stored transposed, as [`forward`] leaves it) on the image's
    /// own rows (`pw` values each): along y first, then along x on those rows only.
    fn inverse(&self, mut b: Vec<Complex<f64>>) -> Vec<Complex<f64>> {
        let (pw, ph) = (self.pw, self.ph);
        self.plans.iy.process(&mut b);
        let mut rows = transpose(&b, ph, pw, self.pad..self.pad + self.height);
        self.plans.ix.process(&mut rows);
        rows
    }

    /// The image's own pixels of [`Spectrum::inverse`]'s rows: the part `part` of each value.
    fn pixels(&self, rows: &[Complex<f64>], part: impl Fn(&Complex<f64>) -> f64) -> Image {
        let scale = 1.0 / (self.pw * self.ph) as f64;
        let mut out = Image::new(self.width, self.height);
        for y in 0..self.height {
            let row = &rows[y * self.pw + self.pad..][..self.width];
            for (o, x) in out.v[y * self.width..][..self.width].iter_mut().zip(row) {
                *o = part(x) * scale;
            }
        }
        out
    }
}

/// (E * K)(x, y) = Σ E(x−i, y−j) K(i, j) with clamp-to-edge E.
pub fn convolve_2d(e: &Image, k: &Kernel2) -> Image {
    Spectrum::new(e, k.half).convolve_dense(k)
}

/// Σᵢ sᵢ·((E * aᵢ)ₓ * aᵢ)ᵧ: a horizontal then a vertical 1D pass per term, clamp-to-edge.
pub fn convolve_separable(e: &Image, s: &Separable) -> Image {
    Spectrum::new(e, s.half()).convolve_separable(s)
}

/// In-place 2D transform: every row, then every column (columns gathered in blocks so each pass
/// reads memory in order).
/// The 2D transform of a `w`-wide, `h`-high row-major array, left transposed (x frequency u
/// at row u, y frequency v at column v): the inverse undoes it without transposing back.
fn forward(
    mut data: Vec<Complex<f64>>,
    w: usize,
    h: usize,
    fx: &dyn Fft<f64>,
    fy: &dyn Fft<f64>,
) -> Vec<Complex<f64>> {
    fx.process(&mut data);
    let mut t = transpose(&data, w, h, 0..w);
    fy.process(&mut t);
    t
}

/// The smallest length ≥ `n` of the form 2ᵃ3ᵇ, whose transforms are fast. Padding beyond the
/// kernel's half-width keeps the circular convolution equal to the linear one in the image's
/// pixels: the extra columns hold clamp-to-edge values as the padding does.
fn fast_len(n: usize) -> usize {
    (n..)
        .find(|&m| {
            let mut m = m;
            for p in [2, 3] {
                while m % p == 0 {
                    m /= p;
                }
            }
            m == 1
        })
        .expect("a 3-smooth length exists above any n")
}

/// The columns `cols` of a `w`-wide, `h`-high row-major matrix as rows (of `h` values each).
fn transpose(
    data: &[Complex<f64>],
    w: usize,
    h: usize,
    cols: std::ops::Range<usize>,
) -> Vec<Complex<f64>> {
    let mut t = vec![Complex::new(0.0, 0.0); cols.len() * h];
    const B: usize = 16;
    for y0 in (0..h).step_by(B) {
        for x0 in cols.clone().step_by(B) {
            for x in x0..(x0 + B).min(cols.end) {
                let out = &mut t[(x - cols.start) * h..][y0..(y0 + B).min(h)];
                for (y, o) in (y0..).zip(out) {
                    *o = data[y * w + x];
                }
            }
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::separable::Term;

    /// The direct clamp-to-edge passes, the definition the transforms must reproduce.
    fn direct_separable(e: &Image, s: &Separable) -> Image {
        let mut out = Image::new(e.width, e.height);
        for t in &s.terms {
            let n = (t.a.len() / 2) as isize;
            let pass = |img: &Image, dx: isize, dy: isize| {
                let mut o = Image::new(img.width, img.height);
                for y in 0..img.height {
                    for x in 0..img.width {
                        o.v[y * img.width + x] =
                            t.a.iter()
                                .enumerate()
                                .map(|(j, w)| {
                                    let d = j as isize - n;
                                    w * img.clamped(x as isize - d * dx, y as isize - d * dy)
                                })
                                .sum();
                    }
                }
                o
            };
            let v = pass(&pass(e, 1, 0), 0, 1);
            out.v
                .iter_mut()
                .zip(&v.v)
                .for_each(|(o, x)| *o += t.sign * x);
        }
        out
    }

    fn test_image(w: usize, h: usize) -> Image {
        let mut e = Image::new(w, h);
        for (p, v) in e.v.iter_mut().enumerate() {
            // Deterministic, rough, with an edge and a bright dot.
            let (x, y) = (p % w, p / w);
            *v = f64::from(x < w / 3)
                + ((p * 7919) % 113) as f64 / 113.0
                + f64::from(x == 5 && y == 7) * 9.0;
        }
        e
    }

    fn asymmetric_terms(half: usize) -> Separable {
        let m = 2 * half + 1;
        Separable {
            h: 0.1,
            terms: vec![
                Term {
                    sign: 1.0,
                    a: (0..m).map(|i| 1.0 / (1.0 + i as f64)).collect(),
                },
                Term {
                    sign: -1.0,
                    a: (0..m).map(|i| ((i * 31) % 7) as f64 * 0.05).collect(),
                },
            ],
        }
    }

    /// The transform path equals the direct passes (clamp-to-edge included: the kernel is wider
    /// than a third of the image) for kernels narrower than the padding, on a non-square image.
    #[test]
    fn separable_transform_equals_direct_passes() {
        let e = test_image(37, 23);
        for half in [0, 1, 6, 19] {
            let s = asymmetric_terms(half);
            let want = direct_separable(&e, &s);
            let scale = want.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for pad in [half, half + 5] {
                let got = Spectrum::new(&e, pad).convolve_separable(&s);
                let d = got
                    .v
                    .iter()
                    .zip(&want.v)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(d <= 1e-12 * scale, "half {half} pad {pad}: {d:e}");
            }
        }
    }

    /// A dense kernel that is the outer product of a term gives the separable result.
    /// Two real images through one inverse transform give each one's own convolution.
    #[test]
    fn a_pair_equals_each_alone() {
        let (e1, e2) = (
            test_image(37, 23),
            Image {
                v: test_image(37, 23).v.iter().map(|x| 1.0 - x * x).collect(),
                ..test_image(37, 23)
            },
        );
        let s = asymmetric_terms(6);
        for pad in [6, 11] {
            let (sp1, sp2) = (Spectrum::new(&e1, pad), Spectrum::new(&e2, pad));
            let (got1, got2) = sp1.convolve_separable_pair(&sp2, &s);
            for (got, want) in [
                (got1, direct_separable(&e1, &s)),
                (got2, direct_separable(&e2, &s)),
            ] {
                let scale = want.v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let d = got.rms_diff(&want);
                assert!(d <= 1e-12 * scale, "pad {pad}: {d:e}");
            }
        }
    }

    #[test]
    fn dense_equals_separable_for_an_outer_product() {
        let e = test_image(30, 41);
        let s = Separable::rank1(
            0.1,
            (0..15)
                .map(|i| (i as f64 - 7.0).abs().exp().recip())
                .collect(),
        );
        let dense = s.to_dense();
        let spectrum = Spectrum::new(&e, 9);
        let (a, b) = (
            spectrum.convolve_dense(&dense),
            spectrum.convolve_separable(&s),
        );
        let d =
            a.v.iter()
                .zip(&b.v)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
        assert!(d < 1e-12, "{d:e}");
        assert!(a.rms_diff(&direct_separable(&e, &s)) < 1e-12);
    }
}
