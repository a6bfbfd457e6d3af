//! The original SSSS skin kernel (Jimenez et al., thesis eq. 4.8), built exactly as the public
//! demo does: the red column of d'Eon & Luebke's six-Gaussian skin profile without its 0.0064 mm²
//! term (carried by the strength t instead), per-channel falloff f stretching the radius,
//! r → r/(0.001 + f); taps at quadratic offsets RANGE·sign(o)·o²/RANGE² (RANGE = 2 mm for ≤ 20 taps,
//! 3 above); weights = profile × the width of each tap's interval, normalized per channel; then
//! the strength: centre tap → lerp(1, w₀, t), others × t. Offsets here are in mm, as in the demo.

/// d'Eon & Luebke (GPU Gems 3) red-channel variances [mm²] and weights, without the 0.0064 term.
const PROFILE: [(f64, f64); 5] = [
    (0.0484, 0.100),
    (0.187, 0.118),
    (0.567, 0.113),
    (1.99, 0.358),
    (7.41, 0.078),
];

/// The demo's defaults.
pub const FALLOFF: [f64; 3] = [1.0, 0.37, 0.3];
pub const STRENGTH: [f64; 3] = [0.48, 0.41, 0.28];

/// SSSS's internal profile p(r/(0.001+f)) per channel at radius `r` [mm].
pub fn profile(r: f64, falloff: [f64; 3]) -> [f64; 3] {
    falloff.map(|f| {
        let rr = r / (0.001 + f);
        PROFILE
            .iter()
            .map(|&(v, w)| w * (-(rr * rr) / (2.0 * v)).exp() / (2.0 * std::f64::consts::PI * v))
            .sum()
    })
}

/// The kernel: (offset [mm], RGB weight) with the centre tap first, then increasing offset, as the
/// demo stores it.
pub fn kernel(taps: usize, falloff: [f64; 3], strength: [f64; 3]) -> Vec<(f64, [f64; 3])> {
    let range = if taps > 20 { 3.0 } else { 2.0 };
    let offs = crate::taps::offsets(taps, range);
    let mut k: Vec<(f64, [f64; 3])> = (0..taps)
        .map(|i| {
            let w0 = if i > 0 {
                (offs[i] - offs[i - 1]).abs()
            } else {
                0.0
            };
            let w1 = if i + 1 < taps {
                (offs[i] - offs[i + 1]).abs()
            } else {
                0.0
            };
            let area = 0.5 * (w0 + w1);
            (offs[i], profile(offs[i], falloff).map(|p| area * p))
        })
        .collect();
    let centre = k.remove(taps / 2);
    k.insert(0, centre);
    for c in 0..3 {
        let sum: f64 = k.iter().map(|t| t.1[c]).sum();
        k.iter_mut().for_each(|t| t.1[c] /= sum);
        k[0].1[c] = (1.0 - strength[c]) + strength[c] * k[0].1[c];
        k[1..].iter_mut().for_each(|t| t.1[c] *= strength[c]);
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Golden values of the public demo's kernel with its defaults, 17 taps
    /// (shared/reference/thesis_tables.md).
    #[test]
    fn matches_the_public_demo() {
        let k = kernel(17, FALLOFF, STRENGTH);
        let golden = [
            (0.0, [0.536343, 0.624624, 0.748867]),
            (-2.0, [0.00317394, 0.000134823, 3.77269e-05]),
            (-1.53125, [0.0100386, 0.000914679, 0.000275702]),
            (-1.125, [0.0144609, 0.00317269, 0.00106399]),
        ];
        for (i, (o, w)) in golden.iter().enumerate() {
            assert!((k[i].0 - o).abs() < 1e-12, "offset {i}: {} vs {o}", k[i].0);
            for c in 0..3 {
                assert!(
                    (k[i].1[c] - w[c]).abs() <= 1e-5 * w[c],
                    "tap {i} channel {c}: {} vs {}",
                    k[i].1[c],
                    w[c]
                );
            }
        }
        // Symmetric, and the weights of a channel sum to 1 (the strength lerp keeps the sum).
        for c in 0..3 {
            assert!((k.iter().map(|t| t.1[c]).sum::<f64>() - 1.0).abs() < 1e-12);
        }
        assert!((k[1].1[0] - k[16].1[0]).abs() < 1e-15);
    }
}
