//! Several photons in flight per core: the walk of [`crate::photon`] traced four or eight
//! photons at a time in SIMD lanes (`wide::f64x4` or `f64x8`: `LANES`), for runs of one
//! interacting layer that keep no per-photon moments below the surface: those that tally only
//! what leaves through the surfaces (every profile of the library, `eval`, `render`, `reproduce`,
//! `simulate` without `--full`), and MCML runs of one layer whose A(r, z) is summed as MCML sums
//! it (`.mci`, `simulate --full`: `TallySet::absorption_rz_se` off).
//!
//! One interaction of a lane is MCML's hop–drop–spin without a branch: the free path
//! s = −ln ξ / μt, the move, the implicit-capture deposit w·μa/μt, and the new direction are
//! computed for all lanes at once, and a lane whose step would cross a surface keeps its
//! state. Such a lane (a boundary hit: MCML's `CrossUpOrNot`/`CrossDnOrNot`, with Fresnel's
//! reflectance), a lane whose weight fell below the roulette threshold, and the periodic
//! importance and path-length roulettes are handled one lane at a time by the scalar walk's own
//! functions. A lane whose photon has ended launches the chunk's next photon. The physics is the
//! scalar walk's with three exact rewritings:
//! - a step cut at a boundary is not resumed with its leftover optical depth: a reflected photon
//!   draws a fresh exponential free path, which has the same distribution (the exponential is
//!   memoryless: given s > d, s − d is again exponential with rate μt);
//! - the deposits of a history are summed in the lane and handed to the scorer when the history
//!   ends (A and A_l per photon); where A(r, z) is tallied without per-photon moments, each
//!   deposit also goes to its cell as it happens;
//! - the periodic roulettes come after every [`IMPORTANCE_INTERVAL`]-th interaction of a photon,
//!   as in the scalar walk, but before MCML's weight roulette of the same step (each is unbiased
//!   on its own, in any order).
//!
//! The lanes' arithmetic is compiled for the machine's vector width (`.cargo/config.toml`).
//!
//! Random numbers: each lane has its own PCG-64 stream, seeded from the chunk's stream, so a
//! chunk's result depends on (seed, chunk) alone, never on threads or shards; the scalar work
//! draws from it. The draws of every interaction come from a second generator per lane,
//! xoshiro256++ run in the vector registers (seeded from the lane's PCG stream: scalar PCG-64
//! draws, one lane at a time, took a fifth of the walk). A lane draws two 64-bit words per
//! interaction: ξ of the free path from the first (52 bits, ξ ∈ (0, 1], so s ≤ 36 mean free
//! paths: P(s > 36/μt) = e⁻³⁶ ≈ 2·10⁻¹⁶), the scattering angle and the azimuth from the two
//! halves of the second (32 bits each, as the scalar walk's azimuth), one step ahead of their use.

use rand::{RngExt, SeedableRng};
use wide::bytemuck::cast;

use crate::fresnel::COS_ZERO;
use crate::photon::{
    Depth, IMPORTANCE_INTERVAL, IMPORTANCE_TARGET, IMPORTANCE_THRESHOLD, Medium,
    PATH_ROULETTE_INTERVAL, Photon, ROULETTE_SURVIVAL, ROULETTE_THRESHOLD, Scorer, cross_or_not,
    hop, importance, launch, roulette, trace,
};
use crate::rng::Rng;

/// Photons in flight per core: one AVX-512 register of f64 where the build has them, else four
/// (measured on AVX-512: eight lanes 7 % faster than four; on AVX2 four lanes 9 % faster than
/// eight, whose state no longer fits the sixteen registers).
#[cfg(target_feature = "avx512f")]
mod width {
    pub type Wide = wide::f64x8;
    pub type WideBits = wide::u64x8;
    pub const LANES: usize = 8;
}
#[cfg(not(target_feature = "avx512f"))]
mod width {
    pub type Wide = wide::f64x4;
    pub type WideBits = wide::u64x4;
    pub const LANES: usize = 4;
}
use width::WideBits;
pub(crate) use width::{LANES, Wide};

