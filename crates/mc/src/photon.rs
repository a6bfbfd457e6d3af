//! One photon packet's random walk through the layered sample, step by step as in MCML
//! (Wang, Jacques & Zheng 1995, §3–4): `launch`, `step_size`, `hit_boundary`, `hop`, `drop`,
//! `spin`, `cross_or_not`, `roulette`.
//!
//! Units: cm and cm⁻¹. Axis: +z into the sample. The walk knows nothing about tallies: it reports
//! every deposit, escape and roulette decision to a [`Scorer`], so one walk serves both the
//! MCML tallies and the batch tallies of many channels at once.

use crate::rng::Rng;
use rand::RngExt;
use rand_distr::{Distribution, Exp1};

use crate::fresnel::{COS_ZERO, cos_critical, fresnel, specular};
use crate::layer::Incidence;
use crate::layer::Sample;
use crate::phase::sample_cos_theta;

/// Weight below which Russian roulette is played (MCML's `WEIGHT`).
pub const ROULETTE_THRESHOLD: f64 = 1.0e-4;
/// Survival probability in Russian roulette (MCML's `CHANCE`).
pub const ROULETTE_SURVIVAL: f64 = 0.1;
/// Interactions after which (and after every further as many) a photon plays a path-length
/// roulette with survival ½. Unbiased, and it bounds the walk when the albedo is 1 exactly, where
/// a photon in a half-space can otherwise wander for an unbounded number of steps. MCML has no
/// such rule; it touches only photons with more than 10⁵ interactions.
pub const PATH_ROULETTE_INTERVAL: u64 = 100_000;

/// Importance roulette (profile-only runs): after every [`IMPORTANCE_INTERVAL`]-th interaction a photon
/// whose importance-weighted weight w·I(z) has fallen below this plays roulette (see
/// [`importance`]).
pub const IMPORTANCE_THRESHOLD: f64 = 0.1;
/// The importance-weighted weight w·I(z) a photon surviving the importance roulette carries
/// (unless that would make its weight exceed 1).
pub const IMPORTANCE_TARGET: f64 = 0.2;
/// Interactions between two importance checks (each costs an exponential).
pub const IMPORTANCE_INTERVAL: u64 = 16;

/// A layer prepared for transport: bounds and derived coefficients.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slab {
    pub z0: f64,
    pub z1: f64,
    pub n: f64,
    pub mu_t: f64,
    /// μa/μt: the fraction of the weight deposited at each interaction.
    pub absorb: f64,
    pub g: f64,
    /// Cosine of the critical angle going up / down out of this slab.
    pub cos_crit_up: f64,
    pub cos_crit_down: f64,
    /// Index of the medium above / below this slab.
    pub n_up: f64,
    pub n_down: f64,
    /// Diffusion's effective attenuation μ_eff = √(3μa(μa + μs(1 − g))) [cm⁻¹] (0 in glass).
    pub mu_eff: f64,
    /// ∫ μ_eff dz from the top surface down to this slab's top, z0 [-].
    pub tau0: f64,
}

/// The sample prepared for transport.
#[derive(Clone, Debug)]
pub(crate) struct Medium {
    pub slabs: Vec<Slab>,
    /// Specular reflectance at entry; the launched weight is 1 − rsp.
    pub rsp: f64,
    /// Index of the first layer a photon is launched into (1 when layer 0 is glass, as MCML does).
    pub first: usize,
    /// Launch direction inside the first layer, in the x–z plane: (sin θt, cos θt).
    pub launch_ux: f64,
    pub launch_uz: f64,
    /// ∫ μ_eff dz over the whole sample [-].
    pub tau_total: f64,
    /// Whether photons play the importance roulette ([`importance`]): only when nothing below
    /// the surfaces is tallied.
    pub importance: bool,
}

