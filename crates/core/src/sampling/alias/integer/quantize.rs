//! The quantization in two chunked passes (module docs of `integer`): the total with every
//! chunk's running sum, then each chunk's masses from its anchor, with the bitmap of large
//! lights and the chunk's census.

use rayon::prelude::*;

use super::heavy::{Census, ChunkCensus, WORDS_PER_CHUNK};
use super::units::{CAPACITY, CHUNK, REACH_FLAG};
use crate::alias::exact::{double_double_sum_and_max, double_double_sum_of, two_product, two_sum};
use crate::powers::{Pow2Scale, pow2_scale_to_unit, unit_exponent};

/// Writes the masses `m_i` (with [`REACH_FLAG`] where due) into `table`, marks the large
/// lights in `heavy` (one bit per light) and returns the chunks' census.
pub(super) fn quantize(powers: &[f64], table: &mut [u64], heavy: &mut [u64]) -> Census {
    let n = powers.len();
    let (ideal, anchors) = IdealMass::with_anchors(powers);
    let chunks: Vec<ChunkCensus> = powers
        .par_chunks(CHUNK)
        .zip(table.par_chunks_mut(CHUNK))
        .zip(heavy.par_chunks_mut(WORDS_PER_CHUNK))
        .zip(anchors.par_windows(2))
        .map(|(((chunk, masses), words), anchor)| {
            chunk_masses(chunk, ideal, anchor[0], anchor[1], masses, words)
        })
        .collect();
    // The anchors telescope to N·C and every chunk ends on its own, so this always holds; a
    // table from masses that did not would be silently wrong, so it is checked in release.
    let total: u64 = chunks.iter().map(|c| c.mass).sum();
    assert_eq!(
        total,
        (n as u64) << 32,
        "integer masses must add up to N·2^32"
    );
    Census::new(&chunks, n)
}

/// One chunk's masses (module docs of `integer`): the cumulative rounding of its lights'
/// fixed-point ideal masses from the chunk's anchor `start`, settled to end on `end`'s
/// rounding, with the chunk's bitmap words and census.
pub(super) fn chunk_masses(
    chunk: &[f64],
    ideal: IdealMass,
    start: u64,
    end: u64,
    masses: &mut [u64],
    heavy: &mut [u64],
) -> ChunkCensus {
    // Two instances rather than a test per light of which formula applies, each run with
    // one product per light; a chunk where some product reached `ONE_PRODUCT_BELOW` (rare:
    // at most 2^13 lights of a set) is run again with the exact path for those lights.
    let (census, reached) = if ideal.folded {
        let fixed_of = |p| ideal.folded_of(p);
        match rounded_masses::<false>(chunk, start, ideal, fixed_of, masses, heavy) {
            Some(done) => done,
            None => rounded_masses::<true>(chunk, start, ideal, fixed_of, masses, heavy)
                .expect("the exact path completes"),
        }
    } else {
        let fixed_of = |p| ideal.scaled_of(p);
        match rounded_masses::<false>(chunk, start, ideal, fixed_of, masses, heavy) {
            Some(done) => done,
            None => rounded_masses::<true>(chunk, start, ideal, fixed_of, masses, heavy)
                .expect("the exact path completes"),
        }
    };
    let wanted = ideal.rounded(end);
    if reached == wanted {
        return census;
    }
    let mut census = census;
    let moved = settle(chunk, ideal, masses, wanted as i64 - reached as i64);
    for (i, before, after) in moved {
        let large = census.replace(before, after);
        let bit = 1u64 << (i % 64);
        heavy[i / 64] = (heavy[i / 64] & !bit) | if large { bit } else { 0 };
    }
    census
}

