//! The app's figures (`app_renders`, `gpu_renders`): each preset at its own resolution, in
//! passes of one sample per pixel as the app's images render it, uniform, alias and
//! spatial: on the CPU the core time per sample (`render::measure_cpu_passes`, the fastest
//! of as many runs as the main table keeps its fastest of), on the GPU the pass time per
//! sample from the device's timestamps or the pass alone on an idle queue
//! (`gpu::measure_passes`). These are the figures the app's Convergence table shows.

// The app's table construction for a scene of N lights (kept here, one place to re-point).
use crate::app::state::construction_for;

use std::sync::Arc;

use lightpick_core::gpu::{self, GpuContext};
use lightpick_core::render::{CpuPassMeasurement, efficiency_of, is_zero_variance_scaled};
use lightpick_core::{Scaled, SceneSamplers, Scheme};
use serde::Serialize;

use super::args::NamedScene;
use super::renders::{RENDER_RUNS, infinite_efficiency};

/// Pass seconds the GPU renders of one preset and scheme aim at (fewer passes when `--quick`).
const GPU_RENDER_SECONDS: [f64; 2] = [0.5, 0.15];
/// Most samples per pixel of one GPU render.
const GPU_RENDER_MAX_SPP: u32 = 256;
/// The schemes the GPU renders (the app's three images).
const GPU_RENDER_SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

/// One preset's CPU figures as the app's CPU images render it.
#[derive(Clone, Debug, Serialize)]
pub struct AppPresetRender {
    /// Preset name.
    pub preset: String,
    /// Image width and height (the preset's own).
    pub size: [u32; 2],
    /// Render threads (rayon's global pool).
    pub threads: usize,
    /// One entry per scheme (uniform, alias, spatial).
    pub schemes: Vec<AppSchemeRender>,
}

/// One scheme's CPU figures as the app's images measure them.
#[derive(Clone, Debug, Serialize)]
pub struct AppSchemeRender {
    /// The measurement: spp, core seconds, `T` (core), `V`.
    #[serde(flatten)]
    pub measured: CpuPassMeasurement,
    /// `1/(V̂·T)` with `T` in core seconds; infinite (`null`) for zero variance, `null`
    /// beyond `f64` too.
    pub efficiency: Scaled,
    /// `log10` of the efficiency, finite whatever its magnitude (`null` when infinite).
    pub efficiency_log10: f64,
    /// Whether `V` is zero up to rounding (the exact spatial pick).
    pub zero_variance: bool,
}

/// One scheme's GPU figures on one preset.
#[derive(Clone, Debug, Serialize)]
pub struct GpuSchemeRender {
    /// The measurement ([`gpu::measure_passes`]): spp, pass seconds, `T`, `V`, clock.
    #[serde(flatten)]
    pub measured: gpu::GpuPassMeasurement,
    /// `1/(V̂·T)`; infinite (`null` in JSON) for a zero-variance scheme, `null` beyond
    /// `f64` too.
    pub efficiency: Scaled,
    /// `log10` of the efficiency, finite whatever its magnitude (`null` when infinite).
    pub efficiency_log10: f64,
    /// Whether `V` is the rounding of zero (the exact spatial pick).
    pub zero_variance: bool,
    /// Efficiency over the uniform scheme's.
    pub efficiency_vs_uniform: f64,
}

