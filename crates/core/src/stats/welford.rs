//! Welford's running mean and variance, mergeable across threads (Chan et al. 1979).

use crate::scaled::Scaled;

/// Running count `n`, mean `x̄` and sum of squared deviations `M2 = Σ (x − x̄)²`, kept in a
/// unit `2^u` chosen by the caller ([`Welford::in_unit`]).
///
/// Update: `δ = x − x̄; x̄ += δ/n; M2 += δ·(x − x̄)`. Numerically stable where the textbook
/// `Σx² − n·x̄²` cancels catastrophically.
///
/// **Scale.** Observations are stored as `x·2^-u`, an exact scaling, so `M2` (a sum of
/// squares) stays in range when `u` follows the data's magnitude (e.g. the binary exponent
/// of the largest contribution): observations `x·2^k` pushed in unit `u + k` leave the
/// state's bits unchanged, and the mean, standard error and variance come out multiplied by
/// exactly `2^k`, `2^k` and `2^(2k)` (while nothing is subnormal). [`Welford::variance`]
/// beyond `f64` is reported by [`Welford::variance_scaled`] (and its `log10`), never as
/// `inf − inf = NaN`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Welford {
    count: u64,
    mean: f64,
    m2: f64,
    unit: i32,
}

impl Welford {
    /// An empty accumulator in unit 1 (`u = 0`).
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty accumulator that stores observations in units of `2^unit_exponent`.
    pub fn in_unit(unit_exponent: i32) -> Self {
        Self {
            unit: unit_exponent,
            ..Self::default()
        }
    }

    /// The unit's binary exponent `u`.
    pub fn unit_exponent(&self) -> i32 {
        self.unit
    }

    /// Adds one observation `x` (in plain units; it is stored as `x·2^-u`).
    #[inline]
    pub fn push(&mut self, x: f64) {
        let in_unit = if self.unit == 0 {
            x
        } else {
            Scaled::new(x, -self.unit).to_f64()
        };
        self.push_in_unit(in_unit);
    }

    /// Adds one observation already expressed in the unit (`x·2^-u`): the way to push a value
    /// whose plain form would overflow.
    #[inline]
    pub fn push_in_unit(&mut self, x: f64) {
        self.count += 1;
        let delta = x - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (x - self.mean);
    }

    /// Combines two accumulators (Chan's parallel formula):
    /// `M2 = M2_a + M2_b + δ²·n_a·n_b/n` with `δ = x̄_b − x̄_a`. The result is in `self`'s
    /// unit (`other` is rescaled exactly when the units differ).
    #[must_use]
    pub fn merge(&self, other: &Welford) -> Welford {
        if other.count == 0 {
            return *self;
        }
        let other = other.rescaled(self.unit);
        if self.count == 0 {
            return other;
        }
        let count = self.count + other.count;
        let (na, nb, n) = (self.count as f64, other.count as f64, count as f64);
        let delta = other.mean - self.mean;
        Welford {
            count,
            mean: self.mean + delta * nb / n,
            m2: self.m2 + other.m2 + delta * delta * na * nb / n,
            unit: self.unit,
        }
    }

    /// The same accumulator in units of `2^unit_exponent` (exact scaling of the mean and
    /// `M2`, unless it leaves the `f64` range).
    fn rescaled(&self, unit_exponent: i32) -> Welford {
        if unit_exponent == self.unit {
            return *self;
        }
        let shift = self.unit - unit_exponent;
        Welford {
            count: self.count,
            mean: Scaled::new(self.mean, shift).to_f64(),
            m2: Scaled::new(self.m2, 2 * shift).to_f64(),
            unit: unit_exponent,
        }
    }

    /// Number of observations.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The sample mean `x̄` (0 when empty).
    pub fn mean(&self) -> f64 {
        self.mean_scaled().to_f64()
    }

    /// The sample mean `x̄` whatever its magnitude.
    pub fn mean_scaled(&self) -> Scaled {
        Scaled::new(self.mean, self.unit)
    }

    /// The sample mean in the unit, `x̄·2^-u`.
    pub fn mean_in_unit(&self) -> f64 {
        self.mean
    }

