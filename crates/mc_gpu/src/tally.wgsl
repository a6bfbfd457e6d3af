// Exact tallies: every score is rounded once to an unsigned 64-bit fixed-point number in units of
// 2^-32 and added with 32-bit atomics, low word first with its carry into the high word. Integer
// addition is associative, so the sums are the same bits whatever order the invocations add in.
// A sum reaching 2^64 (or a score of 2^32 or more) raises the run's overflow flag, which the host
// turns into an error (see tally.rs for the bound).
//
// The tally buffer holds, per entry (the entries of mc's Layout: Rd(r, α), Tt(r, α), A_l, A),
// four words: Σw (lo, hi) and Σ(per-photon w)² (lo, hi); then the run's interactions (lo, hi).

@group(0) @binding(2) var<storage, read_write> tally: array<atomic<u32>>;

// work[0]: the round's next photon to launch; work[1]: the overflow flag; work[2]: slots holding
// a photon after this dispatch; work[3]: photons finished in this dispatch.
@group(0) @binding(3) var<storage, read_write> work: array<atomic<u32>, 4>;

// Adds the 64-bit number (lo, hi) to the words at `word` and `word + 1`.
fn add_u64(word: u32, lo: u32, hi: u32) {
    let old = atomicAdd(&tally[word], lo);
    let inc = hi + select(0u, 1u, old + lo < old);
    if (inc != 0u) {
        let old_hi = atomicAdd(&tally[word + 1u], inc);
        if (old_hi + inc < old_hi) {
            atomicOr(&work[1], 1u);
        }
    }
}

// Adds x ≥ 0 in units of 2^-32, rounded to the nearest unit.
fn add_fixed(word: u32, x: f32) {
    if (x >= 4294967296.0) {
        atomicOr(&work[1], 1u);
        return;
    }
    let hi = floor(x);
    // x − ⌊x⌋ is exact, has at most 24 significant bits and is below 1, so times 2^32 it rounds
    // to at most 2^32 − 256: the low word never carries here.
    add_u64(word, u32(round((x - hi) * 4294967296.0)), u32(hi));
}
