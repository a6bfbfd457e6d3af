//! Batch tracing by similarity: one random walk scores every channel that shares the walk's
//! shape.
//!
//! In a single homogeneous layer, measured in mean free paths 1/μt, the walk depends only on g,
//! the refractive indices and the optical thickness τ = μt·d; μt only rescales lengths
//! (Rd(r) = μt²·R*(μt·r)) and the albedo a enters only through the weight. With implicit capture a
//! channel's weight after n interactions is F·aⁿ, F the product of roulette factors. So one walk in
//! walk units (μt = 1) with the largest albedo a_lead scores every channel k of the group:
//! - it carries w_k, multiplied by a_k at each interaction (the deposit w_k(1−a_k) is channel k's
//!   absorption) and by the roulette factor, which is decided on the lead weight, the largest of
//!   all (unbiased for every channel: the same random factor of expectation 1 multiplies all);
//! - at exit, channel k tallies w_k at radius r/μt_k on its own grid; exit angles are shared.
//!
//! Channels group when g, η and the ambient indices are equal and the optical thicknesses are
//! equal or all at least [`QUASI_INFINITE_MFP`] mean free paths (the thesis's 10⁸ cm half-space):
//! no photon of any practical run gets that deep. Channels that do not interact (μt = 0) form
//! groups of their own and use MCML's glass-layer walk.

use crate::rng::Rng;

use crate::error::{McError, Result};
use crate::grid::{Grid, GridIndex};
use crate::incidence::Incidence;
use crate::layer::{Layer, Sample};
use crate::output::Output;
use crate::photon::{Medium, Photon, Scorer, trace};
use crate::simulate::Job;
use crate::tally::{Layout, Tally, TallySet};

/// Optical thickness [mean free paths 1/μt] from which slabs count as half-spaces for grouping.
pub const QUASI_INFINITE_MFP: f64 = 1.0e6;

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

impl BatchSpec {
    /// Checks every channel and count; errors name the channel and field.
    pub fn validate(&self) -> Result<()> {
        if self.channels.is_empty() {
            return Err(McError::invalid(
                "channels",
                0,
                "at least one channel is required",
            ));
        }
        if self.photons == 0 {
            return Err(McError::invalid("photons", 0, "must be at least 1"));
        }
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
        Ok(())
    }

    /// Channel indices grouped into walks, in order of first appearance.
    pub fn groups(&self) -> Vec<Vec<usize>> {
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for (i, c) in self.channels.iter().enumerate() {
            let found = groups.iter_mut().find(|g| {
                let h = &self.channels[g[0]].layer;
                let l = &c.layer;
                let tau = |l: &Layer| l.mu_t() * l.thickness;
                let same_tau = tau(l) == tau(h)
                    || (tau(l) >= QUASI_INFINITE_MFP && tau(h) >= QUASI_INFINITE_MFP);
                l.mu_t() > 0.0 && h.mu_t() > 0.0 && l.g == h.g && l.n == h.n && same_tau
            });
            match found {
                Some(g) => g.push(i),
                None => groups.push(vec![i]),
            }
        }
        groups
    }
}

/// The walk and scorer setup of one group.
pub(crate) struct GroupJob {
    medium: Medium,
    /// Per channel: albedo, length scale 1/μt [cm per walk unit] (1 for a glass channel), grid.
    albedo: Vec<f64>,
    scale: Vec<f64>,
    grids: Vec<Grid>,
    index: Vec<GridIndex>,
    layout: Layout,
}

impl GroupJob {
    pub fn new(spec: &BatchSpec, group: &[usize], incidence: Incidence) -> Self {
        let chans: Vec<&ChannelSpec> = group.iter().map(|&i| &spec.channels[i]).collect();
        let first = chans[0].layer;
        let albedo: Vec<f64> = chans.iter().map(|c| c.layer.albedo()).collect();
        let (layer, scale) = if first.mu_t() == 0.0 {
            (first, vec![1.0])
        } else {
            let a_lead = albedo.iter().cloned().fold(0.0, f64::max);
            let tau = chans
                .iter()
                .map(|c| c.layer.mu_t() * c.layer.thickness)
                .fold(f64::INFINITY, f64::min);
            let walk = Layer {
                n: first.n,
                mu_a: 1.0 - a_lead,
                mu_s: a_lead,
                g: first.g,
                thickness: tau,
            };
            (walk, chans.iter().map(|c| 1.0 / c.layer.mu_t()).collect())
        };
        let medium = Medium::at(
            &Sample {
                n_above: spec.n_above,
                n_below: spec.n_below,
                layers: vec![layer],
            },
            incidence,
        );
        // Strides are the largest sizes of the group; each channel bins and normalizes on its own grid.
        let max = |f: fn(&Grid) -> usize| chans.iter().map(|c| f(&c.grid)).max().unwrap_or(1);
        let layout = Layout {
            nr: max(|g| g.nr),
            nz: max(|g| g.nz),
            na: max(|g| g.na),
            layers: 1,
            rz: spec.tallies.absorption_rz,
            channels: chans.len(),
            xy: spec.tallies.surface_xy,
        };
        GroupJob {
            medium,
            albedo,
            scale,
            grids: chans.iter().map(|c| c.grid).collect(),
            index: chans.iter().map(|c| GridIndex::new(&c.grid)).collect(),
            layout,
        }
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
        for _ in 0..photons {
            scorer.start(1.0 - self.medium.rsp);
            trace(&self.medium, rng, &mut scorer);
        }
    }
}

