//! The exact integer construction: powers quantized to integer masses that sum to exactly
//! `N·2^32`, then an exact integer sweep. No rounding happens after the quantization, so
//! the packed table realizes exactly the quantized pmf `m_i / (N·2^32)`.
//!
//! # Quantization (one pass, cumulative rounding)
//! With `C = 2^32` (one column's capacity) and `k = N·C / S` (`S = Σ w_i`, a double-double
//! sum of the powers scaled by a power of two), the ideal mass of light `i` is
//! `x_i = w_i·k`. The masses are the increments of the rounded prefix sums,
//! `m_i = round(X_i) − round(X_{i−1})` with `X_i = Σ_{j≤i} x_j`, accumulated in 32.32 fixed
//! point (integer part and fraction in `u64`s, so the prefix never rounds). Hence
//! `|m_i − x_i| < 1` for every light and `Σ m_i = round(X_N)`. `k` is carried as
//! `k_hi + k_lo` so that `X_N = N·C` up to the products' own roundings; whatever integer
//! remainder `D = N·C − Σ m_i` these leave (0 for all but huge `N`, a few units at most) is
//! given one unit each to lights whose `x_i − m_i` has the sign of `D`, which keeps them
//! within one unit too.
//!
//! # The sweep (Hübschle-Schneider & Sanders, "Parallel Weighted Random Sampling", 2019)
//! A light is *small* if `m < C`, else *large*. One pass lists the small indices from the
//! front and the large ones from the back of one `u32` buffer (branch-free). Then the
//! current large column `h`, holding the unassigned rest `w` of its mass, either fills the
//! next small column `l` (threshold `m_l`, alias `h`, `w −= C − m_l`) while `w ≥ C`, or
//! becomes a column itself (threshold `w`, alias the next large `h'`, which continues with
//! `w' = m_{h'} − (C − w)`, and may itself turn at once). Both cursors only move forward.
//! Integer arithmetic conserves the total exactly, so once the small columns have run out
//! and the current large one holds `w ≥ C`, it and every remaining large one hold exactly
//! `C`: threshold "full" (`2^32 − 1` with alias itself, the same light either way).
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
//! packed entry), so a build writes 8 bytes per light plus a 4-byte index scratch, and a
//! rebuild into an existing table allocates nothing.

use super::PackedAliasEntry;
use super::exact::{double_double_sum_of, two_product};
use crate::powers::{Pow2Scale, pow2_scale_to_unit};

/// One column's capacity, `C = 2^32`.
const CAPACITY: u64 = 1 << 32;
/// Marks the mass word of a positive light whose mass rounded to 0.
const REACH_FLAG: u64 = 1 << 63;
/// The largest `N` the integer construction takes: `N·C` and the flag must fit in a `u64`.
pub(crate) const MAX_LEN: usize = (1 << 31) - 1;

/// The packed entry as one `u64` word (the same bytes as [`PackedAliasEntry`]).
#[inline]
fn word(threshold: u32, alias: u32) -> u64 {
    bytemuck::cast(PackedAliasEntry { threshold, alias })
}

/// The "keep always" entry of column `i`.
#[inline]
fn full(i: usize) -> u64 {
    word(u32::MAX, i as u32)
}

/// Builds the packed table of `powers` (finite, `≥ 0`, not all zero, `1 ≤ N ≤ MAX_LEN`)
/// into `table` (one word per light, see [`PackedAliasEntry`]) using `scratch` for the
/// small/large index lists. Both are resized to `N`; at equal `N` nothing is allocated.
pub(crate) fn build(powers: &[f64], max: f64, table: &mut Vec<u64>, scratch: &mut Vec<u32>) {
    let n = powers.len();
    debug_assert!((1..=MAX_LEN).contains(&n));
    table.resize(n, 0);
    scratch.resize(n, 0);
    if n == 1 {
        table[0] = full(0);
        return;
    }
    let small = quantize(powers, max, table, scratch);
    sweep(table, scratch, small);
}