/// The masses `m_i = round(P_i) − round(P_{i−1})` of the running fixed-point sum
/// `P_i = start + Σ_{j≤i} X̂_j` (`X̂_j` the ideal mass in units of `2^-shift` within one such
/// unit: `fixed_of(p_j)` rounded where it is below [`ONE_PRODUCT_BELOW`], else
/// [`IdealMass::fixed_exact`]), with reach flags, bitmap words and census. Returns the
/// census and `round(P_last)`; without `EXACT`, `None` (and the slots written are to be
/// overwritten) when some rounded `fixed_of(p_j)` reached [`ONE_PRODUCT_BELOW`], so the
/// common loop holds no branch for it.
#[inline]
fn rounded_masses<const EXACT: bool>(
    chunk: &[f64],
    start: u64,
    ideal: IdealMass,
    fixed_of: impl Fn(f64) -> f64,
    masses: &mut [u64],
    heavy: &mut [u64],
) -> Option<(ChunkCensus, u64)> {
    let shift = ideal.shift;
    // The running sum is kept half a unit ahead, so that its whole units are round(P).
    let mut sum = start + ((1u64 << shift) >> 1);
    let first = sum >> shift;
    let mut rounded_before = first;
    // Σ min(m, C) and the large lights' count give the census without a test per light.
    let mut capped = 0u64;
    let mut large = 0u64;
    let mut seen = 0u64;
    for ((word, slots), group) in heavy
        .iter_mut()
        .zip(masses.chunks_mut(64))
        .zip(chunk.chunks(64))
    {
        let mut bits = 0u64;
        for (b, (slot, &p)) in slots.iter_mut().zip(group).enumerate() {
            let v = fixed_of(p);
            let x = if EXACT && v >= ONE_PRODUCT_BELOW {
                ideal.fixed_exact(p)
            } else {
                nearest_integer(v)
            };
            // Every `x < 2^63`: their union has a bit from 50 up iff some `x ≥ 2^50`, which
            // every `v ≥ 2^50` gives (rounding is monotone); one `or` per light.
            seen |= x;
            sum += x;
            let rounded = sum >> shift;
            let m = rounded - rounded_before;
            rounded_before = rounded;
            *slot = flagged(m, p);
            capped += m.min(CAPACITY);
            bits |= u64::from(m >= CAPACITY) << b;
        }
        *word = bits;
        large += u64::from(bits.count_ones());
    }
    if !EXACT && seen >= ONE_PRODUCT_BELOW as u64 {
        return None;
    }
    let census = ChunkCensus {
        small: chunk.len() as u64 - large,
        small_mass: capped - large * CAPACITY,
        mass: rounded_before - first,
    };
    Some((census, rounded_before))
}

/// `v` rounded to the nearest integer, ties to even (`0 ≤ v < 2^63`): one instruction on
/// x86-64 (`cvtsd2si` in the default rounding mode), exact for every such `v`; elsewhere
/// [`nearest_integer_portable`], the same integer (tested on ties, half-ulp neighbours and
/// values up to `2^63`).
#[inline]
#[allow(unsafe_code)]
pub(super) fn nearest_integer(v: f64) -> u64 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_cvtsd_si64, _mm_set_sd};
        // SAFETY: SSE2, which these intrinsics need, is part of every x86-64 processor
        // (the target's baseline); they only move and convert a register.
        unsafe { _mm_cvtsd_si64(_mm_set_sd(v)) as u64 }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        nearest_integer_portable(v)
    }
}

/// [`nearest_integer`] without the x86-64 instruction: `v` rounded to the nearest integer,
/// ties to even (`0 ≤ v < 2^63`).
#[inline]
#[cfg_attr(target_arch = "x86_64", allow(dead_code, reason = "compared in tests"))]
pub(super) fn nearest_integer_portable(v: f64) -> u64 {
    v.round_ties_even() as u64
}

