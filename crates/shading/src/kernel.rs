//! A separable kernel's taps as a renderer uploads them (`sss fit`'s kernel file in single
//! precision, checked), with what a renderer asks of them: the response to a uniform image, each
//! tap's jitter cell, the reach, the spatial variance of the depth test, the one-tap kernel of a
//! sub-pixel footprint.

use crate::error::{Result, ShadingError};

/// A separable kernel as a renderer uploads it: per pass, the RGB sign and the taps (RGB weight,
/// offset [cm]), in single precision.
#[derive(Clone, Debug, PartialEq)]
pub struct KernelTaps {
    /// One entry per separable term, in order: its sign per channel R, G, B (±1) and its taps, each
    /// [weight R, weight G, weight B, offset [cm]].
    pub passes: Vec<([f32; 3], Vec<[f32; 4]>)>,
    /// Largest |offset| [cm].
    pub range_cm: f32,
}

/// The most separable terms a kernel may have (rank 6 SVD and d'Eon's 6 Gaussians fit twice).
pub const MAX_PASSES: usize = 12;
/// The most taps per 1D pass.
pub const MAX_TAPS: usize = 1025;

impl KernelTaps {
    /// Converts a `sss fit` kernel file; refuses non-cm units, empty or non-finite taps, more
    /// than [`MAX_PASSES`] terms and more than [`MAX_TAPS`] taps per pass.
    pub fn from_shader_kernel(k: &fit::taps::ShaderKernel) -> Result<KernelTaps> {
        if k.unit != "cm" {
            return Err(ShadingError::invalid(
                "kernel unit",
                &k.unit,
                "expected \"cm\"",
            ));
        }
        if k.pass.is_empty() || k.pass.iter().any(|p| p.tap.is_empty()) {
            return Err(ShadingError::invalid(
                "kernel pass",
                k.pass.len(),
                "needs at least one pass with taps",
            ));
        }
        if k.pass.len() > MAX_PASSES {
            return Err(ShadingError::invalid(
                "kernel passes",
                k.pass.len(),
                format!("at most {MAX_PASSES} separable terms per kernel"),
            ));
        }
        if let Some(p) = k.pass.iter().find(|p| p.tap.len() > MAX_TAPS) {
            return Err(ShadingError::invalid(
                "kernel taps per pass",
                p.tap.len(),
                format!("at most {MAX_TAPS}"),
            ));
        }
        let mut range = 0.0f32;
        let passes = k
            .pass
            .iter()
            .map(|p| {
                let taps = p
                    .tap
                    .iter()
                    .map(|t| {
                        range = range.max(t.offset.abs() as f32);
                        [
                            t.weight[0] as f32,
                            t.weight[1] as f32,
                            t.weight[2] as f32,
                            t.offset as f32,
                        ]
                    })
                    .collect::<Vec<_>>();
                (p.sign.map(|s| s as f32), taps)
            })
            .collect::<Vec<_>>();
        if passes
            .iter()
            .flat_map(|(s, t)| s.iter().chain(t.iter().flatten()))
            .any(|v| !v.is_finite())
        {
            return Err(ShadingError::invalid(
                "kernel taps",
                "NaN/inf",
                "every weight and offset must be finite",
            ));
        }
        Ok(KernelTaps {
            passes,
            range_cm: range,
        })
    }
}

impl KernelTaps {
    /// The kernel's response to a uniform image per channel, Σ_p sign_p·(Σ_t w_t)² (its
    /// integral: 1 for a normalized kernel).
    pub fn total(&self) -> [f32; 3] {
        let mut t = [0.0f32; 3];
        for (sign, taps) in &self.passes {
            for c in 0..3 {
                let s: f32 = taps.iter().map(|w| w[c]).sum();
                t[c] += sign[c] * s * s;
            }
        }
        t
    }

