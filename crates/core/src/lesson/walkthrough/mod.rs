//! The classic explanation of power-based light picking, as steps with live numbers.
//!
//! # The story
//! Lights of power `Φ_i` contribute `f_i` at one shading point. We want `L = Σ f_i` from one
//! light at a time.
//!
//! 1. **Uniform picking**: light `i` with `pdf = 1/N`; one sample estimates `f_i / (1/N)`.
//!    The estimates differ wildly, but their average over the `N` lights is `Σ f_i = L`.
//! 2. **Scaling**: `p_i = Φ_i / ΣΦ`, and `q_i = N·p_i` has mean 1.
//! 3. **The alias table** ([`AliasTable`]): column `c` (picked with probability `1/N`) keeps
//!    its light with probability `threshold_c`, else gives `alias_c`.
//! 4. **Each light's probability**, read off the table column by column:
//!    `P(j) = (1/N)·threshold_j + Σ_{k : alias_k = j, k ≠ j} (1/N)·(1 − threshold_k)`,
//!    which equals `p_j`.
//! 5. **The check**: `Σ P(j) = 1` and `P(j)/P(k) = Φ_j/Φ_k`.
//! 6. **`M` samples** (the classic `27`): each column is picked `M/N` times, keeps its light
//!    in `(M/N)·threshold_c` of them and gives its alias the rest, so light `j` is drawn
//!    `M·p_j` times; each draw weighs `f_j / p_j`, and the average
//!    `Σ_j M·p_j·(f_j/p_j) / M = Σ f_j = L` is exact again.
//!
//! # Numbers follow the powers
//! Each light keeps its *geometry factor* `g_i = f_i / Φ_i` (distance, angle: what the
//! power is multiplied by at the shading point). The classic scene has `Φ = 2, 5, 20`,
//! `g = 0.5, 0.4, 0.75` ([`CLASSIC_GEOMETRY`]), hence `f = 1, 2, 15` and `L = 18`. Changing a
//! power changes that light's contribution `f_i = g_i·Φ_i` and the exact total with it.
//!
//! # Any number of lights
//! The model works for any `N ≥ 1` (one probability step per light); lights beyond the
//! given geometry factors reuse them cyclically. The app shows the walkthrough for exactly
//! three lights, the classic's count, and offers to load the classic scene otherwise.
//!
//! # Exact fractions
//! When every power is a whole number with `ΣΦ ≤ 1000`, every probability, threshold and
//! column share is a multiple of `1/ΣΦ` or `1/(N·ΣΦ)`, and the formulas write it as such
//! (`6/27`, not `0.2222`, and unreduced, as the classic writes it). Otherwise they show
//! short decimals.
//!
//! # Sample count
//! `M = ΣΦ` when the powers are whole and `N` divides `ΣΦ` (the classic's 27 samples: 9 per
//! column), else `M = N·ΣΦ` for whole powers; both make every count a whole number. For
//! other powers `M = 1000` and the counts are expectations (decimals).

use crate::alias::AliasTable;
use crate::fraction::{common_denominator, format_fraction};
use crate::powers::LightPowers;

mod steps;

/// The geometry factors `g_i = f_i/Φ_i` of the classic scene: `f = 0.5·2, 0.4·5, 0.75·20 =
/// 1, 2, 15`.
pub const CLASSIC_GEOMETRY: [f64; 3] = [0.5, 0.4, 0.75];

/// The classic scene's powers `Φ = 2, 5, 20`.
pub const CLASSIC_POWERS: [f64; 3] = [2.0, 5.0, 20.0];

/// A column of the alias table as the app's table shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableField {
    /// The power `Φ_i`.
    Power,
    /// The normalized power `p_i`.
    Pmf,
    /// The threshold of column `i`.
    Threshold,
    /// The alias of column `i`.
    Alias,
}

/// The part of a diagram column a step points at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnPart {
    /// The whole unit column (height `1/N` on the pmf scale).
    Whole,
    /// The column's own light, below its threshold.
    Own,
    /// The alias part, above the threshold.
    Alias,
}

/// What a step highlights: table cells `(row, field)` and diagram parts `(column, part)`,
/// all 0-based.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Highlight {
    /// Table cells.
    pub cells: Vec<(usize, TableField)>,
    /// Diagram column parts.
    pub columns: Vec<(usize, ColumnPart)>,
}

impl Highlight {
    /// Whether the cell `(row, field)` is highlighted.
    pub fn has_cell(&self, row: usize, field: TableField) -> bool {
        self.cells.contains(&(row, field))
    }

