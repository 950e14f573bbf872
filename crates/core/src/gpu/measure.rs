//! The time per sample and variance per sample of one scheme on the GPU, measured the way
//! `lightpick bench` and the app's images both do: the device's own time for the sample
//! passes ([`GpuRenderer::take_pass_seconds`]), never tonemapping, readback or other work.

use super::pass_timer::PassClock;
use super::{GpuContext, GpuError, GpuRenderer};
use crate::Scheme;
use crate::render::{mean_variance_scaled, normalized_variance_per_sample};
use crate::scene::Scene;

/// One scheme's measured cost and variance on the GPU.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GpuPassMeasurement {
    /// The scheme.
    pub scheme: Scheme,
    /// Samples per pixel timed.
    pub spp: u32,
    /// Pixels of the image.
    pub pixels: u64,
    /// Pass seconds of those samples.
    pub seconds: f64,
    /// `T`: pass seconds per pixel sample.
    pub seconds_per_sample: f64,
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
    /// Where the time comes from.
    pub clock: PassClock,
}

/// Renders `scene` with `scheme` on `ctx`: one untimed warm-up pass (pipeline and light tree
/// upload), then passes of `spp_per_pass` samples per pixel (one dispatch each, as the app adds its
/// samples per frame: 1 by default) until they took `min_seconds` or reached `max_spp`, with at
/// least two samples per pixel (for the variance). Each pass's fixed cost (submission, completion)
/// is part of `T`, spread over `spp_per_pass` samples. The variance comes from the same passes'
/// sums.
pub fn measure_passes(
    ctx: &GpuContext,
    scene: &Scene,
    scheme: Scheme,
    seed: u64,
    spp_per_pass: u32,
    min_seconds: f64,
    max_spp: u32,
) -> Result<GpuPassMeasurement, GpuError> {
    let spp_per_pass = spp_per_pass.max(1);
    let mut renderer = GpuRenderer::new(ctx, scene, scheme, seed)?;
    renderer.accumulate(1)?;
    renderer.take_pass_seconds()?;
    renderer.reset();
    let mut seconds = 0.0;
    loop {
        renderer.accumulate(spp_per_pass)?;
        seconds += renderer.take_pass_seconds()?;
        // At least two samples per pixel: one has no variance.
        let spp = renderer.samples_per_pixel();
        if spp >= max_spp.max(2) || (spp >= 2 && seconds >= min_seconds) {
            break;
        }
    }
    let acc = renderer.readback()?;
    let (width, height) = renderer.size();
    let variance = mean_variance_scaled(&acc);
    let normalized = normalized_variance_per_sample(&acc);
    let pixels = u64::from(width) * u64::from(height);
    let spp = renderer.samples_per_pixel();
    Ok(GpuPassMeasurement {
        scheme,
        spp,
        pixels,
        seconds,
        seconds_per_sample: seconds / (f64::from(spp) * pixels as f64),
        variance_per_sample: variance.to_f64(),
        variance_log10: variance.log10(),
        normalized_variance: normalized,
        normalized_variance_log10: normalized.log10(),
        clock: renderer.pass_clock(),
    })
}