impl Medium {
    /// The sample under a beam at `incidence`: at θ = 0 MCML's setup exactly (Rsp with a glass
    /// top layer's multiple reflections, launch along +z); at θ > 0 the beam is refracted into the
    /// first layer by Snell's law and Rsp is the unpolarized Fresnel reflectance at θ. A glass
    /// top layer is refused at θ > 0 ([`Incidence::validate_for`]).
    pub fn at(sample: &Sample, incidence: Incidence) -> Self {
        let mut m = Self::new(sample);
        if incidence.theta_deg > 0.0 {
            let cos_i = incidence.theta_deg.to_radians().cos();
            let (r, cos_t) = fresnel(sample.n_above, sample.layers[0].n, cos_i);
            m.rsp = r;
            m.launch_uz = cos_t;
            m.launch_ux = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        }
        m
    }

    pub fn new(sample: &Sample) -> Self {
        let ls = &sample.layers;
        let (mut z, mut tau) = (0.0, 0.0);
        let slabs = ls
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let n_up = if i == 0 { sample.n_above } else { ls[i - 1].n };
                let n_down = if i + 1 == ls.len() {
                    sample.n_below
                } else {
                    ls[i + 1].n
                };
                let s = Slab {
                    z0: z,
                    z1: z + l.thickness,
                    n: l.n,
                    mu_t: l.mu_t(),
                    absorb: if l.mu_t() > 0.0 {
                        l.mu_a / l.mu_t()
                    } else {
                        0.0
                    },
                    g: l.g,
                    cos_crit_up: cos_critical(l.n, n_up),
                    cos_crit_down: cos_critical(l.n, n_down),
                    n_up,
                    n_down,
                    mu_eff: (3.0 * l.mu_a * (l.mu_a + l.mu_s * (1.0 - l.g))).sqrt(),
                    tau0: tau,
                };
                z += l.thickness;
                tau += s.mu_eff * l.thickness;
                s
            })
            .collect();
        let glass_first = ls[0].is_glass() && ls.len() > 1;
        let rsp = specular(sample.n_above, ls[0].n, glass_first.then(|| ls[1].n));
        Medium {
            slabs,
            rsp,
            first: usize::from(glass_first),
            launch_ux: 0.0,
            launch_uz: 1.0,
            tau_total: tau,
            importance: false,
        }
    }

    /// The same medium with the importance roulette on (`on`) or off.
    pub fn with_importance(mut self, on: bool) -> Self {
        self.importance = on;
        self
    }
}

/// Photon packet state (MCML's `PhotonStruct`).
#[derive(Clone, Copy, Debug)]
pub struct Photon {
    /// Position [cm].
    pub x: f64,
    pub y: f64,
    pub z: f64,
    /// Direction cosines.
    pub ux: f64,
    pub uy: f64,
    pub uz: f64,
    /// Packet weight [-].
    pub w: f64,
    /// Index of the current layer.
    pub layer: usize,
    /// Dimensionless optical depth left over from a step cut at a boundary.
    pub s_left: f64,
    /// Interactions (drops) so far.
    pub interactions: u64,
    pub alive: bool,
}

impl Photon {
    /// Distance from the beam axis [cm].
    #[inline]
    pub fn r(&self) -> f64 {
        (self.x * self.x + self.y * self.y).sqrt()
    }
}

/// What a scorer keeps of the deposits, besides each history's total (A, A_l).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Depth {
    /// Nothing: only the history's total counts.
    None,
    /// Deposits on the (r, z) grid, summed over all photons (no per-photon state).
    Summed,
    /// Deposits on the (r, z) grid gathered per history (per-photon second moments).
    PerPhoton,
}

