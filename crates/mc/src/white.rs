//! "White" Monte Carlo for profile tables: every albedo of a table from one walk.
//!
//! In mean free paths (σt = 1), a photon's path through a homogeneous half-space does not depend
//! on the single-scattering albedo α: with implicit capture only its weight does, w₀·αⁿ after n
//! interactions (MCML's `Drop` keeps the fraction α of the weight at each one). So one walk,
//! tallied by the interaction count n of each exit, gives every albedo's reflectance: an exit of
//! weight W after n interactions of a walk at albedo α_max counts W·(α/α_max)ⁿ for albedo α
//! (Alerstam, Andersson-Engels & Svensson 2008, "White Monte Carlo for time-resolved photon
//! migration", in its interaction-count form).
//!
//! **The walk is the largest albedo's own.** It is traced exactly as the per-albedo build traces
//! α_max (same medium, same random streams, same weight, importance and path-length roulettes,
//! all decided on α_max's weight), so that row of the table is bit-identical to the per-albedo
//! build's, and nothing is cut: a roulette multiplies the weight of every albedo by the same
//! factor 1/p or 0, which leaves each albedo's expectation unchanged (E[factor] = 1). The
//! smaller albedos lose nothing to the roulettes' choice of photons: a photon the roulette plays
//! carries less than 10⁻⁴ of α_max's weight (or, in the importance roulette, is deep enough that
//! diffusion returns less than that), and at least as little of every smaller albedo's, since
//! (α/α_max)ⁿ ≤ 1 and the attenuation μ_eff grows as α falls.
//!
//! **Standard errors** come from the same photons, per albedo: a photon leaves at most once, so
//! each exit adds W_α and W_α² to its bins as in every other tally. The albedos' estimates are
//! correlated with each other (one walk), never within an albedo.
//!
//! Cost: the largest albedo's walk, plus per exit one exponential and one tally update per albedo,
//! instead of one walk per albedo. The largest albedo is tallied on each radial level as its own
//! walk tallies it; every other albedo on the levels' common intervals (between consecutive edges
//! of all levels: each interval lies within one bin of every level), summed into the levels' bins
//! once per chunk. One update per exit and albedo instead of one per level (ten in a table) made
//! the default table's white build 9 % faster, and the exponentials taken [`LANES`] albedos at a
//! time another 4 %.

use std::ops::Range;

use crate::batch::{BatchSpec, GroupJob};
use crate::grid::{Grid, GridIndex};
use crate::job::{Job, accumulate_job};
use crate::lanes::{LANES, Wide, trace_photons};
use crate::layer::Incidence;
use crate::photon::{Depth, Photon, Scorer};
use crate::rng::Rng;
use crate::tally::{Accumulator, Layout, Tally};

/// The white walk of a table: the walk of its largest albedo, tallied for every albedo.
struct WhiteJob {
    /// The largest albedo's walk (its medium, seed and tally layout).
    walk: GroupJob,
    /// ln(α/α_max) (−∞ at α = 0) of the albedos below the largest, in lanes from the largest
    /// down: (first albedo, albedos, their ratios in increasing order, −∞ in unused lanes).
    ln_ratio: Vec<(usize, usize, Wide)>,
    /// Albedos of the table.
    albedos: usize,
    /// The radial grids of a table's levels [mean free paths]: the channels of one albedo.
    levels: Vec<GridIndex>,
    /// The edges of every level's bins, increasing [mean free paths]: interval i is
    /// [edges[i − 1], edges[i]) (from 0, the last to ∞).
    edges: Vec<f64>,
    /// Interval i's bin on level j: `interval_bins[i · levels + j]`.
    interval_bins: Vec<usize>,
    /// Every albedo's levels, albedo-major: channel i·levels + j is albedo i on level j.
    layout: Layout,
}

