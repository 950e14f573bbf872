//! The exact `f64` construction: Vose's pairing with double-double carries.
//!
//! For `N` lights with pmf `p_i`, scale to `q_i = N·p_i` (mean 1) and repeatedly pair a
//! *small* column (`q < 1`) with a *large* one (`q ≥ 1`) (Vose 1991, "A linear algorithm
//! for generating random numbers with a given distribution", IEEE TSE 17(9)): the small
//! one's threshold is its `q` and its alias the large one, which gives away `1 − q_small`:
//! `q_large ← (q_large + q_small) − 1`. Written this way the update adds first and
//! subtracts 1 last, which is exact for `1 ≤ sum < 2^53`; the naive
//! `q_large − (1 − q_small)` rounds `1 − q_small` and loses the small column's low bits.
//! Columns left over when one kind runs out have `q = 1` up to rounding: their threshold is
//! exactly 1 and their alias themselves. A zero power gets threshold 0, and since only large
//! columns ever serve as aliases, a zero-power light is never sampled.
//!
//! ## Where the rounding goes
//! Pairing conserves `Σ q` exactly in real arithmetic, so every rounding error that is not
//! itself conserved ends up on the last leftover column, whose relative error then grows
//! like `N·ε` (measured with the textbook build: 2·10⁻¹² at `N = 2^20`, 10⁻⁸ at `10^6` for
//! random real powers). Three measures conserve the total instead:
//! * the residue `Σ q_i − N` left by rounding `q_i = N·w_i/S` is summed exactly and diffused
//!   back over the large columns as whole-ulp nudges (`spread_residue`);
//! * the active large column's `q` is carried as a double-double (`TwoSum`), so a chain of
//!   donations rounds once, when the column turns small, not once per donation;
//! * that one rounding error is handed on to the next large column instead of dropped.
//!
//! The implied pmf then matches `p_i` to a few ulps for every light (the precision tests
//! bound it by `10^-12` relative on integer, exponential, log-uniform and log-normal
//! powers; docs/numbers.md § Guarantees gives the measured worst cases).
//!
//! Instead of Vose's two work lists, two cursors sweep the array for the next small and the
//! next large column (no allocation beyond the outputs, sequential memory access).
//!
//! The packed `u32` thresholds are `round(threshold·2^32)`, saturating at `2^32 − 1` and at
//! least 1 for a positive threshold, so the packed pmf is within `(1 + a_i)·2^-32/N` of
//! `p_i` (`a_i` columns alias to `i`; each moves its split by at most `2^-32`).

use super::packed::packed_word;
use crate::powers::{LightPowers, pow2_scale_to_unit};

/// The `f64` parts of an exact table: normalized powers, thresholds and aliases.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ExactParts {
    /// `p_i = w_i / S`.
    pub(crate) pmf: Vec<f64>,
    /// Keep probability of each column.
    pub(crate) threshold: Vec<f64>,
    /// Alias of each column.
    pub(crate) alias: Vec<u32>,
}

/// Builds the exact table of `powers` into `parts` and the packed words into `words`,
/// reusing their allocations (nothing is allocated when `N` is unchanged).
///
/// The worked example's powers `2, 5, 20` give thresholds `6/27, 15/27, 1` and aliases `2, 2, 2`,
/// each threshold the correctly rounded `f64` of its fraction.
pub(crate) fn build(powers: &LightPowers, parts: &mut ExactParts, words: &mut Vec<u64>) {
    let values = powers.as_slice();
    let n = values.len();
    let n_f = n as f64;
    let scale = pow2_scale_to_unit(powers.max());
    let sum = double_double_sum_of(values, |p| scale.apply(p)).0;
    parts.pmf.clear();
    parts.threshold.clear();
    for &p in values {
        let w = scale.apply(p);
        parts.pmf.push(w / sum);
        // (w·N)/S rather than p·N: for integer powers w·N is exact, so q is correctly
        // rounded (2·3/27 is exactly the f64 nearest 6/27).
        parts.threshold.push((w * n_f) / sum);
    }
    spread_residue(&mut parts.threshold, n_f);
    parts.alias.clear();
    parts.alias.extend(0..n as u32);
    pair_columns(&mut parts.threshold, &mut parts.alias);
    words.clear();
    words.extend(
        parts
            .threshold
            .iter()
            .zip(&parts.alias)
            .map(|(&t, &a)| packed_word(quantize_threshold(t), a)),
    );
}

