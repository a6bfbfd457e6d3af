//! Monte Carlo transport in bodies that are not a half-space: the inside of a sphere (convex),
//! the medium around a spherical cavity (concave) and a slab, entered by a pencil beam at angle θ
//! to the inward normal, tallied on the body's own surface.
//!
//! Physics as in the rest of `mc` (MCML: Wang, Jacques & Zheng 1995): specular reflection
//! F(θ) at entry and refraction by Snell's law, exponential steps, implicit capture,
//! Henyey–Greenstein scattering, statistical Fresnel reflect-or-escape at the local normal of
//! every surface hit, MCML's roulette. Only the geometry is new (the distance to a sphere from
//! inside and from outside and to a slab's faces, and the normals there) and the tally, which
//! bins exits by the distance from the entry point along the surface (the geodesic on a sphere)
//! and the azimuth about the plane of incidence.
//!
//! Units: lengths in cm, coefficients in cm⁻¹, angles of the beam in degrees. Frame: entry at
//! the origin, +z its inward normal, the beam in the x–z plane travelling towards +x.
//! Normalization: per unit incident power ([`BodyOutput`]). Deterministic: the chunks of
//! [`crate::CHUNK_PHOTONS`] photons each have their own random stream, so the same seed gives the
//! same bits with any number of threads.
//!
//! ```
//! use mc::body::{Body, BodySpec, Coefficients, SurfaceGrid, run_body};
//! use mc::Incidence;
//! let spec = BodySpec {
//!     body: Body::Sphere { radius_cm: 0.5 },
//!     coefficients: Coefficients { n: 1.4, mu_a: 1.0, mu_s: 20.0, g: 0.0 },
//!     incidence: Incidence { theta_deg: 45.0 },
//!     grid: SurfaceGrid { dr: 0.05, nr: 40, n_azimuth: 4, n_exit: 9 },
//!     photons: 5_000,
//!     seed: 1,
//! };
//! let out = run_body(&spec, &|_| {}).unwrap();
//! // Every photon's weight is specular, diffusely reflected or absorbed (roulette keeps it in
//! // expectation).
//! let sum = out.rs + out.r.value + out.a.value;
//! assert!((sum - 1.0).abs() < 4.0 * out.r.se.hypot(out.a.se));
//! // Light entering at 45° comes out ahead of the entry point.
//! assert!(out.reflected.shift.value > 0.0);
//! ```

mod output;
mod shape;
mod slab;
mod spec;
mod sphere;
mod surface;
mod walk;

pub use output::{BodyOutput, SurfaceExits, Window};
pub use shape::Body;
pub use spec::{BodySpec, Coefficients, MAX_SURFACE_BINS, SurfaceGrid};

use rayon::prelude::*;

use crate::error::Result;
use crate::job::{Job, accumulate_job, chunk_count};
use crate::rng::{Rng, stream_seed};
use crate::tally::{Layout, Tally};
use surface::{SurfaceLayout, SurfaceScorer};
use walk::{BodyWalk, trace};

struct BodyJob {
    walk: BodyWalk,
    layout: SurfaceLayout,
}

impl Job for BodyJob {
    fn layout(&self) -> Layout {
        self.layout.tally_layout()
    }

    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64) {
        let mut scorer = SurfaceScorer::new(tally, self.walk.shape, self.layout.grid);
        for _ in 0..photons {
            trace(&self.walk, rng, &mut scorer);
        }
    }
}

/// Runs a body and normalizes its tallies. `progress` gets the photons traced as chunks finish.
///
/// The random streams are seeded by `spec.seed` mixed with the body, its medium and the angle,
/// so runs of different bodies with one seed are independent (and of MCML runs with that seed).
pub fn run_body(spec: &BodySpec, progress: &(dyn Fn(u64) + Sync)) -> Result<BodyOutput> {
    spec.validate()?;
    let job = BodyJob {
        walk: BodyWalk::new(spec),
        layout: SurfaceLayout { grid: spec.grid },
    };
    let c = spec.coefficients;
    let kind = match spec.body {
        Body::Sphere { .. } => 1,
        Body::Cavity { .. } => 2,
        Body::Slab { .. } => 3,
    };
    // −0 and +0 are one value.
    let key = [
        spec.body.size_cm(),
        c.n,
        c.mu_a,
        c.mu_s,
        c.g,
        spec.incidence.theta_deg,
    ]
    .map(|x| (x + 0.0).to_bits());
    let seed = stream_seed(spec.seed, std::iter::once(kind).chain(key));
    let acc = accumulate_job(
        &job,
        spec.photons,
        seed,
        0..chunk_count(spec.photons),
        progress,
    );
    Ok(BodyOutput::from_accumulator(
        spec,
        &acc,
        job.layout,
        job.walk.rs,
    ))
}

/// Runs many bodies (a table's runs), each exactly as [`run_body`]: the outputs in the order of
/// `specs`, bit-identical to running them one at a time whatever the thread count. The runs go
/// in parallel as well as each run's chunks (rayon's work stealing nests them), so that runs of
/// a few chunks each keep every thread busy. Every spec is checked before any is traced.
pub fn run_bodies(specs: &[BodySpec], progress: &(dyn Fn(u64) + Sync)) -> Result<Vec<BodyOutput>> {
    for s in specs {
        s.validate()?;
    }
    specs.par_iter().map(|s| run_body(s, progress)).collect()
}
