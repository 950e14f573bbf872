//! Welford's running mean and variance, mergeable across threads (Chan et al. 1979).

/// Running count `n`, mean `x̄` and sum of squared deviations `M2 = Σ (x − x̄)²`.
///
/// Update: `δ = x − x̄; x̄ += δ/n; M2 += δ·(x − x̄)`. Numerically stable where the textbook
/// `Σx² − n·x̄²` cancels catastrophically.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Welford {
    count: u64,
    mean: f64,
    m2: f64,
}

impl Welford {
    /// An empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one observation.
    #[inline]
    pub fn push(&mut self, x: f64) {
        self.count += 1;
        let delta = x - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (x - self.mean);
    }

    /// Combines two accumulators (Chan's parallel formula):
    /// `M2 = M2_a + M2_b + δ²·n_a·n_b/n` with `δ = x̄_b − x̄_a`.
    #[must_use]
    pub fn merge(&self, other: &Welford) -> Welford {
        if self.count == 0 {
            return *other;
        }
        if other.count == 0 {
            return *self;
        }
        let count = self.count + other.count;
        let (na, nb, n) = (self.count as f64, other.count as f64, count as f64);
        let delta = other.mean - self.mean;
        Welford {
            count,
            mean: self.mean + delta * nb / n,
            m2: self.m2 + other.m2 + delta * delta * na * nb / n,
        }
    }

    /// Number of observations.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The sample mean `x̄` (0 when empty).
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// The unbiased sample variance `M2 / (n − 1)` (0 for fewer than two observations).
    pub fn variance(&self) -> f64 {
        if self.count < 2 {
            0.0
        } else {
            self.m2 / (self.count - 1) as f64
        }
    }

    /// The standard error of the mean, `sqrt(variance / n)`.
    pub fn std_error(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            (self.variance() / self.count as f64).sqrt()
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
}
