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
//! Cost: the largest albedo's walk, plus per exit one exponential and one tally update per albedo
//! and radial level, instead of one walk per albedo.

use std::ops::Range;

use crate::batch::{BatchSpec, GroupJob};
use crate::grid::GridIndex;
use crate::job::{Job, accumulate_job};
use crate::lanes::trace_photons;
use crate::layer::Incidence;
use crate::photon::{Depth, Photon, Scorer};
use crate::rng::Rng;
use crate::tally::{Accumulator, Layout, Tally};

/// The white walk of a table: the walk of its largest albedo, tallied for every albedo.
struct WhiteJob {
    /// The largest albedo's walk (its medium, seed and tally layout).
    walk: GroupJob,
    /// Per albedo, ln(α/α_max) (−∞ at α = 0), in the table's order.
    ln_ratio: Vec<f64>,
    /// The radial grids of a table's levels [mean free paths]: the channels of one albedo.
    levels: Vec<GridIndex>,
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
    let max = *albedos.last().expect("a table has albedos");
    let job = WhiteJob {
        ln_ratio: albedos.iter().map(|&a| (a / max).ln()).collect(),
        levels: last
            .iter()
            .map(|&c| GridIndex::new(&batch.channels[c].grid))
            .collect(),
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

impl Job for WhiteJob {
    fn layout(&self) -> Layout {
        self.layout
    }

    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64) {
        let mut scorer = WhiteScorer {
            job: self,
            tally,
            bins: vec![0; self.levels.len()],
        };
        trace_photons(self.walk.medium(), rng, &mut scorer, photons);
    }
}

/// Scores each exit through the top for every albedo, reweighted by (α/α_max)ⁿ.
struct WhiteScorer<'a> {
    job: &'a WhiteJob,
    tally: &'a mut Tally,
    /// The exit's radial bin on each level (scratch).
    bins: Vec<usize>,
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
        for (b, g) in self.bins.iter_mut().zip(&job.levels) {
            *b = g.ir(r);
        }
        let levels = self.bins.len();
        let n = p.interactions as f64;
        // From the largest albedo down: once a weight underflows, every smaller albedo's does.
        for (i, &ln_ratio) in job.ln_ratio.iter().enumerate().rev() {
            // (α/α_max)ⁿ; n = 0 (no interaction) leaves every albedo's weight alone, even α = 0.
            let w = if p.interactions == 0 {
                p.w
            } else {
                p.w * (n * ln_ratio).exp()
            };
            if w == 0.0 {
                break;
            }
            let w2 = w * w;
            for (j, &ir) in self.bins.iter().enumerate() {
                let o = l.rd_ra(i * levels + j) + ir * l.na;
                self.tally.sum[o] += w;
                self.tally.sum_sq[o] += w2;
            }
        }
    }

    fn finish(&mut self, p: &Photon) {
        self.tally.photons += 1;
        self.tally.interactions += p.interactions;
    }
}
