//! The text report for people (`bench` without `--json`): the table cases and their ratios,
//! the GPU's rate, the render cases, the app's CPU and GPU figures and the plot written.

use std::fmt::Write as _;

use lightpick_core::Scaled;

use super::app_renders::{AppPresetRender, GpuPresetRender};
use super::case::Case;
use super::plot::PlotInfo;
use super::renders::{PresetRender, RENDER_RUNS};

/// The header and one row per table case.
pub(super) fn cases_text(cases: &[Case], quick: bool) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "lightpick bench{} — {} threads; medians of repeated batches; build and per-sample \
         times in ns",
        if quick { " --quick" } else { "" },
        rayon::current_num_threads()
    );
    let _ = writeln!(
        out,
        "{:>9}  {:<31} {:>9} {:>14} {:>14} {:>10} {:>7}",
        "N", "method", "rng", "build ns", "rebuild ns", "sample ns", "threads"
    );
    for c in cases {
        let rebuild = c
            .rebuild_ns
            .map_or_else(|| "-".to_owned(), |r| format!("{r:.1}"));
        let _ = writeln!(
            out,
            "{:>9}  {:<31} {:>9} {:>14.1} {:>14} {:>10.2} {:>7}",
            c.n, c.method, c.rng, c.build_ns, rebuild, c.sample_ns, c.threads
        );
    }
    out
}

/// One line per `N` of each method's times over the alias table's.
pub(super) fn ratios_text(ratios: &[serde_json::Value]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\ntimes of each method over the alias table's (above 1: alias is faster; peers' \
         samples over alias+smallrng, batch over alias-batch):"
    );
    for r in ratios {
        let mut line = format!("{:>9} ", r["n"].as_u64().unwrap_or(0));
        for x in r["ratios"].as_array().into_iter().flatten() {
            let _ = write!(
                line,
                " {} build ×{:.2}",
                x["method"].as_str().unwrap_or("?"),
                x["build_vs_alias"].as_f64().unwrap_or(f64::NAN),
            );
            if let Some(rebuild) = x["rebuild_vs_alias"].as_f64() {
                let _ = write!(line, " rebuild ×{rebuild:.2}");
            }
            let _ = write!(
                line,
                " sample ×{:.2} batch ×{:.2};",
                x["sample_vs_alias"].as_f64().unwrap_or(f64::NAN),
                x["sample_vs_alias_batch"].as_f64().unwrap_or(f64::NAN)
            );
        }
        let _ = writeln!(out, "{line}");
    }
    out
}

/// The GPU's line: the adapter and its samples per second, or why there are none.
pub(super) fn gpu_text(gpu: &serde_json::Value) -> String {
    let adapter = gpu["adapter"].as_str();
    let Some(adapter) = adapter else {
        return gpu["note"].as_str().unwrap_or("no adapter").to_owned();
    };
    let mut s = adapter.to_owned();
    for c in gpu["cases"].as_array().into_iter().flatten() {
        let _ = write!(
            s,
            "; N = {}: {:.3e} samples/s",
            c["n"],
            c["samples_per_second"].as_f64().unwrap_or(f64::NAN)
        );
    }
    if let Some(note) = gpu["note"].as_str() {
        let _ = write!(s, " ({note})");
    }
    s
}

/// `V` as text at any magnitude: `1.2345e-3`, or beyond `f64` the value of its `log10`
/// (`1.2345e400`), never `inf`.
fn variance_text(variance: f64, log10: f64) -> String {
    if variance.is_finite() {
        format!("{variance:.4e}")
    } else {
        format!("{:.4}", Scaled::from_log10(log10))
    }
}

/// An efficiency as text (`inf` for a zero-variance scheme).
fn efficiency_text(efficiency: Scaled, zero_variance: bool) -> String {
    if zero_variance {
        "inf".to_owned()
    } else {
        format!("{efficiency:.4}")
    }
}

/// An efficiency over uniform's as text (`inf` for a zero-variance scheme).
fn vs_uniform_text(ratio: f64, zero_variance: bool) -> String {
    if zero_variance {
        "inf".to_owned()
    } else {
        format!("{ratio:.3e}")
    }
}

