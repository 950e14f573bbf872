//! Figures that may lie beyond `f64`: `m · 2^e` with an `f64` significand and an `i32`
//! binary exponent.
//!
//! Every estimator and metric of the crate accumulates in a unit that is an exact power of
//! two times the scene's scale (see [`crate::render::Accumulator`] and
//! [`crate::point_estimate`]), so its sums stay near 1 whatever the powers. What leaves that
//! unit — a mean, an RMSE, a variance — is a [`Scaled`]: scaling every power by `2^k` adds
//! `k` (or `2k` for a variance) to its exponent and leaves its significand's bits alone.
//! [`Scaled::to_f64`] gives the plain number (`±inf` past `f64::MAX`, `0` below the
//! subnormals), [`Scaled::log10`] a finite figure for any nonzero value.

use std::cmp::Ordering;
use std::fmt;

/// `significand · 2^exponent`, with `1 ≤ |significand| < 2` (or a zero significand and
/// exponent 0), so two values with the same figure have the same bits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scaled {
    significand: f64,
    exponent: i32,
}

impl Scaled {
    /// Zero.
    pub const ZERO: Scaled = Scaled {
        significand: 0.0,
        exponent: 0,
    };

    /// `significand · 2^exponent`, normalized. A non-finite `significand` is kept as it is
    /// (exponent 0): [`Scaled::to_f64`] returns it, [`Scaled::is_finite`] is false.
    pub fn new(significand: f64, exponent: i32) -> Self {
        if significand == 0.0 || !significand.is_finite() {
            return Scaled {
                significand: if significand == 0.0 { 0.0 } else { significand },
                exponent: 0,
            };
        }
        let (m, e) = frexp(significand);
        Scaled {
            significand: m,
            exponent: exponent.saturating_add(e),
        }
    }

    /// The exact value of `x`.
    pub fn from_f64(x: f64) -> Self {
        Self::new(x, 0)
    }

    /// `2^exponent`.
    pub fn pow2(exponent: i32) -> Self {
        Scaled {
            significand: 1.0,
            exponent,
        }
    }

    /// The significand `m` (`1 ≤ |m| < 2`, or 0).
    pub fn significand(self) -> f64 {
        self.significand
    }

    /// The binary exponent `e`.
    pub fn exponent(self) -> i32 {
        self.exponent
    }

    /// Whether the value is a real number (it may still lie beyond `f64`).
    pub fn is_finite(self) -> bool {
        self.significand.is_finite()
    }

    /// Whether [`Scaled::to_f64`] is exact up to the rounding of a subnormal: a finite value
    /// not beyond `f64::MAX`.
    pub fn fits_f64(self) -> bool {
        self.to_f64().is_finite()
    }

    /// The plain value where `f64` holds it: finite, and nonzero unless the value is 0
    /// (`None` beyond `f64::MAX` or below the least subnormal): whether to print the number
    /// itself or its `m.mmme±X` form.
    pub fn as_f64(self) -> Option<f64> {
        let x = self.to_f64();
        (x.is_finite() && (x != 0.0 || self.significand == 0.0)).then_some(x)
    }

    /// `m · 2^e` as an `f64`: exact in the normal range, rounded among the subnormals,
    /// `±inf` beyond `f64::MAX` and `±0` below the least subnormal.
    pub fn to_f64(self) -> f64 {
        ldexp(self.significand, self.exponent)
    }

    /// `log10 |x|`: `log10 |m| + e · log10 2`, finite for every finite nonzero value
    /// (`-inf` for 0, `NaN` for NaN). Its absolute error is below `10^-12` for
    /// `|e| < 10^4`.
    pub fn log10(self) -> f64 {
        if self.significand == 0.0 {
            return f64::NEG_INFINITY;
        }
        self.significand.abs().log10() + f64::from(self.exponent) * std::f64::consts::LOG10_2
    }

    /// The positive value whose [`Scaled::log10`] is `log10` (relative error near
    /// `|log10|·10^-16`): how a figure reported only by its `log10` is shown again.
    pub fn from_log10(log10: f64) -> Self {
        if log10 == f64::NEG_INFINITY {
            return Scaled::ZERO;
        }
        let log2 = log10 / std::f64::consts::LOG10_2;
        if !log2.is_finite() || log2.abs() > 1e9 {
            return Scaled::new(f64::INFINITY, 0);
        }
        let exponent = log2.floor();
        Scaled::new((log2 - exponent).exp2(), exponent as i32)
    }

    /// `x · f` for a plain `f64` factor.
    #[must_use]
    pub fn mul_f64(self, factor: f64) -> Scaled {
        self * Scaled::from_f64(factor)
    }

