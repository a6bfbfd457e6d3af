//! Runs: MCML's single-channel run, batches of channels and error-targeted runs, all on the
//! chunked, thread-count-independent driver of [`crate::job`].
//!
//! Error-targeted runs trace rounds of [`ROUND_CHUNKS`] chunks and stop after the first round at
//! which the target is met; the decision depends only on the tallies, so it is as reproducible as
//! a fixed photon count.

use std::ops::Range;

use crate::batch::{BatchSpec, GroupJob};
use crate::error::{McError, Result};
use crate::grid::Grid;
use crate::job::{Job, accumulate_job, chunk_count};
use crate::lanes::trace_photons;
use crate::layer::Incidence;
use crate::layer::Sample;
use crate::output::Output;
use crate::photon::Medium;
use crate::rng::Rng;
use crate::tally::{Accumulator, Layout, McmlScorer, Tally, TallySet};

/// Chunks per round of an error-targeted run.
pub const ROUND_CHUNKS: u64 = 4;

/// One single-channel simulation of a layered sample: what MCML calls a run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// The layered sample (cm, cm⁻¹).
    pub sample: Sample,
    /// The tally grid [cm].
    pub grid: Grid,
    /// Number of photon packets.
    pub photons: u64,
    /// Seed of every random stream of the run.
    pub seed: u64,
    /// Which optional tallies to record.
    pub tallies: TallySet,
}

impl RunSpec {
    /// The single run of a batch's `channel` with `photons` packets (as the channel's output
    /// reports them): the ambient media, the channel's layer and grid, the batch's seed and
    /// tallies. What MCML's `.mco` header describes for that channel.
    pub fn of_channel(batch: &BatchSpec, channel: usize, photons: u64) -> RunSpec {
        let c = &batch.channels[channel];
        RunSpec {
            sample: Sample {
                n_above: batch.n_above,
                n_below: batch.n_below,
                layers: vec![c.layer],
            },
            grid: c.grid,
            photons,
            seed: batch.seed,
            tallies: batch.tallies,
        }
    }

    /// Checks the sample, grid and photon count.
    pub fn validate(&self) -> Result<()> {
        self.sample.validate()?;
        self.grid.validate()?;
        crate::job::check_photons(self.photons)?;
        Ok(())
    }

    /// Specular reflectance at entry [-].
    pub fn rsp(&self) -> f64 {
        Medium::new(&self.sample).rsp
    }
}

struct McmlJob<'a> {
    medium: Medium,
    spec: &'a RunSpec,
}

impl Job for McmlJob<'_> {
    fn layout(&self) -> Layout {
        let g = self.spec.grid;
        Layout {
            nr: g.nr,
            nz: g.nz,
            na: g.na,
            layers: self.spec.sample.layers.len(),
            rz: self.spec.tallies.absorption_rz,
            rz_se: self.spec.tallies.absorption_rz_se,
            channels: 1,
            xy: self.spec.tallies.surface_xy,
            scores: 0,
        }
    }

    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64) {
        let mut scorer = McmlScorer::new(tally, self.spec.grid);
        trace_photons(&self.medium, rng, &mut scorer, photons);
    }
}

