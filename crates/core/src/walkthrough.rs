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
    /// The table's thresholds ([`AliasTable::build`]).
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
        let table = AliasTable::build(powers);
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

    /// All steps, in order (`6 + N`).
    pub fn steps(&self) -> Vec<WalkStep> {
        let mut steps = vec![
            self.scene_step(),
            self.uniform_step(),
            self.scaled_step(),
            self.table_step(),
        ];
        steps.extend((0..self.len()).map(|j| self.probability_step(j)));
        steps.push(self.check_step());
        steps.push(self.samples_step());
        steps
    }

    fn all_cells(&self, field: TableField) -> Vec<(usize, TableField)> {
        (0..self.len()).map(|i| (i, field)).collect()
    }

    fn all_columns(&self) -> Vec<(usize, ColumnPart)> {
        (0..self.len()).map(|i| (i, ColumnPart::Whole)).collect()
    }

    fn scene_step(&self) -> WalkStep {
        let f = &self.contributions;
        WalkStep {
            kind: StepKind::Scene,
            title: "The scene".to_owned(),
            text: format!(
                "{} point lights. The table only knows their powers Φ; what we want to add \
                 up is their contribution f = g·Φ at one shading point (g: distance and \
                 angle).",
                self.len()
            ),
            formulas: vec![
                format!(
                    "Φ = {}    ΣΦ = {}",
                    list(&self.powers),
                    number(self.total_power)
                ),
                format!(
                    "f = {} = {}",
                    join(
                        self.geometry.iter().zip(&self.powers).map(|(g, p)| format!(
                            "{}·{}",
                            number(*g),
                            number(*p)
                        )),
                        ", "
                    ),
                    list(f)
                ),
                format!("exact total L = {} = {}", sum_of(f), number(self.exact)),
            ],
            highlight: Highlight {
                cells: self.all_cells(TableField::Power),
                columns: Vec::new(),
            },
        }
    }

    fn uniform_step(&self) -> WalkStep {
        let n = self.len();
        let pdf = format!("1/{n}");
        WalkStep {
            kind: StepKind::Uniform,
            title: "Uniform picking".to_owned(),
            text: "Pick a light with probability 1/N and divide its contribution by that \
                   probability. Single estimates are far off, but their average is exact."
                .to_owned(),
            formulas: vec![
                format!("pdf = {pdf} for every light"),
                format!(
                    "f/pdf = {} = {}",
                    join(
                        self.contributions
                            .iter()
                            .map(|f| format!("{}/({pdf})", number(*f))),
                        ", "
                    ),
                    list(&self.uniform_estimates)
                ),
                format!(
                    "average = ({})/{n} = {}",
                    sum_of(&self.uniform_estimates),
                    number(self.uniform_average)
                ),
            ],
            highlight: Highlight {
                cells: Vec::new(),
                columns: self.all_columns(),
            },
        }
    }

    fn scaled_step(&self) -> WalkStep {
        let n = self.len() as f64;
        let q: Vec<String> = self.pmf.iter().map(|p| self.fraction(p * n)).collect();
        WalkStep {
            kind: StepKind::Scaled,
            title: "Probabilities in proportion to power".to_owned(),
            text: "We want to pick each light in proportion to its power. Scaled by N, \
                   these probabilities average 1: the height of every table column."
                .to_owned(),
            formulas: vec![
                format!(
                    "p = Φ/ΣΦ = {}",
                    join(self.pmf.iter().map(|p| self.fraction(*p)), ", ")
                ),
                format!("q = N·p = {}   (mean 1)", q.join(", ")),
            ],
            highlight: Highlight {
                cells: self.all_cells(TableField::Pmf),
                columns: Vec::new(),
            },
        }
    }

    fn table_step(&self) -> WalkStep {
        let n = self.len();
        let mut cells = self.all_cells(TableField::Threshold);
        cells.extend(self.all_cells(TableField::Alias));
        WalkStep {
            kind: StepKind::Table,
            title: "The alias table".to_owned(),
            text: "Every column has the same height. Column c keeps its own light below \
                   its threshold and gives its alias above it (the construction stepper \
                   shows how it is built)."
                .to_owned(),
            formulas: vec![
                format!(
                    "threshold = {}",
                    join(self.thresholds.iter().map(|t| self.fraction(*t)), ", ")
                ),
                format!(
                    "alias = light {}   (index {} from 0)",
                    join(self.aliases.iter().map(|a| format!("{}", a + 1)), ", "),
                    join(self.aliases.iter().map(u32::to_string), ", ")
                ),
                format!(
                    "column c = floor(U1·{n}) + 1; keep light c if U2 < threshold_c, else alias_c"
                ),
            ],
            highlight: Highlight {
                cells,
                columns: self.all_columns(),
            },
        }
    }

    fn probability_step(&self, j: usize) -> WalkStep {
        let n = self.len();
        let prob = &self.probabilities[j];
        let one_over_n = format!("1/{n}");
        let mut symbolic = vec![format!(
            "{one_over_n}·{}",
            self.fraction(self.thresholds[j])
        )];
        let mut evaluated = symbolic.clone();
        let mut values = vec![self.fraction(prob.own)];
        let mut cells = vec![(j, TableField::Threshold), (j, TableField::Pmf)];
        let mut columns = vec![(j, ColumnPart::Own)];
        for &(k, mass) in &prob.from_aliases {
            let t = self.fraction(self.thresholds[k]);
            symbolic.push(format!("{one_over_n}·(1 − {t})"));
            evaluated.push(format!(
                "{one_over_n}·{}",
                self.fraction(1.0 - self.thresholds[k])
            ));
            values.push(self.fraction(mass));
            cells.push((k, TableField::Threshold));
            cells.push((k, TableField::Alias));
            columns.push((k, ColumnPart::Alias));
        }
        let total = self.fraction(prob.total);
        let mut formulas = vec![format!("P(light {}) = {}", j + 1, symbolic.join(" + "))];
        if prob.from_aliases.is_empty() {
            formulas.push(format!("= {total}"));
        } else {
            formulas.push(format!("= {}", evaluated.join(" + ")));
            formulas.push(format!("= {} = {total}", values.join(" + ")));
        }
        formulas.push(format!(
            "same as Φ_{}/ΣΦ = {}",
            j + 1,
            self.fraction(self.pmf[j])
        ));
        let text = if prob.from_aliases.is_empty() {
            format!(
                "Light {} comes only from its own column: the column is picked with \
                 probability 1/{n} and keeps its light below the threshold.",
                j + 1
            )
        } else {
            format!(
                "Light {} comes from its own column and from the top of every column whose \
                 alias it is.",
                j + 1
            )
        };
        WalkStep {
            kind: StepKind::Probability(j),
            title: format!("Probability of light {}", j + 1),
            text,
            formulas,
            highlight: Highlight { cells, columns },
        }
    }

    fn check_step(&self) -> WalkStep {
        let p: Vec<String> = self
            .probabilities
            .iter()
            .map(|p| self.fraction(p.total))
            .collect();
        let sum: f64 = self.probabilities.iter().map(|p| p.total).sum();
        let mut formulas = vec![format!("{} = {}", p.join(" + "), self.fraction(sum))];
        let positive = |&(_, v): &(usize, &f64)| *v > 0.0;
        let hi = self
            .powers
            .iter()
            .enumerate()
            .filter(positive)
            .max_by(|a, b| a.1.total_cmp(b.1));
        let lo = self
            .powers
            .iter()
            .enumerate()
            .filter(positive)
            .min_by(|a, b| a.1.total_cmp(b.1));
        if let (Some((h, _)), Some((l, _))) = (hi, lo)
            && h != l
        {
            let ph = self.probabilities[h].total;
            let pl = self.probabilities[l].total;
            formulas.push(format!(
                "P(light {})/P(light {}) = {} ÷ {} = {} = Φ_{}/Φ_{}",
                h + 1,
                l + 1,
                self.fraction(ph),
                self.fraction(pl),
                number(ph / pl),
                h + 1,
                l + 1
            ));
        }
        WalkStep {
            kind: StepKind::Check,
            title: "Check".to_owned(),
            text: "The probabilities add up to 1 and follow the powers.".to_owned(),
            formulas,
            highlight: Highlight {
                cells: self.all_cells(TableField::Pmf),
                columns: Vec::new(),
            },
        }
    }

    fn samples_step(&self) -> WalkStep {
        let s = &self.samples;
        let m = number(s.count);
        let n = self.len();
        let mut formulas = vec![format!(
            "{m} samples: each column is picked {m}/{n} = {} times",
            number(s.per_column)
        )];
        for c in 0..n {
            let t = self.thresholds[c];
            let a = self.aliases[c] as usize;
            let line = if t >= 1.0 || a == c {
                format!(
                    "column {} keeps light {} all {} times",
                    c + 1,
                    c + 1,
                    number(s.per_column)
                )
            } else {
                format!(
                    "column {}: light {} in {}·{} = {}, light {} in the other {}",
                    c + 1,
                    c + 1,
                    number(s.per_column),
                    self.fraction(t),
                    number(s.kept[c]),
                    a + 1,
                    number(s.given[c])
                )
            };
            formulas.push(line);
        }
        formulas.push(format!("samples per light: {}", list(&s.counts)));
        let drawn: Vec<usize> = (0..n).filter(|&j| s.weighted[j].is_some()).collect();
        formulas.push(format!(
            "f/p = {} = {}",
            join(
                drawn.iter().map(|&j| format!(
                    "{}/({})",
                    number(self.contributions[j]),
                    self.fraction(self.pmf[j])
                )),
                ", "
            ),
            join(
                drawn.iter().map(|&j| number(s.weighted[j].unwrap_or(0.0))),
                ", "
            )
        ));
        let products: Vec<f64> = drawn
            .iter()
            .map(|&j| s.counts[j] * s.weighted[j].unwrap_or(0.0))
            .collect();
        formulas.push(format!(
            "average = ({})/{m} = ({})/{m} = {}",
            join(
                drawn.iter().map(|&j| format!(
                    "{}·{}",
                    number(s.counts[j]),
                    number(s.weighted[j].unwrap_or(0.0))
                )),
                " + "
            ),
            sum_of(&products),
            number(s.average)
        ));
        let text = if self.denominator.is_some() {
            format!(
                "Out of {m} samples, on average light j is drawn in proportion to its power. \
                 Each sample is weighed by f/p, and the average is the exact total again."
            )
        } else {
            format!(
                "Out of {m} samples, light j is drawn M·p_j times on average (decimals: these \
                 powers are not small whole numbers). The weighted average is exact again."
            )
        };
        WalkStep {
            kind: StepKind::Samples,
            title: format!("Importance sampling: {m} samples"),
            text,
            formulas,
            highlight: Highlight {
                cells: self.all_cells(TableField::Pmf),
                columns: self.all_columns(),
            },
        }
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

fn join(items: impl Iterator<Item = String>, sep: &str) -> String {
    items.collect::<Vec<_>>().join(sep)
}

fn list(values: &[f64]) -> String {
    join(values.iter().map(|v| number(*v)), ", ")
}

fn sum_of(values: &[f64]) -> String {
    join(values.iter().map(|v| number(*v)), " + ")
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
