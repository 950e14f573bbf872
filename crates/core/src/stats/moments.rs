//! Exact mean and variance of the one-sample estimator `f(I)/p(I)`.

use crate::scaled::Scaled;

/// The analytic moments of `F̂ = f(I)/p(I)` for a light `I` drawn with pmf `p`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct EstimatorMoments {
    /// The exact total `F = Σ_i f_i` over every light.
    pub exact: f64,
    /// `E[F̂] = Σ_{p_i > 0} f_i`: equals `exact` unless a light with `f_i ≠ 0` has `p_i = 0`.
    pub mean: f64,
    /// `Var[F̂] = Σ_{p_i > 0} f_i²/p_i − E[F̂]²`, the variance of one sample (`inf` where
    /// it exceeds `f64`: [`EstimatorMoments::variance_scaled`] keeps it).
    pub variance: f64,
    /// The same variance whatever its magnitude.
    #[serde(skip)]
    pub variance_scaled: Scaled,
}

impl EstimatorMoments {
    /// `E[F̂] − F`: nonzero only when the scheme never picks a contributing light.
    pub fn bias(&self) -> f64 {
        self.mean - self.exact
    }
}

/// Computes [`EstimatorMoments`] for contributions `f` and pick probabilities `p(i)`.
///
/// The sums run in the unit `2^u` of [`contribution_unit`] (`f_i·2^-u`, exact), so the
/// second moment `Σ f_i²/p_i` neither overflows for contributions near `10^200` nor vanishes
/// near `10^-200`; scaling every `f_i` by `2^k` scales the means by `2^k` and the variance by
/// `2^(2k)` bit for bit (while nothing is subnormal).
///
/// The worked example (`f = 1, 2, 15`) gives variance 366 under uniform picking and 14.85
/// under power picking (`p = 2/27, 5/27, 20/27`), both with mean 18.
pub fn analytic_moments(f: &[f64], p: impl Fn(usize) -> f64) -> EstimatorMoments {
    let unit = contribution_unit(f);
    let mut exact = 0.0;
    let mut mean = 0.0;
    let mut second = 0.0;
    for (i, &fi) in f.iter().enumerate() {
        let fi = Scaled::new(fi, -unit).to_f64();
        exact += fi;
        let pi = p(i);
        if pi > 0.0 {
            mean += fi;
            second += fi * fi / pi;
        }
    }
    // Clamp the rounding residue of a zero-variance scheme (f ∝ p) at zero.
    let variance_scaled = Scaled::new((second - mean * mean).max(0.0), 2 * unit);
    EstimatorMoments {
        exact: Scaled::new(exact, unit).to_f64(),
        mean: Scaled::new(mean, unit).to_f64(),
        variance: variance_scaled.to_f64(),
        variance_scaled,
    }
}

/// The unit `2^u` estimates of contributions `f` are accumulated in: `u` the binary exponent
/// of the largest `|f_i|` (0 when every `f_i` is 0 or none is finite), so scaled
/// contributions lie in `[0, 2)` and one sample `f_i/p_i` stays far from overflow.
pub fn contribution_unit(f: &[f64]) -> i32 {
    let max = f
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, &x| m.max(x.abs()));
    if max > 0.0 {
        Scaled::from_f64(max).exponent()
    } else {
        0
    }
}