    /// Whether any part of diagram column `column` is highlighted, and which parts.
    pub fn parts(&self, column: usize) -> impl Iterator<Item = ColumnPart> + '_ {
        self.columns
            .iter()
            .filter(move |(c, _)| *c == column)
            .map(|(_, p)| *p)
    }
}

/// The kind of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepKind {
    /// Powers, contributions and the exact total.
    Scene,
    /// Uniform picking and its average.
    Uniform,
    /// `p = Φ/ΣΦ` and `q = N·p`.
    Scaled,
    /// The thresholds and aliases.
    Table,
    /// The probability of one light (0-based), read off the table.
    Probability(usize),
    /// The probabilities add up to 1 and follow the powers.
    Check,
    /// The `M`-sample argument.
    Samples,
}

/// One step: a title, a sentence, formulas with the current numbers, and what to highlight.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkStep {
    /// What the step is.
    pub kind: StepKind,
    /// Short title.
    pub title: String,
    /// One or two sentences of explanation.
    pub text: String,
    /// The formulas, one per line, with the current numbers.
    pub formulas: Vec<String>,
    /// The table cells and diagram parts the formulas talk about.
    pub highlight: Highlight,
}

/// Light `j`'s probability read off the table.
#[derive(Clone, Debug, PartialEq)]
pub struct LightProbability {
    /// `(1/N)·threshold_j`: column `j` keeping its own light.
    pub own: f64,
    /// `(k, (1/N)·(1 − threshold_k))` for every other column `k` whose alias is `j`.
    pub from_aliases: Vec<(usize, f64)>,
    /// The sum of the parts: `P(j)`.
    pub total: f64,
}

/// The `M`-sample argument.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleArgument {
    /// The number of samples `M`.
    pub count: f64,
    /// Samples per column, `M/N`.
    pub per_column: f64,
    /// Samples in which column `c` keeps its light: `(M/N)·threshold_c`.
    pub kept: Vec<f64>,
    /// Samples in which column `c` gives its alias: `(M/N)·(1 − threshold_c)`.
    pub given: Vec<f64>,
    /// Samples of each light: `M·P(j)`.
    pub counts: Vec<f64>,
    /// The weighted estimate `f_j / P(j)` of one sample of light `j` (`None` when `P(j) = 0`).
    pub weighted: Vec<Option<f64>>,
    /// `Σ_j counts_j·weighted_j / M`: the exact total again.
    pub average: f64,
}

/// The whole walkthrough for one set of powers.
#[derive(Clone, Debug, PartialEq)]
pub struct Walkthrough {
    /// The powers `Φ_i`.
    pub powers: Vec<f64>,
    /// The geometry factors `g_i`.
    pub geometry: Vec<f64>,
    /// The contributions `f_i = g_i·Φ_i`.
    pub contributions: Vec<f64>,
    /// `ΣΦ`.
    pub total_power: f64,
    /// The exact total `L = Σ f_i`.
    pub exact: f64,
    /// `ΣΦ` when the formulas can write exact fractions.
    pub denominator: Option<u64>,
    /// The normalized powers `p_i`.
    pub pmf: Vec<f64>,
    /// Uniform estimates `f_i / (1/N) = N·f_i`.
    pub uniform_estimates: Vec<f64>,
    /// Their average over the lights: `L`.
    pub uniform_average: f64,
    /// The table's thresholds ([`AliasTable::build_exact`]).
    pub thresholds: Vec<f64>,
    /// The table's aliases, 0-based.
    pub aliases: Vec<u32>,
    /// Each light's probability, read off the table.
    pub probabilities: Vec<LightProbability>,
    /// The `M`-sample argument.
    pub samples: SampleArgument,
}