/// Each preset's render cases: a header line, then one row per scheme.
pub(super) fn renders_text(renders: &[PresetRender]) -> String {
    let mut out = String::new();
    for r in renders {
        let _ = writeln!(
            out,
            "\npreset {} ({} lights, {}×{} px, {} spp, reference {} px, equal time {:.4} s)",
            r.preset, r.lights, r.side, r.side, r.spp, r.reference_pixels, r.equal_time_seconds
        );
        let _ = writeln!(
            out,
            "  {:<17} {:>12} {:>12} {:>10} {:>12} {:>12} {:>9} {:>12} {:>14} {:>10}",
            "scheme",
            "Var/sample",
            "ns/sample",
            "core ns",
            "1/(Var·T)",
            "core eff.",
            "vs unif",
            "RMSE",
            "RMSE equal-t",
            "build ms"
        );
        for s in &r.schemes {
            let _ = writeln!(
                out,
                "  {:<17} {:>12} {:>12.2} {:>10.2} {:>12} {:>12} {:>9} {:>12.4e} {:>14.4e} {:>10.3}{}",
                s.scheme.name(),
                variance_text(s.variance_per_sample, s.variance_log10),
                s.seconds_per_sample * 1e9,
                s.core_seconds_per_sample * 1e9,
                efficiency_text(s.efficiency, s.zero_variance),
                efficiency_text(s.core_efficiency, s.zero_variance),
                vs_uniform_text(s.efficiency_vs_uniform, s.zero_variance),
                s.rmse,
                s.rmse_at_equal_time,
                s.build_seconds * 1e3,
                if s.zero_variance {
                    "  zero variance: rounding only"
                } else {
                    ""
                }
            );
        }
    }
    out
}

/// The app's CPU figures.
pub(super) fn app_renders_text(renders: &[AppPresetRender]) -> String {
    let mut out = String::new();
    for r in renders {
        let _ = writeln!(
            out,
            "\nCPU preset {} as the app renders it ({}×{} px, passes of 1 spp; T = core time \
             per pixel sample: the {} render threads' CPU time, the fastest of {} runs)",
            r.preset, r.size[0], r.size[1], r.threads, RENDER_RUNS
        );
        let _ = writeln!(
            out,
            "  {:<17} {:>6} {:>12} {:>12} {:>12}",
            "scheme", "spp", "Var/sample", "core ns", "1/(Var·T)"
        );
        for s in &r.schemes {
            let _ = writeln!(
                out,
                "  {:<17} {:>6} {:>12} {:>12.2} {:>12}",
                s.measured.scheme.name(),
                s.measured.spp,
                variance_text(s.measured.variance_per_sample, s.measured.variance_log10),
                s.measured.core_seconds_per_sample * 1e9,
                efficiency_text(s.efficiency, s.zero_variance)
            );
        }
    }
    out
}

/// The GPU renders: `T` in ns from the device's clock, `V`, efficiency.
pub(super) fn gpu_renders_text(renders: &[GpuPresetRender]) -> String {
    let mut out = String::new();
    for r in renders {
        let clock = r
            .schemes
            .first()
            .map_or("", |s| s.measured.clock.describe());
        let _ = writeln!(
            out,
            "\nGPU preset {} on {} ({}×{} px; T = pass time per pixel sample from {clock})",
            r.preset, r.adapter, r.size[0], r.size[1]
        );
        if let Some(note) = &r.note {
            let _ = writeln!(out, "  not measured: {note}");
            continue;
        }
        let _ = writeln!(
            out,
            "  {:<17} {:>6} {:>12} {:>12} {:>12} {:>9}",
            "scheme", "spp", "Var/sample", "ns/sample", "1/(Var·T)", "vs unif"
        );
        for s in &r.schemes {
            let _ = writeln!(
                out,
                "  {:<17} {:>6} {:>12} {:>12.2} {:>12} {:>9}",
                s.measured.scheme.name(),
                s.measured.spp,
                variance_text(s.measured.variance_per_sample, s.measured.variance_log10),
                s.measured.seconds_per_sample * 1e9,
                efficiency_text(s.efficiency, s.zero_variance),
                vs_uniform_text(s.efficiency_vs_uniform, s.zero_variance)
            );
        }
    }
    out
}

/// The line naming the plot written, if any.
pub(super) fn plot_text(plot: Option<&PlotInfo>) -> String {
    let mut out = String::new();
    if let Some(plot) = plot {
        let _ = write!(
            out,
            "\nwrote {} (RMSE against seconds, preset {}",
            plot.file.display(),
            plot.preset
        );
        if !plot.zero_variance.is_empty() {
            let _ = write!(
                out,
                "; {}: zero variance, left off the axes",
                plot.zero_variance.join(", ")
            );
        }
        let _ = writeln!(out, ")");
    }
    out
}