/// Bits of 1.0: a 52-bit mantissa under this exponent is uniform in [1, 2).
const ONE_BITS: u64 = 0x3FF0_0000_0000_0000;

/// Traces `photons` photon histories from `rng`'s stream: in lanes where the medium is one
/// interacting layer and the scorer keeps no per-photon moments of A(r, z), else one after another
/// with [`trace`]. (Per-photon A(r, z) scratches do not pay in lanes: that work is bound by
/// memory, and measured 1.4× slower with a scratch per lane.)
pub(crate) fn trace_photons<S: Scorer>(m: &Medium, rng: &mut Rng, scorer: &mut S, photons: u64) {
    if m.slabs.len() == 1 && m.slabs[0].mu_t > 0.0 && scorer.depth() != Depth::PerPhoton {
        Walk::new(m, rng, scorer, photons).run();
    } else {
        for _ in 0..photons {
            trace(m, rng, scorer);
        }
    }
}

/// The photons' states, one per lane. Plain `Copy` data: the walk keeps it in registers and
/// hands it by reference only to the scalar work, which is rare.
#[derive(Clone, Copy)]
struct Lanes {
    x: Wide,
    y: Wide,
    z: Wide,
    ux: Wide,
    uy: Wide,
    uz: Wide,
    w: Wide,
    /// Weight deposited so far in each lane's history.
    absorbed: Wide,
    /// Interactions of each lane's history.
    interactions: WideBits,
    /// All ones in the lanes that hold a photon (none once the chunk has no photon left).
    busy: Wide,
}

/// Lane `k` of `v`.
#[inline(always)]
fn lane(v: Wide, k: usize) -> f64 {
    v.as_array()[k]
}

/// The lanes' states as plain arrays, for the scalar work: unpacked once, edited lane by lane,
/// packed once (writing single lanes of a vector one at a time costs a stalled store forwarding
/// for each).
struct Unpacked {
    x: [f64; LANES],
    y: [f64; LANES],
    z: [f64; LANES],
    ux: [f64; LANES],
    uy: [f64; LANES],
    uz: [f64; LANES],
    w: [f64; LANES],
    absorbed: [f64; LANES],
    interactions: [u64; LANES],
    busy: [bool; LANES],
}

impl Lanes {
    fn unpack(&self) -> Unpacked {
        Unpacked {
            x: self.x.to_array(),
            y: self.y.to_array(),
            z: self.z.to_array(),
            ux: self.ux.to_array(),
            uy: self.uy.to_array(),
            uz: self.uz.to_array(),
            w: self.w.to_array(),
            absorbed: self.absorbed.to_array(),
            interactions: self.interactions.to_array(),
            busy: std::array::from_fn(|k| self.busy.to_bitmask() & (1 << k) != 0),
        }
    }

    fn pack(u: &Unpacked) -> Self {
        let ones = f64::from_bits(u64::MAX);
        Lanes {
            x: Wide::from(u.x),
            y: Wide::from(u.y),
            z: Wide::from(u.z),
            ux: Wide::from(u.ux),
            uy: Wide::from(u.uy),
            uz: Wide::from(u.uz),
            w: Wide::from(u.w),
            absorbed: Wide::from(u.absorbed),
            interactions: WideBits::from(u.interactions),
            busy: Wide::from(u.busy.map(|b| if b { ones } else { 0.0 })),
        }
    }
}

impl Unpacked {
    /// Lane `k` as a scalar photon.
    fn photon(&self, k: usize) -> Photon {
        Photon {
            x: self.x[k],
            y: self.y[k],
            z: self.z[k],
            ux: self.ux[k],
            uy: self.uy[k],
            uz: self.uz[k],
            w: self.w[k],
            layer: 0,
            s_left: 0.0,
            interactions: self.interactions[k],
            alive: true,
        }
    }

    /// Writes a scalar photon into lane `k`.
    fn set(&mut self, k: usize, p: &Photon) {
        self.x[k] = p.x;
        self.y[k] = p.y;
        self.z[k] = p.z;
        self.ux[k] = p.ux;
        self.uy[k] = p.uy;
        self.uz[k] = p.uz;
        self.w[k] = p.w;
        self.interactions[k] = p.interactions;
    }
}

