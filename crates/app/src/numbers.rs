//! Number labels shared by the app's panels and the CLI's text output: exact fractions where
//! the core finds one ([`lightpick_core::fraction`]), else short decimals.

/// `value` as an exact fraction when possible, else with 4 significant digits.
pub fn show(value: f64, den: Option<u64>) -> String {
    lightpick_core::fraction::format_fraction(value, den).unwrap_or_else(|| short(value))
}

/// A number with about 4 significant digits, in scientific notation when far from 1.
pub fn short(value: f64) -> String {
    if value == 0.0 {
        "0".to_owned()
    } else if !value.is_finite() {
        format!("{value}")
    } else if (1e-3..1e5).contains(&value.abs()) {
        let digits = (3 - value.abs().log10().floor() as i32).clamp(0, 6) as usize;
        format!("{value:.digits$}")
    } else {
        format!("{value:.3e}")
    }
}

/// `value` with three significant digits at any magnitude: `1.23`, `0.0123`, `123`,
/// `1.23e-5`, `4.56e7` (never `0.0000` for a small positive value).
pub fn three_significant(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let magnitude = value.abs().log10().floor();
    if (-3.0..5.0).contains(&magnitude) {
        let decimals = (2.0 - magnitude).max(0.0) as usize;
        format!("{value:.decimals$}")
    } else {
        format!("{value:.2e}")
    }
}

/// `count` things in words: "1 group", "3 groups" (`one` and `many`, the two forms).
pub fn count(count: usize, one: &str, many: &str) -> String {
    if count == 1 {
        format!("1 {one}")
    } else {
        format!("{count} {many}")
    }
}

/// How `value` compares with `baseline`, in the words a student reads: "6.91× higher" when
/// `value` is larger, "24.6× lower" when it is smaller (the factor is always `≥ 1`, never
/// "0.145× lower"), "the same" when the two agree to three significant digits. `more` and
/// `less` are the direction words ("higher"/"lower", "more"/"fewer"). "–" when either is not
/// a positive finite number.
pub fn compare(value: f64, baseline: f64, more: &str, less: &str) -> String {
    if !(value.is_finite() && baseline.is_finite() && value > 0.0 && baseline > 0.0) {
        return "–".to_owned();
    }
    let (factor, word) = if value >= baseline {
        (value / baseline, more)
    } else {
        (baseline / value, less)
    };
    // A factor that shows as 1.00 is no difference the class could read.
    if !factor.is_finite() {
        format!("∞× {word}")
    } else if three_significant(factor) == "1.00" {
        "the same".to_owned()
    } else {
        format!("{}× {word}", three_significant(factor))
    }
}

/// Figures near 1 (ratios such as `1.000000001` and `1.00000018`) written side by side with
/// the same number of decimals, enough to show three significant digits of the smaller
/// departure from 1 (at least 3 decimals, at most 15). A value that is exactly 1 needs none
/// of its own.
pub fn near_one<const K: usize>(values: [f64; K]) -> [String; K] {
    let decimals = values
        .iter()
        .filter(|v| v.is_finite() && **v != 1.0)
        .map(|v| (2.0 - (v - 1.0).abs().log10().floor()) as i32)
        .max()
        .unwrap_or(3)
        .clamp(3, 15) as usize;
    values.map(|v| format!("{v:.decimals$}"))
}

/// [`short`] of a figure that may lie beyond `f64` (a variance of powers near `10^200`):
/// the plain form where it fits, else `m.mmme±X` from its `log10`.
pub fn short_scaled(value: lightpick_core::Scaled) -> String {
    value.as_f64().map_or_else(|| format!("{value:.3}"), short)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_fractions() {
        let den = lightpick_core::fraction::common_denominator(&[2.0, 5.0, 20.0], 1000.0);
        assert_eq!(den, Some(27));
        assert_eq!(show(6.0 / 27.0, den), "6/27");
        assert_eq!(show(15.0 / 27.0, den), "15/27");
        assert_eq!(show(1.0, den), "1");
        assert_eq!(short(0.5), "0.5000");
        assert_eq!(short(1e-9), "1.000e-9");
        assert_eq!(three_significant(1.234_5e-5), "1.23e-5");
        assert_eq!(three_significant(0.001_14), "0.00114");
        assert_eq!(three_significant(1.0), "1.00");
        assert_eq!(three_significant(123.4), "123");
        assert_eq!(three_significant(45_600_000.0), "4.56e7");
        let huge = lightpick_core::Scaled::from_f64(3e200).square();
        assert_eq!(short_scaled(huge), "9.000e400");
        assert_eq!(short_scaled(lightpick_core::Scaled::from_f64(2.5)), "2.500");
    }

    #[test]
    fn ratios_near_one_share_their_digits() {
        let [a, b] = near_one([1.000_000_001, 1.000_000_18]);
        assert_eq!(a, "1.00000000100");
        assert_eq!(b, "1.00000018000");
        assert_eq!(a.len(), b.len());
        assert_eq!(near_one([1.0, 1.0]), ["1.000", "1.000"]);
        assert_eq!(near_one([1.5]), ["1.500"]);
    }

    #[test]
    fn comparisons_read_with_a_factor_of_at_least_one() {
        // The inspector on the worked example: power's variance 20.19 against uniform's 2.922.
        assert_eq!(compare(20.19, 2.922, "higher", "lower"), "6.91× higher");
        assert_eq!(compare(2.922, 20.19, "higher", "lower"), "6.91× lower");
        assert_eq!(compare(14.85, 366.0, "more", "fewer"), "24.6× fewer");
        assert_eq!(compare(5.0, 5.0004, "higher", "lower"), "the same");
        assert_eq!(compare(1.0, 0.0, "higher", "lower"), "–");
        assert_eq!(compare(f64::NAN, 1.0, "higher", "lower"), "–");
        assert_eq!(compare(1e300, 1e-300, "higher", "lower"), "∞× higher");
    }
}