/// The exact sums of chunks `chunks` of a white build of `batch` (a table's batch: per albedo,
/// in increasing order, one walk group of channels with one radial grid each, its levels), as the
/// per-albedo build returns them: one accumulator per albedo, each with that group's layout and
/// the run's photons. The walk's interactions are counted once, on the largest albedo's (the
/// walk traced); the others' are 0.
pub(crate) fn accumulate(
    batch: &BatchSpec,
    albedos: &[f64],
    chunks: Range<u64>,
    progress: &(dyn Fn(u64) + Sync),
) -> Vec<Accumulator> {
    let groups = batch.groups();
    debug_assert_eq!(groups.len(), albedos.len());
    let last = groups.last().expect("a table has albedos");
    let walk = GroupJob::new(batch, last, Incidence::NORMAL);
    let per_albedo = walk.layout();
    let grids: Vec<Grid> = last.iter().map(|&c| batch.channels[c].grid).collect();
    let (edges, interval_bins) = intervals(&grids);
    let job = WhiteJob {
        ln_ratio: ratio_lanes(albedos),
        albedos: albedos.len(),
        levels: grids.iter().map(GridIndex::new).collect(),
        edges,
        interval_bins,
        layout: Layout {
            channels: albedos.len() * last.len(),
            ..per_albedo
        },
        walk,
    };
    let seed = job.walk.seed();
    let all = accumulate_job(&job, batch.photons, seed, chunks, progress);
    // Channel blocks are contiguous: albedo i's channels are [i·levels, (i + 1)·levels).
    let block = per_albedo.channels * per_albedo.per_channel();
    (0..albedos.len())
        .map(|i| Accumulator {
            layout: per_albedo,
            sum: all.sum[i * block..(i + 1) * block].to_vec(),
            sum_sq: all.sum_sq[i * block..(i + 1) * block].to_vec(),
            photons: all.photons,
            interactions: if i + 1 == albedos.len() {
                all.interactions
            } else {
                0
            },
        })
        .collect()
}

/// ln(α/α_max) of the albedos below the largest, LANES at a time from the largest down.
fn ratio_lanes(albedos: &[f64]) -> Vec<(usize, usize, Wide)> {
    let max = *albedos.last().expect("a table has albedos");
    let below = albedos.len() - 1;
    (0..below.div_ceil(LANES))
        .map(|c| {
            let hi = below - c * LANES;
            let lo = hi.saturating_sub(LANES);
            let mut lanes = [f64::NEG_INFINITY; LANES];
            for (l, &a) in lanes.iter_mut().zip(&albedos[lo..hi]) {
                *l = (a / max).ln();
            }
            (lo, hi - lo, Wide::from(lanes))
        })
        .collect()
}

/// The common intervals of radial grids: every bin edge of every grid, increasing (edges that
/// agree to 10⁻¹² are one), and each interval's bin on each grid (read at its midpoint; the last
/// interval, beyond every edge, in each grid's last bin).
fn intervals(grids: &[Grid]) -> (Vec<f64>, Vec<usize>) {
    let mut edges: Vec<f64> = grids
        .iter()
        .flat_map(|g| (1..g.nr).map(move |k| k as f64 * g.dr))
        .collect();
    edges.sort_by(f64::total_cmp);
    edges.dedup_by(|b, a| *b - *a <= 1e-12 * *a);
    let index: Vec<GridIndex> = grids.iter().map(GridIndex::new).collect();
    let bins = (0..=edges.len())
        .flat_map(|i| {
            let lo = if i == 0 { 0.0 } else { edges[i - 1] };
            let mid = edges.get(i).map_or(2.0 * lo, |hi| 0.5 * (lo + hi));
            index.iter().map(move |g| g.ir(mid))
        })
        .collect();
    (edges, bins)
}

impl Job for WhiteJob {
    fn layout(&self) -> Layout {
        self.layout
    }

    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64) {
        let intervals = self.edges.len() + 1;
        let others = self.albedos - 1;
        let mut scorer = WhiteScorer {
            job: self,
            tally,
            sum: vec![0.0; others * intervals],
            sum_sq: vec![0.0; others * intervals],
        };
        trace_photons(self.walk.medium(), rng, &mut scorer, photons);
        // The other albedos' intervals into their levels' bins.
        let WhiteScorer {
            tally, sum, sum_sq, ..
        } = scorer;
        let l = tally.layout;
        let levels = self.levels.len();
        for a in 0..others {
            for i in 0..intervals {
                let (s, s2) = (sum[a * intervals + i], sum_sq[a * intervals + i]);
                if s == 0.0 {
                    continue;
                }
                for (j, &ir) in self.interval_bins[i * levels..(i + 1) * levels]
                    .iter()
                    .enumerate()
                {
                    let o = l.rd_ra(a * levels + j) + ir * l.na;
                    tally.sum[o] += s;
                    tally.sum_sq[o] += s2;
                }
            }
        }
    }
}