/// Makes `Σ q_i = N` to a few ulps before pairing.
///
/// Pairing conserves `Σ q` exactly in real arithmetic, so whatever `Σ q_i − N` the rounding
/// of `q_i = N·w_i/S` leaves lands on the last leftover column, whose relative error would
/// grow like `N·ε`: the rounding of `S` scales every `q_i` alike, and repeated powers repeat
/// the same rounding error (measured before this step: 10⁻¹¹ at `N = 1.6·10⁷`). The residue
/// `R` is summed exactly ([`double_double_sum`]) and taken back from the large columns in
/// proportion to their size, `−R·q_i/Σ_{q_j ≥ 1} q_j`. Each such share is below an ulp, so
/// it is diffused: one carry per binary exponent of `q` holds what is not yet applied and
/// releases it as whole-ulp nudges of a column of that exponent once it passes half an ulp
/// (`q + carry` rounds to a neighbour of `q`). A carry never moves between sizes: with eight
/// lanes by index instead, the sub-ulp share of a column of `q = 8.8·10^4` once landed on
/// a column of `q = 1.5`, 4.4·10⁻¹² relative (log-normal powers, σ = 12). Small columns
/// (`q < 1`) are never touched, so the carry can never swamp a small value.
pub(crate) fn spread_residue(q: &mut [f64], n: f64) {
    let mut large_mass = 0.0;
    let (total_hi, total_lo) = double_double_sum(q.iter().map(|&x| {
        large_mass += if x >= 1.0 { x } else { 0.0 };
        x
    }));
    let residue = (total_hi - n) + total_lo;
    if residue == 0.0 || large_mass == 0.0 {
        return;
    }
    let t = -residue / large_mass;
    // One carry per binary exponent of q: a share below an ulp waits for a column of the
    // same size, so a huge column's unapplied share never lands on a column near 1.
    let mut carry = [0.0f64; 64];
    for x in q.iter_mut() {
        let q0 = *x;
        let large = q0 >= 1.0;
        let exponent = ((q0.to_bits() >> 52) & 0x7ff) as usize;
        let c = &mut carry[exponent.saturating_sub(1023).min(63)];
        *c += if large { q0 * t } else { 0.0 };
        let q1 = if large { q0 + *c } else { q0 };
        *c -= q1 - q0; // exact: 0 or one ulp of q0
        *x = q1;
    }
}

/// `Σ x_i` as a double-double `(hi, lo)`: eight independent `TwoSum` lanes (branch-free)
/// whose compensations are summed plainly; the error is that of adding the compensations,
/// negligible against one ulp of the total for any `N < 2^32`.
pub(crate) fn double_double_sum(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut hi = [0.0f64; 8];
    let mut lo = [0.0f64; 8];
    for (i, x) in values.enumerate() {
        let lane = i & 7;
        let (s, e) = two_sum(hi[lane], x);
        hi[lane] = s;
        lo[lane] += e;
    }
    combine_lanes(&hi, &lo)
}

