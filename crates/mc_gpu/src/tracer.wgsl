// One photon packet's random walk through the layered sample, MCML's steps (Wang, Jacques & Zheng
// 1995, §3-4) in f32: launch, step size, boundary hit, hop, drop, spin, cross or not, roulette;
// with mc's path-length roulette and, for runs that tally nothing below the surfaces, its
// importance roulette (crates/mc/src/photon.rs). Units: the run's lengths (cm, or mean free paths
// for a batch channel's walk; the tally grid is scaled to match on the host). +z into the sample.
//
// Each invocation owns a slot: a photon in flight, kept in a storage buffer between dispatches.
// A dispatch takes at most `params.steps` steps per slot, and a slot whose photon ends takes the
// round's next photon index from an atomic counter, so the invocations of a SIMD group stay busy
// while histories differ in length, and no dispatch runs long however long a history is (Mesa's
// lavapipe of Debian 12 silently ends a shader's loops after 65,535 iterations in all, and desktop
// drivers reset a GPU whose dispatch runs for seconds). A photon's random stream depends on its
// index alone, and its state is saved bit for bit, so neither the slots nor the steps per
// dispatch change any result.

const MAX_LAYERS: u32 = 16u;

// The walk's features, fixed when its pipeline is built (tracer.rs's Variant): lavapipe executes
// every branch of the loop under a mask, so code a walk never needs costs it time (measured: the
// glass branch alone, never taken in a half-space, cost 23 % of skin1's run).
// Some layer neither absorbs nor scatters (MCML's glass).
override GLASS: bool = true;
// More than one layer.
override LAYERED: bool = true;
// Photons play mc's importance roulette (runs that tally nothing below the surfaces).
override IMPORTANCE: bool = true;
// Some layer scatters isotropically (g = 0) / some layer does not (phase.wgsl).
override ISOTROPIC: bool = true;
override ANISOTROPIC: bool = true;
// A profile table's walk (mc_gpu's table.rs): each exit through the top is scored once per albedo
// of the table, on the table's radial intervals, and nothing else is tallied.
override TABLE: bool = false;
// MCML's WEIGHT and CHANCE (mc::ROULETTE_THRESHOLD, mc::ROULETTE_SURVIVAL).
const ROULETTE_THRESHOLD: f32 = 1.0e-4;
const ROULETTE_SURVIVAL: f32 = 0.1;
// mc::PATH_ROULETTE_INTERVAL: a survival-½ roulette every this many interactions.
const PATH_ROULETTE_INTERVAL: u32 = 100000u;
// mc::IMPORTANCE_INTERVAL, mc::IMPORTANCE_THRESHOLD, mc::IMPORTANCE_TARGET.
const IMPORTANCE_INTERVAL: u32 = 16u;
const IMPORTANCE_THRESHOLD: f32 = 0.1;
const IMPORTANCE_TARGET: f32 = 0.2;

// The run and this dispatch (tracer.rs's Params).
struct Params {
    seed_lo: u32,
    seed_hi: u32,
    // Index of the round's first photon in the run (64 bits).
    base_lo: u32,
    base_hi: u32,
    // Photons in the round.
    count: u32,
    layers: u32,
    // Layer photons are launched into (1 under a glass top layer, as MCML does).
    first: u32,
    // A table's albedos (TABLE); 0 otherwise.
    albedos: u32,
    // Radial bins (a table's intervals: its edges + 1).
    nr: u32,
    na: u32,
    // Radial bins per length unit of the walk, 1/dr [1/unit].
    inv_dr: f32,
    // Exit-angle bins per radian, 1/da.
    inv_da: f32,
    // Launched weight 1 − Rsp.
    w0: f32,
    // ∫ μ_eff dz over the whole sample [-].
    tau_total: f32,
    // Slots (invocations that hold a photon) and steps per slot in this dispatch.
    slots: u32,
    steps: u32,
}

// A layer prepared for transport (medium.rs's Slab).
struct Slab {
    z0: f32,
    z1: f32,
    n: f32,
    mu_t: f32,
    // μa/μt: the fraction of the weight deposited at each interaction.
    absorb: f32,
    g: f32,
    cos_crit_up: f32,
    cos_crit_down: f32,
    n_up: f32,
    n_down: f32,
    // Diffusion's effective attenuation μ_eff and ∫ μ_eff dz down to z0 (importance roulette).
    mu_eff: f32,
    tau0: f32,
}

struct Photon {
    pos: vec3<f32>,
    u: vec3<f32>,
    w: f32,
    layer: u32,
    // Optical depth left over from a step cut at a boundary.
    s_left: f32,
    interactions: u32,
    alive: bool,
}

