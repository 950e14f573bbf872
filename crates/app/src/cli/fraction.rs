//! Exact fractions for display: the seed document writes thresholds as `6/27`, not 0.2222.

/// `num/den` with `den` the total power, when the powers are small integers so the fraction
/// is exact: returns `Some("6/27")` when `value · den` rounds to an integer `m` with
/// `m / den == value` in `f64`, `Some("1")` for exactly 1, `Some("0")` for 0.
pub(crate) fn as_fraction(value: f64, den: Option<u64>) -> Option<String> {
    if value == 1.0 {
        return Some("1".to_owned());
    }
    if value == 0.0 {
        return Some("0".to_owned());
    }
    let den = den?;
    let m = (value * den as f64).round();
    (m / den as f64 == value).then(|| format!("{}/{den}", m as u64))
}

/// The common denominator for exact display: the total power, when every power is an
/// integer and the total is at most `2^40` (so `m/T` is computed exactly enough to verify).
pub(crate) fn integer_total(powers: &[f64]) -> Option<u64> {
    const LIMIT: f64 = 1_099_511_627_776.0; // 2^40
    if powers.iter().any(|p| p.fract() != 0.0 || *p > LIMIT) {
        return None;
    }
    let total: f64 = powers.iter().sum();
    (total <= LIMIT && total > 0.0).then_some(total as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_fractions() {
        let den = integer_total(&[2.0, 5.0, 20.0]);
        assert_eq!(den, Some(27));
        assert_eq!(as_fraction(6.0 / 27.0, den).as_deref(), Some("6/27"));
        assert_eq!(as_fraction(1.0, den).as_deref(), Some("1"));
        assert_eq!(as_fraction(0.3, den), None);
        assert_eq!(integer_total(&[0.5, 1.0]), None);
    }
}
