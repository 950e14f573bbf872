//! The quantization in three chunked passes (module docs of `integer`): the total, the
//! fractions' prefix, then the masses with their small/large lists.

use rayon::prelude::*;

use super::lists::{ChunkLists, IndexLists, Lists};
use super::{CAPACITY, CHUNK, REACH_FLAG};
use crate::alias::exact::{double_double_sum_of, two_product, two_sum};
use crate::powers::{Pow2Scale, pow2_scale_to_unit, unit_exponent};

/// Writes the masses `m_i` (with [`REACH_FLAG`] where due) into `table`, lists the small
/// and large indices of each chunk in `scratch`, and returns the lists' bookkeeping.
pub(super) fn quantize(powers: &[f64], table: &mut [u64], scratch: &mut [u32]) -> Lists {
    let n = powers.len();
    let ideal = IdealMass::of_powers(powers);

    // The fixed-point prefix at each chunk's start: Σ of the earlier chunks' fractions.
    let fraction_sums: Vec<u64> = powers
        .par_chunks(CHUNK)
        .map(|chunk| {
            if ideal.folded {
                fraction_sum(chunk, |p| ideal.folded_of(p))
            } else {
                fraction_sum(chunk, |p| ideal.scaled_of(p))
            }
        })
        .collect();
    let fraction_before = exclusive_prefix(&fraction_sums);

    let chunks: Vec<ChunkLists> = powers
        .par_chunks(CHUNK)
        .zip(table.par_chunks_mut(CHUNK))
        .zip(scratch.par_chunks_mut(CHUNK))
        .zip(fraction_before.par_iter())
        .enumerate()
        .map(|(c, (((chunk, masses), list), &before))| {
            // Two instances rather than a test per light of which formula applies.
            if ideal.folded {
                masses_of(
                    chunk,
                    c * CHUNK,
                    before,
                    |p| ideal.folded_of(p),
                    masses,
                    list,
                )
            } else {
                masses_of(
                    chunk,
                    c * CHUNK,
                    before,
                    |p| ideal.scaled_of(p),
                    masses,
                    list,
                )
            }
        })
        .collect();
    let mass_sum: u64 = chunks.iter().map(|c| c.mass).sum();
    let wanted = n as u64 * CAPACITY;
    if mass_sum == wanted {
        return Lists::new(&chunks, n);
    }
    settle_remainder(powers, ideal, table, wanted as i64 - mass_sum as i64);
    let chunks: Vec<ChunkLists> = table
        .par_chunks(CHUNK)
        .zip(scratch.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(c, (masses, list))| list_chunk(c * CHUNK, masses, list))
        .collect();
    Lists::new(&chunks, n)
}

/// The scale `2^-e` mapping the largest power into `[1, 2)` and the double-double sum
/// `S = s_hi + s_lo` of the scaled powers. Each chunk sums its powers scaled by its own
/// largest power's scale; rescaling a chunk's sum to the common scale is exact (a power of
/// two) unless it underflows, where it is below `2^-1022` of `S ≥ 1` anyway. One chunk
/// gives exactly the sequential double-double sum.
fn scaled_total(powers: &[f64]) -> (Pow2Scale, f64, f64) {
    let parts: Vec<(f64, f64, f64)> = powers
        .par_chunks(CHUNK)
        .map(|chunk| {
            let max = chunk.iter().copied().fold(0.0, f64::max);
            if max == 0.0 {
                return (0.0, 0.0, 0.0);
            }
            let scale = pow2_scale_to_unit(max);
            let (hi, lo) = double_double_sum_of(chunk, |p| scale.apply(p));
            (max, hi, lo)
        })
        .collect();
    let max = parts.iter().map(|p| p.0).fold(0.0, f64::max);
    let exponent = unit_exponent(max);
    let (mut sum, mut carry) = (0.0, 0.0);
    for &(chunk_max, hi, lo) in &parts {
        if chunk_max == 0.0 {
            continue;
        }
        let shift = unit_exponent(chunk_max) - exponent; // ≤ 0
        let (hi, lo) = (times_pow2(hi, shift), times_pow2(lo, shift));
        let (s, e) = two_sum(sum, hi);
        sum = s;
        carry += e + lo;
    }
    let (s_hi, s_lo) = two_sum(sum, carry);
    (pow2_scale_to_unit(max), s_hi, s_lo)
}

/// `x·2^k` for `k ≤ 0` (down to any `k`), exact unless the result is subnormal.
fn times_pow2(mut x: f64, mut k: i32) -> f64 {
    const STEP: i32 = 1000;
    while k < -STEP {
        x *= f64::from_bits(((1023 - STEP) as u64) << 52);
        k += STEP;
    }
    x * f64::from_bits(((k + 1023) as u64) << 52)
}

