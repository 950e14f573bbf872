//! Error and efficiency of a rendered image against the exact [`Reference`].
//!
//! Over the reference's covered pixels `S` (`|S| = M`), with estimate `Ê_p` (the
//! accumulator's [`Accumulator::mean`]) and exact value `E_p`:
//!
//! * `RMSE = √( (1/M) Σ_{p∈S} (Ê_p − E_p)² )`, in irradiance units;
//! * `relMSE = (1/M) Σ_{p∈S} (Ê_p − E_p)² / (E_p² + ε)` with `ε = REL_MSE_EPSILON · Ē²`,
//!   `Ē = (1/M) Σ_{p∈S} E_p`. The usual rendering definition takes an absolute `ε = 10^-2`
//!   for display-range values; here irradiance spans any range (`extreme-range` reaches
//!   `10^29`), so `ε` is relative to the image's mean: the metric is then invariant under a
//!   global scaling of the powers, and pixels darker than `1%` of the mean cannot dominate it.
//!
//! Over every pixel of the accumulator (`P` pixels, `n` samples each):
//!
//! * variance per sample `V = (1/P) Σ_p s_p²`, with `s_p²` the unbiased sample variance of one
//!   sample at pixel `p` ([`Accumulator::variance_per_sample`]): `E[(Ê_p − E_p)²] = σ_p²/n`;
//! * time per sample `T = seconds / (n·P)`;
//! * efficiency `1/(V̂·T)` with `V̂ = V/Φ_total²` the variance per sample of the normalized
//!   estimate (irradiance per unit of total power): the inverse of the error-variance × time
//!   product, so a scheme twice as efficient reaches a given MSE in half the time. Measured
//!   in units of the scene's total power, it does not change when every power is scaled,
//!   and its ratios between schemes are those of `1/(V·T)`. `V̂` still carries the
//!   geometry (`1/z⁴` under a light at height `z`): a light `10^-100` above a pixel makes it
//!   `≈ 10^400`, so `V̂` and the efficiency are [`Scaled`] ([`efficiency_of`]).
//!
//! # Scale
//! Every figure is computed from the sums in the accumulation unit `U = Φ_total·2^s`
//! ([`Accumulator::unit`], [`Reference::in_unit`]) and scaled out at the end through
//! [`Scaled`]: scaling every power by `2^k` multiplies the RMSE by exactly `2^k` and `V` by
//! `2^(2k)`, and leaves relMSE, `V̂` and the efficiency unchanged bit for bit (while nothing
//! is subnormal). A `V` beyond `f64` is reported as `inf` with its finite
//! [`Efficiency::variance_log10`], never as 0 or NaN; `V̂` and the efficiency keep their
//! value whatever it is, with their `log10` beside them.
//!
//! The RMSE and relMSE sums take every value in units of `2^k ≈ Ē` (an exact power of two,
//! `Ē` the reference's mean in the accumulation unit): the terms have the bits of the
//! definition, and neither `(Ê_p − E_p)²` nor `E_p² + ε` underflows where the whole image is
//! far below the unit (`Ē ≈ 10^-300`), which would otherwise leave `0/0` terms.

use super::Accumulator;
use super::reference::Reference;
use crate::Scaled;

/// The `ε` factor of relMSE: `ε = REL_MSE_EPSILON · Ē²` (see the module docs).
pub const REL_MSE_EPSILON: f64 = 1e-4;

/// A variance at most this fraction of a reference variance (the uniform scheme's, or the
/// largest measured) is the rounding of zero: [`is_zero_variance`].
pub const ZERO_VARIANCE_RTOL: f64 = 1e-12;

