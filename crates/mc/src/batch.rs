//! Batch tracing by similarity: channels whose random walks are the same, measured in mean free
//! paths, share one walk.
//!
//! In a single homogeneous layer, measured in mean free paths 1/μt, the walk depends only on the
//! albedo a = μs/μt, g, the refractive indices and the optical thickness τ = μt·d; μt only
//! rescales lengths (Rd(r) = μt²·R*(μt·r)). A channel's [`walk`] is its layer in those units
//! (μt = 1, μa = 1 − a); channels with equal walks are traced once, and at every deposit and exit
//! each channel k tallies the walk's weight at radius r/μt_k and depth z/μt_k on its own grid.
//! Slabs of at least [`QUASI_INFINITE_MFP`] mean free paths are walked as that thick (the
//! thesis's 10⁸ cm half-space: no photon of any practical run gets that deep). Channels that do not
//! interact (μt = 0) are their own walk, in cm, and use MCML's glass-layer walk.
//!
//! Determinism: a walk's random streams are seeded by (seed, ambient indices, walk) — see
//! [`BatchSpec::groups`] — so every channel's result depends only on the seed, the ambient indices,
//! the tallies asked for and the channel itself: never on which other channels share the batch,
//! their order, or how the run is threaded or sharded. This is why channels of different albedo
//! do not share a walk: a shared walk must carry the largest albedo, and its Russian roulette,
//! decided on that weight with draws from the walk's stream, would make every channel's random
//! numbers depend on which channels it was batched with.

use crate::rng::{Rng, stream_seed};

use crate::error::{McError, Result};
use crate::grid::{Grid, GridIndex};
use crate::job::Job;
use crate::lanes::trace_photons;
use crate::layer::Incidence;
use crate::layer::{Layer, Sample};
use crate::output::Output;
use crate::photon::{Depth, Medium, Photon, Scorer};
use crate::tally::{Layout, Scratch, Tally, TallySet, depth_of};

/// Optical thickness [mean free paths 1/μt] from which slabs count as half-spaces: they are
/// walked as exactly this thick.
pub const QUASI_INFINITE_MFP: f64 = 1.0e6;

/// Most tally entries a batch may need in all (each holds two exact i128 sums: 8 GiB), so that
/// an oversized specification is refused before anything is allocated.
const MAX_TALLY_ENTRIES: u128 = 1 << 28;

/// Most cells of a surface grid Rd(x, y), (2n + 1)², as for the grid's 2D tallies.
const MAX_SURFACE_CELLS: usize = 50_000_000;

/// One channel to simulate: a single homogeneous layer (cm, cm⁻¹) and its own tally grid.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ChannelSpec {
    /// The homogeneous layer (cm, cm⁻¹).
    pub layer: Layer,
    /// This channel's tally grid [cm].
    pub grid: Grid,
}

/// Many single-layer channels between the same ambient media, simulated together.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BatchSpec {
    /// Refractive index of the medium above [-].
    pub n_above: f64,
    /// Refractive index of the medium below [-].
    pub n_below: f64,
    /// The channels, in output order.
    pub channels: Vec<ChannelSpec>,
    /// Photon packets per channel.
    pub photons: u64,
    /// Seed of every random stream.
    pub seed: u64,
    /// Which optional tallies to record.
    pub tallies: TallySet,
}

/// The radius [transport mean free paths] within which [`crate::run_batch_to_error`] judges the
/// profile r·Rd(r) of a channel, through [`BatchSpec::error_radii`].
pub const ERROR_RADIUS_MFP: f64 = 3.0;

impl BatchSpec {
    /// Per channel, the radius [cm] within which a run to an error target judges its profile:
    /// [`ERROR_RADIUS_MFP`] transport mean free paths of the channel's layer.
    pub fn error_radii(&self) -> Vec<f64> {
        self.channels
            .iter()
            .map(|c| ERROR_RADIUS_MFP * c.layer.transport_mfp())
            .collect()
    }

    /// Checks every channel and count; errors name the channel and field.
    pub fn validate(&self) -> Result<()> {
        if self.channels.is_empty() {
            return Err(McError::invalid(
                "channels",
                0,
                "at least one channel is required",
            ));
        }
        crate::job::check_photons(self.photons)?;
        for (i, c) in self.channels.iter().enumerate() {
            let s = Sample {
                n_above: self.n_above,
                n_below: self.n_below,
                layers: vec![c.layer],
            };
            s.validate()
                .and_then(|_| c.grid.validate())
                .map_err(|e| match e {
                    McError::InvalidValue {
                        field,
                        value,
                        reason,
                    } => McError::InvalidValue {
                        field: format!("channel {i} {field}"),
                        value,
                        reason,
                    },
                    other => other,
                })?;
        }
        let n = self.tallies.surface_xy;
        if n > 0 && (2 * n.min(MAX_SURFACE_CELLS) + 1).pow(2) > MAX_SURFACE_CELLS {
            return Err(McError::invalid(
                "surface_xy",
                n,
                "the surface grid Rd(x, y) would exceed 5e7 cells",
            ));
        }
        // Sizes are bounded by now (grids ≤ 10⁶ bins per axis), so these products do not overflow.
        let entries: u128 = self
            .groups()
            .iter()
            .map(|g| {
                let l = self.layout(g);
                l.per_channel() as u128 * l.channels as u128
            })
            .sum();
        if entries > MAX_TALLY_ENTRIES {
            return Err(McError::invalid(
                "tally entries",
                entries,
                "at most 2^28 (8 GiB of exact sums) per batch: use fewer channels or coarser grids",
            ));
        }
        Ok(())
    }