/// What the walk reports. All methods are called with the photon's state at that moment.
/// A walk with several photons in flight (`lanes`, where [`Scorer::depth`] is not
/// [`Depth::PerPhoton`]) hands each deposit to [`Scorer::deposit_summed`] (when
/// [`Depth::Summed`]) and a history's deposits as one sum to [`Scorer::absorb_total`] right
/// before [`Scorer::finish`]: the scorer's per-photon state lives only between those two calls.
pub(crate) trait Scorer {
    /// What the scorer keeps of deposits.
    fn depth(&self) -> Depth;
    /// Weight `dw` deposited at the photon's position (an interaction in an absorbing layer):
    /// the history's total and, where tallied, the (r, z) grid.
    fn absorb(&mut self, p: &Photon, dw: f64);
    /// A deposit `dw` at radius `r` and depth `z` [cm] on the (r, z) grid alone, summed over
    /// photons ([`Depth::Summed`]).
    fn deposit_summed(&mut self, r: f64, z: f64, dw: f64);
    /// Weight `dw` added to the history's total alone (no (r, z) grid).
    fn absorb_total(&mut self, p: &Photon, dw: f64);
    /// The photon leaves through the top (`top`) or bottom surface with its weight `p.w`;
    /// `cos_exit` is |cos| of its direction in the ambient medium.
    fn escape(&mut self, p: &Photon, top: bool, cos_exit: f64);
    /// The photon's history is over (escaped or killed).
    fn finish(&mut self, p: &Photon);
}

/// Traces one photon from launch to death.
pub(crate) fn trace<S: Scorer>(m: &Medium, rng: &mut Rng, scorer: &mut S) {
    let mut p = launch(m);
    while p.alive {
        if m.slabs[p.layer].mu_t == 0.0 {
            hop_in_glass(m, &mut p, rng, scorer);
        } else {
            hop_drop_spin(m, &mut p, rng, scorer);
        }
        if p.alive && p.w < ROULETTE_THRESHOLD {
            roulette(&mut p, rng, ROULETTE_SURVIVAL);
        }
    }
    scorer.finish(&p);
}

/// Pencil beam at the origin, weight 1 − Rsp (MCML's `LaunchPhoton`), along the refracted
/// direction (+z at normal incidence).
pub(crate) fn launch(m: &Medium) -> Photon {
    Photon {
        x: 0.0,
        y: 0.0,
        z: m.slabs[m.first].z0,
        ux: m.launch_ux,
        uy: 0.0,
        uz: m.launch_uz,
        w: 1.0 - m.rsp,
        layer: m.first,
        s_left: 0.0,
        interactions: 0,
        alive: true,
    }
}

/// One step in a scattering/absorbing layer (MCML's `HopDropSpinInTissue`).
#[inline]
fn hop_drop_spin<S: Scorer>(m: &Medium, p: &mut Photon, rng: &mut Rng, scorer: &mut S) {
    let slab = m.slabs[p.layer];
    let s = step_size(p, slab.mu_t, rng);
    match hit_boundary(p, &slab, s) {
        Some(d) => {
            p.s_left = (s - d) * slab.mu_t;
            hop(p, d);
            cross_or_not(m, p, rng, scorer);
        }
        None => {
            hop(p, s);
            drop(p, slab.absorb, scorer);
            spin(p, slab.g, rng);
            if p.interactions.is_multiple_of(PATH_ROULETTE_INTERVAL) {
                roulette(p, rng, 0.5);
            }
            if m.importance && p.alive && p.interactions.is_multiple_of(IMPORTANCE_INTERVAL) {
                importance(m, p, rng);
            }
        }
    }
}

/// A straight flight through a non-interacting layer to its boundary (MCML's `HopInGlass`).
fn hop_in_glass<S: Scorer>(m: &Medium, p: &mut Photon, rng: &mut Rng, scorer: &mut S) {
    if p.uz == 0.0 {
        // Travelling parallel to the boundaries it would never leave: MCML kills it.
        p.alive = false;
        return;
    }
    let slab = m.slabs[p.layer];
    let d = if p.uz > 0.0 {
        (slab.z1 - p.z) / p.uz
    } else {
        (slab.z0 - p.z) / p.uz
    };
    hop(p, d);
    cross_or_not(m, p, rng, scorer);
}