/// Every GPU scheme's figures on one preset, at the preset's own resolution (the app's).
#[derive(Clone, Debug, Serialize)]
pub struct GpuPresetRender {
    /// Preset name.
    pub preset: String,
    /// The adapter.
    pub adapter: String,
    /// Image width and height.
    pub size: [u32; 2],
    /// One entry per scheme (uniform, alias, spatial).
    pub schemes: Vec<GpuSchemeRender>,
    /// Why there are no figures (a scheme the device refused), if so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The app's CPU images' figures for `presets`: at each preset's own resolution, passes of
/// one sample per pixel (the app's default), core time from the render threads' clocks, the
/// scene's shared table and tree (the app's table construction).
pub(super) fn app_cpu_renders(
    presets: &[NamedScene],
    seed: u64,
    quick: bool,
) -> Vec<AppPresetRender> {
    let min_seconds = GPU_RENDER_SECONDS[usize::from(quick)];
    presets
        .iter()
        .map(|named| app_cpu_render(named, seed, min_seconds))
        .collect()
}

/// One preset's [`app_cpu_renders`].
fn app_cpu_render(named: &NamedScene, seed: u64, min_seconds: f64) -> AppPresetRender {
    let scene = Arc::clone(&named.scene);
    let samplers = SceneSamplers::new(Arc::clone(&scene), construction_for(scene.light_count()));
    let exact_pick = lightpick_core::spatial::uses_exact_pick(scene.light_count());
    let mut schemes: Vec<AppSchemeRender> = GPU_RENDER_SCHEMES
        .iter()
        .map(|&scheme| {
            let measured = fastest_cpu_passes(&samplers, scheme, seed, min_seconds);
            let efficiency = efficiency_of(
                measured.normalized_variance,
                measured.core_seconds_per_sample,
            );
            AppSchemeRender {
                efficiency,
                efficiency_log10: efficiency.log10(),
                zero_variance: exact_pick && scheme == Scheme::Spatial,
                measured,
            }
        })
        .collect();
    let uniform_variance = schemes[0].measured.normalized_variance;
    for s in &mut schemes {
        s.zero_variance |=
            is_zero_variance_scaled(s.measured.normalized_variance, uniform_variance);
        if s.zero_variance {
            (s.efficiency, s.efficiency_log10) = infinite_efficiency();
        }
    }
    AppPresetRender {
        preset: named.name.clone(),
        size: [scene.plane.width, scene.plane.height],
        threads: rayon::current_num_threads(),
        schemes,
    }
}

/// The fastest of [`RENDER_RUNS`] measurements of `scheme`'s passes (the least core time
/// per sample), as the main table keeps the fastest of its renders: the passes are
/// deterministic, only their timing varies (the machine may be shared), and a few passes of
/// half a second are what one slow moment moves most.
fn fastest_cpu_passes(
    samplers: &SceneSamplers,
    scheme: Scheme,
    seed: u64,
    min_seconds: f64,
) -> CpuPassMeasurement {
    let measure = || {
        lightpick_core::render::measure_cpu_passes(
            samplers,
            scheme,
            seed,
            1,
            min_seconds,
            GPU_RENDER_MAX_SPP,
        )
    };
    let mut fastest = measure();
    for _ in 1..RENDER_RUNS {
        let run = measure();
        if run.core_seconds_per_sample < fastest.core_seconds_per_sample {
            fastest = run;
        }
    }
    fastest
}

/// The GPU renders of `presets` (empty without an adapter): the time per sample the app's
/// GPU images measure, from the device's own clock.
pub(super) fn gpu_renders(presets: &[NamedScene], seed: u64, quick: bool) -> Vec<GpuPresetRender> {
    let Ok(ctx) = GpuContext::new() else {
        return Vec::new();
    };
    let min_seconds = GPU_RENDER_SECONDS[usize::from(quick)];
    presets
        .iter()
        .map(|named| gpu_render(&ctx, named, seed, min_seconds))
        .collect()
}

/// One preset's [`gpu_renders`]; a scheme the device refuses leaves a note and no figures.
fn gpu_render(
    ctx: &GpuContext,
    named: &NamedScene,
    seed: u64,
    min_seconds: f64,
) -> GpuPresetRender {
    let scene = &named.scene;
    let mut out = GpuPresetRender {
        preset: named.name.clone(),
        adapter: ctx.description(),
        size: [scene.plane.width, scene.plane.height],
        schemes: Vec::new(),
        note: None,
    };
    for scheme in GPU_RENDER_SCHEMES {
        match gpu::measure_passes(ctx, scene, scheme, seed, 1, min_seconds, GPU_RENDER_MAX_SPP) {
            Ok(measured) => {
                let efficiency =
                    efficiency_of(measured.normalized_variance, measured.seconds_per_sample);
                out.schemes.push(GpuSchemeRender {
                    measured,
                    efficiency,
                    efficiency_log10: efficiency.log10(),
                    zero_variance: false,
                    efficiency_vs_uniform: 0.0,
                });
            }
            Err(e) => {
                out.note = Some(format!("{scheme}: {e}"));
                out.schemes.clear();
                return out;
            }
        }
    }
    let uniform_variance = out.schemes[0].measured.normalized_variance;
    let uniform_efficiency = out.schemes[0].efficiency;
    let exact_pick = lightpick_core::spatial::uses_exact_pick(scene.light_count());
    for s in &mut out.schemes {
        // The exact spatial pick is known from N: on the GPU its f32 sums leave a
        // rounding variance near 1e-7 of the signal, far above the f64 test's.
        s.zero_variance = (exact_pick && s.measured.scheme == Scheme::Spatial)
            || is_zero_variance_scaled(s.measured.normalized_variance, uniform_variance);
        if s.zero_variance {
            (s.efficiency, s.efficiency_log10) = infinite_efficiency();
        }
        s.efficiency_vs_uniform = (s.efficiency / uniform_efficiency).to_f64();
    }
    out
}
