//! The precision lab: what each numerical choice of the alias table costs, computed
//! exactly (by counting) wherever that is possible, and measured otherwise.
//!
//! Four questions, one sub-module each:
//!
//! 1. **Table construction in `f32` or `f64`** ([`compare_construction`]). A naive `f32`
//!    Vose build (the way a GPU or C++ port often does it: `f32` sum, `q_i = w_i·N/S`, two
//!    work lists, every leftover set to 1) against the project's `f64` build
//!    ([`crate::AliasTable::build`]). Figures: the probability that leaks onto zero-power
//!    lights, `Σ_{Φ_i = 0} P̂(i)`, and the largest relative error
//!    `max_{Φ_i > 0} |P̂(i) − p_i| / p_i` of the implied pmf
//!    `P̂(i) = (t_i + Σ_{alias_j = i}(1 − t_j))/N`.
//! 2. **Thresholds as `u32` or `f32`** ([`compare_thresholds`]). The packed `u32` threshold
//!    `T_c = round(t_c·2^32)` with the keep test `r2 < T_c` moves each column's split by at
//!    most `2^-32`, so `|P_u32(i) − P̂(i)| ≤ (1 + a_i)·2^-32/N` (`a_i` = columns aliasing
//!    to `i`). An `f32` threshold compared with an `f32` uniform `u = k·2^-24` (24 random
//!    bits) keeps with probability `⌈t_f32·2^24⌉/2^24`, `|t_f32 − t| ≤ 2^-25`, so its bound
//!    is `(1 + a_i)·1.5·2^-24/N`, 384 times looser.
//! 3. **Column pick `f32(u)·N`, raw multiply-high, or exact** ([`f32_column_pick`],
//!    [`multiply_high_column_pick`], [`exact_column_pick`]). Counted over every input: the
//!    `2^24` values of the `f32` uniform; for the raw `⌊r·N/2^32⌋` the closed form
//!    (`⌊2^32/N⌋` or `⌈2^32/N⌉` values of `r` per column, a bias up to `N·2^-32` relative);
//!    for the default pick, multiply-high with Lemire's rejection, exactly `⌊2^32/N⌋`
//!    accepted values of `r` per column (exactly uniform).
//! 4. **One random or two** ([`compare_one_random`]). The exact realized pmf of
//!    [`crate::AliasTable::sample_one_random`], counted per column in `O(1)`, against the
//!    exact realized pmf of the raw two-random [`crate::AliasTable::sample_u32`] ("before"),
//!    of the default [`crate::AliasTable::sample`] (exact column pick: equal to the packed
//!    pmf) and against `p`.
//!
//! [`PrecisionReport`] gathers 1, 2 and 4 for one set of powers; [`column_pick_sweep`] gives
//! 3 over a range of `N`. The test powers come from [`Distribution`].

mod column;
mod construction;
mod distribution;
mod one_random;
mod thresholds;

pub use column::{
    COLUMN_SWEEP, ColumnPickComparison, ColumnPickStats, column_pick_sweep, exact_column_counts,
    exact_column_pick, exact_column_r_range, f32_column, f32_column_pick,
    multiply_high_column_pick, multiply_high_counts,
};
pub use construction::{
    ConstructionComparison, NaiveF32Table, TableAccuracy, accuracy_of, compare_construction,
    exact_pmf, implied_pmf_of,
};
pub use distribution::{Distribution, UnknownDistribution};
pub use one_random::{
    OneRandomComparison, column_r_range, compare_one_random, exact_pick_counts, exact_pick_pmf,
    one_random_column, one_random_counts, one_random_pmf, two_random_pmf,
};
pub use thresholds::{
    F32_SPLIT_ERROR, ThresholdComparison, U32_SPLIT_ERROR, alias_in_degree, compare_thresholds,
    f32_threshold_pmf,
};

use crate::{AliasTable, LightPowers};

/// Every figure of the lab for one set of powers (serialized as one JSON object).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PrecisionReport {
    /// Number of lights `N`.
    pub n: usize,
    /// The distribution the powers were drawn from, if they were.
    pub distribution: Option<Distribution>,
    /// Number of zero-power lights.
    pub zero_lights: usize,
    /// Question 1: `f32` against `f64` construction.
    pub construction: ConstructionComparison,
    /// Question 2: `u32` against `f32` thresholds.
    pub thresholds: ThresholdComparison,
    /// Question 4: one random against two.
    pub one_random: OneRandomComparison,
}

impl PrecisionReport {
    /// Builds the project's table over `powers` once and measures questions 1, 2 and 4.
    pub fn measure(powers: &LightPowers, distribution: Option<Distribution>) -> Self {
        let table = AliasTable::build_exact(powers);
        Self {
            n: powers.len(),
            distribution,
            zero_lights: powers.as_slice().iter().filter(|&&p| p == 0.0).count(),
            construction: compare_construction(powers, &table),
            thresholds: compare_thresholds(&table),
            one_random: compare_one_random(&table),
        }
    }
}