/// [`double_double_sum`] of `f(x)` over a slice, bit for bit the same (value `i` still goes
/// to lane `i mod 8`), but with the lanes in registers: whole chunks of eight, so the
/// compiler keeps `hi` and `lo` out of memory and vectorizes the `TwoSum`s.
pub(crate) fn double_double_sum_of(values: &[f64], f: impl Fn(f64) -> f64) -> (f64, f64) {
    let mut hi = [0.0f64; 8];
    let mut lo = [0.0f64; 8];
    let chunks = values.chunks_exact(8);
    let rest = chunks.remainder();
    for chunk in chunks {
        for ((h, l), &x) in hi.iter_mut().zip(&mut lo).zip(chunk) {
            let (s, e) = two_sum(*h, f(x));
            *h = s;
            *l += e;
        }
    }
    for ((h, l), &x) in hi.iter_mut().zip(&mut lo).zip(rest) {
        let (s, e) = two_sum(*h, f(x));
        *h = s;
        *l += e;
    }
    combine_lanes(&hi, &lo)
}

/// [`double_double_sum_of`] without a function, and the largest value too, in one pass
/// (the same eight lanes, the same bits).
pub(crate) fn double_double_sum_and_max(values: &[f64]) -> (f64, f64, f64) {
    let mut hi = [0.0f64; 8];
    let mut lo = [0.0f64; 8];
    let mut max = [0.0f64; 8];
    let chunks = values.chunks_exact(8);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (((h, l), m), &x) in hi.iter_mut().zip(&mut lo).zip(&mut max).zip(chunk) {
            *m = if x > *m { x } else { *m };
            let (s, e) = two_sum(*h, x);
            *h = s;
            *l += e;
        }
    }
    for (((h, l), m), &x) in hi.iter_mut().zip(&mut lo).zip(&mut max).zip(rest) {
        *m = if x > *m { x } else { *m };
        let (s, e) = two_sum(*h, x);
        *h = s;
        *l += e;
    }
    let (total, comp) = combine_lanes(&hi, &lo);
    (total, comp, max.iter().copied().fold(0.0, f64::max))
}

/// The lanes' `hi` then `lo` words added into one double-double.
fn combine_lanes(hi: &[f64; 8], lo: &[f64; 8]) -> (f64, f64) {
    let (mut total, mut comp) = (0.0, 0.0);
    for &x in hi.iter().chain(lo.iter()) {
        let (s, e) = two_sum(total, x);
        total = s;
        comp += e;
    }
    two_sum(total, comp)
}

/// Vose's pairing on `q` (mean 1) in place: on return `q` holds the thresholds and `alias`
/// the aliases (`alias` must enter as the identity).
fn pair_columns(q: &mut [f64], alias: &mut [u32]) {
    let mut small_scan = 0;
    let mut large_scan = 0;
    let mut small = next_small(q, &mut small_scan);
    let mut large = next_large(q, &mut large_scan);
    // The active large column's q is carried as hi + lo (hi = q[l]) so that a long chain of
    // donations rounds once, when the column turns small, instead of once per donation. Only
    // `hi` is on the dependency chain; the exact error of each step goes into `lo`.
    let mut large_lo = 0.0f64;
    while let (Some(s), Some(l)) = (small, large) {
        alias[s] = l as u32;
        // (q_l + q_s) − 1 exactly: TwoSum gives q_l + q_s = sum + err, and sum − 1 is exact
        // for 1 ≤ sum < 2^53 (1 is a multiple of ulp(sum) and the result is representable).
        let (sum, err) = two_sum(q[l], q[s]);
        let hi = sum - 1.0;
        large_lo += err;
        let (value, rounding) = two_sum(hi, large_lo);
        if value < 1.0 {
            // The large column became small, its threshold the rounded hi + lo. The rounding
            // error goes on to the next large column rather than being dropped: dropped, the
            // errors of all columns would add up on the last leftover (systematically so when
            // powers repeat). If the small cursor already passed this column, handle it now;
            // otherwise the cursor finds it. A column that gave away all its mass can come
            // out a hair below 0 (the carried error of an earlier column): its threshold is
            // then 0 and the deficit is carried on like the rounding.
            q[l] = value.max(0.0);
            large_lo = rounding + value.min(0.0);
            small = if l < small_scan {
                Some(l)
            } else {
                next_small(q, &mut small_scan)
            };
            large = next_large(q, &mut large_scan);
        } else {
            // Still large. Keep the stored q ≥ 1 so the small cursor can never pick it up;
            // a hi just below 1 moves its (exact, by Sterbenz) excess into lo.
            if hi < 1.0 {
                large_lo += hi - 1.0;
                q[l] = 1.0;
            } else {
                q[l] = hi;
            }
            small = next_small(q, &mut small_scan);
        }
    }
    // Leftovers hold q = 1 up to rounding. Their threshold becomes exactly 1, alias self. A
    // small column left without a donor can only be a rounding remnant near 1; a zero one
    // cannot be (its deficit of 1 is far beyond rounding), but it is kept at 0 regardless.
    let mut last_large = large.unwrap_or(0);
    let mut tail = |i: usize, q: &mut [f64], alias: &mut [u32]| {
        if q[i] > 0.0 {
            q[i] = 1.0;
            alias[i] = i as u32;
            last_large = i;
        } else {
            alias[i] = last_large as u32;
        }
    };
    if let Some(l) = large {
        tail(l, q, alias);
        while let Some(l) = next_large(q, &mut large_scan) {
            tail(l, q, alias);
        }
    }
    if let Some(s) = small {
        tail(s, q, alias);
        while let Some(s) = next_small(q, &mut small_scan) {
            tail(s, q, alias);
        }
    }
}