/// The walk of one chunk in lanes: the state, the chunk's progress and each lane's stream.
struct Walk<'a, S> {
    m: &'a Medium,
    scorer: &'a mut S,
    rng: [Rng; LANES],
    /// The per-interaction draws of every lane.
    draws: LaneRng,
    /// Photons launched so far, and the chunk's total.
    launched: u64,
    photons: u64,
}

impl<'a, S: Scorer> Walk<'a, S> {
    fn new(m: &'a Medium, rng: &mut Rng, scorer: &'a mut S, photons: u64) -> Self {
        let mut rng: [Rng; LANES] = std::array::from_fn(|_| Rng::from_rng(rng));
        let draws = LaneRng::new(&mut rng);
        Walk {
            m,
            scorer,
            rng,
            draws,
            launched: 0,
            photons,
        }
    }

    /// Launches the chunk's next photon in lane `k`, or idles the lane when all are launched.
    fn start(&mut self, u: &mut Unpacked, k: usize) {
        u.absorbed[k] = 0.0;
        u.set(k, &launch(self.m));
        u.busy[k] = self.launched < self.photons;
        self.launched += u64::from(u.busy[k]);
    }

    /// After scalar work on lane `k`: the photon goes back into its lane, or its history ends
    /// (its deposits go to the scorer in one sum) and the lane launches the next one.
    fn settle(&mut self, u: &mut Unpacked, k: usize, p: Photon) {
        if p.alive {
            u.set(k, &p);
        } else {
            self.scorer.absorb_total(&p, u.absorbed[k]);
            self.scorer.finish(&p);
            self.start(u, k);
        }
    }

    /// The scalar work of one step: boundary hits (the lanes in `hits`: the photon moves to the
    /// surface and is reflected or escapes) and MCML's weight roulette (the lanes in `light`).
    #[inline(never)]
    fn events(&mut self, v: &mut Lanes, hits: u32, light: u32) {
        let slab = self.m.slabs[0];
        let mut u = v.unpack();
        for k in 0..LANES {
            if !u.busy[k] {
                continue;
            }
            if hits & (1 << k) != 0 {
                let mut p = u.photon(k);
                let bound = if p.uz > 0.0 { slab.z1 } else { slab.z0 };
                let d = (bound - p.z) / p.uz;
                hop(&mut p, d);
                cross_or_not(self.m, &mut p, &mut self.rng[k], self.scorer);
                self.settle(&mut u, k, p);
            }
            if light & (1 << k) != 0 && u.busy[k] {
                let mut p = u.photon(k);
                if p.w < ROULETTE_THRESHOLD {
                    roulette(&mut p, &mut self.rng[k], ROULETTE_SURVIVAL);
                }
                self.settle(&mut u, k, p);
            }
        }
        *v = Lanes::pack(&u);
    }

    /// The periodic roulettes of the scalar walk (`hop_drop_spin`) for the lanes in `due`, whose
    /// photons have just had an interaction whose count is a multiple of [`IMPORTANCE_INTERVAL`]
    /// and which may play one: the path-length roulette every [`PATH_ROULETTE_INTERVAL`]
    /// interactions, then the importance roulette (which decides again, in scalar arithmetic).
    #[inline(never)]
    fn checks(&mut self, v: &mut Lanes, due: u32) {
        let mut u = v.unpack();
        for k in (0..LANES).filter(|k| due & (1 << k) != 0) {
            let mut p = u.photon(k);
            if p.interactions.is_multiple_of(PATH_ROULETTE_INTERVAL) {
                roulette(&mut p, &mut self.rng[k], 0.5);
            }
            if p.alive && self.m.importance {
                importance(self.m, &mut p, &mut self.rng[k]);
            }
            self.settle(&mut u, k, p);
        }
        *v = Lanes::pack(&u);
    }