/// Writes the masses `m_i` (with [`REACH_FLAG`] where due) into `table` and lists the small
/// and large indices in `scratch` (see [`classify`]); returns how many are small.
fn quantize(powers: &[f64], max: f64, table: &mut [u64], scratch: &mut [u32]) -> usize {
    let n = powers.len();
    let scale = pow2_scale_to_unit(max);
    let (s_hi, s_lo) = double_double_sum_of(powers, |p| scale.apply(p));
    let total = n as f64 * CAPACITY as f64; // N·2^32, exact in f64
    // k = total / S to about 2^-100: k_hi rounded, k_lo the correction of its residual.
    let k_hi = total / s_hi;
    let (prod, prod_err) = two_product(k_hi, s_hi);
    let k_lo = (((total - prod) - prod_err) - k_hi * s_lo) / s_hi;
    let ideal = IdealMass::new(scale, k_hi, k_lo);

    let mut fraction_sum = 0u64; // Σ fractions in units of 2^-32 (at most N·2^32 < 2^63)
    let mut rounded_before = 0u64; // round(X_{i−1}) − Σ_{j<i} ⌊x_j⌋
    let mut mass_sum = 0u64;
    let mut lists = IndexLists::new(scratch);
    let mut quantize_one = |i: usize, x: f64, positive: bool, slot: &mut u64| {
        let whole = x as i64; // ⌊x⌋: 0 ≤ x < N·C < 2^63
        let fraction = ((x - whole as f64) * CAPACITY as f64) as i64 as u64; // < 2^32
        fraction_sum += fraction;
        let rounded = (fraction_sum + (CAPACITY >> 1)) >> 32;
        let m = whole as u64 + rounded - rounded_before;
        rounded_before = rounded;
        mass_sum += m;
        *slot = m | if m == 0 && positive { REACH_FLAG } else { 0 };
        lists.push(i, m < CAPACITY);
    };
    // Two loops rather than a test per light of which formula applies.
    if ideal.folded {
        for (i, (slot, &p)) in table.iter_mut().zip(powers).enumerate() {
            quantize_one(i, ideal.folded_of(p), p > 0.0, slot);
        }
    } else {
        for (i, (slot, &p)) in table.iter_mut().zip(powers).enumerate() {
            quantize_one(i, ideal.scaled_of(p), p > 0.0, slot);
        }
    }
    let small = lists.small;
    let wanted = n as u64 * CAPACITY;
    if mass_sum != wanted {
        settle_remainder(powers, ideal, table, wanted as i64 - mass_sum as i64);
        return classify(table, scratch);
    }
    small
}

/// Gives the remainder `d = N·C − Σ m_i` one unit at a time to lights whose rounding
/// `x_i − m_i` has the sign of `d` (each stays within one unit of `x_i`); whatever no such
/// light takes (never seen) goes to the largest mass.
fn settle_remainder(powers: &[f64], ideal: IdealMass, table: &mut [u64], mut d: i64) {
    for (slot, &p) in table.iter_mut().zip(powers) {
        if d == 0 {
            return;
        }
        let m = *slot & !REACH_FLAG;
        let error = ideal.of(p) - m as f64;
        if d > 0 && error > 0.0 && p > 0.0 {
            *slot = m + 1;
            d -= 1;
        } else if d < 0 && error < 0.0 && m > 0 {
            let m = m - 1;
            *slot = m | if m == 0 { REACH_FLAG } else { 0 };
            d += 1;
        }
    }
    if d != 0
        && let Some(largest) = table.iter_mut().max_by_key(|m| **m & !REACH_FLAG)
    {
        *largest = (*largest & !REACH_FLAG).saturating_add_signed(d);
    }
}

/// Lists the small indices ascending from the front of `scratch` and the large ones from
/// the back (the k-th large at `n−1−k`); returns how many are small. Each index is written
/// to both ends and the wrong write is overwritten later, so there is no branch.
fn classify(table: &[u64], scratch: &mut [u32]) -> usize {
    let mut lists = IndexLists::new(scratch);
    for (i, &m) in table.iter().enumerate() {
        lists.push(i, (m & !REACH_FLAG) < CAPACITY);
    }
    lists.small
}

/// The small indices ascending from the front of one buffer, the large ones from the back.
struct IndexLists<'a> {
    scratch: &'a mut [u32],
    small: usize,
    large: usize,
}

impl<'a> IndexLists<'a> {
    fn new(scratch: &'a mut [u32]) -> Self {
        Self {
            scratch,
            small: 0,
            large: 0,
        }
    }

    /// Lists index `i`: written to both ends, and the end it does not belong to is
    /// overwritten by a later index (the two ends never meet before the last one).
    #[inline]
    fn push(&mut self, i: usize, is_small: bool) {
        let n = self.scratch.len();
        self.scratch[self.small] = i as u32;
        self.scratch[n - 1 - self.large] = i as u32;
        self.small += usize::from(is_small);
        self.large += usize::from(!is_small);
    }
}