    /// `x²`.
    #[must_use]
    pub fn square(self) -> Scaled {
        self * self
    }

    /// `√x` for `x ≥ 0` (`NaN` significand for `x < 0`): an even exponent halves exactly.
    #[must_use]
    pub fn sqrt(self) -> Scaled {
        if self.exponent % 2 == 0 {
            Scaled::new(self.significand.sqrt(), self.exponent / 2)
        } else {
            Scaled::new(
                (2.0 * self.significand).sqrt(),
                (self.exponent - 1).div_euclid(2),
            )
        }
    }

    /// `1/x`.
    #[must_use]
    pub fn recip(self) -> Scaled {
        Scaled::from_f64(1.0) / self
    }
}

impl PartialOrd for Scaled {
    /// The order of the values (`None` when one is NaN): the sign first, then for two
    /// finite nonzero values of the same sign the exponent and the significand, which
    /// normalization makes a total order; an infinite value lies beyond every finite one.
    fn partial_cmp(&self, other: &Scaled) -> Option<Ordering> {
        let (a, b) = (self.significand, other.significand);
        if a.is_nan() || b.is_nan() {
            return None;
        }
        let sign = |m: f64| {
            if m == 0.0 {
                0
            } else if m > 0.0 {
                1
            } else {
                -1
            }
        };
        let (sa, sb) = (sign(a), sign(b));
        if sa != sb || sa == 0 {
            return Some(sa.cmp(&sb));
        }
        let magnitude = if a.is_infinite() || b.is_infinite() {
            a.abs().partial_cmp(&b.abs())?
        } else {
            self.exponent
                .cmp(&other.exponent)
                .then(a.abs().partial_cmp(&b.abs())?)
        };
        Some(if sa > 0 {
            magnitude
        } else {
            magnitude.reverse()
        })
    }
}

impl std::ops::Mul for Scaled {
    type Output = Scaled;

    /// `x · y`: the significands multiply in `f64` (one rounding), the exponents add.
    fn mul(self, other: Scaled) -> Scaled {
        Scaled::new(
            self.significand * other.significand,
            self.exponent.saturating_add(other.exponent),
        )
    }
}

impl std::ops::Div for Scaled {
    type Output = Scaled;

    /// `x / y` (`±inf` significand for `y = 0`, `x ≠ 0`).
    fn div(self, other: Scaled) -> Scaled {
        Scaled::new(
            self.significand / other.significand,
            self.exponent.saturating_sub(other.exponent),
        )
    }
}

impl Default for Scaled {
    /// Zero.
    fn default() -> Self {
        Scaled::ZERO
    }
}

impl fmt::Display for Scaled {
    /// The plain number where it fits `f64` (`{:e}` with the given precision, or the
    /// default), else `m.mme±XXX` computed from [`Scaled::log10`], so `4e400` prints as
    /// `4.00e400` rather than `inf`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.to_f64();
        if self.as_f64().is_some() || !self.is_finite() {
            return match f.precision() {
                Some(p) => write!(f, "{x:.p$e}"),
                None => write!(f, "{x:e}"),
            };
        }
        let log = self.log10();
        let mut decade = log.floor();
        let mut mantissa = 10f64.powf(log - decade);
        let digits = f.precision().unwrap_or(2);
        let rounded = format!("{mantissa:.digits$}");
        if rounded.starts_with("10") {
            mantissa /= 10.0;
            decade += 1.0;
        }
        let sign = if self.significand < 0.0 { "-" } else { "" };
        write!(f, "{sign}{mantissa:.digits$}e{decade}")
    }
}

impl serde::Serialize for Scaled {
    /// The `f64` value ([`Scaled::as_f64`]), or `null` where it does not fit: beyond
    /// `f64::MAX`, and below the least subnormal too, where the `f64` would read 0 (pair it
    /// with a `_log10` field).
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self.as_f64() {
            Some(x) => serializer.serialize_f64(x),
            None => serializer.serialize_none(),
        }
    }
}

/// `(m, e)` with `x = m · 2^e`, `1 ≤ |m| < 2`, for finite nonzero `x` (subnormals too).
fn frexp(x: f64) -> (f64, i32) {
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal: scale into the normal range first (exact).
        let (m, e) = frexp(x * TWO_POW_64);
        return (m, e - 64);
    }
    let m = f64::from_bits((bits & !(0x7ff << 52)) | (1023 << 52));
    (m, biased - 1023)
}

const TWO_POW_64: f64 = 18_446_744_073_709_551_616.0;

