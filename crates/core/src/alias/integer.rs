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
use super::exact::{double_double_sum, two_product};
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
    quantize(powers, max, table);
    sweep(table, scratch);
}

/// Writes the masses `m_i` (with [`REACH_FLAG`] where due) into `table`: see the module docs.
fn quantize(powers: &[f64], max: f64, table: &mut [u64]) {
    let n = powers.len();
    let scale = pow2_scale_to_unit(max);
    let (s_hi, s_lo) = double_double_sum(powers.iter().map(|&p| scale.apply(p)));
    let total = n as f64 * CAPACITY as f64; // N·2^32, exact in f64
    // k = total / S to about 2^-100: k_hi rounded, k_lo the correction of its residual.
    let k_hi = total / s_hi;
    let (prod, prod_err) = two_product(k_hi, s_hi);
    let k_lo = (((total - prod) - prod_err) - k_hi * s_lo) / s_hi;

    let mut fraction_sum = 0u64; // Σ fractions in units of 2^-32 (at most N·2^32 < 2^63)
    let mut rounded_before = 0u64; // round(X_{i−1}) − Σ_{j<i} ⌊x_j⌋
    let mut mass_sum = 0u64;
    for (slot, &p) in table.iter_mut().zip(powers) {
        let w = scale.apply(p);
        let x = w * k_hi + w * k_lo;
        let whole = x as i64; // ⌊x⌋: 0 ≤ x < N·C < 2^63
        let fraction = ((x - whole as f64) * CAPACITY as f64) as i64 as u64; // < 2^32
        let whole = whole as u64;
        fraction_sum += fraction;
        let rounded = (fraction_sum + (CAPACITY >> 1)) >> 32;
        let m = whole + rounded - rounded_before;
        rounded_before = rounded;
        mass_sum += m;
        *slot = m | if m == 0 && p > 0.0 { REACH_FLAG } else { 0 };
    }
    let wanted = n as u64 * CAPACITY;
    if mass_sum != wanted {
        settle_remainder(
            powers,
            scale,
            (k_hi, k_lo),
            table,
            wanted as i64 - mass_sum as i64,
        );
    }
}

/// Gives the remainder `d = N·C − Σ m_i` one unit at a time to lights whose rounding
/// `x_i − m_i` has the sign of `d` (each stays within one unit of `x_i`); whatever no such
/// light takes (never seen) goes to the largest mass.
fn settle_remainder(
    powers: &[f64],
    scale: Pow2Scale,
    (k_hi, k_lo): (f64, f64),
    table: &mut [u64],
    mut d: i64,
) {
    for (slot, &p) in table.iter_mut().zip(powers) {
        if d == 0 {
            return;
        }
        let w = scale.apply(p);
        let x = w * k_hi + w * k_lo;
        let m = *slot & !REACH_FLAG;
        let error = x - m as f64;
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

/// The exact integer sweep over the masses in `table`, leaving the packed entries there.
fn sweep(table: &mut [u64], scratch: &mut [u32]) {
    let n = table.len();
    // Small indices ascending from the front, large ones from the back (the k-th large at
    // n−1−k). Each index is written to both ends; the wrong write is overwritten later.
    let mut small = 0usize;
    let mut large = 0usize;
    for (i, &m) in table.iter().enumerate() {
        let is_small = (m & !REACH_FLAG) < CAPACITY;
        scratch[small] = i as u32;
        scratch[n - 1 - large] = i as u32;
        small += usize::from(is_small);
        large += usize::from(!is_small);
    }
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
        if w >= CAPACITY {
            // `h` can fill a small column; when none is left, every remaining mass is C.
            let Some(&l) = scratch[..small].get(s) else {
                break;
            };
            let l = l as usize;
            let raw = table[l];
            let m_l = raw & !REACH_FLAG;
            table[l] = word((m_l | raw >> 63) as u32, h as u32);
            w -= CAPACITY - m_l;
            s += 1;
        } else {
            // `h` becomes a column, aliasing the next large one, which carries on. There is
            // one: the remaining masses add up to C per remaining column.
            if taken_large + 1 >= large {
                debug_assert!(false, "integer sweep ran out of large columns");
                break;
            }
            let h_next = scratch[n - 2 - taken_large] as usize;
            let m_next = table[h_next];
            table[h] = word(w as u32, h_next as u32);
            w = m_next - (CAPACITY - w);
            h = h_next;
            taken_large += 1;
        }
    }
    debug_assert_eq!(w, CAPACITY, "integer sweep must end with a full column");
    table[h] = full(h);
    for &j in &scratch[small..n - 1 - taken_large] {
        table[j as usize] = full(j as usize);
    }
}
