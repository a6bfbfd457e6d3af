//! Random streams. The generator is PCG-64 DXSM (O'Neill's recommended 128-bit PCG with a cheap
//! 64-bit multiplier: the walk's draws form a serial chain, so its latency matters).
//! Each chunk of photons gets its own PCG-64 stream derived from (seed, chunk
//! index) alone, so results never depend on the thread count or the order chunks run in. A batch
//! walk's seed is itself derived from the run's seed and what fixes the walk ([`stream_seed`]), so
//! a channel's streams do not depend on the other channels it is batched with.

/// The generator of every photon walk.
pub type Rng = rand_pcg::Pcg64Dxsm;

/// Photons per chunk: the unit of parallel work, of seeding and of sharding.
pub const CHUNK_PHOTONS: u64 = 16_384;

/// The generator for chunk `chunk` of a run seeded with `seed`.
pub fn chunk_rng(seed: u64, chunk: u64) -> Rng {
    // SplitMix64 finalizer on both halves decorrelates neighbouring (seed, chunk) pairs; the
    // stream (increment) also differs per chunk.
    let hi = splitmix64(seed ^ 0x9E37_79B9_7F4A_7C15);
    let lo = splitmix64(chunk.wrapping_add(splitmix64(seed)));
    Rng::new(((hi as u128) << 64) | lo as u128, chunk as u128)
}

/// A seed for the streams of one of several independent simulations of a run: `seed` mixed with
/// words `key` that identify the simulation by what it is (not by where it comes in a list).
pub(crate) fn stream_seed(seed: u64, key: impl IntoIterator<Item = u64>) -> u64 {
    key.into_iter()
        .fold(splitmix64(seed), |h, word| splitmix64(h ^ word))
}

fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
