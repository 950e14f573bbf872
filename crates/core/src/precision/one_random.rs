//! Question 4: one random (reusing the fraction of `r·N`) or two, computed exactly.
//!
//! # Counting instead of sampling
//! Column `c` receives the 32-bit randoms `r ∈ [r_0, r_1)`, `r_0 = ⌈c·2^32/N⌉`,
//! `r_1 = ⌈(c+1)·2^32/N⌉` ([`column_r_range`]), `m_c = r_1 − r_0 ∈ {Q, Q+1}` of them
//! (`Q = ⌊2^32/N⌋`). [`crate::AliasTable::sample_one_random`] reuses the low word of `r·N`,
//! the fraction `f(r) = r·N − c·2^32`, as its keep random. Over the column it is the
//! arithmetic progression `f_0, f_0 + N, …, f_0 + (m_c − 1)·N` with `f_0 = r_0·N − c·2^32 < N`:
//! only `m_c` distinct values, spaced `N` apart, instead of `2^32`. The keep test `f < T_c`
//! therefore holds for exactly
//!
//! `K_c = ⌈(T_c − f_0)/N⌉` values (0 if `T_c ≤ f_0`),
//!
//! and light `i` is returned by exactly `Σ_c [c = i]·K_c + [alias_c = i]·(m_c − K_c)` of the
//! `2^32` randoms: the realized pmf, in `O(1)` per column ([`one_random_pmf`]). Across all
//! columns the fraction takes `2^32/gcd(N, 2^32)` distinct values.
//!
//! The raw two-random mapping ([`crate::AliasTable::sample_u32`], the default before
//! Lemire's rejection, kept as the "before" figure) picks column `c` with probability
//! `m_c/2^32` and keeps with `T_c/2^32` independently, so its realized pmf is
//! `Σ_c m_c·([c = i]·T_c + [alias_c = i]·(2^32 − T_c)) / 2^64` ([`two_random_pmf`]).
//!
//! The default path ([`crate::AliasTable::sample`]) accepts exactly `Q` randoms in every
//! column (see [`super::column`]) and redraws the rest, then keeps on the next draw, so its
//! realized pmf weights every column by exactly `1/N` ([`exact_pick_pmf`], counted per
//! column from [`super::exact_column_r_range`]): it *is* the packed pmf `P_packed`.
//!
//! # Bounds, against the packed pmf `P_packed` (columns weighted exactly `1/N`)
//! * default (exact pick): `P_exact = P_packed` exactly; only the threshold quantization
//!   remains, `|P_packed(i) − p_i| ≤ (1 + a_i)·2^-32/N`;
//! * raw two random: `|m_c/2^32 − 1/N| < 2^-32`, so `|P_two(i) − P_packed(i)| < (1 + a_i)·2^-32`
//!   (zero when `N` is a power of two: every `m_c = 2^32/N`);
//! * one random: `|K_c − T_c/N| < 1` and `|m_c − 2^32/N| < 1`, so
//!   `|P_one(i) − P_packed(i)| < (1 + 2a_i)·2^-32`, a bias of relative order `N·2^-32` that
//!   stays when `N` is a power of two.
//!
//! Summed over lights, `Σ_i (1 + a_i) ≤ 2N`, so the total variation distance from the packed
//! pmf is 0 for the default path, below `N·2^-32` for the raw two randoms and `1.5·N·2^-32`
//! for one: an estimator `f_i/p_i` is biased by at most that times `max_i f_i/p_i`.

use super::column::exact_column_r_range;
use super::construction::accuracy_of;
use super::thresholds::alias_in_degree;
use crate::AliasTable;

const TWO_32: f64 = 4_294_967_296.0;

/// The randoms `[⌈c·2^32/N⌉, ⌈(c+1)·2^32/N⌉)` that the multiply-high pick sends to column `c`.
#[inline]
pub fn column_r_range(c: u64, n: u64) -> (u64, u64) {
    ((c << 32).div_ceil(n), ((c + 1) << 32).div_ceil(n))
}

/// `(K_c, m_c)`: of the `m_c` randoms of column `c`, how many [`AliasTable::sample_one_random`]
/// keeps (`K_c = ⌈(T_c − f_0)/N⌉`, 0 if `T_c ≤ f_0`); the other `m_c − K_c` go to the alias.
///
/// # Panics
/// If `c` is not a column of `table`.
#[inline]
pub fn one_random_column(table: &AliasTable, c: usize) -> (u64, u64) {
    let n = table.len() as u64;
    let (r0, r1) = column_r_range(c as u64, n);
    let m = r1 - r0;
    // r0 < 2^32 and N < 2^32, so r0·N < 2^64; f0 = r0·N − c·2^32 ∈ [0, N).
    let f0 = r0 * n - ((c as u64) << 32);
    let t = u64::from(table.packed()[c].threshold);
    let kept = if t <= f0 {
        0
    } else {
        (t - f0).div_ceil(n).min(m)
    };
    (kept, m)
}

