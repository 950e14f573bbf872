//! The exact integer construction: powers quantized to integer masses that sum to exactly
//! `N·2^32`, then an exact integer sweep. No rounding happens after the quantization, so
//! the packed table realizes exactly the quantized pmf `m_i / (N·2^32)`.
//!
//! # Quantization (cumulative rounding, anchored per chunk)
//! With `C = 2^32` (one column's capacity) and `k = N·C / S` (`S = Σ w_i`, a double-double sum of
//! the powers scaled by a power of two), the ideal mass of light `i` is `x_i = w_i·k`. It is
//! taken in fixed point, `X_i = x_i·2^f` with `f = 30 − ⌊log2 N⌋` fractional bits so that every
//! running sum fits a `u64` (`N·C·2^f < 2^63`), as an integer `X̂_i` within one fixed-point unit
//! of `X_i`: one `f64` product (`k` carried as `k_hi + k_lo`) rounded to the nearest integer
//! (one `cvtsd2si`) where it is below `2^50`, so that its two roundings stay within `1/4`; above,
//! where one product would be off by up to `2^9` fixed-point units, `2^(9−f)` units of mass (two at
//! `N = 2^22` for a light holding most of the total), a double-double product rounded once:
//! a chunk where some product reaches `2^50` (at most `2^13` lights of any set) is quantized
//! again with that path for those lights, so the common loop holds no branch for it. The masses are the increments of the
//! rounded running sums, `m_i = round(P_i) − round(P_{i−1})` with `P_i = Z_c + Σ X̂_j` over
//! chunk `c`'s lights up to `i`: each chunk of [`CHUNK`](units::CHUNK) lights starts from its
//! *anchor* `Z_c = round(k·S_{<c}·2^f)`, the ideal running sum at its start from the chunks'
//! double-double sums, so no chunk waits for another and rounding errors do not carry from
//! chunk to chunk. `m_i` is `⌊X̂_i/2^f⌋` or `⌈X̂_i/2^f⌉`, and with `|X̂_i − X_i| < 1` that is
//! within one unit: `|m_i − x_i| < 1`. A chunk's masses add up to `round(Z_{c+1}) −
//! round(Z_c)` unless the fixed-point roundings moved its sum across a rounding boundary;
//! then the difference is given one unit each to its lights whose ideal mass lies on its
//! side of their mass (compared exactly, to the double-double's `2^-100`), which keeps them
//! within one unit too. Were there too few such lights (never seen: with exactly rounded
//! anchors there are always enough, so only their double-double rounding could cause it),
//! the rest goes one unit at a time to the lights nearest to taking it: the chunk always
//! ends on its target. The last anchor is `N·C·2^f`,
//! so `Σ m_i = N·C` exactly, checked in release builds as well.
//!
//! These bounds are checked against exact big-integer arithmetic on the powers' mantissas
//! and exponents (`exactness.rs`, sharing nothing with this code): every realized mass
//! within one unit of `x_i` (`1 + a_i` for the lights of the next section), `Σ = N·C`, on
//! property-tested sets of 3 to 6 chunks built on pools of 1, 2 and 3 threads
//! (`tables_meet_the_stated_bounds_exactly_on_every_pool`) and on a light holding 3/4 of
//! the total at `N = 2^22` (`a_dominant_light_at_four_million_lights_is_within_one_unit`,
//! where the one-product fixed point was 1.87 units off).
//!
//! # The sweep (Hübschle-Schneider & Sanders, "Parallel Weighted Random Sampling", 2019)
//! A light is *small* if `m < C`, else *large*; the quantization marks the large ones in a
//! bitmap (`heavy.rs`). Then the current large column `h`, holding the unassigned rest `w`
//! of its mass, either fills the next small column `l` (threshold `m_l`, alias `h`,
//! `w −= C − m_l`) while `w ≥ C`, or becomes a column itself (threshold `w`, alias the next
//! large `h'`, which continues with `w' = m_{h'} − (C − w)`, and may itself turn at once).
//! Both cursors only move forward, each finding its next light with a trailing-zero count
//! in the bitmap: no index lists, two streams over the bitmap and the masses, and no
//! data-dependent branch. Integer arithmetic conserves the total exactly, so once the
//! small columns have run out and the current large one holds `w ≥ C`, it and every
//! remaining large one hold exactly `C`: threshold "full" (`2^32 − 1` with alias itself,
//! the same light either way).
//!
//! # Reachability
//! A positive power whose mass rounds to 0 is flagged (bit 63 of its mass word) and its
//! column gets threshold 1 instead of 0: one unit taken from the column's alias. So every
//! positive light is sampled, a zero power never is (threshold 0 and nobody aliases to it),
//! and a light `i` that `a_i` columns alias to is off by at most `1 + a_i` units:
//! `|P(i) − p_i| ≤ (1 + a_i)·2^-32/N`, and `< 2^-32/N` for every light no flagged column
//! aliases to (all of them unless some `p_i < 2^-32/N`).
//!
//! The masses live in the output array itself (each `u64` slot is later overwritten by its
//! packed entry), so a build writes 8 bytes per light plus one bit, and a rebuild into an
//! existing table allocates only its per-chunk bookkeeping (about 60 bytes per 16384
//! lights).
//!
//! # On every core, the same bits for any thread count
//! Every pass works on fixed chunks of [`CHUNK`](units::CHUNK) lights, whatever the thread count:
//! 1. **Total** (`quantize.rs`): per chunk its largest power and the double-double sum of
//!    its powers scaled by that chunk's power of two; the chunks' sums are rescaled (exactly,
//!    by powers of two) and added in chunk order, which gives every chunk's anchor.
//! 2. **Masses**: each chunk computes its `m_i` from its anchor, its bitmap words, and its
//!    census: how many small lights, its deficit `Σ (C − m)` over small lights and its
//!    excess `Σ (m − C)` over large ones.
//! 3. **Sweep** (`sweep.rs`): the sequential sweep fills the next small column while the
//!    excess opened so far, `E(t+1) = Σ_{j≤t} (m_{h_j} − C)`, covers the deficits filled so
//!    far plus the next, `D(s+1)`; otherwise the current large column turns. That is the
//!    *merge* of the two nondecreasing sequences `D(s)` and `E(t+1)` (ties to the small
//!    side), so cutting it at a value `V` (everything `< V` before, the rest after) is a
//!    state `(s, t)` of the sequential sweep, with `h = h_t` and rest
//!    `w = E(t+1) − D(s) + C`, found from the chunks' prefix sums and one chunk scan. The
//!    pieces between cuts run in parallel and write disjoint columns (each small column is
//!    filled once, each large one turns once), so the table is exactly the sequential
//!    sweep's, for any cuts and any thread count. Cuts are taken at chunk starts
//!    (`V = D` there).
//!
//! Nothing above depends on how many threads run, so the packed table is bit for bit the
//! same on one thread or sixteen (tested with `rayon::ThreadPoolBuilder`). Where the table
//! cannot be viewed as `AtomicU64` words (missing, or aligned to 8 bytes where `u64` is
//! aligned to 4, as on 32-bit x86), the pieces run one after the other on plain words: the
//! same bits (`pieces_need_nothing_from_the_pieces_after_them`).

