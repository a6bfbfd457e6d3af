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

use crate::model::{FittedKernel, KernelModel, SkinParams};
use crate::separable::Separable;
pub use crate::separable::offsets;

/// One tap: offset [cm] and per-channel weight.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tap {
    /// Offset from the centre along the pass's axis, in [`ShaderKernel::unit`] (cm once read by
    /// [`ShaderKernel::from_toml`]).
    pub offset: f64,
    /// Weight per channel R, G, B [-]: the 1D function's integral over the tap's cell.
    pub weight: [f64; 3],
}

/// One separable pass pair (horizontal then vertical) with its per-channel sign.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pass {
    /// The term's sign per channel R, G, B (±1): the vertical pass adds sign × its result.
    pub sign: [f64; 3],
    /// The taps of both 1D passes, by increasing offset.
    pub tap: Vec<Tap>,
}

/// A shader kernel file (`KERNEL.toml`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShaderKernel {
    /// The model the kernel comes from, with its parameters resolved.
    pub model: KernelModel,
    /// The material's name.
    pub material: String,
    /// Length unit of the offsets.
    pub unit: String,
    /// Taps per pass.
    pub taps: usize,
    /// Range R of the quadratic offset mapping [unit].
    pub range: f64,
    /// Fraction of taps the renderer should jitter per pixel (supplement Fig. S.6–S.7); 0 = none.
    pub jitter: f64,
    /// One entry per rank-1 term, each run as a horizontal then a vertical pass.
    pub pass: Vec<Pass>,
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

/// How a model is sampled into taps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TapSpec {
    /// Taps per 1D pass (odd counts include the centre), 1..=1025.
    pub taps: usize,
    /// Fraction of the widest channel's 1D mass inside the tap range, (0, 1].
    pub coverage: f64,
    /// Fraction of taps the renderer should jitter per pixel, [0, 1].
    pub jitter: f64,
}

impl Default for TapSpec {
    /// SSSS's 17 taps; coverage 0.95 balances the channels at 17 taps (measured); no jitter.
    fn default() -> Self {
        TapSpec {
            taps: 17,
            coverage: 0.95,
            jitter: 0.0,
        }
    }
}

impl TapSpec {
    /// Checks the ranges; the error names the field.
    pub fn validate(&self) -> crate::Result<()> {
        if !(1..=1025).contains(&self.taps) {
            return Err(crate::FitError::invalid(
                "taps",
                self.taps,
                "must be in 1..=1025",
            ));
        }
        if !(self.coverage > 0.0 && self.coverage <= 1.0) {
            return Err(crate::FitError::invalid(
                "coverage",
                self.coverage,
                "must be in (0, 1]",
            ));
        }
        if !(0.0..=1.0).contains(&self.jitter) {
            return Err(crate::FitError::invalid(
                "jitter",
                self.jitter,
                "must be in [0, 1]",
            ));
        }
        Ok(())
    }
}

impl ShaderKernel {
    /// How far these taps are from the full-resolution kernel `fitted` they were sampled from,
    /// on the ground truth's grid of `p`: per channel, the worst image RMS over the test signals
    /// (images in [0, 1]) between the two kernels' convolutions.
    pub fn tap_error(&self, p: &crate::Profile, fitted: &FittedKernel) -> Vec<f64> {
        fitted
            .channels
            .iter()
            .enumerate()
            .map(|(c, full)| {
                let gt = crate::ground_truth(p, c, None);
                let eval = crate::metrics::ImageEval::new(&gt, 256, 128);
                let sparse = self.to_separable(c, gt.h, gt.half);
                crate::signals::Signal::ALL
                    .iter()
                    .map(|&s| {
                        let (_, _, f) = eval.images(s, full);
                        let (_, _, t) = eval.images(s, &sparse);
                        f.rms_diff(&t)
                    })
                    .fold(0.0, f64::max)
            })
            .collect()
    }