    fn run(mut self) {
        let m = self.m;
        let slab = m.slabs[0];
        let splat = Wide::splat;
        let (z0, z1) = (splat(slab.z0), splat(slab.z1));
        let inv_mu_t = splat(1.0 / slab.mu_t);
        let absorb = splat(slab.absorb);
        let threshold = splat(ROULETTE_THRESHOLD);
        let summed = self.scorer.depth() == Depth::Summed;
        let (tau0, mu_eff) = (splat(slab.tau0), splat(slab.mu_eff));
        let (depth, tau_total) = (splat(slab.z1 - slab.z0), splat(m.tau_total));
        let importance_threshold = splat(IMPORTANCE_THRESHOLD);
        let zero = [0.0; LANES];
        let mut u = Unpacked {
            x: zero,
            y: zero,
            z: zero,
            ux: zero,
            uy: zero,
            uz: zero,
            w: zero,
            absorbed: zero,
            interactions: [0; LANES],
            busy: [false; LANES],
        };
        for k in 0..LANES {
            self.start(&mut u, k);
        }
        let mut v = Lanes::pack(&u);
        // The next step's draws are made a step ahead: they depend on nothing the step does, so
        // their logarithm's latency overlaps the step's work (the same numbers in the same order).
        let mut next = self.draws.step(inv_mu_t);
        while v.busy.any() {
            let (s, xi_theta, psi) = next;
            next = self.draws.step(inv_mu_t);
            // Hop: s = −ln ξ / μt; lanes whose step ends beyond a surface are boundary hits.
            let z_end = v.z + s * v.uz;
            let hit = z_end.simd_lt(z0) | z_end.simd_gt(z1);
            // Drop and spin on every lane; boundary hits keep their state.
            let (ux, uy, uz) = scatter(slab.g, v.ux, v.uy, v.uz, xi_theta, psi);
            let dw = v.w * absorb;
            v.x = hit.select(v.x, v.x + s * v.ux);
            v.y = hit.select(v.y, v.y + s * v.uy);
            v.z = hit.select(v.z, z_end);
            v.ux = hit.select(v.ux, ux);
            v.uy = hit.select(v.uy, uy);
            v.uz = hit.select(v.uz, uz);
            v.w = hit.select(v.w, v.w - dw);
            v.absorbed = hit.select(v.absorbed, v.absorbed + dw);
            // All ones (−1) where an interaction took place.
            v.interactions -= cast::<Wide, WideBits>(!hit);
            if summed {
                let drops = (!hit & v.busy).to_bitmask();
                let r = (v.x * v.x + v.y * v.y).sqrt();
                for k in (0..LANES).filter(|k| drops & (1 << k) != 0) {
                    self.scorer
                        .deposit_summed(lane(r, k), lane(v.z, k), lane(dw, k));
                }
            }

            // The periodic roulettes, after every IMPORTANCE_INTERVAL-th interaction of a photon.
            let every = WideBits::splat(IMPORTANCE_INTERVAL - 1);
            let due = (v.interactions & every)
                .simd_eq(WideBits::ZERO)
                .to_bitmask()
                & (!hit & v.busy).to_bitmask();
            if due != 0 {
                // Of those, the lanes that may play a roulette: a path-length interval is over,
                // or (`importance`) w·I(z) is below the threshold with a survival below 1.
                let n = v.interactions.as_array();
                let path = (0..LANES)
                    .filter(|&k| n[k].is_multiple_of(PATH_ROULETTE_INTERVAL))
                    .fold(0, |bits, k| bits | 1 << k);
                let low = if m.importance {
                    // A prefilter (`importance` decides exactly): every lane whose w·I(z) may be
                    // below the threshold, from a lower bound of I = e^{−τ} (τ the smaller of
                    // the two attenuations) without an exponential (9 % of a white table).
                    let tau = tau0 + mu_eff * (v.z - z0).clamp(Wide::ZERO, depth);
                    let bound = attenuation_bound(tau.min(tau_total - tau));
                    // The survival max(w·I/target, w) is below 1 exactly when w is, as w·I is
                    // below the threshold, half the target.
                    const { assert!(2.0 * IMPORTANCE_THRESHOLD <= IMPORTANCE_TARGET) };
                    ((v.w * bound).simd_lt(importance_threshold) & v.w.simd_lt(Wide::ONE))
                        .to_bitmask()
                } else {
                    0
                };
                if due & (path | low) != 0 {
                    self.checks(&mut v, due & (path | low));
                }
            }
            let hits = (hit & v.busy).to_bitmask();
            let light = (v.w.simd_lt(threshold) & v.busy).to_bitmask();
            if hits | light != 0 {
                self.events(&mut v, hits, light);
            }
        }
    }
}