/// Scores every channel of a group from one walk.
///
/// Channel k's weight after n interactions is F·aₖⁿ (F: launch weight times roulette factors), so
/// nothing is done per interaction unless A(r,z) is tallied. Absorption is summed per roulette
/// segment in closed form: between interactions n₀ and n at constant F a channel deposits
/// F·(aₖ^{n₀} − aₖⁿ).
struct BatchScorer<'a> {
    job: &'a GroupJob,
    tally: &'a mut Tally,
    /// F: launch weight times the roulette factors so far.
    factor: f64,
    /// Interaction count at the start of the current roulette segment.
    n0: u64,
    /// aₖ^{n₀} per channel.
    a_n0: Vec<f64>,
    /// Weight absorbed so far by each channel in this photon's history.
    absorbed: Vec<f64>,
    /// Current weight F·aₖⁿ of each channel, kept per interaction only when A(r,z) is tallied.
    w: Vec<f64>,
    /// Per-photon A(r,z) and A(z) deposits of every channel (when tallied): dense + touched list.
    rz: Vec<f64>,
    z: Vec<f64>,
    touched_rz: Vec<u32>,
    touched_z: Vec<u32>,
}

/// aⁿ for an interaction count (repeated squaring; counts beyond i32 are unreachable in practice
/// thanks to the path-length roulette, and clamp harmlessly to aⁿ = 0 or 1).
#[inline]
fn pow_n(a: f64, n: u64) -> f64 {
    a.powi(n.min(i32::MAX as u64) as i32)
}

impl<'a> BatchScorer<'a> {
    fn new(job: &'a GroupJob, tally: &'a mut Tally) -> Self {
        let l = job.layout;
        let k = l.channels;
        let (rz, z) = if l.rz {
            (vec![0.0; k * l.nr * l.nz], vec![0.0; k * l.nz])
        } else {
            (Vec::new(), Vec::new())
        };
        BatchScorer {
            job,
            tally,
            factor: 0.0,
            n0: 0,
            a_n0: vec![1.0; k],
            absorbed: vec![0.0; k],
            w: vec![0.0; k],
            rz,
            z,
            touched_rz: Vec::new(),
            touched_z: Vec::new(),
        }
    }

    fn start(&mut self, w0: f64) {
        self.factor = w0;
        self.n0 = 0;
        self.a_n0.fill(1.0);
        self.absorbed.fill(0.0);
        self.w.fill(w0);
    }

    /// Closes the current roulette segment at interaction `n`.
    fn close_segment(&mut self, n: u64) {
        for ((abs, a_n0), &a) in self
            .absorbed
            .iter_mut()
            .zip(self.a_n0.iter_mut())
            .zip(&self.job.albedo)
        {
            let a_n = pow_n(a, n);
            *abs += self.factor * (*a_n0 - a_n);
            *a_n0 = a_n;
        }
        self.n0 = n;
    }
}

impl Scorer for BatchScorer<'_> {
    #[inline]
    fn absorb(&mut self, p: &Photon, _: f64) {
        let job = self.job;
        let l = job.layout;
        if !l.rz {
            return;
        }
        let r = p.r();
        for k in 0..l.channels {
            let dw = self.w[k] * (1.0 - job.albedo[k]);
            self.w[k] -= dw;
            if dw == 0.0 {
                continue;
            }
            let g = &job.index[k];
            let iz = g.iz(p.z * job.scale[k]);
            let i = (k * l.nr + g.ir(r * job.scale[k])) * l.nz + iz; // [k][ir][iz], layout strides
            if self.rz[i] == 0.0 {
                self.touched_rz.push(i as u32);
            }
            self.rz[i] += dw;
            let j = k * l.nz + iz;
            if self.z[j] == 0.0 {
                self.touched_z.push(j as u32);
            }
            self.z[j] += dw;
        }
    }

    fn roulette(&mut self, p: &Photon, factor: f64) {
        self.close_segment(p.interactions);
        self.factor *= factor;
        for w in &mut self.w {
            *w *= factor;
        }
    }

    #[inline]
    fn escape(&mut self, p: &Photon, top: bool, cos_exit: f64) {
        let job = self.job;
        let l = job.layout;
        let r = p.r();
        for k in 0..l.channels {
            let w = self.factor * pow_n(job.albedo[k], p.interactions);
            if w == 0.0 {
                continue;
            }
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
        if self.factor > 0.0 && p.interactions > self.n0 {
            self.close_segment(p.interactions);
        }
        let l = self.job.layout;
        let t = &mut *self.tally;
        for k in 0..l.channels {
            let a = self.absorbed[k];
            for o in [l.a_total(k), l.a_l(k)] {
                t.sum[o] += a;
                t.sum_sq[o] += a * a;
            }
        }
        if l.rz {
            let per_rz = l.nr * l.nz;
            for &i in &self.touched_rz {
                let i = i as usize;
                let (k, j) = (i / per_rz, i % per_rz);
                let v = std::mem::take(&mut self.rz[i]);
                t.sum[l.a_rz(k) + j] += v;
                t.sum_sq[l.a_rz(k) + j] += v * v;
            }
            for &i in &self.touched_z {
                let i = i as usize;
                let (k, j) = (i / l.nz, i % l.nz);
                let v = std::mem::take(&mut self.z[i]);
                t.sum[l.a_z(k) + j] += v;
                t.sum_sq[l.a_z(k) + j] += v * v;
            }
            self.touched_rz.clear();
            self.touched_z.clear();
        }
        t.photons += 1;
        t.interactions += p.interactions;
    }
}