    /// Each tap's cell [cm]: from the midpoint to the next smaller offset to the midpoint to the
    /// next larger one (the outermost cells as wide on their open side as on the other), per pass.
    /// A jittered tap samples uniformly within its cell (supplement Fig. S.6–S.7).
    pub fn cells(&self) -> Vec<Vec<[f32; 2]>> {
        self.passes
            .iter()
            .map(|(_, taps)| {
                let mut sorted: Vec<f32> = taps.iter().map(|t| t[3]).collect();
                sorted.sort_by(f32::total_cmp);
                taps.iter()
                    .map(|t| {
                        let o = t[3];
                        let below = sorted[..sorted.partition_point(|&x| x < o)].last().copied();
                        let above = sorted.get(sorted.partition_point(|&x| x <= o)).copied();
                        let (lo, hi) = match (below, above) {
                            (Some(b), Some(a)) => (0.5 * (b + o), 0.5 * (o + a)),
                            (Some(b), None) => (0.5 * (b + o), o + 0.5 * (o - b)),
                            (None, Some(a)) => (o - 0.5 * (a - o), 0.5 * (o + a)),
                            (None, None) => (o, o),
                        };
                        [lo, hi]
                    })
                    .collect()
            })
            .collect()
    }

    /// The farthest a tap reaches [cm]: the range, or with jitter the outermost cell bound.
    pub fn reach_cm(&self, jitter: f32) -> f32 {
        if jitter > 0.0 {
            self.cells()
                .iter()
                .flatten()
                .fold(self.range_cm, |r, c| r.max(c[0].abs()).max(c[1].abs()))
        } else {
            self.range_cm
        }
    }

    /// The largest spatial variance [cm²] of the first pass's taps over the channels,
    /// Σw·x²/Σw: the τmax of the supplement's depth factor (§E).
    pub fn variance_cm2(&self) -> f32 {
        let Some((_, taps)) = self.passes.first() else {
            return 0.0;
        };
        (0..3)
            .map(|c| {
                let (m0, m2) = taps.iter().fold((0.0f32, 0.0f32), |(a, b), t| {
                    (a + t[c], b + t[c] * t[3] * t[3])
                });
                if m0 > 0.0 { m2 / m0 } else { 0.0 }
            })
            .fold(0.0, f32::max)
    }

    /// One pass of one tap at offset 0 with the kernel's total response: what the kernel
    /// amounts to when its footprint is below a pixel (light stays where it is).
    pub fn point(&self) -> KernelTaps {
        let t = self.total();
        KernelTaps {
            passes: vec![(
                t.map(|v| if v < 0.0 { -1.0 } else { 1.0 }),
                vec![[t[0].abs().sqrt(), t[1].abs().sqrt(), t[2].abs().sqrt(), 0.0]],
            )],
            range_cm: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kernel files the renderer cannot take are refused, naming the field.
    #[test]
    fn kernel_files_that_do_not_fit_are_refused() {
        let a: Vec<f64> = (-20..=20)
            .map(|i| (-(0.01 * i as f64).powi(2) / 0.01).exp())
            .collect();
        let g = fit::Separable::rank1(0.01, a);
        let one = fit::taps::ShaderKernel::from_separable(
            fit::KernelModel::Preint,
            "test",
            [&g, &g, &g],
            9,
            0.99,
            0.0,
        );
        assert!(KernelTaps::from_shader_kernel(&one).is_ok());
        let mut wrong_unit = one.clone();
        wrong_unit.unit = "mm".into();
        let mut too_many = one.clone();
        too_many.pass = vec![one.pass[0].clone(); MAX_PASSES + 1];
        let mut too_wide = one.clone();
        too_wide.pass[0].tap = vec![one.pass[0].tap[0].clone(); MAX_TAPS + 1];
        for (k, field) in [
            (wrong_unit, "kernel unit"),
            (too_many, "kernel passes"),
            (too_wide, "kernel taps per pass"),
        ] {
            let e = KernelTaps::from_shader_kernel(&k).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
    }
}