/// xoshiro256++ (Blackman & Vigna 2021) in every lane: the walk's per-interaction draws.
struct LaneRng {
    s: [WideBits; 4],
}

impl LaneRng {
    /// Each lane's state from four words of that lane's stream (never all zero).
    fn new(rng: &mut [Rng; LANES]) -> Self {
        let mut words = [[0u64; LANES]; 4];
        for (k, r) in rng.iter_mut().enumerate() {
            for w in words.iter_mut() {
                w[k] = r.random();
            }
            words[0][k] |= u64::from(words.iter().all(|w| w[k] == 0));
        }
        LaneRng {
            s: words.map(WideBits::from),
        }
    }

    /// One interaction's draws: the free path s = −ln ξ / μt (ξ ∈ (0, 1] from 52 bits of the
    /// first word) [cm], ξ_θ ∈ [0, 1) from the high half of the second and the azimuth's
    /// (sin ψ, cos ψ) from its low half ([`azimuth`]).
    #[inline(always)]
    fn step(&mut self, inv_mu_t: Wide) -> (Wide, Wide, (Wide, Wide)) {
        let (a, b) = (self.next(), self.next());
        let xi_s = Wide::ONE - fraction(a >> 12);
        (-xi_s.ln() * inv_mu_t, fraction((b >> 32) << 20), azimuth(b))
    }

    #[inline(always)]
    fn next(&mut self) -> WideBits {
        let rotl = |x: WideBits, k: u32| (x << k) | (x >> (64 - k));
        let [mut s0, mut s1, mut s2, mut s3] = self.s;
        let out = rotl(s0 + s3, 23) + s0;
        let t = s1 << 17;
        s2 ^= s0;
        s3 ^= s1;
        s1 ^= s2;
        s0 ^= s3;
        s2 ^= t;
        s3 = rotl(s3, 45);
        self.s = [s0, s1, s2, s3];
        out
    }
}

/// The number in [0, 1) whose 52-bit binary fraction is `mantissa` (exact: 1 + it, less 1).
#[inline(always)]
fn fraction(mantissa: WideBits) -> Wide {
    cast::<WideBits, Wide>(mantissa | WideBits::splat(ONE_BITS)) - Wide::ONE
}

/// A lower bound of e^{−τ} for τ ≥ 0 in five operations: (1 − τ/16)¹⁶ (as (1 − x/n)ⁿ ≤ e^{−x}),
/// 0 from τ = 16; within 17 % of e^{−τ} where e^{−τ} ≥ 0.1.
#[inline(always)]
fn attenuation_bound(tau: Wide) -> Wide {
    let mut bound = (Wide::ONE - tau * Wide::splat(1.0 / 16.0)).max(Wide::ZERO);
    for _ in 0..4 {
        bound = bound * bound;
    }
    bound
}

