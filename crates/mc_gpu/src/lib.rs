//! `mc_gpu`: the Monte Carlo photon tracer on the GPU — `mc`'s MCML walk (Wang, Jacques & Zheng
//! 1995) in a wgpu compute shader, returning `mc`'s own [`mc::Output`], so `.mco` files,
//! profiles and tables use it unchanged.
//!
//! The physics is the CPU tracer's (crates/mc/src/photon.rs): a pencil beam at normal incidence
//! with the specular reflection at entry, exponential steps, implicit capture, Henyey–Greenstein
//! scattering, Fresnel reflection or refraction at every interface (statistical, with total
//! internal reflection), MCML's Russian roulette (threshold 10⁻⁴, survival 0.1), mc's
//! path-length roulette and, when nothing below the surface is tallied, its importance roulette;
//! multiple layers, glass layers included. In f32 (see the WGSL for where that matters). Units:
//! cm and cm⁻¹; +z into the sample.
//!
//! Tallies: Rd(r, α) and Tt(r, α) on MCML's grid, A per layer and in all, each with per-photon
//! second moments, so every field of [`mc::Output`] except A(r, z) and A(z) (refused:
//! [`McGpuError::Unsupported`]) carries the CPU's standard errors with the same meaning. Sums
//! are exact integers ([`tally`]): the same seed gives the same bits on the same adapter
//! whatever the dispatch size. Photon k draws from its own stream of (seed, k).
//!
//! Main items: [`run`] (a layered [`mc::RunSpec`], like [`mc::run`]), [`run_batch`] (the
//! channels of a [`mc::BatchSpec`], like [`mc::run_batch`]), [`tables`] (profile tables of
//! [`mc::table`], white or per albedo), [`Tracer`] (the compiled pass, for many runs and to
//! choose the dispatch size), [`McGpuError`].
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let gpu = gpu::Gpu::new()?;
//! let material = mc::Material::builtin("skin1")?;
//! let spec = mc::SimConfig::thesis()?.batch(&[&material], 100_000, 1, true)?;
//! let outputs = mc_gpu::run_batch(&gpu, &spec, &|_photons| {})?;
//! assert_eq!(outputs.len(), 3);
//! # Ok(()) }
//! ```

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]

mod error;
mod medium;
mod table;
pub mod tally;
mod tracer;

use gpu::Gpu;
use mc::{BatchSpec, Output, RunSpec, TallySet};

pub use error::{McGpuError, Result};
pub use medium::MAX_LAYERS;
pub use table::tables;
pub use tracer::{CPU_SLOTS, Dispatch, GPU_SLOTS, TARGET_DISPATCH_SECONDS, TRACER_WGSL, Tracer};

use medium::Walk;
use tracer::{Target, grid_layout};

/// Runs an MCML run on the GPU and normalizes it, as [`mc::run`] does on the CPU (normal
/// incidence, the run's seed). `progress` is called after each dispatch with the photons it
/// finished.
pub fn run(gpu: &Gpu, spec: &RunSpec, progress: &(dyn Fn(u64) + Sync)) -> Result<Output> {
    Tracer::new(gpu)?.run(gpu, spec, progress)
}

/// Runs every channel of a batch on the GPU for `spec.photons` photons each, as
/// [`mc::run_batch`] does on the CPU; outputs in channel order. Each channel is traced on its own
/// (`progress` counts photons × channels in all), in its mean free paths as mc's batches walk,
/// with streams seeded by the batch's seed and the channel's walk alone.
pub fn run_batch(
    gpu: &Gpu,
    spec: &BatchSpec,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Output>> {
    Tracer::new(gpu)?.run_batch(gpu, spec, progress)
}

impl Tracer {
    /// [`run`] with this tracer.
    pub fn run(
        &self,
        gpu: &Gpu,
        spec: &RunSpec,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Output> {
        spec.validate()?;
        check_tallies(&spec.tallies)?;
        let walk = Walk::new(&spec.sample, !spec.tallies.absorption_rz, 1.0)?;
        let target = Target::Grid(&spec.grid);
        let sums = self.trace(gpu, &walk, &target, spec.photons, spec.seed, progress)?;
        let acc = sums.accumulator(grid_layout(&walk, &spec.grid));
        Ok(Output::from_accumulator(&acc, 0, spec.grid, walk.rsp))
    }

    /// [`run_batch`] with this tracer.
    pub fn run_batch(
        &self,
        gpu: &Gpu,
        spec: &BatchSpec,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<Output>> {
        spec.validate()?;
        check_tallies(&spec.tallies)?;
        (0..spec.channels.len())
            .map(|c| {
                let walk = Walk::of_channel(spec, c)?;
                let grid = spec.channels[c].grid;
                let seed = channel_seed(spec, c);
                let target = Target::Grid(&grid);
                let sums = self.trace(gpu, &walk, &target, spec.photons, seed, progress)?;
                let acc = sums.accumulator(grid_layout(&walk, &grid));
                Ok(Output::from_accumulator(&acc, 0, grid, walk.rsp))
            })
            .collect()
    }
}

/// Refuses the tallies the GPU does not record: A(r, z) and A(z), and the surface grid Rd(x, y).
fn check_tallies(t: &TallySet) -> Result<()> {
    let refuse = |what: &str| {
        Err(McGpuError::Unsupported {
            what: what.to_string(),
            reason: "the GPU tracer tallies Rd(r, α), Tt(r, α), A_l and A; use the CPU tracer"
                .to_string(),
        })
    };
    if t.absorption_rz {
        return refuse("absorption on the (r, z) grid (A_rz, A_z)");
    }
    if t.surface_xy > 0 {
        return refuse("the surface grid Rd(x, y)");
    }
    Ok(())
}

/// The seed of channel `c`'s streams: the batch's seed mixed (SplitMix64) with everything that
/// fixes the channel's walk — the ambient indices and the layer in walk units — so a channel's
/// result does not depend on the other channels of the batch.
fn channel_seed(spec: &BatchSpec, c: usize) -> u64 {
    let (w, _) = medium::channel_walk(&spec.channels[c].layer);
    [
        spec.n_above,
        spec.n_below,
        w.n,
        w.mu_a,
        w.mu_s,
        w.g,
        w.thickness,
    ]
    .map(|x| (x + 0.0).to_bits())
    .into_iter()
    .fold(splitmix64(spec.seed), |h, word| splitmix64(h ^ word))
}

/// SplitMix64's finalizer (Steele, Lea & Flood 2014).
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
