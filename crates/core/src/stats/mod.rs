//! Measuring estimators and samplers: running moments (Welford), the exact moments of an
//! estimator, Pearson's chi-square test of picks, figures beyond `f64` ([`scaled`]), and the
//! per-pixel variance of one sample of a scheme ([`variance_map`]).

pub mod chi_square;
pub mod moments;
pub mod scaled;
pub mod variance_map;
pub mod welford;
