//! The render cases: each preset at a small square resolution, every scheme on the CPU,
//! the variance per sample `V`, the time per sample `T` (wall and core), the efficiency
//! `1/(V̂·T)` and the RMSE each reaches at the same rendering time (the shortest of the
//! schemes' runs, interpolated log-log on its convergence series).

use std::time::Instant;

use anyhow::bail;
use lightpick_core::render::{
    CpuRenderer, Reference, SeriesPoint, convergence_series, efficiency, efficiency_of,
    is_zero_variance_scaled, pool_core_seconds,
};
use lightpick_core::scene::Scene;
use lightpick_core::{Scaled, Scheme};
use serde::Serialize;

use super::args::NamedScene;

/// Runs of each render; the fastest is kept.
pub(super) const RENDER_RUNS: usize = 3;
/// The schemes rendered.
const RENDER_SCHEMES: [Scheme; 5] = [
    Scheme::Uniform,
    Scheme::Alias,
    Scheme::AliasOneRandom,
    Scheme::Cdf,
    Scheme::Spatial,
];

/// One scheme's render figures on one preset.
#[derive(Clone, Debug, Serialize)]
pub struct SchemeRender {
    /// The scheme.
    pub scheme: Scheme,
    /// `V`, mean variance of one sample over the pixels.
    pub variance_per_sample: f64,
    /// `log10 V`, finite whatever its magnitude (`V` is `null` beyond `f64`).
    pub variance_log10: f64,
    /// `V̂ = V/Φ_total²`, the same per unit of total power (the efficiencies divide by it, so
    /// they do not change when the powers are scaled); `null` beyond `f64`.
    pub normalized_variance: Scaled,
    /// `log10 V̂`, finite whatever its magnitude.
    pub normalized_variance_log10: f64,
    /// `T`, seconds per pixel sample (wall time on rayon's threads).
    pub seconds_per_sample: f64,
    /// Core seconds per pixel sample: the CPU time of rayon's threads in the passes
    /// (`pool_core_seconds`), what the app's CPU images show (its render pool leaves a core
    /// to the window, and the window shares the cores, so its wall time is not comparable).
    pub core_seconds_per_sample: f64,
    /// `1/(V̂·T_core)`, the app's CPU efficiency; infinite (`null`) for zero variance,
    /// `null` beyond `f64` too.
    pub core_efficiency: Scaled,
    /// `log10` of the core efficiency (`null` when infinite).
    pub core_efficiency_log10: f64,
    /// `1/(V̂·T)`; infinite (`null` in JSON) for a zero-variance scheme, `null` beyond
    /// `f64` too.
    pub efficiency: Scaled,
    /// `log10` of the efficiency, finite whatever its magnitude (`null` when infinite).
    pub efficiency_log10: f64,
    /// Whether `V` is the rounding of zero (the exact spatial pick on few lights:
    /// [`lightpick_core::render::is_zero_variance`] against the uniform scheme's `V`).
    pub zero_variance: bool,
    /// Efficiency over the uniform scheme's.
    pub efficiency_vs_uniform: f64,
    /// RMSE after the whole run.
    pub rmse: f64,
    /// RMSE at the preset's equal-time point (log-log interpolation of the series).
    pub rmse_at_equal_time: f64,
    /// Seconds to build the renderer's sampler (alias table, CDF, light tree).
    pub build_seconds: f64,
    /// The convergence series.
    pub series: Vec<SeriesPoint>,
}

/// Every scheme's render figures on one preset.
#[derive(Clone, Debug, Serialize)]
pub struct PresetRender {
    /// Preset name.
    pub preset: String,
    /// Number of lights.
    pub lights: usize,
    /// Image side in pixels.
    pub side: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Pixels the reference covers.
    pub reference_pixels: usize,
    /// The equal-time point: the shortest of the schemes' rendering times.
    pub equal_time_seconds: f64,
    /// One entry per scheme.
    pub schemes: Vec<SchemeRender>,
}

/// The efficiency of a zero-variance scheme, with its `log10`: `+inf` (`null` in JSON).
pub(super) fn infinite_efficiency() -> (Scaled, f64) {
    (Scaled::from_f64(f64::INFINITY), f64::INFINITY)
}

/// Renders `named` at `side`×`side` pixels, `spp` samples per pixel, with every scheme,
/// against its reference (fewer reference pixels when `quick`).
pub(super) fn render_preset(
    named: &NamedScene,
    side: u32,
    spp: u32,
    seed: u64,
    quick: bool,
) -> anyhow::Result<PresetRender> {
    let name = named.name.as_str();
    let mut scene = Scene::clone(&named.scene);
    scene.plane.width = side;
    scene.plane.height = side;
    let budget = if quick { 1 << 26 } else { 1 << 29 };
    let reference = Reference::with_budget(&scene, budget);
    let mut schemes = Vec::new();
    for scheme in RENDER_SCHEMES {
        let Some(run) = fastest_render(&scene, scheme, seed, spp, &reference) else {
            bail!("no render of {name}");
        };
        let samples = f64::from(spp) * f64::from(side) * f64::from(side);
        schemes.push(run.figures(scheme, samples));
    }
    let equal_time = schemes
        .iter()
        .filter_map(|s| s.series.last().map(|p| p.seconds))
        .fold(f64::INFINITY, f64::min);
    compare_schemes(&mut schemes, equal_time);
    Ok(PresetRender {
        preset: name.to_owned(),
        lights: scene.light_count(),
        side,
        spp,
        reference_pixels: reference.pixels().len(),
        equal_time_seconds: equal_time,
        schemes,
    })
}

