//! Exact fractions for the table: the seed example reads `6/27`, not `0.2222`.
//!
//! When every power is an integer and the total `S` is small, every pmf value `Φ_i/S` and
//! every threshold (`N·Φ_i/S` after donations of whole `1`s) is a multiple of `1/S`; the
//! table then shows `m/S` unreduced, the way the seed example writes it.

/// The common denominator `S = Σ Φ_i` when every power is an integer and `S ≤ 2^40`.
pub fn integer_total(powers: &[f64]) -> Option<u64> {
    const LIMIT: f64 = 1_099_511_627_776.0; // 2^40
    if powers.len() > 100_000 || powers.iter().any(|p| p.fract() != 0.0 || *p > LIMIT) {
        return None;
    }
    let total: f64 = powers.iter().sum();
    (total > 0.0 && total <= LIMIT).then_some(total as u64)
}

/// `value` as `m/den` when that is exact in `f64` (`"1"` and `"0"` for the ends).
pub fn as_fraction(value: f64, den: Option<u64>) -> Option<String> {
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

/// `value` as an exact fraction when possible, else with 4 significant digits.
pub fn show(value: f64, den: Option<u64>) -> String {
    as_fraction(value, den).unwrap_or_else(|| short(value))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_fractions() {
        let den = integer_total(&[2.0, 5.0, 20.0]);
        assert_eq!(den, Some(27));
        assert_eq!(show(6.0 / 27.0, den), "6/27");
        assert_eq!(show(15.0 / 27.0, den), "15/27");
        assert_eq!(show(1.0, den), "1");
        assert_eq!(integer_total(&[0.5]), None);
        assert_eq!(short(0.5), "0.5000");
        assert_eq!(short(1e-9), "1.000e-9");
    }
}
