// rng.wgsl: the bit-exact twin of crates/core/src/rng.rs and of the integer sampling paths
// of AliasTable::sample / sample_one_random and Uniform::sample / sample_u32. Prepended to every
// kernel at pipeline creation (gpu::shader_source). Only u32 arithmetic, which wraps modulo
// 2^32 in WGSL exactly as Rust's wrapping_* operations do.

const PCG_LCG_MULTIPLIER: u32 = 747796405u;
const PCG_LCG_INCREMENT: u32 = 2891336453u;
const PCG_PERMUTE_MULTIPLIER: u32 = 277803737u;

// One LCG step: s' = 747796405·s + 2891336453 (mod 2^32).
fn pcg_lcg_step(state: u32) -> u32 {
    return state * PCG_LCG_MULTIPLIER + PCG_LCG_INCREMENT;
}

// The PCG hash of Jarzynski & Olano (JCGT 2020): an LCG step, then RXS-M-XS.
fn pcg_hash(input: u32) -> u32 {
    let state = pcg_lcg_step(input);
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * PCG_PERMUTE_MULTIPLIER;
    return (word >> 22u) ^ word;
}

// Rng::new(seed, stream) with both 64-bit keys split into (lo, hi) words: the state is
// pcg_hash(seed_lo ^ pcg_hash(seed_hi ^ pcg_hash(stream_lo ^ pcg_hash(stream_hi)))).
fn rng_new(seed_lo: u32, seed_hi: u32, stream_lo: u32, stream_hi: u32) -> u32 {
    return pcg_hash(seed_lo ^ pcg_hash(seed_hi ^ pcg_hash(stream_lo ^ pcg_hash(stream_hi))));
}

// Rng::next_u32: output pcg_hash(state), then advance the state by one LCG step.
fn rng_next(state: ptr<function, u32>) -> u32 {
    let out = pcg_hash(*state);
    *state = pcg_lcg_step(*state);
    return out;
}

// The high word of the 64-bit product a·b, i.e. floor(a·b / 2^32), from 16-bit halves:
// a·b = hh·2^32 + (hl + lh)·2^16 + ll. The middle column sums the high half of ll and the
// low halves of hl and lh (each < 2^16, so the sum < 2^18 cannot wrap); its carry and the
// high halves of hl and lh go to the high word. The low word is the wrapping a * b.
fn mulhi32(a: u32, b: u32) -> u32 {
    let a_lo = a & 0xffffu;
    let a_hi = a >> 16u;
    let b_lo = b & 0xffffu;
    let b_hi = b >> 16u;
    let ll = a_lo * b_lo;
    let hl = a_hi * b_lo;
    let lh = a_lo * b_hi;
    let hh = a_hi * b_hi;
    let middle = (ll >> 16u) + (hl & 0xffffu) + (lh & 0xffffu);
    return hh + (hl >> 16u) + (lh >> 16u) + (middle >> 16u);
}

// Uniform::sample_u32, the raw pick floor(r·N / 2^32) of one draw: 2^32 mod N values get
// one draw more than the others (bias < 2^-32 per value). Kept for the one-random alias
// (whose column is this raw map); the exact pick is pick_uniform.
fn sample_uniform(r: u32, n: u32) -> u32 {
    return mulhi32(r, n);
}

// Uniform::sample, the exact pick (Lemire, ACM TOMACS 2019): draw r, m = r·N; while the low
// word of m is below t = 2^32 mod N = (0 − N) % N, draw again from the same stream; return the
// high word of m. Every value of 0..N is accepted for exactly floor(2^32/N) draws. t is
// computed only when the low word is below N (t < N), the rare case, so the common pick
// has no division; the draws consumed are exactly those of the CPU loop, in the same order.
fn pick_uniform(n: u32, state: ptr<function, u32>) -> u32 {
    var r = rng_next(state);
    var low = r * n;
    if low < n {
        let t = (0u - n) % n;
        while low < t {
            r = rng_next(state);
            low = r * n;
        }
    }
    return mulhi32(r, n);
}

// The alias keep-or-redirect step: column `column` with packed entry (threshold, alias)
// keeps its own light when keep_random < threshold, else yields the alias.
fn alias_resolve(column: u32, entry: vec2<u32>, keep_random: u32) -> u32 {
    return select(entry.y, column, keep_random < entry.x);
}
