//! Question 1: building the table in `f32` the naive way, or in `f64` the project's way.
//!
//! # The naive `f32` build
//! What a direct port to a GPU or to C++ `float` usually looks like (Vose's algorithm as
//! in Schwarz's "Darts, Dice, and Coins"): `S = Σ w_i` summed left to right in `f32`,
//! `q_i = w_i·N / S` in `f32`, two stacks of small (`q < 1`) and large columns, the pairing
//! update `q_l ← (q_l + q_s) − 1` in `f32`, and — Vose's guard against rounding — every
//! column left on either stack gets threshold 1 and itself as alias.
//!
//! That guard is where zero-power lights leak: pairing conserves `Σ q` only up to rounding,
//! and the `f32` sum `S` is off by up to `N·2^-24` relative, so the stacks rarely run out
//! together. When the large stack empties first, the small columns left over are
//! promoted to threshold 1, a zero-power one included, which then receives `1/N` of the
//! probability. The project's build keeps a zero column at threshold 0 whatever happens
//! (see [`crate::AliasTable`]).
//!
//! # The figures
//! For a table with thresholds `t` and aliases `a`, the implied pmf is
//! `P̂(i) = (t_i + Σ_{a_j = i}(1 − t_j))/N`, evaluated in `f64` with compensated summation
//! (error `≲ 2^-52·P̂(i)`, far below what is measured). Against the exact pmf
//! `p_i = Φ_i/ΣΦ` (computed by [`exact_pmf`] to within a few ulps):
//!
//! * `zero_leak = Σ_{Φ_i = 0} P̂(i)` (exactly 0 for the project's table),
//! * `max_rel_error = max_{Φ_i > 0} |P̂(i) − p_i| / p_i` (documented bound for the project's
//!   table: `10^-12`).

use crate::{AliasTable, LightPowers};

/// A table built by the naive `f32` Vose algorithm of the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct NaiveF32Table {
    /// Keep probability of each column, in `f32`.
    pub threshold: Vec<f32>,
    /// Alias of each column.
    pub alias: Vec<u32>,
}

impl NaiveF32Table {
    /// Builds the table from `powers` (converted to `f32`, as a port would store them).
    pub fn build(powers: &[f64]) -> Self {
        let n = powers.len();
        let w: Vec<f32> = powers.iter().map(|&p| p as f32).collect();
        let sum: f32 = w.iter().sum();
        let n_f = n as f32;
        let mut q: Vec<f32> = w.iter().map(|&x| x * n_f / sum).collect();
        let mut small = Vec::new();
        let mut large = Vec::new();
        for (i, &x) in q.iter().enumerate() {
            if x < 1.0 {
                small.push(i);
            } else {
                large.push(i);
            }
        }
        let mut threshold = vec![1.0f32; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        while !small.is_empty() && !large.is_empty() {
            let (Some(s), Some(l)) = (small.pop(), large.pop()) else {
                break;
            };
            threshold[s] = q[s];
            alias[s] = l as u32;
            q[l] = (q[l] + q[s]) - 1.0;
            if q[l] < 1.0 {
                small.push(l);
            } else {
                large.push(l);
            }
        }
        // Vose's guard: whatever is left holds q ≈ 1 in exact arithmetic; set it to 1.
        for i in large.into_iter().chain(small) {
            threshold[i] = 1.0;
            alias[i] = i as u32;
        }
        Self { threshold, alias }
    }

    /// The pmf this table implies, `P̂(i) = (t_i + Σ_{a_j = i}(1 − t_j))/N` in `f64`.
    pub fn implied_pmf(&self) -> Vec<f64> {
        let t: Vec<f64> = self.threshold.iter().map(|&x| f64::from(x)).collect();
        implied_pmf_of(&t, &self.alias)
    }
}

/// The pmf `p_i = w_i / S` with `S = Σ w_i` summed with Neumaier's compensation (relative
/// error `≲ 2^-52`, independent of `N`), from the exactly rescaled powers
/// ([`LightPowers::normalized`]). The lab's reference: [`LightPowers::pmf`] divides by a
/// plainly summed `S`, whose rounding (up to `N/8` ulps) scales every `p_i` alike and would
/// be charged to the table under test.
pub fn exact_pmf(powers: &LightPowers) -> Vec<f64> {
    let (w, _) = powers.normalized();
    let (mut sum, mut compensation) = (0.0f64, 0.0f64);
    for &x in &w {
        let t = sum + x;
        compensation += if sum >= x {
            (sum - t) + x
        } else {
            (x - t) + sum
        };
        sum = t;
    }
    let total = sum + compensation;
    w.into_iter().map(|x| x / total).collect()
}

/// `P̂(i) = (t_i + Σ_{a_j = i}(1 − t_j))/N` for any thresholds `t` and aliases `a`, each
/// light's terms added with Neumaier's compensated summation.
pub fn implied_pmf_of(threshold: &[f64], alias: &[u32]) -> Vec<f64> {
    let n = threshold.len();
    let mut sum = threshold.to_vec();
    let mut compensation = vec![0.0f64; n];
    for (&t, &a) in threshold.iter().zip(alias) {
        let a = a as usize;
        let x = 1.0 - t; // exact for t in [0.5, 1]; for t < 0.5 an ulp of 1 at most
        let s = sum[a] + x;
        compensation[a] += if sum[a].abs() >= x.abs() {
            (sum[a] - s) + x
        } else {
            (x - s) + sum[a]
        };
        sum[a] = s;
    }
    sum.iter()
        .zip(&compensation)
        .map(|(s, c)| (s + c) / n as f64)
        .collect()
}

/// How far one table's implied pmf is from the exact pmf (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TableAccuracy {
    /// `Σ_{Φ_i = 0} P̂(i)`: probability of picking a light that emits nothing.
    pub zero_leak: f64,
    /// How many zero-power lights have `P̂(i) > 0`.
    pub leaking_lights: usize,
    /// `max_{Φ_i > 0} |P̂(i) − p_i| / p_i`.
    pub max_rel_error: f64,
    /// The light where `max_rel_error` is reached.
    pub worst_light: usize,
}