/// Moves `d` units of a chunk's masses so that they add up to the chunk's target: one unit
/// each to lights whose ideal mass lies above theirs (`d > 0`) or below (`d < 0`), compared
/// to about `2^-100` relative ([`IdealMass::gap`]), from the chunk's first light on, so every
/// light stays within one unit of its ideal mass. Needed where the fixed-point roundings
/// moved the chunk's sum across a rounding boundary (at `N = 10^6` one chunk in a few
/// hundred, at `1.6·10^7` one in three); `|d|` is 1 then, and the chunk has such a light
/// (its masses and ideal masses add up to within one unit of each other). Whatever no such
/// light takes (never seen) goes one unit at a time to the light nearest to taking it, the
/// largest `x_i − m_i` (`d > 0`) or the smallest among positive masses (`d < 0`): the chunk
/// always ends on its target, because its target is `≥ 0`. Returns the lights moved with
/// their masses before and after (a light may appear more than once).
pub(super) fn settle(
    chunk: &[f64],
    ideal: IdealMass,
    masses: &mut [u64],
    mut d: i64,
) -> Vec<(usize, u64, u64)> {
    let mut moved = Vec::new();
    for (i, (slot, &p)) in masses.iter_mut().zip(chunk).enumerate() {
        if d == 0 {
            return moved;
        }
        let m = *slot & !REACH_FLAG;
        let gap = ideal.gap(p, m);
        let after = if d > 0 && gap > 0.0 {
            m + 1
        } else if d < 0 && gap < 0.0 {
            m - 1
        } else {
            continue;
        };
        d -= after as i64 - m as i64;
        *slot = flagged(after, p);
        moved.push((i, m, after));
    }
    while d != 0 {
        let mass = |i: usize| masses[i] & !REACH_FLAG;
        let gap = |i: &usize| ideal.gap(chunk[*i], mass(*i));
        let nearest = if d > 0 {
            (0..masses.len()).max_by(|a, b| gap(a).total_cmp(&gap(b)))
        } else {
            (0..masses.len())
                .filter(|&i| mass(i) > 0)
                .min_by(|a, b| gap(a).total_cmp(&gap(b)))
        };
        let Some(i) = nearest else {
            unreachable!("a chunk's target is at least 0 and its masses are not");
        };
        let m = mass(i);
        let after = if d > 0 { m + 1 } else { m - 1 };
        d -= after as i64 - m as i64;
        masses[i] = flagged(after, chunk[i]);
        moved.push((i, m, after));
    }
    moved
}

/// Mass `m` of a light of power `p`, with [`REACH_FLAG`] when it is 0 and `p` is not.
#[inline]
#[allow(
    clippy::needless_bitwise_bool,
    reason = "no branch on a zero mass (half the lights of some scenes, in any order)"
)]
fn flagged(m: u64, p: f64) -> u64 {
    m | (u64::from((m == 0) & (p > 0.0)) << 63)
}

/// One chunk's part of the total: its largest power and the double-double sum of its
/// powers scaled by that power's power of two (0 for an all-zero chunk).
#[derive(Clone, Copy, Debug)]
struct ChunkTotal {
    max: f64,
    hi: f64,
    lo: f64,
}

/// Every chunk's [`ChunkTotal`]. Each chunk's sum is taken in its own largest power's
/// scale; rescaling it to the common scale is exact (a power of two) unless it underflows,
/// where it is below `2^-1022` of the total `≥ 1` anyway. One pass sums and finds the
/// largest power at once, unscaled; where that largest power lies outside `2^±960` (a sum
/// could overflow, or its compensation lose bits below `2^-1074`) a second pass sums the
/// scaled powers.
fn chunk_totals(powers: &[f64]) -> Vec<ChunkTotal> {
    const SAFE: std::ops::RangeInclusive<f64> = 1.0e-289..=1.0e289; // within 2^±960
    powers
        .par_chunks(CHUNK)
        .map(|chunk| {
            let (hi, lo, max) = double_double_sum_and_max(chunk);
            if max == 0.0 {
                return ChunkTotal {
                    max,
                    hi: 0.0,
                    lo: 0.0,
                };
            }
            let scale = pow2_scale_to_unit(max);
            let (hi, lo) = if SAFE.contains(&max) {
                (scale.apply(hi), scale.apply(lo))
            } else {
                double_double_sum_of(chunk, |p| scale.apply(p))
            };
            ChunkTotal { max, hi, lo }
        })
        .collect()
}

/// Where the one-product fixed point ([`IdealMass::folded_of`], [`IdealMass::scaled_of`]) stops being within a quarter of
/// a unit of the ideal `X` (its two roundings are half an ulp each, at most `2^-3` there).
const ONE_PRODUCT_BELOW: f64 = (1u64 << 50) as f64;