/// Free path s = −ln ξ / μt [cm] (sampled with the ziggurat method, no logarithm), or the optical
/// depth left over from the last boundary hit.
#[inline]
pub(crate) fn step_size(p: &mut Photon, mu_t: f64, rng: &mut Rng) -> f64 {
    if p.s_left == 0.0 {
        let tau: f64 = Exp1.sample(rng);
        tau / mu_t
    } else {
        let s = p.s_left / mu_t;
        p.s_left = 0.0;
        s
    }
}

/// Distance to the layer boundary along the direction when it is shorter than `s` [cm]. The test
/// z + s·uz beyond the boundary needs no division; the distance is computed only on a hit.
#[inline]
pub(crate) fn hit_boundary(p: &Photon, slab: &Slab, s: f64) -> Option<f64> {
    let z_end = p.z + s * p.uz;
    if z_end > slab.z1 {
        Some((slab.z1 - p.z) / p.uz)
    } else if z_end < slab.z0 {
        Some((slab.z0 - p.z) / p.uz)
    } else {
        None
    }
}

#[inline]
pub(crate) fn hop(p: &mut Photon, s: f64) {
    p.x += s * p.ux;
    p.y += s * p.uy;
    p.z += s * p.uz;
}

/// Implicit capture: deposit w·μa/μt, keep the rest (MCML's `Drop`).
#[inline]
pub(crate) fn drop<S: Scorer>(p: &mut Photon, absorb: f64, scorer: &mut S) {
    let dw = p.w * absorb;
    p.w -= dw;
    p.interactions += 1;
    scorer.absorb(p, dw);
}

/// New direction after a Henyey–Greenstein scattering (MCML's `Spin`). Isotropic scattering
/// (g = 0) forgets the old direction, so the new one is drawn directly on the sphere; otherwise
/// the sampled (θ, ψ) are applied in the frame of the old direction.
#[inline(always)]
pub(crate) fn spin(p: &mut Photon, g: f64, rng: &mut Rng) {
    if g == 0.0 {
        // Marsaglia (1972): for (u, v) uniform in the unit disk and s = u² + v²,
        // (2u√(1−s), 2v√(1−s), 1 − 2s) is uniform on the unit sphere.
        let (u, v, s) = disk_point(rng);
        let t = 2.0 * (1.0 - s).sqrt();
        p.ux = u * t;
        p.uy = v * t;
        p.uz = 1.0 - 2.0 * s;
        return;
    }
    let xi_theta: f64 = rng.random();
    let cos_t = sample_cos_theta(g, xi_theta);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    // (cos ψ, sin ψ) of a uniform azimuth without trigonometry: a disk point's polar angle ψ' is
    // uniform, and ((u² − v²), 2uv)/s = (cos 2ψ', sin 2ψ').
    let (u, v, s) = disk_point(rng);
    let (cos_p, sin_p) = ((u * u - v * v) / s, 2.0 * u * v / s);
    if p.uz.abs() > COS_ZERO {
        p.ux = sin_t * cos_p;
        p.uy = sin_t * sin_p;
        p.uz = if p.uz > 0.0 { cos_t } else { -cos_t };
    } else {
        let t = (1.0 - p.uz * p.uz).sqrt();
        let ux = sin_t * (p.ux * p.uz * cos_p - p.uy * sin_p) / t + p.ux * cos_t;
        let uy = sin_t * (p.uy * p.uz * cos_p + p.ux * sin_p) / t + p.uy * cos_t;
        p.uz = -sin_t * cos_p * t + p.uz * cos_t;
        p.ux = ux;
        p.uy = uy;
    }
}

/// A point (u, v) uniform in the unit disk (excluding a 10⁻¹² neighbourhood of the centre) and
/// s = u² + v², by rejection from the square. Both coordinates come from one 64-bit draw (32 bits
/// each: angular resolution 2⁻³¹, far below any tally's), so the walk spends fewer draws per event.
#[inline]
fn disk_point(rng: &mut Rng) -> (f64, f64, f64) {
    const SCALE: f64 = 1.0 / 2_147_483_648.0; // 2⁻³¹
    loop {
        let bits: u64 = rng.random();
        // Through i64: one signed conversion instruction (u64 → f64 is a long sequence on x86-64).
        let u = ((bits >> 32) as i64) as f64 * SCALE - 1.0;
        let v = ((bits & 0xFFFF_FFFF) as i64) as f64 * SCALE - 1.0;
        let s = u * u + v * v;
        if s <= 1.0 && s > 1.0e-12 {
            return (u, v, s);
        }
    }
}

