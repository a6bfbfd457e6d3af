//! Evaluation of every kernel model on one material's profile: kernel-space RMS (raw and
//! L1-normalized by eq. 5.12), L1 error, image-space RMS per test signal, fit time; plus what the
//! plots need (kernel slices, singular values, convolution images).
//!
//! Models: `svd` ranks 1–6, `preint`, `guided` k = 0, 1, 2 (b = 0), `manual` (Table A.1 when the
//! material has a row, else the image-space fit), `deon` N = 1–6, `skin` (the original SSSS
//! kernel with its defaults, scaled in mm; variant `fitted, eq. 4.13`: its strength and falloff
//! fitted to the profile), `burley` (variant `radial`: dense 2D; `projected`:
//! rank-1 pre-integration of it).

use std::time::Instant;

use crate::kernel2d::{Kernel2, ground_truth};
use crate::metrics::{ImageEval, kernel_rms, l1_error};
use crate::separable::Separable;
use crate::signals::Signal;
use crate::skin::Skin;
use crate::{Burley, Gaussians, Guided, Manual, Profile, preint, svd, top_eigen_to};

/// One model on one channel.
#[derive(Clone, Debug)]
pub struct Row {
    pub model: &'static str,
    pub variant: Option<&'static str>,
    pub rank: Option<usize>,
    pub k: Option<f64>,
    pub channel: usize,
    pub kernel_rms: f64,
    pub kernel_rms_normalized: f64,
    pub l1_error: f64,
    pub image_rms: Vec<(Signal, f64)>,
    pub fit_seconds: f64,
    /// Main-axis slice A(x, 0) and diagonal slice A(x, x) of the (raw) model, x ≥ 0.
    pub axis: Vec<f64>,
    pub diagonal: Vec<f64>,
}

impl Row {
    /// A short label for legends: `svd1`, `guided k=1`, `burley (radial)`, …
    pub fn label(&self) -> String {
        match (self.model, self.rank, self.k, self.variant) {
            ("svd" | "deon", Some(n), _, _) => format!("{}{n}", self.model),
            (m, _, Some(k), _) => format!("{m} k={k}"),
            (m, _, _, Some(v)) => format!("{m} ({v})"),
            (m, _, _, _) => m.to_string(),
        }
    }
}

/// Everything measured for one material.
pub struct Evaluation {
    pub rows: Vec<Row>,
    /// The first 30 singular values per channel (thesis Fig. 5.1).
    pub singular_values: [Vec<f64>; 3],
    /// Ground truth slices per channel (axis, diagonal), x ≥ 0, and the sample spacing [cm].
    pub truth_axis: [Vec<f64>; 3],
    pub truth_diagonal: [Vec<f64>; 3],
    pub h: f64,
    /// Rank-1 models and the image evaluator per channel, for convolution plots.
    pub rank1: Vec<(String, usize, Separable)>,
    pub images: Vec<ImageEval>,
}

fn slices(a: &Separable) -> (Vec<f64>, Vec<f64>) {
    let n = a.half();
    let axis = (0..=n)
        .map(|j| a.terms.iter().map(|t| t.sign * t.a[n + j] * t.a[n]).sum())
        .collect();
    let diag = (0..=n)
        .map(|j| {
            a.terms
                .iter()
                .map(|t| t.sign * t.a[n + j] * t.a[n + j])
                .sum()
        })
        .collect();
    (axis, diag)
}

fn dense_slices(k: &Kernel2) -> (Vec<f64>, Vec<f64>) {
    let n = k.half;
    (
        (0..=n).map(|j| k.at(n, n + j)).collect(),
        (0..=n).map(|j| k.at(n + j, n + j)).collect(),
    )
}

/// Size of the image-space evaluation: test signals of `size` pixels, kernels binned to a
/// half-width of at most `max_half` pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    pub size: usize,
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