/// [`TableAccuracy`] of an implied pmf against the exact one.
pub fn accuracy_of(implied: &[f64], exact: &[f64]) -> TableAccuracy {
    let mut out = TableAccuracy {
        zero_leak: 0.0,
        leaking_lights: 0,
        max_rel_error: 0.0,
        worst_light: 0,
    };
    for (i, (&got, &p)) in implied.iter().zip(exact).enumerate() {
        if p == 0.0 {
            if got != 0.0 {
                out.zero_leak += got;
                out.leaking_lights += 1;
            }
        } else {
            let rel = (got - p).abs() / p;
            if rel > out.max_rel_error {
                out.max_rel_error = rel;
                out.worst_light = i;
            }
        }
    }
    out
}

/// The constructions against the exact pmf, on the same powers: the project's exact `f64`
/// build, its default integer build, and a naive `f32` build.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ConstructionComparison {
    /// The exact construction's `f64` table ([`AliasTable::build_exact`],
    /// [`AliasTable::implied_pmf`]).
    pub f64_build: TableAccuracy,
    /// The integer construction's packed table ([`AliasTable::build`],
    /// [`AliasTable::implied_pmf_packed`], what it samples). Its relative error is large for
    /// powers near `2^-32/N`, which it resolves in absolute terms:
    /// see [`ConstructionComparison::integer_max_error_units`].
    pub integer_build: TableAccuracy,
    /// The integer build's worst `|P(i) − p_i|` in units of `2^-32/N` (below 1 unless some
    /// `p_i < 2^-32/N`, then below `1 + a_i`).
    pub integer_max_error_units: f64,
    /// The naive `f32` table ([`NaiveF32Table`]).
    pub f32_build: TableAccuracy,
}

/// Builds the integer and the naive `f32` tables over `powers` and compares all three with
/// the exact pmf; `table` must be [`AliasTable::build_exact`]`(powers)`.
pub fn compare_construction(powers: &LightPowers, table: &AliasTable) -> ConstructionComparison {
    let exact = exact_pmf(powers);
    let naive = NaiveF32Table::build(powers.as_slice());
    let integer = AliasTable::build(powers).implied_pmf_packed();
    let unit = 1.0 / (powers.len() as f64 * 4_294_967_296.0);
    let integer_max_error_units = integer
        .iter()
        .zip(&exact)
        .map(|(got, want)| (got - want).abs() / unit)
        .fold(0.0, f64::max);
    ConstructionComparison {
        f64_build: accuracy_of(&table.implied_pmf(), &exact),
        integer_build: accuracy_of(&integer, &exact),
        integer_max_error_units,
        f32_build: accuracy_of(&naive.implied_pmf(), &exact),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn naive_build_of_the_seed_is_close() {
        let t = NaiveF32Table::build(&[2.0, 5.0, 20.0]);
        assert_eq!(t.alias, vec![2, 2, 2]);
        let p = t.implied_pmf();
        for (got, want) in p.iter().zip([2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]) {
            assert!((got - want).abs() < 1e-6, "{got} vs {want}");
        }
    }

    #[test]
    fn accuracy_counts_leaks_and_relative_errors() {
        let a = accuracy_of(&[0.1, 0.45, 0.45], &[0.0, 0.5, 0.5]);
        assert_eq!(a.leaking_lights, 1);
        assert!((a.zero_leak - 0.1).abs() < 1e-15);
        assert!((a.max_rel_error - 0.1).abs() < 1e-12);
    }
}
