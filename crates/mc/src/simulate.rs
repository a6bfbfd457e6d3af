//! The run driver: splits N photons into fixed chunks of [`CHUNK_PHOTONS`], traces the chunks in
//! parallel on the caller's rayon pool, each with its own random stream, and sums the chunk
//! tallies exactly. The same seed therefore gives bit-identical results with any thread count,
//! and a run can be cut into shards (disjoint chunk ranges) that merge into the unsharded run.

use std::ops::Range;

use rayon::prelude::*;

use crate::error::{McError, Result};
use crate::grid::Grid;
use crate::layer::Sample;
use crate::output::Output;
use crate::photon::{trace, Medium};
use crate::rng::{chunk_rng, CHUNK_PHOTONS};
use crate::tally::{Accumulator, Layout, McmlScorer, Tally, TallySet};

/// One single-channel simulation: what MCML calls a run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    pub sample: Sample,
    pub grid: Grid,
    /// Number of photon packets.
    pub photons: u64,
    /// Seed of every random stream of the run.
    pub seed: u64,
    pub tallies: TallySet,
}

impl RunSpec {
    pub fn validate(&self) -> Result<()> {
        self.sample.validate()?;
        self.grid.validate()?;
        if self.photons == 0 {
            return Err(McError::invalid("photons", 0, "must be at least 1"));
        }
        Ok(())
    }

    /// Number of chunks the photons are split into.
    pub fn chunks(&self) -> u64 {
        self.photons.div_ceil(CHUNK_PHOTONS)
    }

    /// Layout of this run's tallies.
    pub fn layout(&self) -> Layout {
        Layout {
            nr: self.grid.nr,
            nz: self.grid.nz,
            na: self.grid.na,
            layers: self.sample.layers.len(),
            rz: self.tallies.absorption_rz,
            channels: 1,
        }
    }

    /// Specular reflectance at entry [-].
    pub fn rsp(&self) -> f64 {
        Medium::new(&self.sample).rsp
    }
}

/// Photons in chunk `c` of a run of `photons`.
pub(crate) fn chunk_len(photons: u64, c: u64) -> u64 {
    CHUNK_PHOTONS.min(photons - c * CHUNK_PHOTONS)
}

/// Runs the whole simulation and normalizes it. `progress` is called after each chunk with the
/// number of photons just finished (from any thread).
pub fn run(spec: &RunSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<Output> {
    let acc = accumulate(spec, 0..spec.chunks(), progress)?;
    Ok(Output::from_accumulator(&acc, 0, spec.grid, spec.rsp()))
}

/// Traces the chunks in `chunks` (a shard of the run) and returns their exact sums.
pub fn accumulate(spec: &RunSpec, chunks: Range<u64>, progress: &(dyn Fn(u64) + Sync)) -> Result<Accumulator> {
    spec.validate()?;
    if chunks.end > spec.chunks() {
        return Err(McError::invalid("chunks", chunks.end, "beyond the run's last chunk"));
    }
    let medium = Medium::new(&spec.sample);
    let layout = spec.layout();
    let acc = chunks
        .into_par_iter()
        .fold(
            || (Tally::new(layout), Accumulator::new(layout)),
            |(mut tally, mut acc), c| {
                let n = chunk_len(spec.photons, c);
                let mut rng = chunk_rng(spec.seed, c);
                let mut scorer = McmlScorer::new(&mut tally, spec.grid);
                for _ in 0..n {
                    trace(&medium, &mut rng, &mut scorer);
                }
                tally.drain_into(&mut acc);
                progress(n);
                (tally, acc)
            },
        )
        .map(|(_, acc)| acc)
        .reduce(
            || Accumulator::new(layout),
            |mut a, b| {
                a.merge(&b);
                a
            },
        );
    Ok(acc)
}
