//! Exact fractions for display: the worked example writes thresholds as `6/27`, not `0.2222`.
//!
//! When every power `Φ_i` is a whole number, every pmf value `Φ_i/S` and every alias-table
//! threshold (`N·Φ_i/S` less whole donations of 1) is a multiple of `1/S`, `S = Σ Φ_i`. The
//! table, the diagram and the CLI then show `m/S` unreduced, as the worked example does.

/// The common denominator `S = Σ Φ_i` when every power is a whole number and `S` lies in
/// `[1, max_total]` (`max_total ≤ 2^40`, where `m/S` is still resolved by an `f64`).
pub fn common_denominator(powers: &[f64], max_total: f64) -> Option<u64> {
    let limit = max_total.min(1_099_511_627_776.0);
    if powers.iter().any(|p| p.fract() != 0.0 || *p > limit) {
        return None;
    }
    let total: f64 = powers.iter().sum();
    (1.0..=limit).contains(&total).then_some(total as u64)
}

/// `value` as `"m/den"` when `value·den` is within `10⁻⁶` of a whole number `m` (a table
/// built from whole powers lands within a few ulps of `m/den`, far inside that), `"0"` and
/// `"1"` for the ends; `None` when it is no such fraction.
pub fn format_fraction(value: f64, den: Option<u64>) -> Option<String> {
    if value == 0.0 || value == 1.0 {
        return Some(format!("{value}"));
    }
    let den = den?;
    let scaled = value * den as f64;
    let m = scaled.round();
    if (scaled - m).abs() > 1e-6 * m.abs().max(1.0) {
        return None;
    }
    let m = m as u64;
    Some(match m {
        0 => "0".to_owned(),
        _ if m == den => "1".to_owned(),
        _ => format!("{m}/{den}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_fractions() {
        let den = common_denominator(&[2.0, 5.0, 20.0], 1e12);
        assert_eq!(den, Some(27));
        assert_eq!(format_fraction(6.0 / 27.0, den).as_deref(), Some("6/27"));
        assert_eq!(
            format_fraction(1.0 - 6.0 / 27.0, den).as_deref(),
            Some("21/27")
        );
        assert_eq!(format_fraction(1.0, den).as_deref(), Some("1"));
        assert_eq!(format_fraction(0.3, den), None);
        assert_eq!(format_fraction(0.3, None), None);
    }

    #[test]
    fn denominators_need_whole_powers_within_the_limit() {
        assert_eq!(common_denominator(&[0.5, 1.0], 1e12), None);
        assert_eq!(common_denominator(&[600.0, 600.0], 1000.0), None);
        assert_eq!(common_denominator(&[0.0, 3.0], 1000.0), Some(3));
    }
}
