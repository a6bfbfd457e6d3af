//! Shader-ready kernels: for each separable pass, N taps at importance-sampled offsets with RGB
//! weights integrated over each tap's interval (not point-sampled).
//!
//! Offsets follow SSSS's quadratic mapping: oᵢ evenly spaced in [−R, R] map to
//! R·sign(oᵢ)·oᵢ²/R², dense near the centre where kernels peak. Unlike the public SSSS shader, R is
//! the kernel's own range (the radius holding `coverage` of the widest channel's 1D mass), not a
//! fixed constant. Each tap's weight is ∫ a(x) dx over its cell (midpoints between neighbouring
//! offsets; the outer cells extend to the end of the kernel so no energy is lost), with each of
//! the model's samples spread uniformly over its own grid cell.

use serde::{Deserialize, Serialize};

use crate::separable::Separable;

/// One tap: offset [cm] and per-channel weight.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tap {
    pub offset: f64,
    pub weight: [f64; 3],
}

/// One separable pass pair (horizontal then vertical) with its per-channel sign.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pass {
    pub sign: [f64; 3],
    pub tap: Vec<Tap>,
}

/// A shader kernel file (`KERNEL.toml`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShaderKernel {
    pub model: String,
    pub material: String,
    /// Length unit of the offsets.
    pub unit: String,
    /// Taps per pass.
    pub taps: usize,
    /// Range R of the quadratic offset mapping [unit].
    pub range: f64,
    /// Fraction of taps the renderer should jitter per pixel (supplement Fig. S.6–S.7); 0 = none.
    pub jitter: f64,
    pub pass: Vec<Pass>,
}

/// SSSS's quadratic offsets for `n` taps over [−range, range], centre tap included for odd n.
pub fn offsets(n: usize, range: f64) -> Vec<f64> {
    if n == 1 {
        return vec![0.0];
    }
    let step = 2.0 * range / (n - 1) as f64;
    (0..n)
        .map(|i| {
            let o = -range + i as f64 * step;
            o.signum() * o * o / range
        })
        .collect()
}

/// ∫ from x0 to x1 of the model's 1D function as a density: sample a[i] spread uniformly over
/// its cell [(i − half − ½)h, (i − half + ½)h]. Cells of the taps partition the line, so the
/// weights of a pass sum to Σa exactly.
fn integrate(a: &[f64], h: f64, x0: f64, x1: f64) -> f64 {
    let half = (a.len() / 2) as f64;
    let (t0, t1) = (x0 / h + half + 0.5, x1 / h + half + 0.5); // in cell units, cell i = [i, i+1)
    let (first, last) = (
        t0.floor().max(0.0) as usize,
        (t1.ceil().max(0.0) as usize).min(a.len()),
    );
    (first..last)
        .map(|i| a[i] * ((t1.min(i as f64 + 1.0) - t0.max(i as f64)).max(0.0)))
        .sum()
}

/// The radius holding `coverage` of the L1 mass of a centred 1D function.
pub fn range_of(a: &[f64], h: f64, coverage: f64) -> f64 {
    let half = a.len() / 2;
    let total: f64 = a.iter().map(|x| x.abs()).sum();
    let mut acc = a[half].abs();
    for d in 1..=half {
        if acc >= coverage * total {
            return d as f64 * h;
        }
        acc += a[half - d].abs() + a[half + d].abs();
    }
    half as f64 * h
}