/// (sin ψ, cos ψ) of the azimuth ψ = 2π·u, u = (low 32 bits of `bits`)/2³² ∈ [0, 1).
///
/// The argument comes from bits, so its reduction is exact: 4u is split into the nearest whole
/// quarter turn k and the rest f = 4u − k ∈ [−½, ½] (both exact in f64), and sin and cos of
/// x = f·π/2 ∈ [−π/4, π/4] come from Cephes' minimax polynomials (as in `wide`'s `sin_cos`, whose
/// general reduction of any argument took a quarter of the walk's time); the quarter turns then
/// swap and negate them: ψ = kπ/2 + x.
#[inline(always)]
fn azimuth(bits: WideBits) -> (Wide, Wide) {
    let one = Wide::ONE;
    let v = fraction((bits << 32) >> 12) * Wide::splat(4.0);
    let k = v.round();
    let x = (v - k) * Wide::splat(std::f64::consts::FRAC_PI_2);
    let x2 = x * x;
    let poly = |c: [f64; 6]| {
        c.iter()
            .rev()
            .fold(Wide::ZERO, |acc, &ci| acc.mul_add(x2, Wide::splat(ci)))
    };
    let sin_x = (x * x2).mul_add(
        poly([
            -1.666_666_666_666_663e-1,
            8.333_333_333_322_118e-3,
            -1.984_126_982_958_954e-4,
            2.755_731_362_138_572_2e-6,
            -2.505_074_776_285_780_7e-8,
            1.589_623_015_765_465_6e-10,
        ]),
        x,
    );
    let cos_x = (x2 * x2).mul_add(
        poly([
            4.166_666_666_666_659_5e-2,
            -1.388_888_888_887_305_6e-3,
            2.480_158_728_885_170_4e-5,
            -2.755_731_417_929_674e-7,
            2.087_570_084_197_473e-9,
            -1.135_853_652_138_768_2e-11,
        ]),
        x2.mul_neg_add(Wide::splat(0.5), one),
    );
    // k ∈ {0, …, 4} as an integer: the low bits of k + 2⁵².
    let q = cast::<Wide, WideBits>(k + Wide::splat(4_503_599_627_370_496.0));
    let odd = cast::<WideBits, Wide>((q & WideBits::splat(1)).simd_eq(WideBits::splat(1)));
    let (sin, cos) = (odd.select(cos_x, sin_x), odd.select(sin_x, cos_x));
    // sin ψ is negative in quarters 2 and 3, cos ψ in quarters 1 and 2 (the sign bit's xor).
    let sign = |m: WideBits| cast::<WideBits, Wide>((m & WideBits::splat(2)) << 62);
    (sin ^ sign(q), cos ^ sign(q + WideBits::splat(1)))
}

