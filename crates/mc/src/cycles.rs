//! Blender Cycles' subsurface random walk as it runs, traced by `mc`: what a Principled BSDF with
//! Subsurface Method "Random Walk" reflects, for comparison with the medium it was given.
//!
//! Read from the Cycles source Blender 5.0.1 ships (`kernel/integrator/subsurface_random_walk.h`,
//! `subsurface.h`, `kernel/types.h`). Cycles' loop `for (bounce = 0; bounce < BSSRDF_MAX_BOUNCES;
//! bounce++)` does, at each bounce: (bounce > 0) a new direction from the phase function of that
//! bounce's medium, then a free flight in it, which either reaches the surface (the walk ends
//! there: no Fresnel reflection or refraction, it leaves through a diffuse BSDF) or ends in a
//! scattering event weighted by that medium's σs/σt. With `SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL`
//! 9, bounces 0–9 trace the given medium (σs, σt, Henyey–Greenstein g) and bounces from 10 on the
//! similarity-scaled one: σs* = σs(1 − g), σt* = σt − σs + σs*, isotropic. In `mc`'s terms
//! (interactions counted from 1): flights 1–10 and the albedo of interactions 1–10 are the
//! medium's, the directions after interactions 1–9 are Henyey–Greenstein's with g; from
//! interaction 10 on directions are isotropic, and flights 11 on and the albedo of interactions
//! 11 on are the scaled medium's. A walk still inside after 256 flights (`BSSRDF_MAX_BOUNCES`) is
//! dropped: its light is lost. Cycles' guided (Dwivedi) sampling, its colour-channel MIS and its
//! throughput floor (10⁻⁶) change the variance, not the expectation (the floor drops less than
//! 10⁻⁶ of a path's weight); `mc` traces the analog walk with MCML's implicit capture and
//! roulette. The walk enters along the refracted view ray (smooth, by Cycles' IOR, at least
//! 1.01): the caller's [`Incidence`].
//!
//! Only an index-matched layer is traced this way (the surrounding media's index equal to the
//! layer's): Cycles' walk has no boundary reflection, which is `mc`'s walk where nothing
//! reflects. A half-space or a slab between two index-matched half-spaces (light leaving through
//! the bottom does not come back, as in Cycles where it leaves facing away).

use crate::error::{McError, Result};
use crate::job::{Job, accumulate_job, chunk_count};
use crate::layer::{Incidence, Layer, Sample};
use crate::output::Output;
use crate::photon::{
    IMPORTANCE_INTERVAL, Medium, PATH_ROULETTE_INTERVAL, ROULETTE_SURVIVAL, ROULETTE_THRESHOLD,
    Scorer, cross_or_not, drop, hit_boundary, hop, importance, launch, roulette, spin, step_size,
};
use crate::rng::Rng;
use crate::simulate::RunSpec;
use crate::tally::{Layout, McmlScorer, Tally};

/// Which walk [`run_cycles`] traces: how many flights trace the given medium before the
/// similarity-scaled one takes over, and how many flights a walk may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CyclesWalk {
    /// Flights (and the interactions that end them) in the given medium (σs, σt, g); the
    /// directions after the first `exact_flights − 1` interactions follow its phase function.
    /// Later flights and interactions are the similarity-scaled medium's (σs(1 − g), isotropic).
    /// Cycles: `SUBSURFACE_RANDOM_WALK_SIMILARITY_LEVEL` + 1 = 10. 0: the scaled medium from the
    /// start; `u32::MAX`: the given medium throughout.
    pub exact_flights: u32,
    /// Flights after which a walk still inside is dropped (its light lost). Cycles:
    /// `BSSRDF_MAX_BOUNCES` = 256; `u32::MAX`: never.
    pub max_flights: u32,
}

impl CyclesWalk {
    /// The walk Blender 3.0–5.0's Cycles runs: 10 flights in the given medium, at most 256.
    pub const BLENDER: CyclesWalk = CyclesWalk {
        exact_flights: 10,
        max_flights: 256,
    };
    /// The given medium throughout, never dropped: `mc`'s own walk (for checks).
    pub const EXACT: CyclesWalk = CyclesWalk {
        exact_flights: u32::MAX,
        max_flights: u32::MAX,
    };
}

/// The similarity-scaled layer Cycles switches to: σs(1 − g), the same σa, isotropic.
pub fn similarity_scaled(l: &Layer) -> Layer {
    Layer {
        mu_s: l.mu_s * (1.0 - l.g),
        g: 0.0,
        ..*l
    }
}