    /// Channel indices grouped into walks, in order of first appearance: channels share a walk
    /// when their layers are the same in mean free paths (equal albedo, g and η, and equal optical
    /// thickness or both at least [`QUASI_INFINITE_MFP`]). Each walk is traced with random streams
    /// seeded by (seed, ambient indices, walk) alone, so a channel's result does not depend on the
    /// other channels of the batch.
    pub fn groups(&self) -> Vec<Vec<usize>> {
        let mut groups: Vec<(Layer, Vec<usize>)> = Vec::new();
        for (i, c) in self.channels.iter().enumerate() {
            let w = walk(&c.layer);
            match groups.iter_mut().find(|(v, _)| *v == w) {
                Some((_, g)) => g.push(i),
                None => groups.push((w, vec![i])),
            }
        }
        groups.into_iter().map(|(_, g)| g).collect()
    }

    /// The tally layout of a group: strides are the largest sizes of its channels (each channel
    /// bins and normalizes on its own grid).
    pub(crate) fn layout(&self, group: &[usize]) -> Layout {
        let max = |f: fn(&Grid) -> usize| {
            group
                .iter()
                .map(|&i| f(&self.channels[i].grid))
                .max()
                .unwrap_or(1)
        };
        Layout {
            nr: max(|g| g.nr),
            nz: max(|g| g.nz),
            na: max(|g| g.na),
            layers: 1,
            rz: self.tallies.absorption_rz,
            rz_se: self.tallies.absorption_rz_se,
            channels: group.len(),
            xy: self.tallies.surface_xy,
            scores: 0,
        }
    }

    /// The seed of the random streams of `walk`: the run's seed mixed with everything that fixes
    /// the walk, and nothing else.
    fn walk_seed(&self, walk: &Layer) -> u64 {
        let w = walk;
        // −0 and +0 are one value.
        stream_seed(
            self.seed,
            [
                self.n_above,
                self.n_below,
                w.n,
                w.mu_a,
                w.mu_s,
                w.g,
                w.thickness,
            ]
            .map(|x| (x + 0.0).to_bits()),
        )
    }
}

/// The walk that traces a channel: its layer in walk units (lengths in mean free paths, μt = 1,
/// μa = 1 − a) and at most [`QUASI_INFINITE_MFP`] thick. A layer that does not interact (glass)
/// is its own walk, in cm.
pub(crate) fn walk(layer: &Layer) -> Layer {
    if layer.is_glass() {
        return *layer;
    }
    let mu_t = layer.mu_t();
    let absorb = layer.mu_a / mu_t;
    Layer {
        n: layer.n,
        mu_a: absorb,
        mu_s: 1.0 - absorb,
        g: layer.g,
        thickness: (mu_t * layer.thickness).min(QUASI_INFINITE_MFP),
    }
}

/// The walk and scorer setup of one group.
pub(crate) struct GroupJob {
    medium: Medium,
    /// Seed of the walk's random streams.
    seed: u64,
    /// Per channel: length scale 1/μt [cm per walk unit] (1 for a glass channel), grid.
    scale: Vec<f64>,
    grids: Vec<Grid>,
    index: Vec<GridIndex>,
    layout: Layout,
}

impl GroupJob {
    pub fn new(spec: &BatchSpec, group: &[usize], incidence: Incidence) -> Self {
        let chans: Vec<&ChannelSpec> = group.iter().map(|&i| &spec.channels[i]).collect();
        let walk = walk(&chans[0].layer);
        let medium = Medium::at(
            &Sample {
                n_above: spec.n_above,
                n_below: spec.n_below,
                layers: vec![walk],
            },
            incidence,
        )
        .with_importance(!spec.tallies.absorption_rz);
        let scale = chans
            .iter()
            .map(|c| {
                if c.layer.is_glass() {
                    1.0
                } else {
                    1.0 / c.layer.mu_t()
                }
            })
            .collect();
        GroupJob {
            medium,
            seed: spec.walk_seed(&walk),
            scale,
            grids: chans.iter().map(|c| c.grid).collect(),
            index: chans.iter().map(|c| GridIndex::new(&c.grid)).collect(),
            layout: spec.layout(group),
        }
    }

    /// The medium its walk traces (in walk units).
    pub fn medium(&self) -> &Medium {
        &self.medium
    }

