//! `mc`: Monte Carlo photon transport in multi-layered turbid media, following MCML
//! (Wang, Jacques & Zheng, "MCML — Monte Carlo modeling of light transport in multi-layered
//! tissues", Comput. Methods Programs Biomed. 47, 1995).
//!
//! Conventions: lengths in cm, coefficients in cm⁻¹; +z points into the sample; a pencil beam
//! enters at the origin, at normal incidence as in MCML or at a polar angle θ ([`Incidence`]).
//! `Rd(r)` is the diffuse reflectance per unit area [cm⁻²], excluding the specular reflection,
//! exactly as MCML's `Rd_r`. Every tallied number comes with its standard error from per-photon
//! second moments, except A(r, z) where a run sums it as MCML does (`TallySet::absorption_rz_se`
//! off): its standard errors are then NaN, marked not estimated.
//!
//! Main types: [`Sample`] and [`Layer`] (the medium), [`Grid`] (MCML's tally grid), [`RunSpec`]
//! (one run), [`Output`] (normalized results), [`Material`] (RGB coefficients of a named
//! material); [`mci`] and [`mco`] read and write MCML's files; [`body`] traces a sphere, a
//! spherical cavity and a slab entered at an angle, tallied on the body's own surface.
//!
//! ```
//! use mc::{Grid, Layer, RunSpec, Sample, TallySet};
//! let layer = Layer { n: 1.0, mu_a: 10.0, mu_s: 90.0, g: 0.75, thickness: 0.02 };
//! let spec = RunSpec {
//!     sample: Sample::single(layer),
//!     grid: Grid { dr: 0.01, dz: 0.01, nr: 50, nz: 2, na: 10 },
//!     photons: 20_000,
//!     seed: 1,
//!     tallies: TallySet::default(),
//! };
//! let out = mc::run(&spec, &|_| {}).unwrap();
//! // van de Hulst's slab: Rd = 0.09739, Tt = 0.66096.
//! assert!((out.rd.value - 0.09739).abs() < 5.0 * out.rd.se);
//! ```

#![deny(missing_docs)]
// Units are written in brackets as in the papers, [cm⁻¹]; rustdoc would take them for links.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod artist;
mod batch;
pub mod bench;
pub mod body;
pub mod builtin;
mod cfmt;
mod channel;
mod config;
pub mod cycles;
mod error;
pub mod exitance;
mod fresnel;
mod grid;
pub mod incidence;
pub mod input;
mod job;
pub mod job_array;
mod lanes;
mod layer;
mod material;
pub mod mci;
pub mod mco;
mod output;
pub mod outputs;
mod phase;
mod photon;
pub mod progress;
pub mod provenance;
mod rng;
pub mod shard;
mod simulate;
pub mod slab;
pub mod table;
mod tally;
mod white;

pub use batch::{BatchSpec, ChannelSpec, ERROR_RADIUS_MFP, QUASI_INFINITE_MFP};
pub use config::{GridRule, SimConfig, THESIS_TOML};
pub use error::{McError, Result};
pub use fresnel::{cos_critical, fresnel, specular};
pub use grid::Grid;
pub use job::{MAX_PHOTONS, chunk_count};
pub use layer::{Incidence, Layer, Sample};
pub use material::{CHANNELS, Material};
pub use output::{Estimate, Output};
pub use phase::{pdf_cos_theta, sample_cos_theta};
pub use photon::{
    IMPORTANCE_INTERVAL, IMPORTANCE_TARGET, IMPORTANCE_THRESHOLD, PATH_ROULETTE_INTERVAL,
    ROULETTE_SURVIVAL, ROULETTE_THRESHOLD,
};
pub use rng::CHUNK_PHOTONS;
pub use simulate::{
    ROUND_CHUNKS, RunSpec, accumulate, accumulate_batch, batch_outputs, relative_error, run,
    run_at, run_batch, run_batch_at, run_batch_to_error,
};
pub use tally::{Accumulator, Layout, TallySet};