    /// The shader kernel of a fitted model. The SSSS skin model keeps the demo's own taps (fixed
    /// range 2 or 3 mm times its width, converted to cm) so that engines shipping SSSS get the
    /// numbers they expect; every other model is sampled by [`ShaderKernel::from_separable`].
    pub fn from_fitted(f: &FittedKernel, material: &str, spec: TapSpec) -> crate::Result<Self> {
        spec.validate()?;
        if let KernelModel::Skin(SkinParams::Given(skin)) = f.model {
            let mut tap: Vec<Tap> = skin
                .kernel(spec.taps)
                .into_iter()
                .map(|(o, w)| Tap {
                    offset: 0.1 * o,
                    weight: w,
                })
                .collect();
            tap.sort_by(|x, y| x.offset.total_cmp(&y.offset));
            let range = 0.1 * skin.width * if spec.taps > 20 { 3.0 } else { 2.0 };
            return Ok(ShaderKernel {
                model: f.model,
                material: material.into(),
                unit: "cm".into(),
                taps: spec.taps,
                range,
                jitter: spec.jitter,
                pass: vec![Pass {
                    sign: [1.0; 3],
                    tap,
                }],
            });
        }
        let c = &f.channels;
        if c.len() != 3 {
            return Err(crate::FitError::invalid(
                "channels",
                c.len(),
                "a kernel needs three channels",
            ));
        }
        Ok(Self::from_separable(
            f.model,
            material,
            [&c[0], &c[1], &c[2]],
            spec.taps,
            spec.coverage,
            spec.jitter,
        ))
    }

    /// Builds taps for RGB separable models (one per channel, the same number of terms each).
    pub fn from_separable(
        model: KernelModel,
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
            model,
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
    pub fn dense(model: KernelModel, material: &str, channels: [&Separable; 3]) -> Self {
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
            model,
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

    /// The kernel file's text (`KERNEL.toml`), as [`ShaderKernel::from_toml`] reads it.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("kernel serializes")
    }

    /// The kernel file `sss fit` writes: comments naming its model, material and the profile
    /// it was fitted to (`profile`) and how to apply it, then [`ShaderKernel::to_toml`].
    pub fn file_text(&self, profile: &str) -> String {
        let (model, material) = (self.model, &self.material);
        format!(
            "# sss fit: model {model}, material {material}, profile {profile}\n# offsets in cm; each [[pass]] is one horizontal + one vertical 1D convolution; sum the passes' results\n{}",
            self.to_toml()
        )
    }

    /// Parses and validates a kernel file: offsets in cm (a file in mm is converted), at least one
    /// pass, `taps` taps (1..=1025) in every pass, jitter in [0, 1], numbers finite as f32, signs
    /// of ±1.
    pub fn from_toml(text: &str, source_name: &str) -> crate::Result<Self> {
        let mut k: ShaderKernel = toml::from_str(text).map_err(|e| crate::FitError::Parse {
            source_name: source_name.into(),
            line: e
                .span()
                .map(|s| text[..s.start].lines().count().max(1))
                .unwrap_or(0),
            message: e.message().to_string(),
        })?;
        let to_cm = match k.unit.as_str() {
            "cm" => 1.0,
            "mm" => 0.1,
            other => {
                return Err(crate::FitError::invalid(
                    "unit",
                    format!("{other:?}"),
                    "must be \"cm\" or \"mm\"",
                ));
            }
        };
        if k.pass.is_empty() {
            return Err(crate::FitError::invalid(
                "pass",
                0,
                "a kernel needs at least one [[pass]]",
            ));
        }
        // The header's taps and jitter obey the limits of the tap sampler that writes them.
        TapSpec {
            taps: k.taps,
            coverage: 1.0,
            jitter: k.jitter,
        }
        .validate()?;
        // Shaders read every number as f32: a finite f64 beyond its range would become inf there.
        let f32_finite = |v: f64| v.is_finite() && v.abs() <= f32::MAX as f64;
        if !(f32_finite(k.range) && k.range >= 0.0) {
            return Err(crate::FitError::invalid(
                "range",
                format!("{:?}", k.range),
                "must be non-negative and finite as f32",
            ));
        }
        for (i, p) in k.pass.iter().enumerate() {
            if p.tap.len() != k.taps {
                return Err(crate::FitError::invalid(
                    format!("pass[{i}] taps"),
                    p.tap.len(),
                    format!("the header says taps = {}", k.taps),
                ));
            }
            if let Some(s) = p.sign.iter().find(|s| s.abs() != 1.0) {
                return Err(crate::FitError::invalid(
                    format!("pass[{i}].sign"),
                    s,
                    "must be 1 or -1",
                ));
            }
            for (j, t) in p.tap.iter().enumerate() {
                if !(f32_finite(t.offset) && t.weight.iter().all(|&w| f32_finite(w))) {
                    return Err(crate::FitError::invalid(
                        format!("pass[{i}].tap[{j}]"),
                        format!("{:?}", t),
                        "offset and weights must be finite as f32",
                    ));
                }
            }
        }
        if to_cm != 1.0 {
            k.unit = "cm".into();
            k.range *= to_cm;
            k.pass
                .iter_mut()
                .flat_map(|p| p.tap.iter_mut())
                .for_each(|t| t.offset *= to_cm);
        }
        Ok(k)
    }
}