// A photon in flight between dispatches, with its stream and its history's deposits so far.
struct Slot {
    x: f32,
    y: f32,
    z: f32,
    ux: f32,
    uy: f32,
    uz: f32,
    w: f32,
    s_left: f32,
    layer: u32,
    interactions: u32,
    alive: u32,
    absorbed_here: f32,
    rng: vec4<u32>,
    absorbed: array<f32, MAX_LAYERS>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> slabs: array<Slab>;
@group(0) @binding(4) var<storage, read_write> slots: array<Slot>;
// TABLE: per albedo ln(α/α_walk) (in the table's order, increasing), then the radial intervals'
// nr − 1 edges [walk units], increasing. One unused word otherwise.
@group(0) @binding(5) var<storage, read> table: array<f32>;

// The current history's deposits in the layers it has left, per layer, and in the layer it is
// in; and that layer (loaded when the photon enters it, not at every step).
var<private> absorbed: array<f32, MAX_LAYERS>;
var<private> absorbed_here: f32;
// The history's escape, if any: its tally entry and weight (0: none).
var<private> escaped_entry: u32;
var<private> escaped_w: f32;
// Its interactions (TABLE).
var<private> escaped_n: u32;
var<private> slab: Slab;

// The photon enters `layer`: what it deposited in the one it leaves is put by, the new one loaded.
fn enter(from_layer: u32, layer: u32) {
    absorbed[from_layer] += absorbed_here;
    absorbed_here = 0.0;
    slab = slabs[layer];
}

// Pencil beam at the origin along +z, weight 1 − Rsp (MCML's LaunchPhoton).
fn launch() -> Photon {
    absorbed = array<f32, MAX_LAYERS>();
    absorbed_here = 0.0;
    escaped_w = 0.0;
    slab = slabs[params.first];
    return Photon(
        vec3<f32>(0.0, 0.0, slabs[params.first].z0),
        vec3<f32>(0.0, 0.0, 1.0),
        params.w0,
        params.first,
        0.0,
        0u,
        true,
    );
}

// Free path s = −ln ξ / μt (eq. 3.6), or the optical depth left over from the last boundary.
fn step_size(p: ptr<function, Photon>, mu_t: f32, rng: ptr<function, Rng>) -> f32 {
    if ((*p).s_left == 0.0) {
        return -log(rand01_open(rng)) / mu_t;
    }
    let s = (*p).s_left / mu_t;
    (*p).s_left = 0.0;
    return s;
}

// Moves the photon to the boundary it reaches within s (eq. 3.14-3.15) and returns true, or
// returns false. The photon is put exactly on the boundary, so that f32's rounding never leaves
// it outside its layer.
fn hit_boundary(p: ptr<function, Photon>, s: f32) -> bool {
    let z_end = (*p).pos.z + s * (*p).u.z;
    var z_b: f32;
    if (z_end > slab.z1) {
        z_b = slab.z1;
    } else if (z_end < slab.z0) {
        z_b = slab.z0;
    } else {
        return false;
    }
    let d = (z_b - (*p).pos.z) / (*p).u.z;
    (*p).s_left = (s - d) * slab.mu_t;
    (*p).pos = vec3<f32>((*p).pos.xy + d * (*p).u.xy, z_b);
    return true;
}

// Implicit capture: deposit w·μa/μt, keep the rest (MCML's Drop, eq. 3.23).
fn drop(p: ptr<function, Photon>, absorb: f32) {
    let dw = (*p).w * absorb;
    (*p).w -= dw;
    (*p).interactions += 1u;
    absorbed_here += dw;
}

// Russian roulette: survive with probability `survival` and weight / survival (eq. 3.44).
fn roulette(p: ptr<function, Photon>, rng: ptr<function, Rng>, survival: f32) {
    if (rand01(rng) < survival) {
        (*p).w /= survival;
    } else {
        (*p).w = 0.0;
        (*p).alive = false;
    }
}

// mc's importance roulette (photon.rs `importance`): a photon whose weight times its diffusion
// importance I(z) = max(e^−τ(z), e^−(τ_T − τ(z))) is below IMPORTANCE_THRESHOLD survives with
// p = max(w·I / IMPORTANCE_TARGET, w) (when below 1) and weight w/p. Unbiased.
fn importance(p: ptr<function, Photon>, rng: ptr<function, Rng>) {
    let tau = slab.tau0 + slab.mu_eff * clamp((*p).pos.z - slab.z0, 0.0, slab.z1 - slab.z0);
    let weighted = (*p).w * exp(max(-tau, tau - params.tau_total));
    let survival = max(weighted / IMPORTANCE_TARGET, (*p).w);
    if (weighted < IMPORTANCE_THRESHOLD && survival < 1.0) {
        roulette(p, rng, survival);
    }
}

// The photon leaves through the top (Rd) or the bottom (Tt) with weight w; cos_exit is |cos| of
// its direction outside. Bins as mc's GridIndex: truncated, the last one collecting the rest.
// The score is made when the history ends (`finish`).
fn escape(p: Photon, top: bool, cos_exit: f32) {
    let r = length(p.pos.xy);
    if (TABLE) {
        // A half-space table tallies only what leaves through the top.
        if (top) {
            // The interval: how many edges are ≤ r (an exit on an edge counts above it, as
            // mc's GridIndex bins), by bisection.
            var lo = 0u;
            var hi = params.nr - 1u;
            while (lo < hi) {
                let mid = (lo + hi) / 2u;
                if (table[params.albedos + mid] <= r) {
                    lo = mid + 1u;
                } else {
                    hi = mid;
                }
            }
            escaped_entry = lo;
            escaped_n = p.interactions;
            escaped_w = p.w;
        }
        return;
    }
    let ir = min(u32(r * params.inv_dr), params.nr - 1u);
    let ia = min(u32(acos(min(cos_exit, 1.0)) * params.inv_da), params.na - 1u);
    let off = select(params.nr * params.na, 0u, top);
    escaped_entry = off + ir * params.na + ia;
    escaped_w = p.w;
}

// At a boundary: reflect with the Fresnel probability (total internal reflection beyond the
// critical angle), else refract into the next layer (Snell, eq. 3.17) or escape (MCML's
// CrossUpOrNot / CrossDnOrNot, statistical mode).
fn cross_or_not(p: ptr<function, Photon>, rng: ptr<function, Rng>) {
    let up = (*p).u.z < 0.0;
    let n_t = select(slab.n_down, slab.n_up, up);
    let cos_crit = select(slab.cos_crit_down, slab.cos_crit_up, up);
    let cos_i = abs((*p).u.z);
    var rt = vec2<f32>(1.0, 0.0);
    if (cos_i > cos_crit) {
        rt = fresnel(slab.n, n_t, cos_i);
    }
    if (rand01(rng) > rt.x) {
        let last = !LAYERED || select((*p).layer + 1u == params.layers, (*p).layer == 0u, up);
        if (last) {
            escape(*p, up, rt.y);
            (*p).alive = false;
        } else {
            let ratio = slab.n / n_t;
            let next = select((*p).layer + 1u, (*p).layer - 1u, up);
            enter((*p).layer, next);
            (*p).layer = next;
            (*p).u = vec3<f32>((*p).u.xy * ratio, select(rt.y, -rt.y, up));
        }
    } else {
        (*p).u.z = -(*p).u.z;
    }
}

// One step in a scattering/absorbing layer (MCML's HopDropSpinInTissue).
fn hop_drop_spin(p: ptr<function, Photon>, rng: ptr<function, Rng>) {
    let s = step_size(p, slab.mu_t, rng);
    if (hit_boundary(p, s)) {
        cross_or_not(p, rng);
        return;
    }
    (*p).pos += s * (*p).u;
    drop(p, slab.absorb);
    spin(p, slab.g, rng);
    if ((*p).interactions % PATH_ROULETTE_INTERVAL == 0u) {
        roulette(p, rng, 0.5);
    }
    if (IMPORTANCE && (*p).alive && (*p).interactions % IMPORTANCE_INTERVAL == 0u) {
        importance(p, rng);
    }
}

// A straight flight through a non-interacting layer to its boundary (MCML's HopInGlass).
fn hop_in_glass(p: ptr<function, Photon>, rng: ptr<function, Rng>) {
    if ((*p).u.z == 0.0) {
        // Parallel to the boundaries it would never leave: MCML kills it.
        (*p).alive = false;
        return;
    }
    let z_b = select(slab.z0, slab.z1, (*p).u.z > 0.0);
    let d = (z_b - (*p).pos.z) / (*p).u.z;
    (*p).pos = vec3<f32>((*p).pos.xy + d * (*p).u.xy, z_b);
    cross_or_not(p, rng);
}

// The history is over: each layer's deposits and their sum, as one score each.
// Scores j = 0 (the escape, if any), 1 (A), 2, 3, ... (A_l per layer, when LAYERED; a single
// layer's A_l is its A, copied on the host) are made by one loop over (score, Σx or Σx²), so the
// shader holds a single copy of the atomics, which lavapipe runs lane by lane at every step.
fn finish(layer: u32) {
    if (TABLE) {
        finish_table();
        return;
    }
    let a_l = 2u * params.nr * params.na;
    var total = absorbed_here;
    if (LAYERED) {
        enter(layer, layer);
        total = 0.0;
        for (var l = 0u; l < params.layers; l++) {
            total += absorbed[l];
        }
    }
    let scores = select(2u, 2u + params.layers, LAYERED);
    for (var k = 2u * select(1u, 0u, escaped_w > 0.0); k < 2u * scores; k++) {
        let j = k / 2u;
        var entry = escaped_entry;
        var x = escaped_w;
        if (j == 1u) {
            entry = a_l + params.layers;
            x = total;
        } else if (j >= 2u) {
            entry = a_l + j - 2u;
            x = absorbed[j - 2u];
        }
        let square = k % 2u == 1u;
        add_fixed(4u * entry + select(0u, 2u, square), select(x, x * x, square));
    }
}

// A table's scores: the exit's weight for every albedo α, w·(α/α_walk)ⁿ after n interactions
// (mc's white.rs), from the walk's albedo down, until a weight rounds to 0 in the tallies' fixed
// point (every smaller albedo's is smaller still, so nothing it would add is lost).
fn finish_table() {
    if (escaped_w == 0.0) {
        return;
    }
    let n = f32(escaped_n);
    for (var i = params.albedos; i > 0u; i--) {
        var w = escaped_w;
        if (escaped_n > 0u) {
            w *= exp(n * table[i - 1u]);
        }
        if (w < 0.5 / 4294967296.0) {
            break;
        }
        let entry = (i - 1u) * params.nr + escaped_entry;
        add_fixed(4u * entry, w);
        add_fixed(4u * entry + 2u, w * w);
    }
}

// The slot's photon, its stream and deposits (into the private variables), from the buffer.
fn load(i: u32, rng: ptr<function, Rng>) -> Photon {
    let q = slots[i];
    *rng = Rng(q.rng.x, q.rng.y, q.rng.z, q.rng.w);
    absorbed = q.absorbed;
    absorbed_here = q.absorbed_here;
    slab = slabs[q.layer];
    return Photon(
        vec3<f32>(q.x, q.y, q.z),
        vec3<f32>(q.ux, q.uy, q.uz),
        q.w,
        q.layer,
        q.s_left,
        q.interactions,
        q.alive != 0u,
    );
}

fn save(i: u32, p: Photon, rng: Rng) {
    slots[i] = Slot(
        p.pos.x,
        p.pos.y,
        p.pos.z,
        p.u.x,
        p.u.y,
        p.u.z,
        p.w,
        p.s_left,
        p.layer,
        p.interactions,
        u32(p.alive),
        absorbed_here,
        vec4<u32>(rng.s0, rng.s1, rng.s2, rng.s3),
        absorbed,
    );
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.slots) {
        return;
    }
    var rng: Rng;
    var p = load(id.x, &rng);
    // This dispatch's finished photons and their interactions (64 bits).
    var finished = 0u;
    var inter_lo = 0u;
    var inter_hi = 0u;
    for (var step = 0u; step < params.steps; step++) {
        if (!p.alive) {
            let i = atomicAdd(&work[0], 1u);
            if (i >= params.count) {
                break;
            }
            // The photon's index in the run: the round's base + i, in 64 bits.
            let lo = params.base_lo + i;
            let hi = params.base_hi + select(0u, 1u, lo < i);
            rng = rng_for(params.seed_lo, params.seed_hi, lo, hi);
            p = launch();
        }
        if (GLASS && slab.mu_t == 0.0) {
            hop_in_glass(&p, &rng);
        } else {
            hop_drop_spin(&p, &rng);
        }
        if (p.alive && p.w < ROULETTE_THRESHOLD) {
            roulette(&p, &rng, ROULETTE_SURVIVAL);
        }
        if (!p.alive) {
            finish(p.layer);
            finished += 1u;
            let lo = inter_lo + p.interactions;
            inter_hi += select(0u, 1u, lo < inter_lo);
            inter_lo = lo;
        }
    }
    save(id.x, p, rng);
    if (p.alive) {
        atomicAdd(&work[2], 1u);
    }
    if (finished > 0u) {
        atomicAdd(&work[3], finished);
        let entries = select(2u * params.nr * params.na + params.layers + 1u, params.albedos * params.nr, TABLE);
        add_u64(4u * entries, inter_lo, inter_hi);
    }
}