/// Runs an MCML run and normalizes it.
pub fn run(spec: &RunSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<Output> {
    run_at(spec, Incidence::NORMAL, progress)
}

/// Runs an MCML run under a beam at `incidence` and normalizes it.
pub fn run_at(
    spec: &RunSpec,
    incidence: Incidence,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Output> {
    spec.validate()?;
    incidence.validate_for(&spec.sample)?;
    let job = McmlJob {
        medium: Medium::at(&spec.sample, incidence).with_importance(!spec.tallies.absorption_rz),
        spec,
    };
    let acc = accumulate_job(
        &job,
        spec.photons,
        spec.seed,
        0..chunk_count(spec.photons),
        progress,
    );
    Ok(Output::from_accumulator(&acc, 0, spec.grid, job.medium.rsp))
}

/// Traces the chunks `chunks` (a shard) of an MCML run.
pub fn accumulate(
    spec: &RunSpec,
    chunks: Range<u64>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Accumulator> {
    spec.validate()?;
    check_chunks(&chunks, spec.photons)?;
    let job = McmlJob {
        medium: Medium::new(&spec.sample).with_importance(!spec.tallies.absorption_rz),
        spec,
    };
    Ok(accumulate_job(
        &job,
        spec.photons,
        spec.seed,
        chunks,
        progress,
    ))
}

fn check_chunks(chunks: &Range<u64>, photons: u64) -> Result<()> {
    if chunks.start > chunks.end || chunks.end > chunk_count(photons) {
        return Err(McError::invalid(
            "chunks",
            format!("{chunks:?}"),
            "outside the run's chunks",
        ));
    }
    Ok(())
}

/// Traces chunks `chunks` of every group of a batch (one accumulator per group, in
/// [`BatchSpec::groups`] order).
pub fn accumulate_batch(
    spec: &BatchSpec,
    chunks: Range<u64>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Accumulator>> {
    accumulate_batch_at(spec, Incidence::NORMAL, chunks, progress)
}

fn accumulate_batch_at(
    spec: &BatchSpec,
    incidence: Incidence,
    chunks: Range<u64>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Accumulator>> {
    spec.validate()?;
    for c in &spec.channels {
        incidence.validate_for(&Sample {
            n_above: spec.n_above,
            n_below: spec.n_below,
            layers: vec![c.layer],
        })?;
    }
    check_chunks(&chunks, spec.photons)?;
    Ok(spec
        .groups()
        .iter()
        .map(|group| {
            let job = GroupJob::new(spec, group, incidence);
            accumulate_job(&job, spec.photons, job.seed(), chunks.clone(), progress)
        })
        .collect())
}

/// Normalizes a batch's group accumulators into one [`Output`] per channel, in channel order.
pub fn batch_outputs(spec: &BatchSpec, accs: &[Accumulator]) -> Vec<Output> {
    batch_outputs_at(spec, Incidence::NORMAL, accs)
}

fn batch_outputs_at(spec: &BatchSpec, incidence: Incidence, accs: &[Accumulator]) -> Vec<Output> {
    let mut out: Vec<Option<Output>> = vec![None; spec.channels.len()];
    for (group, acc) in spec.groups().iter().zip(accs) {
        let job = GroupJob::new(spec, group, incidence);
        for (k, &ch) in group.iter().enumerate() {
            out[ch] = Some(job.output(acc, k));
        }
    }
    out.into_iter()
        .map(|o| o.expect("every channel is in one group"))
        .collect()
}

/// Runs every channel of a batch, grouped by similarity, for `spec.photons` photons each.
pub fn run_batch(spec: &BatchSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<Vec<Output>> {
    run_batch_at(spec, Incidence::NORMAL, progress)
}

/// [`run_batch`] under a beam at `incidence`.
pub fn run_batch_at(
    spec: &BatchSpec,
    incidence: Incidence,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Output>> {
    let accs = accumulate_batch_at(spec, incidence, 0..chunk_count(spec.photons), progress)?;
    Ok(batch_outputs_at(spec, incidence, &accs))
}

/// The stopping statistic of an error-targeted run for one channel: the larger of
/// - the relative standard error of total Rd, and
/// - the relative RMS noise of the profile r·Rd(r) (the energy per annulus, what a kernel is
///   built from) over the bins with r ≤ `r_max` [cm]: √(Σ rᵢ² seᵢ²) / √(Σ rᵢ² Rdᵢ²).
///
/// The CLI uses `r_max` = 3 transport mean free paths of the channel. Infinite while nothing
/// has been scored.
pub fn relative_error(o: &Output, r_max: f64) -> f64 {
    let rel_rd = if o.rd.value > 0.0 {
        o.rd.se / o.rd.value
    } else {
        f64::INFINITY
    };
    let (mut noise, mut signal) = (0.0, 0.0);
    for i in (0..o.grid.nr).take_while(|&i| i == 0 || i as f64 * o.grid.dr <= r_max) {
        let r = o.grid.r_optimal(i);
        noise += (r * o.rd_r[i].se).powi(2);
        signal += (r * o.rd_r[i].value).powi(2);
    }
    let rel_profile = if signal > 0.0 {
        (noise / signal).sqrt()
    } else {
        f64::INFINITY
    };
    rel_rd.max(rel_profile)
}

/// Runs each group of a batch in rounds of [`ROUND_CHUNKS`] chunks until every channel's
/// [`relative_error`] (with `r_max[channel]`, e.g. [`BatchSpec::error_radii`]) is at most `target`, or `spec.photons` photons are
/// traced. Returns the outputs (photon counts may differ between groups).
pub fn run_batch_to_error(
    spec: &BatchSpec,
    target: f64,
    r_max: &[f64],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Output>> {
    spec.validate()?;
    if !(target.is_finite() && target > 0.0) {
        return Err(McError::invalid("target_error", target, "must be positive"));
    }
    let total = chunk_count(spec.photons);
    let mut out: Vec<Option<Output>> = vec![None; spec.channels.len()];
    for group in spec.groups().iter() {
        let job = GroupJob::new(spec, group, Incidence::NORMAL);
        let mut acc = Accumulator::new(job.layout());
        let mut next = 0;
        loop {
            let end = (next + ROUND_CHUNKS).min(total);
            acc.merge(&accumulate_job(
                &job,
                spec.photons,
                job.seed(),
                next..end,
                progress,
            ));
            next = end;
            let worst = group
                .iter()
                .enumerate()
                .map(|(k, &ch)| relative_error(&job.output(&acc, k), r_max[ch]))
                .fold(0.0, f64::max);
            if worst <= target || next == total {
                break;
            }
        }
        for (k, &ch) in group.iter().enumerate() {
            out[ch] = Some(job.output(&acc, k));
        }
    }
    Ok(out
        .into_iter()
        .map(|o| o.expect("every channel is in one group"))
        .collect())
}