/// The exclusive prefix sums of `values` (length `values.len() + 1`).
pub(super) fn exclusive_prefix(values: &[u64]) -> Vec<u64> {
    let mut prefix = Vec::with_capacity(values.len() + 1);
    let mut sum = 0u64;
    prefix.push(0);
    for &v in values {
        sum += v;
        prefix.push(sum);
    }
    prefix
}

/// `⌊x⌋` and the fraction `frac(x)` in units of `2^-32` (`0 ≤ x < N·C < 2^63`).
#[inline]
pub(super) fn split_ideal(x: f64) -> (u64, u64) {
    let whole = x as i64;
    let fraction = ((x - whole as f64) * CAPACITY as f64) as i64 as u64; // < 2^32
    (whole as u64, fraction)
}

/// `Σ frac(x_i)` over one chunk, in units of `2^-32` (below `CHUNK·2^32`).
#[inline]
fn fraction_sum(chunk: &[f64], x_of: impl Fn(f64) -> f64) -> u64 {
    chunk.iter().map(|&p| split_ideal(x_of(p)).1).sum()
}

/// One chunk's masses, from the fixed-point prefix `fraction_before` of the chunks before
/// it (so `m_i = round(X_i) − round(X_{i−1})` exactly as one pass over all lights), listed
/// into `list` as they are made.
#[inline]
fn masses_of(
    chunk: &[f64],
    first: usize,
    fraction_before: u64,
    x_of: impl Fn(f64) -> f64,
    masses: &mut [u64],
    list: &mut [u32],
) -> ChunkLists {
    // Only the fractions' rounding carries from chunk to chunk: round(X_i) is the sum of
    // the whole parts (chunk-local) plus round(Σ fractions).
    let mut fraction_sum = fraction_before;
    let mut rounded_before = (fraction_sum + (CAPACITY >> 1)) >> 32;
    let mut lists = IndexLists::new(list);
    let mut stats = ChunkLists::default();
    for (i, (slot, &p)) in masses.iter_mut().zip(chunk).enumerate() {
        let (whole, fraction) = split_ideal(x_of(p));
        fraction_sum += fraction;
        let rounded = (fraction_sum + (CAPACITY >> 1)) >> 32;
        let m = whole + rounded - rounded_before;
        rounded_before = rounded;
        *slot = m | if m == 0 && p > 0.0 { REACH_FLAG } else { 0 };
        stats.add(m);
        lists.push(first + i, m < CAPACITY);
    }
    stats.small = lists.small;
    stats
}

/// Lists one chunk's indices again (after [`settle_remainder`] moved masses).
fn list_chunk(first: usize, masses: &[u64], list: &mut [u32]) -> ChunkLists {
    let mut lists = IndexLists::new(list);
    let mut stats = ChunkLists::default();
    for (i, &word) in masses.iter().enumerate() {
        let m = word & !REACH_FLAG;
        stats.add(m);
        lists.push(first + i, m < CAPACITY);
    }
    stats.small = lists.small;
    stats
}

/// Gives the remainder `d = N·C − Σ m_i` one unit at a time to lights whose rounding
/// `x_i − m_i` has the sign of `d` (each stays within one unit of `x_i`); whatever no such
/// light takes (never seen) goes to the largest mass. Sequential: it runs only when the
/// products' roundings leave a remainder (never seen below `N = 10^8`).
pub(super) fn settle_remainder(powers: &[f64], ideal: IdealMass, table: &mut [u64], mut d: i64) {
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

/// The ideal mass `x = w·k` of a power, `k = N·2^32/S` carried as `k_hi + k_lo`.
#[derive(Clone, Copy)]
pub(super) struct IdealMass {
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
    /// The ideal masses of `powers`: `k = N·C/S` from their [`scaled_total`].
    pub(super) fn of_powers(powers: &[f64]) -> Self {
        let (scale, s_hi, s_lo) = scaled_total(powers);
        let total = powers.len() as f64 * CAPACITY as f64; // N·2^32, exact in f64
        // k = total / S to about 2^-100: k_hi rounded, k_lo the correction of its residual.
        let k_hi = total / s_hi;
        let (prod, prod_err) = two_product(k_hi, s_hi);
        let k_lo = (((total - prod) - prod_err) - k_hi * s_lo) / s_hi;
        Self::new(scale, k_hi, k_lo)
    }

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

    /// `x` the way the quantization computes it.
    pub(super) fn of(self, p: f64) -> f64 {
        if self.folded {
            self.folded_of(p)
        } else {
            self.scaled_of(p)
        }
    }
}
