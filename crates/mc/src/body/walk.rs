//! One photon's walk in a body: MCML's steps ([`crate::photon`]'s `step_size`, `hop`, `drop`,
//! `spin`, `roulette`) between boundaries that are a sphere or two planes, with the statistical
//! Fresnel reflect-or-escape at the local normal wherever a flight reaches the surface.
//!
//! Units: cm, cm⁻¹. Frame: the entry point is the origin, +z its inward normal; the beam comes
//! in within the x–z plane, refracted by Snell's law into (sin θt, 0, cos θt), with the specular
//! reflectance Rs = F(θ) (unpolarized Fresnel, air to η) taken off its weight as MCML does.

use rand::RngExt;

use super::shape::Shape;
use super::slab::Face;
use super::spec::BodySpec;
use super::sphere::dot;
use crate::fresnel::fresnel;
use crate::photon::{
    PATH_ROULETTE_INTERVAL, Photon, ROULETTE_SURVIVAL, ROULETTE_THRESHOLD, Scorer, drop, hop,
    roulette, spin, step_size,
};
use crate::rng::Rng;

/// A body and its medium prepared for the walk.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyWalk {
    pub shape: Shape,
    /// Refractive index η of the medium (air, n = 1, outside).
    pub n: f64,
    /// σt [cm⁻¹]; 0 in a medium that neither absorbs nor scatters.
    pub mu_t: f64,
    /// σa/σt: the fraction of the weight deposited at each interaction.
    pub absorb: f64,
    pub g: f64,
    /// Specular reflectance at entry [-]; the launched weight is 1 − rs.
    pub rs: f64,
    /// Launch direction inside the medium, in the x–z plane: (sin θt, cos θt).
    pub launch_ux: f64,
    pub launch_uz: f64,
}

impl BodyWalk {
    pub fn new(spec: &BodySpec) -> Self {
        let c = spec.coefficients;
        let cos_i = spec.incidence.theta_deg.to_radians().cos();
        let (rs, cos_t) = fresnel(1.0, c.n, cos_i);
        BodyWalk {
            shape: Shape::from(spec.body),
            n: c.n,
            mu_t: c.mu_t(),
            absorb: if c.mu_t() > 0.0 {
                c.mu_a / c.mu_t()
            } else {
                0.0
            },
            g: c.g,
            rs,
            launch_ux: (1.0 - cos_t * cos_t).max(0.0).sqrt(),
            launch_uz: cos_t,
        }
    }
}

/// Traces one photon from launch at the entry point to death.
pub(crate) fn trace<S: Scorer>(walk: &BodyWalk, rng: &mut Rng, scorer: &mut S) {
    let mut p = Photon {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        ux: walk.launch_ux,
        uy: 0.0,
        uz: walk.launch_uz,
        w: 1.0 - walk.rs,
        layer: 0,
        s_left: 0.0,
        interactions: 0,
        alive: true,
    };
    while p.alive {
        hop_drop_spin(walk, &mut p, rng, scorer);
        if p.alive && p.w < ROULETTE_THRESHOLD {
            roulette(&mut p, rng, ROULETTE_SURVIVAL);
        }
    }
    scorer.finish(&p);
}

/// One flight: to the next interaction (deposit, new direction), or to the surface, carrying the
/// optical depth left over across a reflection as MCML does. In a medium with σt = 0 a flight
/// always reaches the surface (a cavity's medium is refused then: [`BodySpec::validate`]).
#[inline]
fn hop_drop_spin<S: Scorer>(walk: &BodyWalk, p: &mut Photon, rng: &mut Rng, scorer: &mut S) {
    let s = if walk.mu_t > 0.0 {
        step_size(p, walk.mu_t, rng)
    } else {
        f64::INFINITY
    };
    match walk.shape.distance([p.x, p.y, p.z], [p.ux, p.uy, p.uz]) {
        Some((d, face)) if d < s => {
            p.s_left = if walk.mu_t > 0.0 {
                (s - d) * walk.mu_t
            } else {
                0.0
            };
            hop(p, d);
            reflect_or_escape(walk, p, face, rng, scorer);
        }
        _ => {
            hop(p, s);
            drop(p, walk.absorb, scorer);
            spin(p, walk.g, rng);
            if p.interactions.is_multiple_of(PATH_ROULETTE_INTERVAL) {
                roulette(p, rng, 0.5);
            }
        }
    }
}

/// At the surface, with n̂ the outward normal and cos θi = u·n̂: escape with probability
/// 1 − F(θi) (unpolarized Fresnel, η to air; total internal reflection beyond the critical
/// angle), scored where it leaves; otherwise the specular reflection u − 2(u·n̂)n̂ (MCML's
/// `CrossUpOrNot`, statistical mode, with the normal of a curved surface).
fn reflect_or_escape<S: Scorer>(
    walk: &BodyWalk,
    p: &mut Photon,
    face: Face,
    rng: &mut Rng,
    scorer: &mut S,
) {
    let normal = walk.shape.outward_normal([p.x, p.y, p.z], face);
    let cos_i = dot([p.ux, p.uy, p.uz], normal);
    if cos_i <= 0.0 {
        // Rounding on a grazing ray at a curved surface: it already points back in.
        return;
    }
    let (r, cos_t) = fresnel(walk.n, 1.0, cos_i.min(1.0));
    let xi_fresnel: f64 = rng.random();
    if xi_fresnel > r {
        scorer.escape(p, face == Face::Entry, cos_t);
        p.alive = false;
    } else {
        let k = 2.0 * cos_i;
        p.ux -= k * normal[0];
        p.uy -= k * normal[1];
        p.uz -= k * normal[2];
    }
}