    /// The unbiased sample variance `M2 / (n − 1)` (0 for fewer than two observations);
    /// `inf` beyond `f64` ([`Welford::variance_scaled`] keeps the value).
    pub fn variance(&self) -> f64 {
        self.variance_scaled().to_f64()
    }

    /// The unbiased sample variance whatever its magnitude.
    pub fn variance_scaled(&self) -> Scaled {
        Scaled::new(self.variance_in_unit(), 2 * self.unit)
    }

    /// The unbiased sample variance in the squared unit, `M2·2^-2u / (n − 1)`.
    pub fn variance_in_unit(&self) -> f64 {
        if self.count < 2 {
            0.0
        } else {
            self.m2 / (self.count - 1) as f64
        }
    }

    /// The standard error of the mean, `sqrt(variance / n)`.
    pub fn std_error(&self) -> f64 {
        self.std_error_scaled().to_f64()
    }

    /// The standard error of the mean whatever its magnitude: `√(s²/n)` computed in the unit
    /// and scaled by `2^u`.
    pub fn std_error_scaled(&self) -> Scaled {
        if self.count == 0 {
            Scaled::ZERO
        } else {
            Scaled::new(
                (self.variance_in_unit() / self.count as f64).sqrt(),
                self.unit,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_two_pass_formulas() {
        let xs = [1.0, 2.0, 4.0, 8.0, 16.0];
        let mut w = Welford::new();
        for &x in &xs {
            w.push(x);
        }
        let mean = xs.iter().sum::<f64>() / 5.0;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 4.0;
        assert_eq!(w.count(), 5);
        assert!((w.mean() - mean).abs() < 1e-14);
        assert!((w.variance() - var).abs() < 1e-12);
    }

    #[test]
    fn merge_equals_sequential() {
        let xs: Vec<f64> = (0..100).map(|i| f64::from(i).sin() * 1e3 + 1e6).collect();
        let mut all = Welford::new();
        for &x in &xs {
            all.push(x);
        }
        let (mut a, mut b) = (Welford::new(), Welford::new());
        xs[..37].iter().for_each(|&x| a.push(x));
        xs[37..].iter().for_each(|&x| b.push(x));
        let merged = a.merge(&b);
        assert_eq!(merged.count(), all.count());
        assert!((merged.mean() - all.mean()).abs() < 1e-9);
        assert!((merged.variance() / all.variance() - 1.0).abs() < 1e-9);
        assert_eq!(Welford::new().merge(&a), a);
    }

    #[test]
    fn a_unit_keeps_huge_and_tiny_variances() {
        let xs = [1.0, 3.0, 2.0, 7.0];
        let mut plain = Welford::new();
        for &x in &xs {
            plain.push(x);
        }
        for k in [-1070, -600, -300, 300, 600, 1000] {
            let mut w = Welford::in_unit(k);
            for &x in &xs {
                w.push_in_unit(x);
            }
            assert_eq!(w.mean_in_unit(), plain.mean());
            assert_eq!(
                w.variance_scaled().significand(),
                plain.variance_scaled().significand()
            );
            assert_eq!(
                w.variance_scaled().exponent(),
                plain.variance_scaled().exponent() + 2 * k
            );
            let expected_log = plain.variance().log10() + 2.0 * f64::from(k) * 2f64.log10();
            assert!((w.variance_scaled().log10() - expected_log).abs() < 1e-10);
            assert!(!w.variance().is_nan());
        }
    }

    #[test]
    fn merging_across_units_rescales() {
        let mut a = Welford::in_unit(3);
        let mut b = Welford::in_unit(-2);
        let mut all = Welford::new();
        for x in [1.0, 2.0, 4.0] {
            a.push(x);
            all.push(x);
        }
        for x in [8.0, 16.0] {
            b.push(x);
            all.push(x);
        }
        let m = a.merge(&b);
        assert_eq!(m.unit_exponent(), 3);
        assert_eq!(m.count(), 5);
        assert!((m.mean() - all.mean()).abs() < 1e-12);
        assert!((m.variance() / all.variance() - 1.0).abs() < 1e-12);
    }
}