impl Walkthrough {
    /// The walkthrough of `powers`, light `i` having geometry factor
    /// `geometry[i mod len]` (1 when `geometry` is empty).
    pub fn new(powers: &LightPowers, geometry: &[f64]) -> Self {
        let phi = powers.as_slice().to_vec();
        let n = phi.len();
        let n_f = n as f64;
        let g: Vec<f64> = (0..n)
            .map(|i| {
                if geometry.is_empty() {
                    1.0
                } else {
                    geometry[i % geometry.len()]
                }
            })
            .collect();
        let f: Vec<f64> = phi.iter().zip(&g).map(|(p, g)| p * g).collect();
        let exact = f.iter().sum();
        let table = AliasTable::build_exact(powers);
        let thresholds = table.thresholds().to_vec();
        let aliases = table.aliases().to_vec();
        let probabilities = (0..n)
            .map(|j| {
                let own = thresholds[j] / n_f;
                let from_aliases: Vec<(usize, f64)> = (0..n)
                    .filter(|&k| k != j && aliases[k] as usize == j && thresholds[k] < 1.0)
                    .map(|k| (k, (1.0 - thresholds[k]) / n_f))
                    .collect();
                let total = own + from_aliases.iter().map(|(_, m)| m).sum::<f64>();
                LightProbability {
                    own,
                    from_aliases,
                    total,
                }
            })
            .collect::<Vec<_>>();
        let denominator = common_denominator(&phi, 1000.0);
        let total_power = powers.total();
        let count = match denominator {
            Some(s) if s % n as u64 == 0 => s as f64,
            Some(s) => (s * n as u64) as f64,
            None => 1000.0,
        };
        let per_column = count / n_f;
        let pmf = table.pmf_slice().to_vec();
        let counts: Vec<f64> = pmf.iter().map(|p| count * p).collect();
        let weighted: Vec<Option<f64>> = pmf
            .iter()
            .zip(&f)
            .map(|(&p, &fi)| (p > 0.0).then(|| fi / p))
            .collect();
        let average = counts
            .iter()
            .zip(&weighted)
            .map(|(c, w)| w.map_or(0.0, |w| c * w))
            .sum::<f64>()
            / count;
        let samples = SampleArgument {
            count,
            per_column,
            kept: thresholds.iter().map(|t| per_column * t).collect(),
            given: thresholds.iter().map(|t| per_column * (1.0 - t)).collect(),
            counts,
            weighted,
            average,
        };
        let uniform_estimates: Vec<f64> = f.iter().map(|fi| fi * n_f).collect();
        let uniform_average = uniform_estimates.iter().sum::<f64>() / n_f;
        Self {
            powers: phi,
            geometry: g,
            contributions: f,
            total_power,
            exact,
            denominator,
            pmf,
            uniform_estimates,
            uniform_average,
            thresholds,
            aliases,
            probabilities,
            samples,
        }
    }

    /// The classic scene: `Φ = 2, 5, 20`, `f = 1, 2, 15`.
    pub fn classic() -> Self {
        let powers = LightPowers::new(CLASSIC_POWERS.to_vec()).unwrap_or_else(|_| unreachable!());
        Self::new(&powers, &CLASSIC_GEOMETRY)
    }

    /// Number of lights `N`.
    pub fn len(&self) -> usize {
        self.powers.len()
    }

    /// Always `false` (validated powers are never empty).
    pub fn is_empty(&self) -> bool {
        self.powers.is_empty()
    }

    /// A probability-like value as an exact fraction over `ΣΦ` or `N·ΣΦ` when it is one,
    /// else a short decimal.
    pub fn fraction(&self, v: f64) -> String {
        let n = self.len() as u64;
        format_fraction(v, self.denominator)
            .or_else(|| format_fraction(v, self.denominator.map(|d| d * n)))
            .unwrap_or_else(|| number(v))
    }
}

