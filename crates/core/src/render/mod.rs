//! Progressive rendering of the receiver plane: one light sample per pixel sample.
//!
//! # The estimator contract (CPU and GPU)
//! Pixel `p` (row-major, `p = py·width + px`) takes its `k`-th sample (`k` counts from 0
//! across passes) from the stream `Rng::new(seed, (k << 32) | p)`, picks a light `i` with
//! [`crate::Sampler::pick_light`] (uniform and alias: the exact column pick, which draws
//! again from the same stream, in order, while Lemire's test rejects a draw; alias then
//! keeps on the next draw), and evaluates the *normalized* estimate
//!
//! * uniform: `N · p_i · G_i(x)` (that is `f/pdf = N·Φ_i·G_i` divided by `Φ_total`),
//! * power-proportional (alias, alias-one-random, cdf): `G_i(x)` (the power cancels:
//!   `f/pdf = Φ_i·G_i / (Φ_i/Φ_total) = Φ_total·G_i`),
//!
//! * spatial (contribution-aware, [`crate::spatial`]): the sample draws from the same stream
//!   through [`crate::spatial::SpatialSampler::sample`] at the pixel centre `x` (the exact
//!   pick: one draw; the light tree: one draw per level) and the estimate is
//!   `p_i·G_i(x) / P(i | x)` (the exact pick: `Σ_j p_j·G_j(x)` for every pick),
//!
//! where `p_i = Φ_i/Φ_total` and `G` is [`crate::scene::geometry_term`]. Sums of the
//! normalized estimate and of its square are accumulated per pixel; the image is
//! `Φ_total · sum / spp`. Factoring `Φ_total` out keeps every GPU quantity within `f32`
//! range whatever the powers are, and no tiny pdf is ever divided by.
//!
//! The pdf the estimate divides by is the one the pick realizes: uniform picks have
//! probability exactly `1/N`, and the alias picks realize exactly the packed pmf
//! [`crate::AliasTable::implied_pmf_packed`], within `(1 + a_i)·2^-32/N` of `p_i` (the
//! threshold quantization), so the power-proportional estimate is biased by at most
//! `Σ_i |P(i) − p_i|·G_i ≤ 2^-31 · max_i G_i` (total variation `≤ 2^-32`) relative to
//! `Φ_total`; the one-random option adds up to `1.5·N·2^-32` in total variation.

mod accumulator;
mod convergence;
mod core_clock;
mod cpu;
mod measure;
mod metrics;
mod reference;
mod tonemap;

pub use accumulator::Accumulator;
pub use convergence::{
    ProgressiveRenderer, SchemeSeries, SeriesPoint, convergence_series, series_spp,
};
pub use core_clock::pool_core_seconds;
pub use cpu::{CpuRenderer, cpu_convergence};
pub use measure::{CpuPassMeasurement, measure_cpu_passes};
pub use metrics::{
    Efficiency, ErrorMetrics, REL_MSE_EPSILON, ZERO_VARIANCE_RTOL, efficiency, efficiency_of,
    error_metrics, is_zero_variance, is_zero_variance_scaled, mean_variance_per_sample,
    mean_variance_scaled, normalized_variance_per_sample, rmse,
};
pub use reference::{
    DEFAULT_REFERENCE_BUDGET, IrradianceOverflow, LIGHT_CHUNK, MIN_REFERENCE_PIXELS, PIXEL_BLOCK,
    Reference, subset_pixels,
};
pub use tonemap::{linear_to_srgb, tonemap_rgba8, tonemap_value};
