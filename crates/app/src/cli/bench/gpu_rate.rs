//! The GPU's sampling rate: samples per second of `gpu::histogram` (alias, two randoms)
//! at 1000 and `10^6` lights, where an adapter exists; a note saying why not otherwise.

use std::time::Instant;

use lightpick_core::gpu::{self, GpuContext};
use lightpick_core::precision::Distribution;
use lightpick_core::{LightPowers, Sampler, Scheme};
use serde_json::json;

/// GPU samples per second of the alias histogram, or a note saying why there are none.
pub(super) fn gpu_rate(quick: bool, seed: u64) -> serde_json::Value {
    let ctx = match GpuContext::new() {
        Ok(ctx) => ctx,
        Err(e) => return json!({ "adapter": null, "note": format!("no adapter ({e})") }),
    };
    // A software adapter (lavapipe) runs at tens of millions of samples per second.
    let count: u64 = match (quick, ctx.is_software()) {
        (true, _) => 1 << 22,
        (false, true) => 1 << 24,
        (false, false) => 1 << 28,
    };
    let mut rows = Vec::new();
    for n in [1000usize, 1_000_000] {
        let Ok(powers) = LightPowers::new(Distribution::Exponential.powers(n, seed)) else {
            continue;
        };
        let sampler = Sampler::build(Scheme::Alias, &powers);
        match histogram_seconds(&ctx, &sampler, count, seed) {
            Ok(seconds) => rows.push(json!({
                "n": n,
                "method": "alias",
                "count": count,
                "seconds": seconds,
                "samples_per_second": count as f64 / seconds,
            })),
            Err(e) => {
                return json!({ "adapter": ctx.description(), "note": format!("histogram failed: {e}") });
            }
        }
    }
    json!({
        "adapter": ctx.description(),
        "software": ctx.is_software(),
        "note": "includes table upload and readback",
        "cases": rows,
    })
}

/// The median seconds of three histograms of `count` samples, after one untimed run that
/// compiles the pipeline.
fn histogram_seconds(
    ctx: &GpuContext,
    sampler: &Sampler,
    count: u64,
    seed: u64,
) -> Result<f64, gpu::GpuError> {
    gpu::histogram(ctx, sampler, 1 << 16, seed)?;
    let mut times = Vec::new();
    for rep in 0..3u64 {
        let start = Instant::now();
        gpu::histogram(ctx, sampler, count, seed + rep)?;
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok(times[1])
}
