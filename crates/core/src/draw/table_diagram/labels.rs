//! The diagram's number labels: exact fractions of the total power when they stay short,
//! short decimals otherwise.

use crate::draw::axes;
use crate::powers::LightPowers;

/// The exact denominator for fraction labels: the total power, when every power is a whole
/// number and the total is at most 1000, so fractions stay short (the worked example's powers 2, 5, 20
/// give 27: labels read `6/27`, `15/27`, `60/27`). `None` otherwise: labels are decimals.
pub fn fraction_denominator(powers: &LightPowers) -> Option<u64> {
    crate::fraction::common_denominator(powers.as_slice(), 1000.0)
}

/// `v` as `k/denominator` when it is one (within rounding), `0` and `1` plainly, else a
/// short decimal.
pub(crate) fn fraction_label(v: f64, denominator: Option<u64>) -> String {
    if let Some(label) = crate::fraction::format_fraction(v, denominator) {
        return label;
    }
    if v >= 10.0 {
        format!("{v:.1}")
    } else if v >= 0.01 {
        format!("{v:.3}")
    } else {
        axes::format_sci(v, 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AliasTable, WorkedExample};

    #[test]
    fn seed_fractions() {
        let powers = WorkedExample::powers();
        let d = fraction_denominator(&powers);
        assert_eq!(d, Some(27));
        let table = AliasTable::build_exact(&powers);
        let labels: Vec<String> = table
            .thresholds()
            .iter()
            .map(|&t| fraction_label(t, d))
            .collect();
        assert_eq!(labels, ["6/27", "15/27", "1"]);
        let masses: Vec<String> = table
            .pmf_slice()
            .iter()
            .map(|&p| fraction_label(3.0 * p, d))
            .collect();
        assert_eq!(masses, ["6/27", "15/27", "60/27"]);
        assert_eq!(fraction_label(21.0 / 27.0, d), "21/27");
    }

    #[test]
    fn fractions_fall_back_to_decimals() {
        let powers = LightPowers::new(vec![0.5, 1.5]).expect("valid test input");
        assert_eq!(fraction_denominator(&powers), None);
        assert_eq!(fraction_label(0.5, None), "0.500");
        assert_eq!(fraction_label(1.0, None), "1");
        assert_eq!(fraction_label(0.1, Some(3)), "0.100");
    }
}