/// `x·2^k` for `k ≤ 0` (down to any `k`), exact unless the result is subnormal.
fn times_pow2(mut x: f64, mut k: i32) -> f64 {
    const STEP: i32 = 1000;
    while k < -STEP {
        x *= f64::from_bits(((1023 - STEP) as u64) << 52);
        k += STEP;
    }
    x * f64::from_bits(((k + 1023) as u64) << 52)
}

/// The ideal mass `x = w·k` of a power in fixed point: `k = N·2^32/S` carried as
/// `k_hi + k_lo`, and `x` counted in units of `2^-shift` (`shift = 30 − ⌊log2 N⌋`, so that
/// `N·2^32·2^shift < 2^63` and every running sum fits a `u64`).
#[derive(Clone, Copy, Debug)]
pub(super) struct IdealMass {
    scale: Pow2Scale,
    /// `2^shift·k_hi`, `2^shift·k_lo`.
    k_hi: f64,
    k_lo: f64,
    /// `2^s·2^shift·k_hi`, `2^s·2^shift·k_lo`: the power-of-two scale folded in as well.
    fold_hi: f64,
    fold_lo: f64,
    /// Whether the folded factors are exact (normal): `p·(2^s·k)` then rounds exactly
    /// like `(p·2^s)·k`, one multiply instead of three.
    folded: bool,
    /// Fractional bits of the fixed point.
    pub(super) shift: u32,
}

impl IdealMass {
    /// The ideal masses of `powers` and every chunk's anchor: the fixed-point ideal running
    /// sum `Z_c = round(k·S_{<c}·2^shift)` at the start of chunk `c` (`S_{<c}` the
    /// double-double sum of the chunks before it), nondecreasing, from `Z_0 = 0` to
    /// `Z_last = N·2^32·2^shift` exactly (`chunks + 1` values).
    pub(super) fn with_anchors(powers: &[f64]) -> (Self, Vec<u64>) {
        let n = powers.len();
        let parts = chunk_totals(powers);
        let max = parts.iter().map(|p| p.max).fold(0.0, f64::max);
        let exponent = unit_exponent(max);
        // The running sum before each chunk, in the common scale 2^-exponent.
        let mut before = Vec::with_capacity(parts.len() + 1);
        let (mut sum, mut carry) = (0.0, 0.0);
        before.push((0.0, 0.0));
        for part in &parts {
            if part.max > 0.0 {
                let shift = unit_exponent(part.max) - exponent; // ≤ 0
                let (hi, lo) = (times_pow2(part.hi, shift), times_pow2(part.lo, shift));
                let (s, e) = two_sum(sum, hi);
                sum = s;
                carry += e + lo;
            }
            before.push(two_sum(sum, carry));
        }
        let (s_hi, s_lo) = before[parts.len()];
        let shift = 30 - n.ilog2();
        let target = (n as u64) << 32; // N·2^32
        let total = target as f64 * f64::from(1u32 << shift); // N·2^32·2^shift, exact
        // k = total / S to about 2^-100: k_hi rounded, k_lo the correction of its residual.
        let k_hi = total / s_hi;
        let (prod, prod_err) = two_product(k_hi, s_hi);
        let k_lo = (((total - prod) - prod_err) - k_hi * s_lo) / s_hi;
        let ideal = Self::new(pow2_scale_to_unit(max), k_hi, k_lo, shift);
        let end = target << shift;
        let mut anchors: Vec<u64> = before
            .iter()
            .map(|&(hi, lo)| ideal.fixed_sum(hi, lo).min(end))
            .collect();
        for c in 1..anchors.len() {
            anchors[c] = anchors[c].max(anchors[c - 1]);
        }
        anchors[0] = 0;
        anchors[parts.len()] = end;
        (ideal, anchors)
    }

    fn new(scale: Pow2Scale, k_hi: f64, k_lo: f64, shift: u32) -> Self {
        let (fold_hi, fold_lo) = (scale.apply(k_hi), scale.apply(k_lo));
        Self {
            scale,
            k_hi,
            k_lo,
            fold_hi,
            fold_lo,
            folded: fold_hi.is_normal() && (fold_lo.is_normal() || fold_lo == 0.0),
            shift,
        }
    }