/// At a boundary: reflect with the Fresnel probability, otherwise refract into the next layer or
/// escape into the ambient medium (MCML's `CrossUpOrNot` / `CrossDnOrNot`, statistical mode).
#[inline]
pub(crate) fn cross_or_not<S: Scorer>(m: &Medium, p: &mut Photon, rng: &mut Rng, scorer: &mut S) {
    let slab = m.slabs[p.layer];
    let up = p.uz < 0.0;
    let (n_t, cos_crit) = if up {
        (slab.n_up, slab.cos_crit_up)
    } else {
        (slab.n_down, slab.cos_crit_down)
    };
    let cos_i = p.uz.abs();
    let (r, cos_t) = if cos_i <= cos_crit {
        (1.0, 0.0)
    } else {
        fresnel(slab.n, n_t, cos_i)
    };
    let xi_fresnel: f64 = rng.random();
    if xi_fresnel > r {
        let last = if up {
            p.layer == 0
        } else {
            p.layer + 1 == m.slabs.len()
        };
        if last {
            scorer.escape(p, up, cos_t);
            p.alive = false;
        } else {
            p.layer = if up { p.layer - 1 } else { p.layer + 1 };
            let ratio = slab.n / n_t;
            p.ux *= ratio;
            p.uy *= ratio;
            p.uz = cos_t.copysign(p.uz);
        }
    } else {
        p.uz = -p.uz;
    }
}

/// Importance roulette, for runs that tally only what leaves through the surfaces. A photon at
/// depth z reaches a surface with a probability that falls as
/// I(z) = max(e^{−τ(z)}, e^{−(τ_T − τ(z))}), τ(z) = ∫₀^z μ_eff dz' (diffusion theory's
/// attenuation towards the top and the bottom surface; τ_T over the whole sample). When its
/// importance-weighted weight w·I(z) is below [`IMPORTANCE_THRESHOLD`] it survives with
/// probability p = max(w·I(z) / [`IMPORTANCE_TARGET`], w) and weight w/p, never above 1.
/// Unbiased for every tally whatever I is (E[weight] = w); I only decides where the work goes:
/// photons a few 1/μ_eff deep in a weakly absorbing half-space carry a thousandth of the
/// reflected light but most of the interactions (Soy milk R: 72 % of the events are spent by
/// photons that go deeper than 3/μ_eff, which bring back 0.1 % of the reflected weight). The cap
/// on the survivor's weight bounds what one deep photon adds to the absorption tallies' variance.
/// Off when absorption is tallied in depth, where every deposit matters.
pub(crate) fn importance(m: &Medium, p: &mut Photon, rng: &mut Rng) {
    let slab = &m.slabs[p.layer];
    let tau = slab.tau0 + slab.mu_eff * (p.z - slab.z0).clamp(0.0, slab.z1 - slab.z0);
    // One exponential of the larger exponent: the other would underflow in a half-space.
    let weighted = p.w * (-tau).max(tau - m.tau_total).exp();
    let survival = (weighted / IMPORTANCE_TARGET).max(p.w);
    if weighted < IMPORTANCE_THRESHOLD && survival < 1.0 {
        roulette(p, rng, survival);
    }
}

/// Russian roulette: survive with probability `survival` and weight / `survival`, else die.
pub(crate) fn roulette(p: &mut Photon, rng: &mut Rng, survival: f64) {
    let xi_roulette: f64 = rng.random();
    let factor = if xi_roulette < survival {
        1.0 / survival
    } else {
        0.0
    };
    p.w *= factor;
    if factor == 0.0 {
        p.alive = false;
    }
}