    /// Seed of this group's random streams (chunk streams are derived from it and the chunk index).
    pub fn seed(&self) -> u64 {
        self.seed
    }

    pub fn output(&self, acc: &crate::tally::Accumulator, k: usize) -> Output {
        Output::from_accumulator(acc, k, self.grids[k], self.medium.rsp)
    }
}

impl Job for GroupJob {
    fn layout(&self) -> Layout {
        self.layout
    }

    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64) {
        let mut scorer = BatchScorer::new(self, tally);
        trace_photons(&self.medium, rng, &mut scorer, photons);
    }
}

/// Scores every channel of a group from one walk. The channels' walks are the walk, so its
/// weight is every channel's weight; only the bins differ (lengths times 1/μt_k, on channel k's
/// own grid).
struct BatchScorer<'a> {
    job: &'a GroupJob,
    tally: &'a mut Tally,
    /// Weight absorbed so far in this photon's history.
    absorbed: f64,
    /// This history's A(r,z) and A(z) deposits of every channel, [k][ir][iz] and [k][iz] with the
    /// layout's strides, when their per-photon moments are tallied.
    rz: Option<(Scratch, Scratch)>,
}

impl<'a> BatchScorer<'a> {
    fn new(job: &'a GroupJob, tally: &'a mut Tally) -> Self {
        let l = job.layout;
        let k = l.channels;
        let rz = (l.rz && l.rz_se).then(|| (Scratch::new(k * l.nr * l.nz), Scratch::new(k * l.nz)));
        BatchScorer {
            job,
            tally,
            absorbed: 0.0,
            rz,
        }
    }

    /// Channel `k`'s (A(r,z) cell, A(z) cell) of a deposit at radius `r` and depth `z` [walk
    /// units], counted from the channel's first cell.
    #[inline]
    fn cells(job: &GroupJob, k: usize, r: f64, z: f64) -> (usize, usize) {
        let l = job.layout;
        let g = &job.index[k];
        let iz = g.iz(z * job.scale[k]);
        (g.ir(r * job.scale[k]) * l.nz + iz, iz)
    }
}

impl Scorer for BatchScorer<'_> {
    fn depth(&self) -> Depth {
        depth_of(&self.job.layout)
    }

    #[inline]
    fn absorb(&mut self, p: &Photon, dw: f64) {
        if dw == 0.0 {
            return;
        }
        self.absorbed += dw;
        let l = self.job.layout;
        if let Some((a_rz, a_z)) = &mut self.rz {
            let r = p.r();
            for k in 0..l.channels {
                let (rz, z) = Self::cells(self.job, k, r, p.z);
                a_rz.add(k * l.nr * l.nz + rz, dw);
                a_z.add(k * l.nz + z, dw);
            }
        } else if l.rz {
            self.deposit_summed(p.r(), p.z, dw);
        }
    }

    #[inline]
    fn deposit_summed(&mut self, r: f64, z: f64, dw: f64) {
        let l = self.job.layout;
        for k in 0..l.channels {
            let (rz, z) = Self::cells(self.job, k, r, z);
            self.tally.sum[l.a_rz(k) + rz] += dw;
            self.tally.sum[l.a_z(k) + z] += dw;
        }
    }

    #[inline]
    fn absorb_total(&mut self, _: &Photon, dw: f64) {
        self.absorbed += dw;
    }

    #[inline]
    fn escape(&mut self, p: &Photon, top: bool, cos_exit: f64) {
        let job = self.job;
        let l = job.layout;
        let (r, w) = (p.r(), p.w);
        for k in 0..l.channels {
            let g = &job.index[k];
            let o = if top { l.rd_ra(k) } else { l.tt_ra(k) };
            let i = o + g.ir(r * job.scale[k]) * l.na + g.ia(cos_exit);
            self.tally.sum[i] += w;
            self.tally.sum_sq[i] += w * w;
            if top
                && l.xy > 0
                && let Some(j) = g.ixy(p.x * job.scale[k], p.y * job.scale[k], l.xy)
            {
                self.tally.sum[l.rd_xy(k) + j] += w;
                self.tally.sum_sq[l.rd_xy(k) + j] += w * w;
            }
        }
    }

    fn finish(&mut self, p: &Photon) {
        let l = self.job.layout;
        let t = &mut *self.tally;
        let a = std::mem::take(&mut self.absorbed);
        for k in 0..l.channels {
            for o in [l.a_total(k), l.a_l(k)] {
                t.sum[o] += a;
                t.sum_sq[o] += a * a;
            }
        }
        if let Some((a_rz, a_z)) = &mut self.rz {
            let mut add = |o: usize, v: f64| {
                t.sum[o] += v;
                t.sum_sq[o] += v * v;
            };
            let per_rz = l.nr * l.nz;
            a_rz.drain(|i, v| add(l.a_rz(i / per_rz) + i % per_rz, v));
            a_z.drain(|i, v| add(l.a_z(i / l.nz) + i % l.nz, v));
        }
        t.photons += 1;
        t.interactions += p.interactions;
    }
}