/// Knuth's `TwoSum`: `a + b = s + e` exactly, `s = fl(a + b)`.
#[inline]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The next column at or after `*cursor` with `q < 1`; the cursor moves past it.
#[inline]
pub(crate) fn next_small(q: &[f64], cursor: &mut usize) -> Option<usize> {
    let found = q[*cursor..].iter().position(|&x| x < 1.0)? + *cursor;
    *cursor = found + 1;
    Some(found)
}

/// The next column at or after `*cursor` with `q ≥ 1`; the cursor moves past it.
#[inline]
pub(crate) fn next_large(q: &[f64], cursor: &mut usize) -> Option<usize> {
    let found = q[*cursor..].iter().position(|&x| x >= 1.0)? + *cursor;
    *cursor = found + 1;
    Some(found)
}

/// `round(t·2^32)` clamped to `[1, 2^32 − 1]` for `t > 0`, and 0 for `t = 0`.
fn quantize_threshold(t: f64) -> u32 {
    if t <= 0.0 {
        return 0;
    }
    let scaled = (t * 4_294_967_296.0).round();
    if scaled >= 4_294_967_295.0 {
        u32::MAX
    } else {
        (scaled as u32).max(1)
    }
}

/// Dekker's `TwoProduct` without FMA: `a·b = p + e` exactly, `p = fl(a·b)` (Veltkamp split;
/// exact unless `a·b` over- or underflows).
pub(crate) fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (a_hi, a_lo) = split(a);
    let (b_hi, b_lo) = split(b);
    let e = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
    (p, e)
}

/// Veltkamp's split of `a` into two 26-bit halves, `a = hi + lo`.
fn split(a: f64) -> (f64, f64) {
    let c = 134_217_729.0 * a; // 2^27 + 1
    let hi = c - (c - a);
    (hi, a - hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantization_rounds_and_keeps_positive_thresholds_reachable() {
        assert_eq!(quantize_threshold(0.0), 0);
        assert_eq!(quantize_threshold(1e-300), 1);
        assert_eq!(quantize_threshold(0.5), 1 << 31);
        assert_eq!(quantize_threshold(1.0), u32::MAX);
        assert_eq!(quantize_threshold(1.0 - 1e-12), u32::MAX);
    }

    #[test]
    fn two_product_is_exact() {
        let (a, b) = (0.1f64, 3.0e17);
        let (p, e) = two_product(a, b);
        // (p + e) reproduces a·b: the error term is what rounding dropped.
        assert_ne!(e, 0.0);
        let (p2, e2) = two_product(b, a);
        assert_eq!((p, e), (p2, e2));
        assert_eq!(two_product(3.0, 7.0), (21.0, 0.0));
    }
}