/// How many of the `2^32` randoms [`AliasTable::sample_one_random`] maps to each light,
/// counted exactly per column ([`one_random_column`]).
pub fn one_random_counts(table: &AliasTable) -> Vec<u64> {
    let mut counts = vec![0u64; table.len()];
    for (c, e) in table.packed().iter().enumerate() {
        let (kept, m) = one_random_column(table, c);
        counts[c] += kept;
        counts[e.alias as usize] += m - kept;
    }
    counts
}

/// The exact realized pmf of [`AliasTable::sample_one_random`]: counts `/ 2^32`.
pub fn one_random_pmf(table: &AliasTable) -> Vec<f64> {
    one_random_counts(table)
        .into_iter()
        .map(|k| k as f64 / TWO_32)
        .collect()
}

/// The exact realized pmf of the raw [`AliasTable::sample_u32`] with two independent
/// randoms (no rejection: the "before" figure), column weights `m_c/2^32` included:
/// `Σ_c m_c·(…)/2^64` in `u128`, then rounded once.
pub fn two_random_pmf(table: &AliasTable) -> Vec<f64> {
    let n = table.len() as u64;
    let mut mass = vec![0u128; table.len()];
    for (c, e) in table.packed().iter().enumerate() {
        let (r0, r1) = column_r_range(c as u64, n);
        let m = u128::from(r1 - r0);
        let t = u128::from(e.threshold);
        mass[c] += m * t;
        mass[e.alias as usize] += m * ((1u128 << 32) - t);
    }
    mass.into_iter()
        .map(|x| x as f64 / (TWO_32 * TWO_32))
        .collect()
}

/// How many `(r1, r2)` pairs of the default path ([`AliasTable::sample`]) give each light,
/// over the accepted `r1` only: `Σ_c m_c·([c = i]·T_c + [alias_c = i]·(2^32 − T_c))` with
/// `m_c` the accepted count of column `c` from [`exact_column_r_range`] (`⌊2^32/N⌋` for every
/// column). Returns the counts and their total `Σ_c m_c·2^32`.
pub fn exact_pick_counts(table: &AliasTable) -> (Vec<u128>, u128) {
    let n = table.len() as u64;
    let mut mass = vec![0u128; table.len()];
    let mut total = 0u128;
    for (c, e) in table.packed().iter().enumerate() {
        let (first, end) = exact_column_r_range(c as u64, n);
        let m = u128::from(end - first);
        let t = u128::from(e.threshold);
        mass[c] += m * t;
        mass[e.alias as usize] += m * ((1u128 << 32) - t);
        total += m << 32;
    }
    (mass, total)
}

/// The exact realized pmf of the default path [`AliasTable::sample`] (rejected draws are
/// redrawn, so the accepted pairs are equally likely): [`exact_pick_counts`] over their
/// total, reduced by the common factor of the column counts before rounding once. Every
/// column accepts the same count, so this equals [`AliasTable::implied_pmf_packed`] bit for
/// bit.
pub fn exact_pick_pmf(table: &AliasTable) -> Vec<f64> {
    let n = table.len() as u64;
    let common = (0..n)
        .map(|c| {
            let (first, end) = exact_column_r_range(c, n);
            end - first
        })
        .fold(0u64, gcd);
    let common = u128::from(common.max(1));
    let (mass, total) = exact_pick_counts(table);
    let denominator = (total / common) as f64;
    mass.into_iter()
        .map(|x| (x / common) as f64 / denominator)
        .collect()
}

