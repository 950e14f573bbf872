//! Question 3: picking the column, `f32(u)·N` or multiply-high `⌊r·N/2^32⌋`.
//!
//! # `f32(u)·N` (the naive GPU way)
//! `u = k·2^-24` for 24 random bits `k` (exact in `f32`), column
//! `min(⌊fl32(u·fl32(N))⌋, N − 1)`. There are only `2^24` values of `u`, so past
//! `N = 2^24` at least `N − 2^24` columns are never picked; below it, `fl32(N)` and the
//! rounding of the product make some columns receive `⌊2^24/N⌋` values and others more.
//! The map `k ↦ column` is non-decreasing (rounding and truncation are monotone), so one
//! pass over the `2^24` values of `k`, tracking runs, counts every column exactly without
//! an `N`-sized array ([`f32_column_pick`]).
//!
//! # Raw multiply-high (the "before" figure; still the one-random option's column)
//! Column `c` receives the `r` with `c·2^32 ≤ r·N < (c+1)·2^32`, that is
//! `r ∈ [⌈c·2^32/N⌉, ⌈(c+1)·2^32/N⌉)`. Writing `2^32 = Q·N + R` (`0 ≤ R < N`), each count
//! is `Q` or `Q + 1`, and since they add up to `2^32` exactly `R` columns get `Q + 1`. So
//! for every `N ≤ 2^32` all columns are reachable and the largest-to-smallest frequency
//! ratio is `(Q + 1)/Q` (1 when `N` is a power of two): at most `1 + N/2^32` roughly,
//! `1.0156` at `N = 2^26` ([`multiply_high_column_pick`]; [`multiply_high_counts`] lists the
//! counts from the interval formula, to check the closed form).
//!
//! # Exact pick, multiply-high with Lemire's rejection (the project's default)
//! With `t = R = 2^32 mod N`, a draw is accepted when `r·N mod 2^32 ≥ t`
//! ([`crate::Uniform::accept`]). Column `c` accepts the `r` with
//! `c·2^32 + t ≤ r·N < (c+1)·2^32`, that is `r ∈ [⌈(c·2^32 + t)/N⌉, ⌈(c+1)·2^32/N⌉)`
//! ([`exact_column_r_range`]): an interval of `r·N` of length `2^32 − t = Q·N`, so exactly
//! `Q` values of `r` for **every** column. The `t` rejected draws are redrawn, so each column
//! is picked with probability exactly `Q/(Q·N) = 1/N`: ratio 1 for every `N`
//! ([`exact_column_pick`]; [`exact_column_counts`] evaluates the interval formula).

/// Column counts of one pick method at one `N`, counted over every input.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ColumnPickStats {
    /// Number of columns `N`.
    pub n: u64,
    /// Number of distinct inputs (`2^24` values of `u`, or `2^32` of `r`).
    pub inputs: u64,
    /// Columns no input reaches.
    pub unreachable: u64,
    /// `unreachable / N`.
    pub unreachable_share: f64,
    /// The most inputs any column receives.
    pub max_count: u64,
    /// The fewest inputs a reachable column receives.
    pub min_count: u64,
    /// `max_count / min_count` over reachable columns (the frequency ratio; `∞` over all
    /// columns as soon as one is unreachable).
    pub max_min_ratio: f64,
}

impl ColumnPickStats {
    fn new(n: u64, inputs: u64, reachable: u64, max_count: u64, min_count: u64) -> Self {
        let unreachable = n - reachable;
        Self {
            n,
            inputs,
            unreachable,
            unreachable_share: unreachable as f64 / n as f64,
            max_count,
            min_count,
            max_min_ratio: max_count as f64 / min_count as f64,
        }
    }
}

/// The naive column of 24 random bits `k`: `min(⌊fl32(k·2^-24 · fl32(N))⌋, N − 1)`.
#[inline]
pub fn f32_column(k: u32, n: u32) -> u32 {
    let u = (k & 0x00ff_ffff) as f32 * (1.0 / 16_777_216.0);
    ((u * n as f32) as u32).min(n - 1)
}

/// Exact [`ColumnPickStats`] of [`f32_column`] over all `2^24` inputs (one pass, by runs).
///
/// # Panics
/// If `n` is 0.
pub fn f32_column_pick(n: u32) -> ColumnPickStats {
    assert!(n > 0, "no columns");
    let (mut reachable, mut max_count, mut min_count) = (0u64, 0u64, u64::MAX);
    let mut current = f32_column(0, n);
    let mut run = 0u64;
    for k in 0..1u32 << 24 {
        let c = f32_column(k, n);
        if c == current {
            run += 1;
        } else {
            reachable += 1;
            max_count = max_count.max(run);
            min_count = min_count.min(run);
            current = c;
            run = 1;
        }
    }
    reachable += 1;
    max_count = max_count.max(run);
    min_count = min_count.min(run);
    ColumnPickStats::new(u64::from(n), 1 << 24, reachable, max_count, min_count)
}