/// Whether `variance` is a zero variance up to rounding next to `reference`:
/// `0 < reference` and `variance ≤` [`ZERO_VARIANCE_RTOL`]` · reference`.
///
/// The exact spatial pick on few lights (`P(i | x) ∝ p_i·G_i(x)`) has variance 0, but its
/// estimates differ from the `f64` reference by a few ulps: a relative error near `10^-16`,
/// so a variance (and an MSE) near `10^-32` of the squared signal. A real estimator's
/// variance is many orders of magnitude above `10^-12` of the uniform scheme's even when it
/// is a million times better (the `dominant` preset), so the two cannot be confused. The
/// same test applies to mean squared errors at equal samples per pixel
/// (`MSE = V/spp` for an unbiased estimator).
pub fn is_zero_variance(variance: f64, reference: f64) -> bool {
    reference > 0.0 && variance <= ZERO_VARIANCE_RTOL * reference
}

/// Whether `variance` is a zero variance up to rounding next to `reference`, at any
/// magnitude: [`is_zero_variance`] for [`Scaled`] figures (a `V̂` of `10^400` is not the
/// rounding of another `10^400`).
pub fn is_zero_variance_scaled(variance: Scaled, reference: Scaled) -> bool {
    reference > Scaled::ZERO && variance <= reference.mul_f64(ZERO_VARIANCE_RTOL)
}

/// The efficiency `1/(V̂·T)` of a normalized variance per sample `V̂` and a time per sample
/// `T` (seconds), whatever its magnitude: `+inf` when `V̂·T = 0` (a zero-variance
/// estimator). The one formula behind every efficiency the crate and the app report.
pub fn efficiency_of(normalized_variance: Scaled, seconds_per_sample: f64) -> Scaled {
    normalized_variance.mul_f64(seconds_per_sample).recip()
}

/// RMSE and relMSE of an image against a reference (see the module docs for the formulas).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ErrorMetrics {
    /// `√((1/M) Σ (Ê_p − E_p)²)` over the reference's pixels (`inf` beyond `f64`).
    pub rmse: f64,
    /// `log10` of the RMSE, finite whatever its magnitude (`-inf` for 0).
    pub rmse_log10: f64,
    /// `(1/M) Σ (Ê_p − E_p)²/(E_p² + ε)` over the reference's pixels.
    pub rel_mse: f64,
    /// `M`, the number of pixels compared.
    pub pixels: usize,
}

/// Variance, time and efficiency of a rendering (see the module docs for the formulas).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Efficiency {
    /// `V = (1/P) Σ_p s_p²`, the mean variance of one sample, in irradiance² units (`inf`
    /// beyond `f64`).
    pub variance_per_sample: f64,
    /// `log10 V`, finite whatever its magnitude (`-inf` for 0).
    pub variance_log10: f64,
    /// `V̂ = V/Φ_total²`, the variance of one sample of irradiance per unit of total power:
    /// unchanged when the powers are scaled (JSON: `null` beyond `f64`).
    pub normalized_variance: Scaled,
    /// `log10 V̂`, finite whatever its magnitude (`-inf` for 0).
    pub normalized_variance_log10: f64,
    /// `T = seconds/(n·P)`, seconds per pixel sample.
    pub seconds_per_sample: f64,
    /// `1/(V̂·T)` ([`efficiency_of`]; `+inf` when `V = 0`, a zero-variance estimator; JSON:
    /// `null` beyond `f64`).
    pub efficiency: Scaled,
    /// `log10` of the efficiency, finite whatever its magnitude (`+inf` for an infinite one).
    pub efficiency_log10: f64,
}