/// `m · 2^e` in `f64` for a normalized significand (`1 ≤ |m| < 2`): exact in the normal
/// range, one rounding among the subnormals (`m · 2^-1022` is exact, the second factor
/// rounds), `±inf` above and `±0` below.
fn ldexp(m: f64, e: i32) -> f64 {
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    match e {
        1024.. => m * f64::INFINITY,
        -1022..=1023 => m * pow2(e),
        -2044..=-1023 => m * pow2(-1022) * pow2(e + 1022),
        _ => m * 0.0,
    }
}

/// `2^k` for `k` in `[-1022, 1023]`.
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_every_kind_of_f64() {
        for x in [
            1.0,
            -3.5,
            27.0,
            1e-300,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            1.5e-310,
            -2.2e200,
        ] {
            let s = Scaled::from_f64(x);
            assert_eq!(s.to_f64(), x, "{x:e}");
            assert!((1.0..2.0).contains(&s.significand().abs()), "{x:e}");
        }
        assert_eq!(Scaled::from_f64(0.0), Scaled::ZERO);
    }

    #[test]
    fn squares_beyond_f64_keep_their_value() {
        let x = Scaled::from_f64(3e200);
        let sq = x.square();
        assert_eq!(sq.to_f64(), f64::INFINITY);
        assert!((sq.log10() - (9f64.log10() + 400.0)).abs() < 1e-12);
        assert_eq!(sq.sqrt().to_f64(), 3e200);
        let tiny = Scaled::from_f64(1e-200).square();
        assert_eq!(tiny.to_f64(), 0.0);
        assert!((tiny.log10() + 400.0).abs() < 1e-12);
        assert_eq!(
            format!("{:.2}", Scaled::from_f64(4e200).square()),
            "1.60e401"
        );
        assert_eq!(format!("{:.2}", Scaled::from_f64(2.5)), "2.50e0");
    }

    #[test]
    fn powers_of_two_shift_only_the_exponent() {
        let x = Scaled::from_f64(0.3);
        for k in [-1100, -1000, -3, 0, 5, 1000, 1100] {
            let y = x * Scaled::pow2(k);
            assert_eq!(y.significand().to_bits(), x.significand().to_bits());
            assert_eq!(y.exponent(), x.exponent() + k);
        }
        assert_eq!((Scaled::new(0.3, 1100) * Scaled::pow2(-1100)).to_f64(), 0.3);
        assert_eq!(Scaled::new(1.0, -1074).to_f64(), 5e-324);
        assert_eq!(Scaled::new(1.0, 1023).to_f64(), 2f64.powi(1023));
        assert_eq!(Scaled::new(1.0, 1024).to_f64(), f64::INFINITY);
    }

    #[test]
    fn json_gives_null_where_f64_cannot_hold_the_value() {
        let json = |x: Scaled| serde_json::to_string(&x).unwrap_or_default();
        assert_eq!(json(Scaled::from_f64(1.5)), "1.5");
        assert_eq!(json(Scaled::ZERO), "0.0");
        assert_eq!(json(Scaled::from_f64(1e200).square()), "null");
        // 10^-400 is not 0: null (with its log10 beside it), never 0.
        assert_eq!(json(Scaled::from_f64(1e-200).square()), "null");
        assert_eq!(json(Scaled::from_f64(f64::INFINITY)), "null");
    }

    #[test]
    fn orders_values_beyond_f64() {
        let huge = Scaled::from_f64(3e200).square();
        let tiny = Scaled::from_f64(1e-200).square();
        let inf = Scaled::from_f64(f64::INFINITY);
        let neg = |x: Scaled| x.mul_f64(-1.0);
        let ascending = [
            neg(inf),
            neg(huge),
            Scaled::from_f64(-1.0),
            neg(tiny),
            Scaled::ZERO,
            tiny,
            Scaled::from_f64(0.5),
            Scaled::from_f64(0.75),
            Scaled::from_f64(1.0),
            huge,
            huge * Scaled::from_f64(1.5),
            inf,
        ];
        for (i, a) in ascending.iter().enumerate() {
            for (j, b) in ascending.iter().enumerate() {
                assert_eq!(a.partial_cmp(b), Some(i.cmp(&j)), "{a:?} vs {b:?}");
            }
        }
        let nan = Scaled::from_f64(f64::NAN);
        assert_eq!(nan.partial_cmp(&Scaled::ZERO), None);
        assert_eq!(Scaled::ZERO.partial_cmp(&nan), None);
    }

    #[test]
    fn odd_exponents_take_exact_square_roots() {
        let x = Scaled::from_f64(8.0);
        assert_eq!(x.sqrt().to_f64(), 8f64.sqrt());
        assert_eq!(Scaled::new(1.0, -3).sqrt().to_f64(), 0.125f64.sqrt());
        assert_eq!(Scaled::from_f64(16.0).sqrt().to_f64(), 4.0);
    }
}