    /// `round(k·(hi + lo))` in fixed point for a double-double sum of scaled powers
    /// (`≥ 0`, at most the total).
    fn fixed_sum(self, hi: f64, lo: f64) -> u64 {
        let (p, e) = two_product(hi, self.k_hi);
        let rest = e + (hi * self.k_lo + lo * self.k_hi);
        let whole = p.floor();
        let fraction = ((p - whole) + rest + 0.5).floor();
        (whole as u64).saturating_add_signed(fraction as i64)
    }

    /// The fixed-point `x` with the folded factors (only when [`IdealMass::folded`]).
    #[inline]
    fn folded_of(self, p: f64) -> f64 {
        p * self.fold_hi + p * self.fold_lo
    }

    /// The fixed-point `x`, scaling the power first.
    #[inline]
    fn scaled_of(self, p: f64) -> f64 {
        let w = self.scale.apply(p);
        w * self.k_hi + w * self.k_lo
    }

    /// The fixed-point `x` in `f64` the way the quantization computes it (`< 2^63`; within
    /// `1/4` of the product `w·(k_hi + k_lo)` below [`ONE_PRODUCT_BELOW`], not above).
    #[cfg(test)]
    fn fixed_of(self, p: f64) -> f64 {
        if self.folded {
            self.folded_of(p)
        } else {
            self.scaled_of(p)
        }
    }

    /// The ideal mass of power `p` in fixed point as an integer `X̂` with `|X̂ − X| < 1`
    /// (`X = w·(k_hi + k_lo)` exactly), by the quantization's rule: the one-product value
    /// `v = fixed_of(p)` rounded where it is below [`ONE_PRODUCT_BELOW`] (each of its two
    /// roundings is then at most `2^-3`, so `|X̂ − X| ≤ 1/2 + 1/4`), else
    /// [`IdealMass::fixed_exact`] (at most `2^13` lights of any set: each holds over `2^-13`
    /// of the total `< 2^63`).
    #[cfg(test)]
    pub(super) fn fixed(self, p: f64) -> u64 {
        let v = self.fixed_of(p);
        if v < ONE_PRODUCT_BELOW {
            nearest_integer(v)
        } else {
            self.fixed_exact(p)
        }
    }

    /// `X` of a large product rounded to the nearest integer (`|X̂ − X| ≤ 1/2` up to the
    /// double-double's `2^-100`), where one `f64` product would be off by up to
    /// `ulp(X)/2 = 2^9` fixed-point units (`X` up to `2^63`).
    #[cold]
    #[inline(never)]
    fn fixed_exact(self, p: f64) -> u64 {
        let (whole, fraction) = self.ideal_parts(p);
        whole.saturating_add_signed((fraction + 0.5).floor() as i64)
    }

    /// `X = whole + fraction` for power `p` as a double-double product `w·(k_hi + k_lo)`
    /// (`w` the scaled power), `whole` an integer and `|fraction|` below `2^12`.
    fn ideal_parts(self, p: f64) -> (u64, f64) {
        let w = self.scale.apply(p);
        let (hi, error) = two_product(w, self.k_hi);
        let lo = error + w * self.k_lo;
        let whole = hi.floor();
        (whole as u64, (hi - whole) + lo)
    }

    /// `X − m·2^shift` for power `p` and mass `m`: its sign exact for the double-double `X`
    /// (`> 0` when the ideal mass lies above `m`), its value to `f64` precision.
    pub(super) fn gap(self, p: f64, m: u64) -> f64 {
        let (whole, fraction) = self.ideal_parts(p);
        // Both below 2^64: the difference is exact in i128, and rounding it and adding the
        // fraction keeps the sign (a rounded sum is 0 only where the exact one is).
        (i128::from(whole) - (i128::from(m) << self.shift)) as f64 + fraction
    }

    /// `round(z)` of a fixed-point running sum: the whole units of its nearest integer
    /// (halves up).
    #[inline]
    pub(super) fn rounded(self, z: u64) -> u64 {
        (z + ((1u64 << self.shift) >> 1)) >> self.shift
    }
}
