//! CPU reference convolutions with clamp-to-edge boundaries (an edge stays additively separable up
//! to the image border): the full 2D convolution with a dense kernel by FFT (exact up to
//! rounding), and the separable convolution with each model's 1D passes.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::kernel2d::Kernel2;
use crate::separable::Separable;

/// A single-channel float image, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub v: Vec<f64>,
}

impl Image {
    pub fn new(width: usize, height: usize) -> Self {
        Image {
            width,
            height,
            v: vec![0.0; width * height],
        }
    }

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

/// (E * K)(x, y) = Σ E(x−i, y−j) K(i, j) with clamp-to-edge E, by FFT over the padded image.
pub fn convolve_2d(e: &Image, k: &Kernel2) -> Image {
    let n = k.half as isize;
    let (pw, ph) = (e.width + 2 * k.half, e.height + 2 * k.half);
    let mut planner = FftPlanner::<f64>::new();
    let (fx, fy) = (planner.plan_fft_forward(pw), planner.plan_fft_forward(ph));
    let (ix, iy) = (planner.plan_fft_inverse(pw), planner.plan_fft_inverse(ph));
    // Padded image (clamp-to-edge), and the kernel wrapped around the origin.
    let mut a: Vec<Complex<f64>> = (0..pw * ph)
        .map(|p| Complex::new(e.clamped((p % pw) as isize - n, (p / pw) as isize - n), 0.0))
        .collect();
    let mut b = vec![Complex::new(0.0, 0.0); pw * ph];
    let m = k.side();
    for i in 0..m {
        for j in 0..m {
            let (dy, dx) = (i as isize - n, j as isize - n);
            let (y, x) = (
                dy.rem_euclid(ph as isize) as usize,
                dx.rem_euclid(pw as isize) as usize,
            );
            b[y * pw + x] += Complex::new(k.at(i, j), 0.0);
        }
    }
    fft2(&mut a, pw, ph, &*fx, &*fy);
    fft2(&mut b, pw, ph, &*fx, &*fy);
    a.iter_mut().zip(&b).for_each(|(x, y)| *x *= y);
    fft2(&mut a, pw, ph, &*ix, &*iy);
    let scale = 1.0 / (pw * ph) as f64;
    let mut out = Image::new(e.width, e.height);
    for y in 0..e.height {
        for x in 0..e.width {
            out.v[y * e.width + x] = a[(y + k.half) * pw + x + k.half].re * scale;
        }
    }
    out
}

fn fft2(
    data: &mut [Complex<f64>],
    w: usize,
    h: usize,
    fx: &dyn rustfft::Fft<f64>,
    fy: &dyn rustfft::Fft<f64>,
) {
    for row in data.chunks_mut(w) {
        fx.process(row);
    }
    let mut col = vec![Complex::new(0.0, 0.0); h];
    for x in 0..w {
        for y in 0..h {
            col[y] = data[y * w + x];
        }
        fy.process(&mut col);
        for y in 0..h {
            data[y * w + x] = col[y];
        }
    }
}

/// Σᵢ sᵢ·((E * aᵢ)ₓ * aᵢ)ᵧ: a horizontal then a vertical 1D pass per term, clamp-to-edge.
pub fn convolve_separable(e: &Image, s: &Separable) -> Image {
    let mut out = Image::new(e.width, e.height);
    for t in &s.terms {
        let n = (t.a.len() / 2) as isize;
        let mut tmp = Image::new(e.width, e.height);
        for y in 0..e.height {
            for x in 0..e.width {
                tmp.v[y * e.width + x] =
                    t.a.iter()
                        .enumerate()
                        .map(|(j, w)| w * e.clamped(x as isize - (j as isize - n), y as isize))
                        .sum();
            }
        }
        for y in 0..e.height {
            for x in 0..e.width {
                let v: f64 =
                    t.a.iter()
                        .enumerate()
                        .map(|(j, w)| w * tmp.clamped(x as isize, y as isize - (j as isize - n)))
                        .sum();
                out.v[y * e.width + x] += t.sign * v;
            }
        }
    }
    out
}
