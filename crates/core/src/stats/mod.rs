//! Measuring estimators and samplers: running moments (Welford), the exact moments of an
//! estimator, Pearson's chi-square test of picks, and figures beyond `f64` ([`scaled`]).

pub mod chi_square;
pub mod moments;
pub mod scaled;
pub mod welford;