/// Scores each exit through the top for every albedo, reweighted by (α/α_max)ⁿ.
struct WhiteScorer<'a> {
    job: &'a WhiteJob,
    tally: &'a mut Tally,
    /// Σw and Σw² per albedo below the largest and interval, albedo-major.
    sum: Vec<f64>,
    sum_sq: Vec<f64>,
}

impl Scorer for WhiteScorer<'_> {
    fn depth(&self) -> Depth {
        Depth::None
    }

    // A table keeps only what leaves through the top: deposits are not tallied.
    fn absorb(&mut self, _: &Photon, _: f64) {}
    fn deposit_summed(&mut self, _: f64, _: f64, _: f64) {}
    fn absorb_total(&mut self, _: &Photon, _: f64) {}

    #[inline]
    fn escape(&mut self, p: &Photon, top: bool, _: f64) {
        // The half-space is 10⁶ mean free paths thick: nothing reaches its bottom (e^{−10⁶}), and
        // a table has no transmittance to tally.
        if !top {
            return;
        }
        let job = self.job;
        let l = self.tally.layout;
        let r = p.r();
        let levels = job.levels.len();
        let top = job.albedos - 1;
        // The largest albedo: its own walk's weight, on each level as that walk tallies it.
        let w2 = p.w * p.w;
        for (j, g) in job.levels.iter().enumerate() {
            let o = l.rd_ra(top * levels + j) + g.ir(r) * l.na;
            self.tally.sum[o] += p.w;
            self.tally.sum_sq[o] += w2;
        }
        let intervals = job.edges.len() + 1;
        let i = job.edges.partition_point(|&e| e <= r);
        let n = Wide::splat(p.interactions as f64);
        // From the largest albedo down: once a weight underflows, every smaller albedo's does.
        for &(lo, len, ln_ratio) in &job.ln_ratio {
            // (α/α_max)ⁿ; n = 0 (no interaction) leaves every albedo's weight alone, even α = 0.
            let w = if p.interactions == 0 {
                [p.w; LANES]
            } else {
                ((n * ln_ratio).exp() * Wide::splat(p.w)).to_array()
            };
            for (k, &w) in w[..len].iter().enumerate() {
                self.sum[(lo + k) * intervals + i] += w;
                self.sum_sq[(lo + k) * intervals + i] += w * w;
            }
            if w[len - 1] == 0.0 {
                break;
            }
        }
    }

    fn finish(&mut self, p: &Photon) {
        self.tally.photons += 1;
        self.tally.interactions += p.interactions;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every radius falls in the interval whose bins are its own bins on each level: the
    /// intervals of a table's levels (widths 10⁻³·4ʲ, 20 bins) sum into the levels' bins exactly
    /// as the exits would have been binned one by one.
    #[test]
    fn an_interval_lies_in_one_bin_of_every_level() {
        let grids: Vec<Grid> = (0..10)
            .map(|j| Grid {
                dr: 1e-3 * 4f64.powi(j),
                dz: 1.0,
                nr: 20,
                nz: 1,
                na: 1,
            })
            .collect();
        let (edges, bins) = intervals(&grids);
        // Level 0's 19 edges, then 15 new ones per level (its first four are the last level's).
        assert_eq!(edges.len(), 19 + 9 * 15);
        assert!(edges.windows(2).all(|w| w[0] < w[1]));
        let index: Vec<GridIndex> = grids.iter().map(GridIndex::new).collect();
        let mut x = 1u64;
        let radii = (0..20_000).map(|_| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            // Log-uniform from 10⁻⁴ to 10⁴ mean free paths.
            10f64.powf(-4.0 + 8.0 * (x >> 11) as f64 / (1u64 << 53) as f64)
        });
        for r in radii.chain(edges.iter().map(|e| e * (1.0 + 1e-9))) {
            let i = edges.partition_point(|&e| e <= r);
            for (j, g) in index.iter().enumerate() {
                assert_eq!(bins[i * grids.len() + j], g.ir(r), "r = {r}, level {j}");
            }
        }
    }
}
