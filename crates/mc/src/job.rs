//! The driver every run shares: a [`Job`] traces photons into a tally, and [`accumulate_job`]
//! splits N photons into fixed chunks of [`CHUNK_PHOTONS`], traces them in parallel on the
//! caller's rayon pool, each chunk with its own random stream derived from (seed, chunk), and sums
//! the chunk tallies exactly: the same seed gives bit-identical sums with any thread count, and
//! disjoint chunk ranges (shards) merge into exactly the unsharded run.

use std::ops::Range;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::rng::{CHUNK_PHOTONS, Rng, chunk_rng};
use crate::tally::{Accumulator, Layout, Tally};

/// Something that traces photons into a tally: an MCML run or a batch group.
pub(crate) trait Job: Sync {
    fn layout(&self) -> Layout;
    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64);
}

/// The most photon packets per channel a run takes: 10¹⁴, weeks of a large cluster's time at
/// this tracer's speed and far beyond what any profile needs (published references use 10⁸–10⁹).
/// A count above it is a mistake (a unit slip, an exponent typed twice), not a run to start.
pub const MAX_PHOTONS: u64 = 100_000_000_000_000;

/// Refuses a photon count of 0 or above [`MAX_PHOTONS`], naming the field.
pub(crate) fn check_photons(photons: u64) -> crate::Result<()> {
    if photons == 0 {
        return Err(crate::McError::invalid("photons", 0, "must be at least 1"));
    }
    if photons > MAX_PHOTONS {
        return Err(crate::McError::invalid(
            "photons",
            photons,
            "must be at most 1e14 per channel",
        ));
    }
    Ok(())
}

/// Number of chunks a run of `photons` is split into.
pub fn chunk_count(photons: u64) -> u64 {
    photons.div_ceil(CHUNK_PHOTONS)
}

/// Traces chunks `chunks` of a run of `photons` and returns their exact sums. `progress` is called
/// after each chunk with the photons just finished.
///
/// One worker per pool thread, each with one reusable chunk tally, takes the next chunk index from
/// a shared counter and drains its tally into the shared accumulator: exact sums make the result
/// independent of which worker traced which chunk.
pub(crate) fn accumulate_job<J: Job>(
    job: &J,
    photons: u64,
    seed: u64,
    chunks: Range<u64>,
    progress: &(dyn Fn(u64) + Sync),
) -> Accumulator {
    let layout = job.layout();
    let acc = Mutex::new(Accumulator::new(layout));
    let next = AtomicU64::new(chunks.start);
    let workers = rayon::current_num_threads()
        .min((chunks.end - chunks.start) as usize)
        .max(1);
    rayon::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|_| {
                let mut tally = Tally::new(layout);
                loop {
                    let c = next.fetch_add(1, Ordering::Relaxed);
                    if c >= chunks.end {
                        break;
                    }
                    let n = CHUNK_PHOTONS.min(photons - c * CHUNK_PHOTONS);
                    job.trace_chunk(&mut tally, &mut chunk_rng(seed, c), n);
                    tally.drain_into(
                        &mut acc.lock().expect("no worker panics while holding the lock"),
                    );
                    progress(n);
                }
            });
        }
    });
    acc.into_inner().expect("workers are done")
}