struct CyclesJob<'a> {
    given: Medium,
    scaled: Medium,
    walk: CyclesWalk,
    spec: &'a RunSpec,
}

impl Job for CyclesJob<'_> {
    fn layout(&self) -> Layout {
        let g = self.spec.grid;
        Layout {
            nr: g.nr,
            nz: g.nz,
            na: g.na,
            layers: 1,
            rz: self.spec.tallies.absorption_rz,
            rz_se: self.spec.tallies.absorption_rz_se,
            channels: 1,
            xy: self.spec.tallies.surface_xy,
            scores: 0,
        }
    }

    fn trace_chunk(&self, tally: &mut Tally, rng: &mut Rng, photons: u64) {
        let mut scorer = McmlScorer::new(tally, self.spec.grid);
        for _ in 0..photons {
            trace(&self.given, &self.scaled, self.walk, rng, &mut scorer);
        }
    }
}

/// One photon of Cycles' walk: `mc`'s scalar walk ([`crate::photon`]'s steps) with the medium
/// chosen by the interactions so far. With [`CyclesWalk::EXACT`] it draws the same numbers as
/// `photon::trace` and gives the same bits.
fn trace<S: Scorer>(
    given: &Medium,
    scaled: &Medium,
    walk: CyclesWalk,
    rng: &mut Rng,
    scorer: &mut S,
) {
    let exact = u64::from(walk.exact_flights);
    let mut p = launch(given);
    while p.alive {
        if walk.max_flights != u32::MAX && p.interactions >= u64::from(walk.max_flights) {
            // Cycles' loop ends without reaching the surface: the walk's light is lost.
            p.alive = false;
            break;
        }
        let m = if p.interactions < exact {
            given
        } else {
            scaled
        };
        let slab = m.slabs[p.layer];
        let s = step_size(&mut p, slab.mu_t, rng);
        match hit_boundary(&p, &slab, s) {
            Some(d) => {
                p.s_left = (s - d) * slab.mu_t;
                hop(&mut p, d);
                cross_or_not(m, &mut p, rng, scorer);
            }
            None => {
                hop(&mut p, s);
                drop(&mut p, slab.absorb, scorer);
                // The direction leaving interaction k is bounce k's: the given g while k < exact.
                let g = if p.interactions < exact {
                    given.slabs[p.layer].g
                } else {
                    0.0
                };
                spin(&mut p, g, rng);
                if p.interactions.is_multiple_of(PATH_ROULETTE_INTERVAL) {
                    roulette(&mut p, rng, 0.5);
                }
                if m.importance && p.alive && p.interactions.is_multiple_of(IMPORTANCE_INTERVAL) {
                    importance(m, &mut p, rng);
                }
            }
        }
        if p.alive && p.w < ROULETTE_THRESHOLD {
            roulette(&mut p, rng, ROULETTE_SURVIVAL);
        }
    }
    scorer.finish(&p);
}

/// Traces Cycles' random walk (`walk`) through the one index-matched layer of `spec` under a
/// beam at `incidence` and normalizes it as [`crate::run_at`] does (same tallies, same seed
/// rules). Refuses a sample of several layers, a non-interacting layer, or one whose index
/// differs from the media around it.
pub fn run_cycles(
    spec: &RunSpec,
    incidence: Incidence,
    walk: CyclesWalk,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Output> {
    spec.validate()?;
    incidence.validate_for(&spec.sample)?;
    let s = &spec.sample;
    if s.layers.len() != 1 {
        return Err(McError::invalid(
            "layers",
            s.layers.len(),
            "Cycles' walk is traced in one layer",
        ));
    }
    let l = s.layers[0];
    if l.mu_t() <= 0.0 {
        return Err(McError::invalid(
            "mu_t",
            l.mu_t(),
            "Cycles' walk needs an interacting layer",
        ));
    }
    if s.n_above != l.n || s.n_below != l.n {
        return Err(McError::invalid(
            "n",
            l.n,
            "Cycles' walk has no boundary reflection: the media around the layer must have its index",
        ));
    }
    let importance = !spec.tallies.absorption_rz;
    let scaled = Sample {
        layers: vec![similarity_scaled(&l)],
        ..s.clone()
    };
    let job = CyclesJob {
        given: Medium::at(s, incidence).with_importance(importance),
        scaled: Medium::at(&scaled, incidence).with_importance(importance),
        walk,
        spec,
    };
    let acc = accumulate_job(
        &job,
        spec.photons,
        spec.seed,
        0..chunk_count(spec.photons),
        progress,
    );
    Ok(Output::from_accumulator(&acc, 0, spec.grid, job.given.rsp))
}