#[cfg(test)]
mod exactness;
mod heavy;
mod quantize;
#[cfg(test)]
mod reference;
mod sweep;
#[cfg(test)]
mod tests;
mod units;

pub(crate) use units::MAX_LEN;
use units::full;

/// Builds the packed table of `powers` (finite, `≥ 0`, not all zero, `1 ≤ N ≤ MAX_LEN`)
/// into `table` (one word per light, see [`crate::alias::PackedAliasEntry`]) using `heavy` for the
/// bitmap of large lights (`⌈N/64⌉` words). Both are resized; at equal `N` only the
/// per-chunk bookkeeping is allocated. Runs on the current rayon pool; the result does not
/// depend on its size.
pub(crate) fn build(powers: &[f64], table: &mut Vec<u64>, heavy: &mut Vec<u64>) {
    let n = powers.len();
    debug_assert!((1..=MAX_LEN).contains(&n));
    if table.capacity() < n {
        // A fresh table: untouched pages, faulted in by the parallel passes that write them.
        *table = super::pages::fresh_words(n);
    }
    table.resize(n, 0);
    heavy.resize(n.div_ceil(64), 0);
    if n == 1 {
        table[0] = full(0);
        return;
    }
    let census = quantize::quantize(powers, table, heavy);
    sweep::sweep(table, heavy, &census, sweep::Order::Parallel);
}
