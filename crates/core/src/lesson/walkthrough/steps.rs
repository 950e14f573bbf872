//! The walkthrough's steps as text: a title, a sentence and formulas with the current
//! numbers, plus what each step highlights (see the parent module for the story).

use super::{ColumnPart, Highlight, StepKind, TableField, WalkStep, Walkthrough, number};

impl Walkthrough {
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

fn join(items: impl Iterator<Item = String>, sep: &str) -> String {
    items.collect::<Vec<_>>().join(sep)
}

fn list(values: &[f64]) -> String {
    join(values.iter().map(|v| number(*v)), ", ")
}

fn sum_of(values: &[f64]) -> String {
    join(values.iter().map(|v| number(*v)), " + ")
}