/// Euclid's greatest common divisor (`gcd(0, b) = b`).
fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// One random against two, exactly (see the module docs for the bounds).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct OneRandomComparison {
    /// Spacing of the reused fraction's values within a column: `N`.
    pub fraction_step: u64,
    /// Fewest distinct fraction values in a column (`Q = ⌊2^32/N⌋`).
    pub min_values_per_column: u64,
    /// Most distinct fraction values in a column (`Q` or `Q + 1`).
    pub max_values_per_column: u64,
    /// Distinct values the fraction takes over all `r`: `2^32/gcd(N, 2^32)`.
    pub distinct_fractions: u64,
    /// `max_i |P_one(i) − P_two(i)| / P_two(i)` over lights with `P_two(i) > 0`: the bias the
    /// speed option adds to the default path.
    pub one_vs_two_max_rel: f64,
    /// `max_{p_i > 0} |P_one(i) − p_i| / p_i`.
    pub one_max_rel_error: f64,
    /// `max_{p_i > 0} |P_two(i) − p_i| / p_i` of the raw two-random mapping, column weights
    /// `m_c/2^32` included (the default path before Lemire's rejection).
    pub two_max_rel_error: f64,
    /// `max_{p_i > 0} |P_exact(i) − p_i| / p_i` of the default path (exact column pick):
    /// equal to `packed_max_rel_error`.
    pub exact_max_rel_error: f64,
    /// `max_i |P_exact(i) − P_packed(i)|`, from the integer counts: 0 (the column pick adds
    /// nothing to the threshold quantization).
    pub exact_minus_packed: f64,
    /// `max_{p_i > 0} |P_packed(i) − p_i| / p_i` (columns weighted exactly `1/N`).
    pub packed_max_rel_error: f64,
    /// Total variation distance `½ Σ_i |P_packed(i) − p_i|` (threshold quantization only).
    pub packed_total_variation: f64,
    /// Total variation distance `½ Σ_i |P_two(i) − p_i|` of the raw two-random mapping: what
    /// it could bias an estimate by, relative to the largest contribution `max_i f_i/p_i`.
    pub two_total_variation: f64,
    /// Total variation distance `½ Σ_i |P_exact(i) − p_i|` of the default path: equal to
    /// `packed_total_variation`.
    pub exact_total_variation: f64,
    /// Total variation distance `½ Σ_i |P_one(i) − p_i|`.
    pub one_total_variation: f64,
    /// `max_i |P_one(i) − P_packed(i)| / ((1 + 2a_i)·2^-32)` (below 1).
    pub one_error_over_bound: f64,
    /// `max_i |P_two(i) − P_packed(i)| / ((1 + a_i)·2^-32)` (below 1).
    pub two_error_over_bound: f64,
    /// `max_i |P_exact(i) − p_i| / ((1 + a_i)·2^-32/N)`: the default path against the
    /// threshold quantization bound (below 1, up to the `f64` table's own error).
    pub exact_error_over_bound: f64,
    /// Probability the one-random path gives to zero-power lights (0).
    pub one_zero_leak: f64,
    /// Probability the two-random path gives to zero-power lights (0).
    pub two_zero_leak: f64,
    /// Probability the default path gives to zero-power lights (0).
    pub exact_zero_leak: f64,
}

/// `½ Σ_i |a_i − b_i|`.
fn total_variation(a: &[f64], b: &[f64]) -> f64 {
    0.5 * a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f64>()
}

/// Computes the exact realized pmfs of both paths over `table` and compares them.
pub fn compare_one_random(table: &AliasTable) -> OneRandomComparison {
    let n = table.len() as u64;
    let exact = table.pmf_slice();
    let packed = table.implied_pmf_packed();
    let one = one_random_pmf(table);
    let two = two_random_pmf(table);
    let exact_pmf = exact_pick_pmf(table);
    let degree = alias_in_degree(table);
    let over = |pmf: &[f64], per_alias: f64| {
        pmf.iter()
            .zip(&packed)
            .zip(&degree)
            .map(|((&got, &want), &a)| {
                (got - want).abs() / ((1.0 + per_alias * f64::from(a)) / TWO_32)
            })
            .fold(0.0, f64::max)
    };
    let one_vs_two = one
        .iter()
        .zip(&two)
        .filter(|&(_, &t)| t > 0.0)
        .map(|(&o, &t)| (o - t).abs() / t)
        .fold(0.0, f64::max);
    let q = (1u64 << 32) / n;
    let one_acc = accuracy_of(&one, exact);
    let two_acc = accuracy_of(&two, exact);
    let exact_acc = accuracy_of(&exact_pmf, exact);
    let exact_minus_packed = exact_pmf
        .iter()
        .zip(&packed)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let exact_error_over_bound = exact_pmf
        .iter()
        .zip(exact)
        .zip(&degree)
        .map(|((&got, &want), &a)| {
            (got - want).abs() / ((1.0 + f64::from(a)) / (TWO_32 * n as f64))
        })
        .fold(0.0, f64::max);
    OneRandomComparison {
        fraction_step: n,
        min_values_per_column: q,
        max_values_per_column: if (1u64 << 32).is_multiple_of(n) {
            q
        } else {
            q + 1
        },
        distinct_fractions: (1u64 << 32) >> n.trailing_zeros().min(32),
        one_vs_two_max_rel: one_vs_two,
        one_max_rel_error: one_acc.max_rel_error,
        two_max_rel_error: two_acc.max_rel_error,
        exact_max_rel_error: exact_acc.max_rel_error,
        exact_minus_packed,
        packed_max_rel_error: accuracy_of(&packed, exact).max_rel_error,
        packed_total_variation: total_variation(&packed, exact),
        two_total_variation: total_variation(&two, exact),
        exact_total_variation: total_variation(&exact_pmf, exact),
        one_total_variation: total_variation(&one, exact),
        one_error_over_bound: over(&one, 2.0),
        two_error_over_bound: over(&two, 1.0),
        exact_error_over_bound,
        one_zero_leak: one_acc.zero_leak,
        two_zero_leak: two_acc.zero_leak,
        exact_zero_leak: exact_acc.zero_leak,
    }
}
