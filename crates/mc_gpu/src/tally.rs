//! The GPU's exact tallies and their sum into mc's [`Accumulator`].
//!
//! Fixed point: the shader rounds each score x (a photon's escaping weight, its deposits in a
//! layer or in all, and their squares) once to an unsigned 64-bit integer in units of 2⁻³²
//! (`GPU_ONE`) and adds it atomically as two 32-bit words with a carry (`tally.wgsl`). Integer
//! sums do not depend on the order of the additions, so a run's result is the same bits whatever
//! the dispatch size or scheduling. The rounding error is at most 2⁻³³ per score, below 10⁻⁹ of
//! any tally of a photon's weight (Rd, Tt, A ≥ ~10⁻⁴ per photon where they matter, and unbiased).
//!
//! Bound: the tallies are read back, added to the host's [`Accumulator`] (i128 in units of
//! 2⁻⁶⁴: the CPU tracer's own exact sums) and cleared after every round of at most
//! [`ROUND_PHOTONS`] = 2²² photons. A score is at most the photon's weight w (its square w²),
//! and w ≤ 1 except after mc's path-length roulette, which doubles a survivor's weight every 10⁵
//! interactions. An entry's round sum is therefore below 2²² · w̄ · 2³² = 2⁵⁴ · w̄ units, w̄ the
//! round's mean score per photon, which leaves its 2⁶⁴ with room for w̄ < 2¹⁰ = 1024: never
//! reached unless photons survive ten path-length roulettes in a row (10⁶ interactions, chance
//! 2⁻¹⁰ given the walk lasts so long). Should it happen, the shader raises a flag and the run
//! fails with [`McGpuError::TallyOverflow`] instead of returning a wrong sum. The host's
//! accumulator holds |sums| < 2⁶³ (in units of 1), more than [`mc::MAX_PHOTONS`] = 10¹⁴ < 2⁴⁷
//! photons of weight ≤ 1 need. Interactions are summed in 64-bit integers per invocation and per
//! round.

use mc::{Accumulator, Layout};

use crate::error::{McGpuError, Result};

/// Photons per round: the tallies are read back and cleared after each (see the module's bound).
pub const ROUND_PHOTONS: u64 = 1 << 22;

/// One unit of the GPU's fixed point, 2⁻³², is this many units of the host's 2⁻⁶⁴.
const GPU_ONE: u32 = 32;

/// The tally buffer's layout in 32-bit words for `entries` entries: per entry Σx (lo, hi) and Σx²
/// (lo, hi), then the interactions (lo, hi).
pub(crate) fn words(entries: usize) -> usize {
    4 * entries + 2
}

/// The u64 at `words[i]` (lo), `words[i + 1]` (hi).
fn u64_at(words: &[u32], i: usize) -> u64 {
    u64::from(words[i]) | (u64::from(words[i + 1]) << 32)
}

/// A run's exact sums per shader entry, in the host's fixed point (units of 2⁻⁶⁴, as mc's
/// [`Accumulator`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Sums {
    pub sum: Vec<i128>,
    pub sum_sq: Vec<i128>,
    pub photons: u64,
    pub interactions: u64,
}

impl Sums {
    pub fn new(entries: usize) -> Sums {
        Sums {
            sum: vec![0; entries],
            sum_sq: vec![0; entries],
            photons: 0,
            interactions: 0,
        }
    }

    /// Adds a round's tally words (and its `photons`); `overflow` is the shader's flag.
    pub fn add_round(&mut self, words: &[u32], photons: u64, overflow: bool) -> Result<()> {
        if overflow {
            return Err(McGpuError::TallyOverflow {
                round_photons: ROUND_PHOTONS,
            });
        }
        let entries = self.sum.len();
        for e in 0..entries {
            self.sum[e] += i128::from(u64_at(words, 4 * e)) << GPU_ONE;
            self.sum_sq[e] += i128::from(u64_at(words, 4 * e + 2)) << GPU_ONE;
        }
        self.interactions += u64_at(words, 4 * entries);
        self.photons += photons;
        Ok(())
    }

    /// The sums of a run on a grid as mc's accumulator of `layout`.
    pub fn accumulator(&self, layout: Layout) -> Accumulator {
        let mut acc = Accumulator::new(layout);
        // One layer's absorption is the photon's whole absorption: the shader scores it once, as A.
        for e in 0..layout.entries() {
            let from = if layout.layers == 1 && e == layout.a_l(0) {
                layout.a_total(0)
            } else {
                e
            };
            acc.sum[e] = self.sum[from];
            acc.sum_sq[e] = self.sum_sq[from];
        }
        acc.photons = self.photons;
        acc.interactions = self.interactions;
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> Layout {
        Layout {
            nr: 2,
            nz: 1,
            na: 1,
            layers: 1,
            rz: false,
            rz_se: false,
            channels: 1,
            xy: 0,
            scores: 0,
        }
    }

    #[test]
    fn a_round_adds_in_the_hosts_fixed_point() {
        let l = layout();
        let entries = l.entries();
        let mut w = vec![0u32; words(entries)];
        // Entry 1 (Rd of the second radial bin): Σx = 1.5, Σx² = 2^-32.
        (w[4], w[5]) = (1 << 31, 1);
        w[6] = 1;
        // Interactions: 2^32 + 7.
        let n = w.len();
        (w[n - 2], w[n - 1]) = (7, 1);
        let mut sums = Sums::new(entries);
        sums.add_round(&w, 10, false).unwrap();
        sums.add_round(&w, 10, false).unwrap();
        let acc = sums.accumulator(l);
        assert_eq!(acc.s(1), 3.0);
        assert_eq!(acc.sum_sq[1], 2 << 32);
        assert_eq!((acc.photons, acc.interactions), (20, 2 * ((1 << 32) + 7)));
        // A single layer's A_l is the A the shader scored.
        let mut a = vec![0u32; words(entries)];
        a[4 * l.a_total(0)] = 5;
        let mut sums = Sums::new(entries);
        sums.add_round(&a, 1, false).unwrap();
        let acc = sums.accumulator(l);
        assert_eq!(acc.sum[l.a_l(0)], 5 << 32);
        assert_eq!(acc.sum[l.a_total(0)], 5 << 32);
        assert!(matches!(
            sums.add_round(&w, 10, true),
            Err(McGpuError::TallyOverflow { .. })
        ));
    }
}