/// Evaluates every model on every channel of a profile. `material` selects Table A.1 rows.
pub fn evaluate(p: &Profile, material: &str, image: ImageSize) -> Evaluation {
    let mut rows = Vec::new();
    let mut singular_values: [Vec<f64>; 3] = Default::default();
    let mut truth_axis: [Vec<f64>; 3] = Default::default();
    let mut truth_diagonal: [Vec<f64>; 3] = Default::default();
    let mut rank1 = Vec::new();
    let mut images = Vec::new();
    let table = crate::manual::table_a1(material);
    let mut h = p.dr;
    // The SSSS skin model fitted to the profile (§4.6, eq. 4.13) shares its width across channels.
    let t = Instant::now();
    let truths: Vec<Kernel2> = (0..3).map(|c| ground_truth(p, c, None)).collect();
    let skin_fit = Skin::fit([&truths[0], &truths[1], &truths[2]]);
    let skin_fit_seconds = t.elapsed().as_secs_f64() / 3.0;
    for (c, k) in truths.into_iter().enumerate() {
        h = k.h;
        (truth_axis[c], truth_diagonal[c]) = dense_slices(&k);
        let eval = ImageEval::new(&k, image.size, image.max_half);
        let push = |model: &'static str,
                    variant: Option<&'static str>,
                    rank: Option<usize>,
                    kk: Option<f64>,
                    a: &Separable,
                    seconds: f64,
                    rows: &mut Vec<Row>| {
            let (axis, diagonal) = slices(a);
            rows.push(Row {
                model,
                variant,
                rank,
                k: kk,
                channel: c,
                kernel_rms: kernel_rms(&k, a),
                kernel_rms_normalized: kernel_rms(&k, &a.clone().renormalized(k.l1())),
                l1_error: l1_error(&k, a),
                image_rms: eval.rms(a),
                fit_seconds: seconds,
                axis,
                diagonal,
            });
        };

        let t = Instant::now();
        let (svd6, _) = svd(&k, 6);
        let svd_seconds = t.elapsed().as_secs_f64();
        singular_values[c] = top_eigen_to(&k, 30, 1e-6, 200)
            .values
            .iter()
            .map(|v| v.abs())
            .collect();
        for n in 1..=6 {
            let a = Separable {
                h: k.h,
                terms: svd6.terms[..n.min(svd6.terms.len())].to_vec(),
            };
            push("svd", None, Some(n), None, &a, svd_seconds, &mut rows);
            if n == 1 {
                rank1.push(("svd1".to_string(), c, a));
            }
        }
        let t = Instant::now();
        let pre = preint(&k);
        push(
            "preint",
            None,
            None,
            None,
            &pre,
            t.elapsed().as_secs_f64(),
            &mut rows,
        );
        rank1.push(("preint".to_string(), c, pre));
        for kk in [0.0, 1.0, 2.0] {
            let g = Guided {
                k: kk,
                ..Guided::default()
            }
            .fit(&k);
            push(
                "guided",
                None,
                None,
                Some(kk),
                &g.kernel,
                g.seconds,
                &mut rows,
            );
            if kk == 1.0 {
                rank1.push(("guided k=1".to_string(), c, g.kernel));
            }
        }
        let t = Instant::now();
        let (manual, variant) = match &table {
            Some(rows) => (rows[c], "table A.1"),
            None => (
                Manual::fit_image_space(&k, Manual::start(&k)),
                "image-space fit",
            ),
        };
        let m = manual.separable(k.half, k.h);
        push(
            "manual",
            Some(variant),
            None,
            None,
            &m,
            t.elapsed().as_secs_f64(),
            &mut rows,
        );
        rank1.push(("manual".to_string(), c, m));
        let t = Instant::now();
        let deon = Gaussians::fit_up_to(&k, 6);
        let deon_seconds = t.elapsed().as_secs_f64();
        for (n, g) in deon.iter().enumerate() {
            push(
                "deon",
                None,
                Some(n + 1),
                None,
                &g.to_separable(k.half, k.h),
                deon_seconds,
                &mut rows,
            );
        }
        let skin = Skin::DEMO.separable(c, k.half, k.h);
        push(
            "skin",
            Some("SSSS defaults"),
            None,
            None,
            &skin,
            0.0,
            &mut rows,
        );
        push(
            "skin",
            Some("fitted, eq. 4.13"),
            None,
            None,
            &skin_fit.separable(c, k.half, k.h),
            skin_fit_seconds,
            &mut rows,
        );
        let t = Instant::now();
        let b = Burley::fit(&k);
        let fit_s = t.elapsed().as_secs_f64();
        let projected = b.projected(k.half, k.h);
        push(
            "burley",
            Some("projected"),
            None,
            None,
            &projected,
            fit_s,
            &mut rows,
        );
        // Radial use: a dense, non-separable kernel, convolved in 2D.
        let dense = b.kernel(k.half, k.h);
        let normalized = {
            let mut d = dense.clone();
            let s = k.l1() / d.l1();
            d.v.iter_mut().for_each(|x| *x *= s);
            d
        };
        let kr = |d: &Kernel2| {
            (k.v.iter()
                .zip(&d.v)
                .map(|(p, q)| (p - q).powi(2))
                .sum::<f64>()
                / k.v.len() as f64)
                .sqrt()
        };
        let image_rms = eval.rms_dense(&normalized);
        let (axis, diagonal) = dense_slices(&dense);
        rows.push(Row {
            model: "burley",
            variant: Some("radial"),
            rank: None,
            k: None,
            channel: c,
            kernel_rms: kr(&dense),
            kernel_rms_normalized: kr(&normalized),
            l1_error: (dense.l1() - k.l1()).abs() / k.l1(),
            image_rms,
            fit_seconds: fit_s,
            axis,
            diagonal,
        });
        images.push(eval);
    }
    Evaluation {
        rows,
        singular_values,
        truth_axis,
        truth_diagonal,
        h,
        rank1,
        images,
    }
}
