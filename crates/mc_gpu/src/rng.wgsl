// Random streams of the GPU walk: one xoshiro128** generator (Blackman & Vigna 2018; period
// 2^128 - 1) per photon, its state drawn from a PCG hash (Jarzynski & Olano 2020, "Hash functions
// for GPU rendering") of (seed, photon index) alone. A photon's draws therefore do not depend on
// which invocation traces it, on the dispatch size or on the order of the dispatches.

struct Rng {
    s0: u32,
    s1: u32,
    s2: u32,
    s3: u32,
}

// The PCG hash: one LCG step of a 32-bit PCG followed by its RXS-M-XS output permutation.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The generator of photon `index` (64 bits as lo, hi) of a run seeded with `seed` (lo, hi): four
// chained hashes of the four words give the key, and each state word is a hash of the key and its
// position. An all-zero state (the one xoshiro cannot leave) is replaced by a fixed one.
fn rng_for(seed_lo: u32, seed_hi: u32, index_lo: u32, index_hi: u32) -> Rng {
    let key = pcg_hash(index_lo ^ pcg_hash(index_hi ^ pcg_hash(seed_lo ^ pcg_hash(seed_hi))));
    var r = Rng(
        pcg_hash(key ^ 0x9E3779B9u),
        pcg_hash(key ^ 0x3C6EF372u),
        pcg_hash(key ^ 0xDAA66D2Bu),
        pcg_hash(key ^ 0x78DDE6E4u),
    );
    if ((r.s0 | r.s1 | r.s2 | r.s3) == 0u) {
        r.s0 = 1u;
    }
    return r;
}

fn rotl(x: u32, k: u32) -> u32 {
    return (x << k) | (x >> (32u - k));
}

// The next 32 random bits (xoshiro128**).
fn next_u32(r: ptr<function, Rng>) -> u32 {
    let result = rotl((*r).s1 * 5u, 7u) * 9u;
    let t = (*r).s1 << 9u;
    (*r).s2 ^= (*r).s0;
    (*r).s3 ^= (*r).s1;
    (*r).s1 ^= (*r).s2;
    (*r).s0 ^= (*r).s3;
    (*r).s2 ^= t;
    (*r).s3 = rotl((*r).s3, 11u);
    return result;
}

// ξ uniform in [0, 1) on a 2^-24 lattice (every value exact in f32).
fn rand01(r: ptr<function, Rng>) -> f32 {
    return f32(next_u32(r) >> 8u) * 0x1p-24f;
}

// ξ in (0, 1] for the free path's logarithm: (u + 1)·2^-32 (rounded to f32), so
// -ln ξ ≤ 32 ln 2 = 22.2: a step is cut at 22.2/μt, which a free path exceeds with probability
// e^-22.2 = 2.3·10^-10.
fn rand01_open(r: ptr<function, Rng>) -> f32 {
    return (f32(next_u32(r)) + 1.0) * 0x1p-32f;
}