/// New directions after a Henyey–Greenstein scattering of all lanes (the scalar walk's `spin`,
/// without its branches): cos θ by inversion of the CDF from `xi_theta`, the azimuth's
/// (sin ψ, cos ψ) from [`azimuth`], applied in the frame of the old direction (u_x, u_y, u_z), or
/// about the z axis where |u_z| > [`COS_ZERO`] (MCML's `Spin`). Isotropic scattering (g = 0)
/// draws cos θ = 1 − 2ξ directly in the fixed frame.
#[inline(always)]
fn scatter(
    g: f64,
    ux: Wide,
    uy: Wide,
    uz: Wide,
    xi_theta: Wide,
    (sin_psi, cos_psi): (Wide, Wide),
) -> (Wide, Wide, Wide) {
    let one = Wide::ONE;
    if g == 0.0 {
        let cos_t = one - (xi_theta + xi_theta);
        // sin θ = √(1 − cos²θ) = 2√(ξ(1 − ξ)), exact near the poles.
        let sin_t = (xi_theta * (one - xi_theta)).sqrt() * Wide::splat(2.0);
        return (sin_t * cos_psi, sin_t * sin_psi, cos_t);
    }
    let cos_t = if g.abs() == 1.0 {
        Wide::splat(g)
    } else {
        // (phase.rs) cos θ = (1 + g² − t²)/(2g), t = (1 − g²)/(1 − g + 2gξ).
        let gv = Wide::splat(g);
        let t = Wide::splat(1.0 - g * g) / (Wide::splat(1.0 - g) + gv * (xi_theta + xi_theta));
        ((Wide::splat(1.0 + g * g) - t * t) * Wide::splat(0.5 / g))
            .fast_max(-one)
            .fast_min(one)
    };
    let sin_t = (one - cos_t * cos_t).fast_max(Wide::ZERO).sqrt();
    let (sx, sy) = (sin_t * cos_psi, sin_t * sin_psi);
    // Near the axis the old frame is degenerate: rotate about z.
    let on_axis = uz.abs().simd_gt(Wide::splat(COS_ZERO));
    let axis_uz = uz.simd_lt(Wide::ZERO).select(-cos_t, cos_t);
    let t = (one - uz * uz).fast_max(Wide::splat(1.0e-300)).sqrt();
    // sin θ / √(1 − u_z²), one division for both transverse components.
    let k = sin_t / t;
    let gen_ux = k * (ux * uz * cos_psi - uy * sin_psi) + ux * cos_t;
    let gen_uy = k * (uy * uz * cos_psi + ux * sin_psi) + uy * cos_t;
    let gen_uz = uz * cos_t - sx * t;
    (
        on_axis.select(sx, gen_ux),
        on_axis.select(sy, gen_uy),
        on_axis.select(axis_uz, gen_uz),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::{RngCore, SeedableRng};

    /// Each lane's draws are the reference xoshiro256++ (rand_xoshiro) from the four words its
    /// PCG stream gave first.
    #[test]
    fn each_lane_draws_xoshiro256_plus_plus() {
        let mut pcg: [Rng; LANES] = std::array::from_fn(|k| crate::rng::chunk_rng(7, k as u64));
        let mut reference: Vec<Xoshiro256PlusPlus> = pcg
            .clone()
            .iter_mut()
            .map(|r| {
                let mut seed = [0u8; 32];
                for word in seed.chunks_mut(8) {
                    word.copy_from_slice(&r.random::<u64>().to_le_bytes());
                }
                Xoshiro256PlusPlus::from_seed(seed)
            })
            .collect();
        let mut lanes = LaneRng::new(&mut pcg);
        for _ in 0..1000 {
            let drawn = lanes.next().to_array();
            for (k, r) in reference.iter_mut().enumerate() {
                assert_eq!(drawn[k], r.next_u64(), "lane {k}");
            }
        }
    }

    /// The importance prefilter's bound never exceeds e^{−τ} (else it would skip roulettes that
    /// are due) and stays close to it where the roulette's threshold lies.
    #[test]
    fn the_attenuation_bound_is_below_the_exponential() {
        for i in 0..=200_000 {
            let tau = i as f64 * 1e-4
                + if i > 100_000 {
                    1e3 * (i - 100_000) as f64
                } else {
                    0.0
                };
            let b = attenuation_bound(Wide::splat(tau)).as_array()[0];
            let e = (-tau).exp();
            assert!(b <= e && b >= 0.0, "τ = {tau}: {b} > {e}");
            if e >= 0.1 {
                assert!(b >= 0.83 * e, "τ = {tau}: {b} against {e}");
            }
        }
    }

    /// The azimuth is (sin, cos) of 2π·u to 10⁻¹⁵ (the reference's own argument 2π·u is rounded
    /// by up to 4.4·10⁻¹⁶; a wrong quarter turn or sign is off by order 1), on the quarter turns'
    /// edges and between them.
    #[test]
    fn the_azimuth_is_the_sine_and_cosine_of_two_pi_u() {
        let mut words: Vec<u64> = (0..=8u64)
            .flat_map(|e| [e << 29, (e << 29).wrapping_sub(1), (e << 29) + 1])
            .filter(|&w| w < 1 << 32)
            .collect();
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        words.extend((0..100_000).map(|_| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            x >> 32
        }));
        for chunk in words.chunks(LANES) {
            let mut bits = [0u64; LANES];
            bits[..chunk.len()].copy_from_slice(chunk);
            // High bits are not the azimuth's: they must not matter.
            let high = bits.map(|b| b | 0xDEAD_BEEF << 32);
            let (sin, cos) = azimuth(WideBits::from(high));
            for (k, &w) in chunk.iter().enumerate() {
                let psi = std::f64::consts::TAU * (w as f64 / 4_294_967_296.0);
                let (s, c) = (sin.as_array()[k], cos.as_array()[k]);
                assert!(
                    (s - psi.sin()).abs() < 1e-15,
                    "sin at {w}: {s} vs {}",
                    psi.sin()
                );
                assert!(
                    (c - psi.cos()).abs() < 1e-15,
                    "cos at {w}: {c} vs {}",
                    psi.cos()
                );
            }
        }
    }
}