/// Exact [`ColumnPickStats`] of `⌊r·N/2^32⌋` over all `2^32` inputs, in closed form
/// (`Q = ⌊2^32/N⌋`, `R = 2^32 mod N`: `R` columns get `Q + 1`, the rest `Q`).
///
/// # Panics
/// If `n` is 0.
pub fn multiply_high_column_pick(n: u32) -> ColumnPickStats {
    assert!(n > 0, "no columns");
    let (q, r) = ((1u64 << 32) / u64::from(n), (1u64 << 32) % u64::from(n));
    // R < N, so N − R ≥ 1 columns get Q (the minimum) and Q ≥ 1 since N < 2^32.
    let max = if r > 0 { q + 1 } else { q };
    ColumnPickStats::new(u64::from(n), 1 << 32, u64::from(n), max, q)
}

/// The count of every column of `⌊r·N/2^32⌋` from the interval formula
/// `⌈(c+1)·2^32/N⌉ − ⌈c·2^32/N⌉` (`O(N)`, for checking the closed form).
pub fn multiply_high_counts(n: u32) -> Vec<u64> {
    let n = u64::from(n);
    let first = |c: u64| (c << 32).div_ceil(n);
    (0..n).map(|c| first(c + 1) - first(c)).collect()
}

/// The accepted randoms `[⌈(c·2^32 + t)/N⌉, ⌈(c+1)·2^32/N⌉)` of column `c` under Lemire's
/// rejection (`t = 2^32 mod N`): those of the raw range whose low word `r·N mod 2^32 ≥ t`.
#[inline]
pub fn exact_column_r_range(c: u64, n: u64) -> (u64, u64) {
    let t = (1u64 << 32) % n;
    (((c << 32) + t).div_ceil(n), ((c + 1) << 32).div_ceil(n))
}

/// The accepted count of every column of the exact pick from the interval formula
/// ([`exact_column_r_range`], `O(N)`): `⌊2^32/N⌋` for each, which tests check.
pub fn exact_column_counts(n: u32) -> Vec<u64> {
    let n = u64::from(n);
    (0..n)
        .map(|c| {
            let (first, end) = exact_column_r_range(c, n);
            end - first
        })
        .collect()
}

/// Exact [`ColumnPickStats`] of the default pick (multiply-high with Lemire's rejection), in
/// closed form: every column accepts `Q = ⌊2^32/N⌋` of the `2^32` draws and the other
/// `2^32 mod N` are redrawn, so `inputs = Q·N`, `min = max = Q` and the ratio is 1.
///
/// # Panics
/// If `n` is 0.
pub fn exact_column_pick(n: u32) -> ColumnPickStats {
    assert!(n > 0, "no columns");
    let q = (1u64 << 32) / u64::from(n);
    ColumnPickStats::new(u64::from(n), q * u64::from(n), u64::from(n), q, q)
}

/// The `N` of the default sweep: small, around `2^24`, and up to `2^26`.
pub const COLUMN_SWEEP: [u32; 9] = [
    3,
    1000,
    (1 << 20) + 1,
    (1 << 24) - 1,
    1 << 24,
    (1 << 24) + 1,
    (1 << 25) + 3,
    50_000_000,
    1 << 26,
];

/// The pick methods at one `N`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ColumnPickComparison {
    /// Number of columns.
    pub n: u64,
    /// `f32(u)·N` with 24-bit `u`.
    pub f32_pick: ColumnPickStats,
    /// `⌊r·N/2^32⌋` of one draw, no rejection (the raw map, "before").
    pub multiply_high: ColumnPickStats,
    /// `⌊r·N/2^32⌋` with Lemire's rejection (the default pick: every column `⌊2^32/N⌋`).
    pub exact: ColumnPickStats,
}

/// The three methods at each `N` of `ns` (each `f32` figure is one pass over `2^24` inputs).
pub fn column_pick_sweep(ns: &[u32]) -> Vec<ColumnPickComparison> {
    use rayon::prelude::*;
    ns.par_iter()
        .map(|&n| ColumnPickComparison {
            n: u64::from(n),
            f32_pick: f32_column_pick(n),
            multiply_high: multiply_high_column_pick(n),
            exact: exact_column_pick(n),
        })
        .collect()
}
