//! Log-log plot axes for `egui_plot`: the plots carry `log10` of their values, and these
//! helpers put the grid where a reader of log paper expects it (every `m·10^k`, `m = 1…9`)
//! and label it with the values themselves (`0.2`, `0.5`, `1`, `1e-4`), never with
//! fractional exponents such as `1e-0.30000000000000004`.

use std::ops::RangeInclusive;

use egui_plot::{GridInput, GridMark, Plot};

/// `step_size` of the decade lines (`10^k`): the strongest lines, always labelled when the
/// decades are far enough apart.
const DECADE: f64 = 1.0;
/// `step_size` of the `2·10^k` and `5·10^k` lines: labelled when the plot spans few decades
/// (their spacing is about a third of a decade).
const TWO_FIVE: f64 = 0.3;
/// `step_size` of the other lines (`3, 4, 6, 7, 8, 9 · 10^k`): faint, never labelled.
const MINOR: f64 = 0.1;

/// Decades beyond which only the decade lines are drawn (the minor ones would be noise).
const MAX_DECADES_WITH_MINOR: f64 = 12.0;

/// Grid marks at `log10(m·10^k)` over the visible `log10` bounds: decades, then `2` and `5`,
/// then the other mantissas, each with its own `step_size` (line strength and labelling).
#[allow(clippy::needless_pass_by_value)] // The signature egui_plot's grid spacers take.
pub fn log_grid_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return Vec::new();
    }
    let first = lo.floor() as i64 - 1;
    let last = hi.ceil() as i64 + 1;
    let minor = hi - lo <= MAX_DECADES_WITH_MINOR;
    let mut marks = Vec::new();
    for k in first..=last {
        let base = k as f64;
        marks.push(GridMark {
            value: base,
            step_size: decade_step(k),
        });
        if !minor {
            continue;
        }
        for m in 2..=9u8 {
            let step_size = if m == 2 || m == 5 { TWO_FIVE } else { MINOR };
            marks.push(GridMark {
                value: base + f64::from(m).log10(),
                step_size,
            });
        }
    }
    marks.retain(|mark| (lo..=hi).contains(&mark.value));
    marks
}

/// `step_size` of the decade line `10^k`: the largest of `1, 2, 5, 10, 20, 50` decades that
/// divides `k`, so that on a plot spanning many decades every 2nd, 5th or 10th one keeps a
/// strong, labelled line while egui fades and unlabels the crowded others.
fn decade_step(k: i64) -> f64 {
    [50, 20, 10, 5, 2]
        .into_iter()
        .find(|s| k % s == 0)
        .map_or(DECADE, |s| s as f64)
}

/// Below this many visible decades every mantissa line is labelled (else `1`, `2`, `5`).
const LABEL_ALL_BELOW_DECADES: f64 = 1.2;

/// The label of a mark at `log10 x = v`: `x` as a short decimal for `10^-3 ≤ x < 10^4`
/// (`0.002`, `0.5`, `20`), else `m·e k` (`2e-5`, `1e6`); empty for the minor lines unless the
/// visible `range` spans less than `LABEL_ALL_BELOW_DECADES` (1.2).
pub fn log_tick_label(mark: GridMark, range: &RangeInclusive<f64>) -> String {
    let span = range.end() - range.start();
    if mark.step_size < TWO_FIVE && span >= LABEL_ALL_BELOW_DECADES {
        return String::new();
    }
    value_label(mark.value)
}

/// `10^v` written as `m·10^k` with the mantissa rounded to the grid's `1…9`.
fn value_label(v: f64) -> String {
    let k = v.floor();
    let m = 10f64.powf(v - k).round();
    let (m, k) = if m >= 10.0 { (1.0, k + 1.0) } else { (m, k) };
    if (-3.0..4.0).contains(&k) {
        let x = m * 10f64.powf(k);
        let digits = (-k).max(0.0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{m}e{k}")
    }
}

/// A plot whose two axes are `log10` values: the log grid and its labels on both.
pub fn log_log_plot(plot: Plot<'_>) -> Plot<'_> {
    plot.x_grid_spacer(log_grid_marks)
        .y_grid_spacer(log_grid_marks)
        .x_axis_formatter(log_tick_label)
        .y_axis_formatter(log_tick_label)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn marks(lo: f64, hi: f64) -> Vec<GridMark> {
        log_grid_marks(GridInput {
            bounds: (lo, hi),
            base_step_size: 0.01,
        })
    }

    #[test]
    fn labels_are_the_values_not_fractional_exponents() {
        assert_eq!(value_label(0.0), "1");
        assert_eq!(value_label(-1.0), "0.1");
        assert_eq!(value_label(2f64.log10() - 1.0), "0.2");
        assert_eq!(value_label(5f64.log10() - 3.0), "0.005");
        assert_eq!(value_label(2f64.log10() + 1.0), "20");
        assert_eq!(value_label(-6.0), "1e-6");
        assert_eq!(value_label(5f64.log10() + 8.0), "5e8");
        // log10 rounding just below a decade still reads as that decade.
        assert_eq!(value_label(-0.999_999_999_999), "0.1");
    }

    #[test]
    fn a_narrow_range_gets_one_two_five_and_minor_marks() {
        let m = marks(-0.6, 0.05);
        let labelled: Vec<String> = m
            .iter()
            .map(|&g| log_tick_label(g, &(-3.0..=1.0)))
            .filter(|s| !s.is_empty())
            .collect();
        assert_eq!(labelled, ["0.5", "1"]);
        // Zoomed in to under 1.2 decades, every line is labelled.
        let all: Vec<String> = m
            .iter()
            .map(|&g| log_tick_label(g, &(-0.6..=0.05)))
            .collect();
        assert_eq!(all, ["0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1"]);
        // 0.3, 0.4, 0.6, 0.7, 0.8, 0.9 are faint unlabelled lines.
        assert_eq!(m.len(), 8);
        assert!(m.iter().all(|g| (-0.6..=0.05).contains(&g.value)));
    }

    #[test]
    fn a_wide_range_keeps_only_decades() {
        let m = marks(-16.0, 1.0);
        assert_eq!(m.len(), 18);
        assert!(
            m.iter()
                .all(|g| g.step_size >= DECADE && g.value.fract() == 0.0)
        );
        // Every 5th and 10th decade is stronger, so some labels survive egui's crowding.
        let step = |v: f64| m.iter().find(|g| g.value == v).map(|g| g.step_size);
        assert_eq!(step(-10.0), Some(10.0));
        assert_eq!(step(-15.0), Some(5.0));
        assert_eq!(step(-4.0), Some(2.0));
        assert_eq!(step(-3.0), Some(DECADE));
    }

    #[test]
    fn empty_or_invalid_bounds_give_no_marks() {
        assert!(marks(1.0, 1.0).is_empty());
        assert!(marks(f64::NAN, 1.0).is_empty());
    }
}