/// The fastest of [`RENDER_RUNS`] renders of one scheme, and the least build and core time.
struct Run {
    renderer: CpuRenderer,
    series: Vec<SeriesPoint>,
    build_seconds: f64,
    core_seconds: f64,
}

/// Renders `scene` with `scheme` [`RENDER_RUNS`] times and keeps the fastest: the render is
/// deterministic, only its timing varies (the machine may be shared).
fn fastest_render(
    scene: &Scene,
    scheme: Scheme,
    seed: u64,
    spp: u32,
    reference: &Reference,
) -> Option<Run> {
    let mut best: Option<(CpuRenderer, Vec<SeriesPoint>)> = None;
    let mut build_seconds = f64::INFINITY;
    let mut core_seconds = f64::INFINITY;
    for _ in 0..RENDER_RUNS {
        let started = Instant::now();
        let mut renderer = CpuRenderer::new(scene, scheme, seed);
        build_seconds = build_seconds.min(started.elapsed().as_secs_f64());
        // The RMSEs between passes run on this (non-pool) thread: not in the core time.
        let (series, core) =
            pool_core_seconds(|| convergence_series(&mut renderer, reference, spp));
        core_seconds = core_seconds.min(core);
        let seconds = series.last().map_or(0.0, |p| p.seconds);
        if best
            .as_ref()
            .is_none_or(|(_, b)| b.last().is_some_and(|p| seconds < p.seconds))
        {
            best = Some((renderer, series));
        }
    }
    best.map(|(renderer, series)| Run {
        renderer,
        series,
        build_seconds,
        core_seconds,
    })
}

impl Run {
    /// The run's figures over `samples` pixel samples; the comparisons with the other
    /// schemes are left to [`compare_schemes`].
    fn figures(self, scheme: Scheme, samples: f64) -> SchemeRender {
        let seconds = self.series.last().map_or(0.0, |p| p.seconds);
        let e = efficiency(self.renderer.accumulator(), seconds);
        let core_seconds_per_sample = self.core_seconds / samples;
        let core_efficiency = efficiency_of(e.normalized_variance, core_seconds_per_sample);
        SchemeRender {
            scheme,
            variance_per_sample: e.variance_per_sample,
            variance_log10: e.variance_log10,
            normalized_variance: e.normalized_variance,
            normalized_variance_log10: e.normalized_variance_log10,
            seconds_per_sample: e.seconds_per_sample,
            core_seconds_per_sample,
            core_efficiency,
            core_efficiency_log10: core_efficiency.log10(),
            efficiency: e.efficiency,
            efficiency_log10: e.efficiency_log10,
            zero_variance: false,
            efficiency_vs_uniform: 0.0,
            rmse: self.series.last().map_or(0.0, |p| p.rmse),
            rmse_at_equal_time: 0.0,
            build_seconds: self.build_seconds,
            series: self.series,
        }
    }
}

/// Fills what each scheme's figures owe the others: the RMSE at `equal_time`, zero
/// variance (against the uniform scheme's, the first) and the efficiency over uniform's.
fn compare_schemes(schemes: &mut [SchemeRender], equal_time: f64) {
    let uniform_eff = schemes[0].efficiency;
    let uniform_variance = schemes[0].normalized_variance;
    for s in schemes {
        s.rmse_at_equal_time = rmse_at(&s.series, equal_time);
        s.zero_variance = is_zero_variance_scaled(s.normalized_variance, uniform_variance);
        if s.zero_variance {
            (s.efficiency, s.efficiency_log10) = infinite_efficiency();
            (s.core_efficiency, s.core_efficiency_log10) = infinite_efficiency();
        }
        s.efficiency_vs_uniform = (s.efficiency / uniform_eff).to_f64();
    }
}

/// The RMSE of a series at `seconds`, interpolated linearly in `(log t, log rmse)`
/// between the points around it (the first point's RMSE before it, the last's after).
fn rmse_at(series: &[SeriesPoint], seconds: f64) -> f64 {
    let Some(first) = series.first() else {
        return f64::NAN;
    };
    if seconds <= first.seconds {
        return first.rmse;
    }
    for w in series.windows(2) {
        let (a, b) = (w[0], w[1]);
        if seconds <= b.seconds {
            if a.seconds <= 0.0 || a.rmse <= 0.0 || b.rmse <= 0.0 || b.seconds <= a.seconds {
                return b.rmse;
            }
            let f = (seconds.ln() - a.seconds.ln()) / (b.seconds.ln() - a.seconds.ln());
            return (a.rmse.ln() + f * (b.rmse.ln() - a.rmse.ln())).exp();
        }
    }
    series.last().map_or(f64::NAN, |p| p.rmse)
}