/// [`ErrorMetrics`] of `acc` against `reference` over the reference's pixels.
///
/// # Panics
/// If the accumulator and the reference have different image sizes.
pub fn error_metrics(acc: &Accumulator, reference: &Reference) -> ErrorMetrics {
    assert_same_size(acc, reference);
    let m = reference.pixels().len();
    if m == 0 {
        return ErrorMetrics {
            rmse: 0.0,
            rmse_log10: f64::NEG_INFINITY,
            rel_mse: 0.0,
            pixels: 0,
        };
    }
    let exact_in_unit = reference.in_unit();
    let mean_in_unit = exact_in_unit.iter().sum::<f64>() / m as f64;
    // Values in units of 2^k ≈ Ē (module docs): exact, and the mean lands in [1, 2).
    let k = Scaled::from_f64(mean_in_unit).exponent().clamp(-1022, 1022);
    let to_mean = Scaled::pow2(-k).to_f64();
    // Both in the reference's unit (1 for a renderer of the same scene), then in 2^k.
    let to_reference_unit = (acc.unit() / reference.unit()).to_f64() * to_mean;
    let mean = mean_in_unit * to_mean;
    let eps = REL_MSE_EPSILON * mean * mean;
    let (mut se, mut rel) = (0.0, 0.0);
    for (&p, &exact) in reference.pixels().iter().zip(exact_in_unit) {
        let exact = exact * to_mean;
        let d = acc.mean_in_unit(p as usize) * to_reference_unit - exact;
        se += d * d;
        let denominator = exact * exact + eps;
        // At least `ε ≥ 10^-4` unless the whole reference is 0 (every light below the
        // plane), where the estimates are exactly 0 too: the pixel adds no relative error.
        if denominator > 0.0 {
            rel += d * d / denominator;
        }
    }
    let rmse = (reference.unit() * Scaled::pow2(k)).mul_f64((se / m as f64).sqrt());
    ErrorMetrics {
        rmse: rmse.to_f64(),
        rmse_log10: rmse.log10(),
        rel_mse: rel / m as f64,
        pixels: m,
    }
}

/// `RMSE` of `acc` against `reference` ([`error_metrics`]`.rmse`).
///
/// # Panics
/// If the accumulator and the reference have different image sizes.
pub fn rmse(acc: &Accumulator, reference: &Reference) -> f64 {
    error_metrics(acc, reference).rmse
}

/// `V = (1/P) Σ_p s_p²`, the mean over all pixels of [`Accumulator::variance_per_sample`]
/// (0 before two samples; `inf` beyond `f64`: [`mean_variance_scaled`] keeps it).
pub fn mean_variance_per_sample(acc: &Accumulator) -> f64 {
    mean_variance_scaled(acc).to_f64()
}

/// `V` whatever its magnitude: the mean in the squared unit, times `U²`.
pub fn mean_variance_scaled(acc: &Accumulator) -> Scaled {
    acc.unit().square().mul_f64(mean_variance_in_unit(acc))
}

/// `V̂ = V/Φ_total²`, the variance per sample of irradiance per unit of total power: the
/// mean in the squared unit times `2^(2s)`; unchanged when the powers are scaled, kept
/// whatever its magnitude (`≈ 10^400` under a light `10^-100` above a pixel).
pub fn normalized_variance_per_sample(acc: &Accumulator) -> Scaled {
    Scaled::new(mean_variance_in_unit(acc), 2 * acc.shift)
}

/// `(1/P) Σ_p s_p²` in the accumulator's squared unit.
fn mean_variance_in_unit(acc: &Accumulator) -> f64 {
    let p = acc.sum.len();
    if p == 0 {
        return 0.0;
    }
    (0..p).map(|i| acc.variance_in_unit(i)).sum::<f64>() / p as f64
}

/// [`Efficiency`] of `acc`, rendered in `seconds` of wall time.
pub fn efficiency(acc: &Accumulator, seconds: f64) -> Efficiency {
    let samples = f64::from(acc.samples_per_pixel) * acc.sum.len() as f64;
    let variance = mean_variance_scaled(acc);
    let normalized = normalized_variance_per_sample(acc);
    let per_sample = if samples > 0.0 {
        seconds / samples
    } else {
        0.0
    };
    let efficiency = efficiency_of(normalized, per_sample);
    Efficiency {
        variance_per_sample: variance.to_f64(),
        variance_log10: variance.log10(),
        normalized_variance: normalized,
        normalized_variance_log10: normalized.log10(),
        seconds_per_sample: per_sample,
        efficiency,
        efficiency_log10: efficiency.log10(),
    }
}

fn assert_same_size(acc: &Accumulator, reference: &Reference) {
    assert!(
        acc.width == reference.width() && acc.height == reference.height(),
        "accumulator {}×{} vs reference {}×{}",
        acc.width,
        acc.height,
        reference.width(),
        reference.height()
    );
}