impl ShaderKernel {
    /// Builds taps for RGB separable models (one per channel, the same number of terms each).
    pub fn from_separable(
        model: &str,
        material: &str,
        channels: [&Separable; 3],
        taps: usize,
        coverage: f64,
        jitter: f64,
    ) -> Self {
        let h = channels[0].h;
        let passes = channels.iter().map(|s| s.terms.len()).max().unwrap_or(0);
        let range = channels
            .iter()
            .flat_map(|s| s.terms.iter().map(|t| range_of(&t.a, h, coverage)))
            .fold(h, f64::max);
        let offs = offsets(taps, range);
        let end = (channels[0].half() as f64 + 0.5) * h;
        // Cells: midpoints between offsets, outer cells to the kernel's end.
        let mut bounds = vec![-end];
        bounds.extend(offs.windows(2).map(|w| 0.5 * (w[0] + w[1])));
        bounds.push(end);
        let pass = (0..passes)
            .map(|p| {
                let sign =
                    [0, 1, 2].map(|c| channels[c].terms.get(p).map(|t| t.sign).unwrap_or(1.0));
                let tap = offs
                    .iter()
                    .enumerate()
                    .map(|(i, &o)| Tap {
                        offset: o,
                        weight: [0, 1, 2].map(|c| {
                            channels[c]
                                .terms
                                .get(p)
                                .map(|t| integrate(&t.a, h, bounds[i], bounds[i + 1]))
                                .unwrap_or(0.0)
                        }),
                    })
                    .collect();
                Pass { sign, tap }
            })
            .collect();
        ShaderKernel {
            model: model.into(),
            material: material.into(),
            unit: "cm".into(),
            taps,
            range,
            jitter,
            pass,
        }
    }

    /// One tap per grid sample (offset (i − half)·h, weight aᵢ): the separable model exactly, for
    /// renderers that can afford the taps and for checking a GPU path against the CPU.
    pub fn dense(model: &str, material: &str, channels: [&Separable; 3]) -> Self {
        let h = channels[0].h;
        let passes = channels.iter().map(|s| s.terms.len()).max().unwrap_or(0);
        let n = channels
            .iter()
            .flat_map(|s| s.terms.iter().map(|t| t.a.len()))
            .max()
            .unwrap_or(1);
        let half = n / 2;
        let pass = (0..passes)
            .map(|p| Pass {
                sign: [0, 1, 2].map(|c| channels[c].terms.get(p).map_or(1.0, |t| t.sign)),
                tap: (0..n)
                    .map(|i| Tap {
                        offset: (i as f64 - half as f64) * h,
                        weight: [0, 1, 2].map(|c| {
                            channels[c].terms.get(p).map_or(0.0, |t| {
                                let off = (t.a.len() / 2) as isize + i as isize - half as isize;
                                if off >= 0 && (off as usize) < t.a.len() {
                                    t.a[off as usize]
                                } else {
                                    0.0
                                }
                            })
                        }),
                    })
                    .collect(),
            })
            .collect();
        ShaderKernel {
            model: model.into(),
            material: material.into(),
            unit: "cm".into(),
            taps: n,
            range: half as f64 * h,
            jitter: 0.0,
            pass,
        }
    }

    /// The 1D functions of channel `c` on a fine grid (spacing `h`, half-width `half`), each tap's
    /// weight deposited at its offset by linear splitting: what the shader's sparse taps amount to.
    pub fn to_separable(&self, c: usize, h: f64, half: usize) -> Separable {
        let terms = self
            .pass
            .iter()
            .map(|p| {
                let mut a = vec![0.0; 2 * half + 1];
                for t in &p.tap {
                    let x = t.offset / h + half as f64;
                    let i = x.floor().clamp(0.0, (2 * half) as f64) as usize;
                    let w = (x - i as f64).clamp(0.0, 1.0);
                    a[i] += t.weight[c] * (1.0 - w);
                    if i < 2 * half {
                        a[i + 1] += t.weight[c] * w;
                    }
                }
                crate::separable::Term { sign: p.sign[c], a }
            })
            .collect();
        Separable { h, terms }
    }

    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("kernel serializes")
    }

    pub fn from_toml(text: &str, source_name: &str) -> crate::Result<Self> {
        toml::from_str(text).map_err(|e| crate::FitError::Parse {
            source_name: source_name.into(),
            line: e
                .span()
                .map(|s| text[..s.start].lines().count().max(1))
                .unwrap_or(0),
            message: e.message().to_string(),
        })
    }
}
