//! The core time per sample and variance per sample of one scheme on the CPU, measured the
//! way the app's CPU images render: passes of a few samples per pixel at the scene's own
//! resolution, timed by the render threads' CPU clocks ([`pool_core_seconds`]). `lightpick
//! bench` prints it beside its convergence runs (which use large passes on a small image,
//! where a sample costs less: fewer cache misses per pixel row).

use super::{CpuRenderer, mean_variance_scaled, normalized_variance_per_sample, pool_core_seconds};
use crate::{SceneSamplers, Scheme};

/// One scheme's measured core time and variance on the CPU.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CpuPassMeasurement {
    /// The scheme.
    pub scheme: Scheme,
    /// Samples per pixel timed.
    pub spp: u32,
    /// Pixels of the image.
    pub pixels: u64,
    /// Core seconds of those samples (the render threads' CPU time).
    pub core_seconds: f64,
    /// `T`: core seconds per pixel sample.
    pub core_seconds_per_sample: f64,
    /// `V`: mean variance of one normalized sample over the pixels (`inf` beyond `f64`,
    /// JSON `null`).
    pub variance_per_sample: f64,
    /// `log10 V`, finite whatever its magnitude (`-inf` for 0).
    pub variance_log10: f64,
    /// `V̂ = V/Φ_total²`: the same in units of the total power, what the efficiency
    /// `1/(V̂·T)` divides by ([`crate::render::efficiency_of`]), whatever its magnitude
    /// (JSON: `null` beyond `f64`, with `normalized_variance_log10`).
    pub normalized_variance: crate::Scaled,
    /// `log10 V̂`, finite whatever its magnitude (`-inf` for 0).
    pub normalized_variance_log10: f64,
}

/// Renders `samplers`' scene with `scheme` on the current rayon pool: one untimed warm-up
/// pass, then passes of `spp_per_pass` samples per pixel until they took `min_core_seconds`
/// or reached `max_spp`, with at least two samples per pixel (for the variance).
pub fn measure_cpu_passes(
    samplers: &SceneSamplers,
    scheme: Scheme,
    seed: u64,
    spp_per_pass: u32,
    min_core_seconds: f64,
    max_spp: u32,
) -> CpuPassMeasurement {
    let spp_per_pass = spp_per_pass.max(1);
    let mut renderer = CpuRenderer::from_samplers(samplers, scheme, seed);
    renderer.accumulate(1);
    renderer.reset();
    let mut core_seconds = 0.0;
    loop {
        core_seconds += pool_core_seconds(|| renderer.accumulate(spp_per_pass)).1;
        // At least two samples per pixel: one has no variance.
        let spp = renderer.samples_per_pixel();
        if spp >= max_spp.max(2) || (spp >= 2 && core_seconds >= min_core_seconds) {
            break;
        }
    }
    let acc = renderer.accumulator();
    let variance = mean_variance_scaled(acc);
    let normalized = normalized_variance_per_sample(acc);
    let pixels = u64::from(acc.width) * u64::from(acc.height);
    let spp = acc.samples_per_pixel;
    CpuPassMeasurement {
        scheme,
        spp,
        pixels,
        core_seconds,
        core_seconds_per_sample: core_seconds / (f64::from(spp) * pixels as f64),
        variance_per_sample: variance.to_f64(),
        variance_log10: variance.log10(),
        normalized_variance: normalized,
        normalized_variance_log10: normalized.log10(),
    }
}