/// The ideal mass `x = w·k` of a power, `k = N·2^32/S` carried as `k_hi + k_lo`.
#[derive(Clone, Copy)]
struct IdealMass {
    scale: Pow2Scale,
    k_hi: f64,
    k_lo: f64,
    /// `2^s·k_hi`, `2^s·k_lo`: the power-of-two scale folded into `k`.
    fold_hi: f64,
    fold_lo: f64,
    /// Whether the folded factors are exact (normal): `p·(2^s·k)` then rounds exactly
    /// like `(p·2^s)·k`, one multiply instead of three.
    folded: bool,
}

impl IdealMass {
    fn new(scale: Pow2Scale, k_hi: f64, k_lo: f64) -> Self {
        let (fold_hi, fold_lo) = (scale.apply(k_hi), scale.apply(k_lo));
        Self {
            scale,
            k_hi,
            k_lo,
            fold_hi,
            fold_lo,
            folded: fold_hi.is_normal() && (fold_lo.is_normal() || fold_lo == 0.0),
        }
    }

    /// `x` with the folded factors (only when [`IdealMass::folded`]).
    #[inline]
    fn folded_of(self, p: f64) -> f64 {
        p * self.fold_hi + p * self.fold_lo
    }

    /// `x` scaling the power first.
    #[inline]
    fn scaled_of(self, p: f64) -> f64 {
        let w = self.scale.apply(p);
        w * self.k_hi + w * self.k_lo
    }

    /// `x` the way the quantization computed it.
    fn of(self, p: f64) -> f64 {
        if self.folded {
            self.folded_of(p)
        } else {
            self.scaled_of(p)
        }
    }
}

/// The exact integer sweep over the masses in `table` (the first `small` indices of
/// `scratch` small, the rest large from the back), leaving the packed entries there.
///
/// Each step finishes one column, either the next small one (filled by `h`) or `h` itself,
/// and both candidates are computed and one selected, so the step has no data-dependent
/// branch to mispredict (about half the steps would, with powers in random order).
fn sweep(table: &mut [u64], scratch: &[u32], small: usize) {
    let n = table.len();
    let large = n - small;
    if large == 0 {
        // Impossible when Σ m = N·C; keep the table valid regardless.
        for (i, slot) in table.iter_mut().enumerate() {
            *slot = full(i);
        }
        return;
    }
    let mut h = scratch[n - 1] as usize;
    let mut w = table[h];
    let mut taken_large = 0usize; // large columns finished before `h`
    let mut s = 0usize;
    loop {
        // All ones when `h` fills the next small column, zero when `h` itself turns. The
        // step selects with this mask (bit operations, no branch on `fill`, which the
        // compiler otherwise turns back into a mispredicted jump).
        let fill = u64::from(w >= CAPACITY).wrapping_neg();
        let filling = fill & 1;
        // The end, as one condition: no small column left to fill (every remaining mass is
        // then exactly C), or no large column left to turn into (impossible when
        // Σ m = N·C: the rest would hold less than C per column).
        let no_small = u64::from(s == small);
        let no_large = u64::from(taken_large + 1 == large);
        if (no_small & fill) | (no_large & !fill) != 0 {
            debug_assert!(filling == 1, "integer sweep ran out of large columns");
            break;
        }
        // The next small column (when none is left, a large index: then unused) and the
        // next large one (when none is left, the last small index: then unused).
        let l = u64::from(scratch[s]);
        let h_next = u64::from(scratch[(n - 2).saturating_sub(taken_large)]);
        let raw = table[l as usize];
        let m_l = raw & !REACH_FLAG;
        let m_next = table[h_next as usize] & !REACH_FLAG;
        let h64 = h as u64;
        let column = (l & fill) | (h64 & !fill);
        let threshold = ((m_l | raw >> 63) & fill) | (w & !fill);
        let alias = (h64 & fill) | (h_next & !fill);
        table[column as usize] = word(threshold as u32, alias as u32);
        // Filled: h gives C − m_l. Turned: h_next gives C − w to h's column.
        let w_fill = w.wrapping_add(m_l).wrapping_sub(CAPACITY);
        let w_turn = m_next.wrapping_add(w).wrapping_sub(CAPACITY);
        w = (w_fill & fill) | (w_turn & !fill);
        h = ((h64 & fill) | (h_next & !fill)) as usize;
        s += filling as usize;
        taken_large += (filling ^ 1) as usize;
    }
    debug_assert_eq!(w, CAPACITY, "integer sweep must end with a full column");
    table[h] = full(h);
    for &j in &scratch[small..n - 1 - taken_large] {
        table[j as usize] = full(j as usize);
    }
}
