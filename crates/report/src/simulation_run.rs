//! What `sss simulate` runs for named materials: one batch of their channels (walks shared by
//! similarity, [`mc::run_batch`]), optionally to a target error, with Rd(θ) per material; or one
//! deterministic slice of the batch's photon chunks as a shard for `sss merge`. Progress goes to
//! the caller's [`Progress`].

use std::time::Instant;

use mc::incidence::IncidenceRow;
use mc::progress::Progress;
use mc::shard::{self, Shard};
use mc::{BatchSpec, CHANNELS, Material, Output, SimConfig};

use crate::error::Result;
use crate::simulation::Finished;

/// A run of named materials.
pub struct Simulation<'a> {
    /// (slug, material) per material, in the order of the outputs.
    pub materials: Vec<(&'a str, &'a Material)>,
    /// The run settings (grid rule, thickness, ambient η).
    pub config: &'a SimConfig,
    /// Photon packets per channel (the cap with a target error).
    pub photons: u64,
    /// Seed of every random stream.
    pub seed: u64,
    /// Tally A(r, z) as MCML does, for `.mco` files.
    pub full: bool,
    /// Stop each walk group once the relative standard error of total Rd and of r·Rd(r) within
    /// [`mc::ERROR_RADIUS_MFP`] is at most this.
    pub target_error: Option<f64>,
    /// Polar angles [degrees] at which to measure total Rd(θ) per material (none: no Rd(θ)).
    pub incidence_angles: Vec<f64>,
    /// Photon packets per channel and angle for Rd(θ).
    pub incidence_photons: u64,
    /// Trace the profiles on this GPU ([`mc_gpu::run_batch`]) instead of the CPU's threads (Rd(θ)
    /// stays on the CPU); not with a target error or shards.
    pub gpu: Option<&'a gpu::Gpu>,
}

/// A finished run, owned; [`Simulated::finished`] lends it for writing.
pub struct Simulated {
    /// The batch.
    pub spec: BatchSpec,
    /// `SLUG:R`, `SLUG:G`, `SLUG:B` per material.
    pub labels: Vec<String>,
    /// The results, one per channel.
    pub outputs: Vec<Output>,
    /// Rd(θ) per material, or empty.
    pub incidence: Vec<Vec<IncidenceRow>>,
    /// The profile run's wall time [s] (Rd(θ) not included).
    pub seconds: f64,
    /// The relative standard error the run stopped at, if it ran to one.
    pub target_error: Option<f64>,
}

impl Simulated {
    /// The run that shard files of `sss simulate --shard` make up (`sss merge`), given each
    /// file's name and text; its time is the merge's.
    pub fn merge(texts: &[(String, String)]) -> Result<Simulated> {
        let start = Instant::now();
        let shards = (texts.iter())
            .map(|(name, text)| Ok((name.clone(), Shard::from_json(text, name)?)))
            .collect::<mc::Result<Vec<_>>>()?;
        let (spec, labels, accs) = shard::merge(&shards)?;
        shard::check_labels(&labels)?;
        Ok(Simulated {
            outputs: mc::batch_outputs(&spec, &accs),
            spec,
            labels,
            incidence: Vec::new(),
            seconds: start.elapsed().as_secs_f64(),
            target_error: None,
        })
    }

    /// The run as [`Finished`], with the pool's `threads`.
    pub fn finished(&self, threads: usize) -> Finished<'_> {
        Finished {
            spec: &self.spec,
            labels: &self.labels,
            outputs: &self.outputs,
            incidence: &self.incidence,
            seconds: self.seconds,
            threads,
            target_error: self.target_error,
        }
    }
}

impl Simulation<'_> {
    /// The batch of every material's channels and their labels.
    pub fn batch(&self) -> Result<(BatchSpec, Vec<String>)> {
        let materials: Vec<&Material> = self.materials.iter().map(|(_, m)| *m).collect();
        let spec = self
            .config
            .batch(&materials, self.photons, self.seed, !self.full)?;
        let labels = self
            .materials
            .iter()
            .flat_map(|(slug, _)| CHANNELS.iter().map(move |c| format!("{slug}:{c}")))
            .collect();
        Ok((spec, labels))
    }

    /// Runs the batch, then Rd(θ) per material (one profile-only batch each, so that its table
    /// does not depend on which other materials share the run), in the current rayon pool.
    pub fn run(&self, progress: &dyn Progress) -> Result<Simulated> {
        let (spec, labels) = self.batch()?;
        let start = Instant::now();
        let channels = spec.channels.len();
        // The GPU traces each channel on its own; the CPU shares walks within a group.
        let (walks, label) = match self.gpu {
            Some(g) => (
                channels,
                format!("{channels} channel(s) on {}", g.adapter_name),
            ),
            None => {
                let groups = spec.groups().len();
                (
                    groups,
                    format!("{channels} channel(s) in {groups} walk group(s)"),
                )
            }
        };
        progress.begin(&label, self.photons * walks as u64);
        let advance = |k| progress.advance(k);
        let outputs = match (self.gpu, self.target_error) {
            (Some(g), None) => mc_gpu::run_batch(g, &spec, &advance).map_err(Into::into),
            (Some(_), Some(e)) => Err(crate::ReportError::Invalid {
                field: "target_error".into(),
                value: e.to_string(),
                reason: "the GPU tracer runs a fixed number of photons".into(),
            }),
            (None, Some(e)) => {
                mc::run_batch_to_error(&spec, e, &spec.error_radii(), &advance).map_err(Into::into)
            }
            (None, None) => mc::run_batch(&spec, &advance).map_err(Into::into),
        };
        progress.end();
        let outputs = outputs?;
        let seconds = start.elapsed().as_secs_f64();
        let mut incidence = Vec::new();
        for &(slug, m) in self
            .materials
            .iter()
            .filter(|_| !self.incidence_angles.is_empty())
        {
            let s = self
                .config
                .batch(&[m], self.incidence_photons, self.seed, true)?;
            let angles = &self.incidence_angles;
            let total = s.photons * s.groups().len() as u64 * angles.len() as u64;
            progress.begin(
                &format!("{slug}: Rd(θ) at {} angle(s)", angles.len()),
                total,
            );
            let rows = mc::incidence::rd_table(&s, angles, &|k| progress.advance(k));
            progress.end();
            incidence.push(rows?);
        }
        Ok(Simulated {
            spec,
            labels,
            outputs,
            incidence,
            seconds,
            target_error: self.target_error,
        })
    }

    /// Traces the `i`-th of `n` slices of the batch's photon chunks (1-based) as a shard.
    pub fn shard(&self, i: u64, n: u64, progress: &dyn Progress) -> Result<Shard> {
        let (spec, labels) = self.batch()?;
        let chunks = shard::shard_chunks(self.photons, i - 1, n);
        let groups = spec.groups().len() as u64;
        let total = shard::chunk_photons(self.photons, &chunks) * groups;
        progress.begin(&format!("shard {i}/{n}"), total);
        let accs = mc::accumulate_batch(&spec, chunks.clone(), &|k| progress.advance(k));
        progress.end();
        Ok(Shard {
            spec,
            labels,
            chunks,
            groups: accs?,
        })
    }
}