/// A number as the formulas write it: whole numbers without decimals (`18`), others with
/// up to four significant digits and no trailing zeros (`13.5`, `0.75`), very large or small
/// ones in scientific notation.
pub fn number(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let r = v.round();
    if (v - r).abs() <= 1e-9 * v.abs().max(1.0) && r.abs() < 1e15 {
        return format!("{}", r as i64);
    }
    let a = v.abs();
    if !(1e-4..1e6).contains(&a) {
        return format!("{v:.3e}");
    }
    let digits = (3 - a.log10().floor() as i32).clamp(0, 8) as usize;
    let s = format!("{v:.digits$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_formulas(w: &Walkthrough) -> String {
        w.steps()
            .iter()
            .flat_map(|s| s.formulas.clone())
            .collect::<Vec<_>>()
            .join("\n")
    }

    #[test]
    fn classic_numbers_are_exact() {
        let w = Walkthrough::classic();
        assert_eq!(w.contributions, vec![1.0, 2.0, 15.0]);
        assert_eq!(w.exact, 18.0);
        assert_eq!(w.uniform_estimates, vec![3.0, 6.0, 45.0]);
        assert_eq!(w.uniform_average, 18.0);
        assert_eq!(w.thresholds, vec![6.0 / 27.0, 15.0 / 27.0, 1.0]);
        assert_eq!(w.aliases, vec![2, 2, 2]);
        let p: Vec<String> = w
            .probabilities
            .iter()
            .map(|p| w.fraction(p.total))
            .collect();
        assert_eq!(p, ["2/27", "5/27", "20/27"]);
        let third = &w.probabilities[2];
        assert_eq!(w.fraction(third.own), "9/27");
        let parts: Vec<(usize, String)> = third
            .from_aliases
            .iter()
            .map(|(k, m)| (*k, w.fraction(*m)))
            .collect();
        assert_eq!(parts, [(0, "7/27".to_owned()), (1, "4/27".to_owned())]);
        assert_eq!(w.samples.count, 27.0);
        assert_eq!(w.samples.per_column, 9.0);
        for (got, want) in w.samples.counts.iter().zip([2.0, 5.0, 20.0]) {
            assert!((got - want).abs() < 1e-12, "{got}");
        }
        assert!((w.samples.average - 18.0).abs() < 1e-12);
        assert_eq!(number(w.samples.average), "18");
    }

    #[test]
    fn classic_formulas_read_like_the_explanation() {
        let w = Walkthrough::classic();
        let steps = w.steps();
        assert_eq!(steps.len(), 9);
        let text = all_formulas(&w);
        for needle in [
            "exact total L = 1 + 2 + 15 = 18",
            "average = (3 + 6 + 45)/3 = 18",
            "threshold = 6/27, 15/27, 1",
            "alias = light 3, 3, 3   (index 2, 2, 2 from 0)",
            "P(light 1) = 1/3·6/27",
            "= 2/27",
            "P(light 3) = 1/3·1 + 1/3·(1 − 6/27) + 1/3·(1 − 15/27)",
            "= 9/27 + 7/27 + 4/27 = 20/27",
            "2/27 + 5/27 + 20/27 = 1",
            "P(light 3)/P(light 1) = 20/27 ÷ 2/27 = 10",
            "27 samples: each column is picked 27/3 = 9 times",
            "samples per light: 2, 5, 20",
            "f/p = 1/(2/27), 2/(5/27), 15/(20/27) = 13.5, 10.8, 20.25",
            "average = (2·13.5 + 5·10.8 + 20·20.25)/27 = (27 + 54 + 405)/27 = 18",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in\n{text}");
        }
        let p3 = &steps[6];
        assert_eq!(p3.kind, StepKind::Probability(2));
        assert!(p3.highlight.has_cell(0, TableField::Alias));
        assert_eq!(
            p3.highlight.parts(0).collect::<Vec<_>>(),
            [ColumnPart::Alias]
        );
        assert_eq!(p3.highlight.parts(2).collect::<Vec<_>>(), [ColumnPart::Own]);
    }

    #[test]
    fn numbers_follow_a_changed_power() {
        let powers = LightPowers::new(vec![7.0, 5.0, 20.0]).unwrap();
        let w = Walkthrough::new(&powers, &CLASSIC_GEOMETRY);
        assert_eq!(w.contributions, vec![3.5, 2.0, 15.0]);
        assert_eq!(w.exact, 20.5);
        assert_eq!(w.fraction(w.probabilities[0].total), "7/32");
        // 32 is not a multiple of 3: 3·32 = 96 samples keep every count whole.
        assert_eq!(w.samples.count, 96.0);
        assert!((w.samples.average - 20.5).abs() < 1e-12);
        let text = all_formulas(&w);
        assert!(
            text.contains("exact total L = 3.5 + 2 + 15 = 20.5"),
            "{text}"
        );
        assert!(text.contains("7/32 + 5/32 + 20/32 = 1"), "{text}");
    }

    #[test]
    fn decimal_powers_and_other_counts() {
        let powers = LightPowers::new(vec![0.5, 1.25, 0.0, 3.0]).unwrap();
        let w = Walkthrough::new(&powers, &CLASSIC_GEOMETRY);
        assert_eq!(w.denominator, None);
        assert_eq!(w.geometry[3], 0.5);
        assert_eq!(w.steps().len(), 10);
        assert_eq!(w.samples.weighted[2], None);
        assert!((w.samples.average - w.exact).abs() < 1e-12 * w.exact);
        let sum: f64 = w.probabilities.iter().map(|p| p.total).sum();
        assert!((sum - 1.0).abs() < 1e-15);
        for (p, want) in w.probabilities.iter().zip(&w.pmf) {
            assert!((p.total - want).abs() < 1e-15);
        }
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(number(18.0), "18");
        assert_eq!(number(13.5), "13.5");
        assert_eq!(number(10.8), "10.8");
        assert_eq!(number(20.25), "20.25");
        assert_eq!(number(0.75), "0.75");
        assert_eq!(number(1.0 / 3.0), "0.3333");
        assert_eq!(number(17.999_999_999_999_996), "18");
    }
}
