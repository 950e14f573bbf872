//! Question 2: storing thresholds as `u32` (the project) or as `f32` (a naive port).
//!
//! # `u32` (the project's packed form)
//! `T_c = round(t_c·2^32)`, clamped to `[1, 2^32 − 1]` for `t_c > 0`; the keep test
//! `r2 < T_c` on a 32-bit random is true with probability exactly `T_c/2^32`, so each
//! column's split moves by `|T_c/2^32 − t_c| ≤ 2^-32` ([`U32_SPLIT_ERROR`]; the clamps cost at
//! most one unit). Light `i` gains or loses mass through its own column and the `a_i`
//! columns aliasing to it, each weighted `1/N`:
//!
//! `|P_u32(i) − P̂(i)| ≤ (1 + a_i)·2^-32/N`.
//!
//! # `f32` (threshold and uniform both `f32`)
//! `t_f32 = fl32(t_c)` (`|t_f32 − t_c| ≤ 2^-25` for `t_c ≤ 1`) and the uniform `u = k·2^-24`
//! from 24 random bits `k`, the naive `f32(u) < t` test: it keeps for exactly
//! `min(⌈t_f32·2^24⌉, 2^24)` of the `2^24` values of `k`, which adds up to `2^-24`. So
//! each split moves by at most `1.5·2^-24` ([`F32_SPLIT_ERROR`]) and
//!
//! `|P_f32(i) − P̂(i)| ≤ (1 + a_i)·1.5·2^-24/N`,
//!
//! a bound `384` times the `u32` one. Worse, any positive threshold below `2^-24` keeps
//! with probability `2^-24`, and one below `2^-149` rounds to 0: a light that dim is
//! then never picked unless another column aliases to it.
//!
//! `P̂` is the `f64` table's implied pmf ([`crate::AliasTable::implied_pmf`], within `10^-12`
//! relative of `p`); both realized pmfs are exact rationals evaluated in `f64`.

use super::construction::{accuracy_of, implied_pmf_of};
use crate::AliasTable;

/// Largest move of one column's split by the `u32` threshold: `2^-32`.
pub const U32_SPLIT_ERROR: f64 = 1.0 / 4_294_967_296.0;

/// Largest move of one column's split by an `f32` threshold tested against a 24-bit `f32`
/// uniform: `2^-25` (rounding `t`) `+ 2^-24` (the uniform's resolution) `= 1.5·2^-24`.
pub const F32_SPLIT_ERROR: f64 = 1.5 / 16_777_216.0;

/// `a_i`: how many columns other than `i` alias to light `i`.
pub fn alias_in_degree(table: &AliasTable) -> Vec<u32> {
    let mut degree = vec![0u32; table.len()];
    for (c, &a) in table.aliases().iter().enumerate() {
        if a as usize != c {
            degree[a as usize] += 1;
        }
    }
    degree
}

/// The pmf realized by `f32` thresholds tested against a 24-bit `f32` uniform: column `c`
/// keeps with probability `min(⌈fl32(t_c)·2^24⌉, 2^24)/2^24` (see the module docs).
pub fn f32_threshold_pmf(table: &AliasTable) -> Vec<f64> {
    let keep: Vec<f64> = table
        .thresholds()
        .iter()
        .map(|&t| {
            let t32 = f64::from(t as f32);
            (t32 * 16_777_216.0).ceil().min(16_777_216.0) / 16_777_216.0
        })
        .collect();
    implied_pmf_of(&keep, table.aliases())
}

/// The `u32` and `f32` threshold forms of one table against their bounds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ThresholdComparison {
    /// `max_c |T_c/2^32 − t_c| / 2^-32`: the largest split move of the `u32` form, in units of
    /// its bound (at most 1).
    pub u32_max_split_error: f64,
    /// `max_i |P_u32(i) − P̂(i)| / ((1 + a_i)·2^-32/N)`: the measured pmf error over its bound
    /// (at most 1).
    pub u32_error_over_bound: f64,
    /// `max_{p_i > 0} |P_u32(i) − p_i| / p_i`.
    pub u32_max_rel_error: f64,
    /// `max_c |keep_c − t_c| / (1.5·2^-24)` for the `f32` form (at most 1).
    pub f32_max_split_error: f64,
    /// `max_i |P_f32(i) − P̂(i)| / ((1 + a_i)·1.5·2^-24/N)` (at most 1).
    pub f32_error_over_bound: f64,
    /// `max_{p_i > 0} |P_f32(i) − p_i| / p_i`.
    pub f32_max_rel_error: f64,
    /// Lights of positive power that the `u32` form never picks (0: a positive threshold is
    /// stored as at least 1).
    pub u32_lost_lights: usize,
    /// Lights of positive power that the `f32` form never picks: thresholds below the
    /// smallest `f32` (`2^-149`) round to 0, and a light no column aliases to is then lost.
    pub f32_lost_lights: usize,
    /// `max_i (1 + a_i)·2^-32/N`: the largest absolute `u32` bound on this table.
    pub u32_bound_max: f64,
    /// `max_i (1 + a_i)·1.5·2^-24/N`: the largest absolute `f32` bound on this table.
    pub f32_bound_max: f64,
}

/// Measures both threshold forms of `table` against the `f64` split and their bounds.
pub fn compare_thresholds(table: &AliasTable) -> ThresholdComparison {
    let n = table.len() as f64;
    let degree = alias_in_degree(table);
    let reference = implied_pmf_of(table.thresholds(), table.aliases());
    let exact = table.pmf_slice();
    let u32_pmf = table.implied_pmf_packed();
    let f32_pmf = f32_threshold_pmf(table);
    let over_bound = |pmf: &[f64], unit: f64| {
        pmf.iter()
            .zip(&reference)
            .zip(&degree)
            .map(|((&got, &want), &a)| (got - want).abs() / ((1.0 + f64::from(a)) * unit / n))
            .fold(0.0, f64::max)
    };
    let u32_split = table
        .thresholds()
        .iter()
        .zip(table.packed())
        .map(|(&t, e)| (f64::from(e.threshold) * U32_SPLIT_ERROR - t).abs() / U32_SPLIT_ERROR)
        .fold(0.0, f64::max);
    let f32_split = table
        .thresholds()
        .iter()
        .map(|&t| {
            let keep = (f64::from(t as f32) * 16_777_216.0)
                .ceil()
                .min(16_777_216.0)
                / 16_777_216.0;
            (keep - t).abs() / F32_SPLIT_ERROR
        })
        .fold(0.0, f64::max);
    let lost = |pmf: &[f64]| {
        pmf.iter()
            .zip(exact)
            .filter(|&(&got, &p)| p > 0.0 && got == 0.0)
            .count()
    };
    let max_degree = f64::from(degree.iter().copied().max().unwrap_or(0));
    ThresholdComparison {
        u32_max_split_error: u32_split,
        u32_error_over_bound: over_bound(&u32_pmf, U32_SPLIT_ERROR),
        u32_max_rel_error: accuracy_of(&u32_pmf, exact).max_rel_error,
        f32_max_split_error: f32_split,
        f32_error_over_bound: over_bound(&f32_pmf, F32_SPLIT_ERROR),
        f32_max_rel_error: accuracy_of(&f32_pmf, exact).max_rel_error,
        u32_lost_lights: lost(&u32_pmf),
        f32_lost_lights: lost(&f32_pmf),
        u32_bound_max: (1.0 + max_degree) * U32_SPLIT_ERROR / n,
        f32_bound_max: (1.0 + max_degree) * F32_SPLIT_ERROR / n,
    }
}
