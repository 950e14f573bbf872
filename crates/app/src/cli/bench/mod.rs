//! `lightpick bench`: a timing harness. Every figure is measured in this run, peers
//! included; nothing here is asserted by tests beyond its shape.
//!
//! * Tables: for each `N`, build time and time per sample of the alias table (two randoms,
//!   one random), the inverse CDF and uniform picking, all drawing from the project's
//!   [`Rng`]; the alias table again drawing from `SmallRng`, beside the peers
//!   `rand_distr::weighted::WeightedAliasIndex` and `rand::distr::weighted::WeightedIndex`
//!   (which draw from `SmallRng`), so the peer ratios compare like with like. The integer
//!   table builds on rayon's pool (`alias`, `threads` = the pool) and again on one thread
//!   (`alias-1t`): the same table bit for bit, so the two rows time the same work.
//! * Memory: the copy bandwidth of one thread and the floor it puts on a table build
//!   (`16·N` bytes at least, see `bandwidth`).
//! * GPU: samples per second of `gpu::histogram` (alias, two randoms), where an adapter
//!   exists.
//! * Renders: for each preset, at a small resolution, the variance per sample `V`, the
//!   time per sample `T` and the efficiency `1/(V̂·T)` (`V̂ = V/Φ_total²`) of each scheme on
//!   the CPU, and the RMSE each reaches at the same rendering time (the shortest of the
//!   schemes' runs, interpolated log-log on its convergence series). The spatial
//!   (contribution-aware) scheme is one of them; each row also gives the sampler's build
//!   time (the light tree's `O(N log N)` for spatial). A zero-variance row (the exact
//!   spatial pick, `N ≤ 16`) has an infinite efficiency, written `null` in the JSON; `V̂`
//!   and the efficiencies are `Scaled` (a scene with a light `10^-100` above a pixel has
//!   `V̂ ≈ 10^400`): `null` beyond `f64` with their `*_log10` beside them, text
//!   `1.234e-392`. Beside `T` (wall time on rayon's threads) each row has the core time
//!   (the threads' CPU time, `render::pool_core_seconds`).
//! * The app's figures (`app_renders`, `gpu_renders`): each preset at its own resolution, in
//!   passes of one sample per pixel as the app's images render it, uniform, alias and
//!   spatial: on the CPU the core time per sample (`render::measure_cpu_passes`), on the GPU
//!   the pass time per sample from the device's timestamps or the pass alone on an idle
//!   queue (`gpu::measure_passes`). These are the figures the app's Convergence table shows.
//!
//! A timing is the median of several repetitions, each timing a batch of many operations
//! (`std::time::Instant`, results through `std::hint::black_box`).
//!
//! The files, in the order a run measures: [`args`] (what to time and render), [`timing`]
//! (medians of batches), [`tables`] (the table cases and their ratios, with [`tree`] for
//! the light tree and the app's repower), [`gpu_rate`], [`renders`] (the render cases),
//! [`app_renders`] (the app's CPU and GPU figures), [`plot`], [`memory`] (bandwidth and
//! random-read floors, from [`bandwidth`] and [`machine`]); [`text`] writes the report for
//! people, this file runs them in order and writes the JSON.

mod app_renders;
mod args;
mod bandwidth;
mod case;
mod gpu_rate;
mod machine;
mod memory;
mod plot;
mod renders;
mod tables;
mod text;
mod timing;
mod tree;

use anyhow::bail;
use serde_json::json;

use self::app_renders::{AppPresetRender, GpuPresetRender, app_cpu_renders, gpu_renders};
pub use self::args::BenchArgs;
use self::case::Case;
use self::memory::MemoryFloors;
use self::plot::{PlotInfo, write_plot};
use self::renders::{PresetRender, render_preset};
use self::tables::{ratios, time_tables};
use self::timing::Plan;

/// Everything one run measured, in the order it was measured.
struct Report {
    quick: bool,
    /// The table cases, per size.
    cases: Vec<Case>,
    /// The GPU's sampling rate (or why there is none).
    gpu: serde_json::Value,
    /// The render cases, per preset.
    renders: Vec<PresetRender>,
    /// The app's CPU figures, per preset.
    app_renders: Vec<AppPresetRender>,
    /// The app's GPU figures, per preset (none with `--no-gpu` or no adapter).
    gpu_renders: Vec<GpuPresetRender>,
    /// What `--plot` wrote.
    plot: Option<PlotInfo>,
    /// Each method's times over the alias table's, per size.
    ratios: Vec<serde_json::Value>,
    /// The memory's floors under the tables' figures.
    memory: MemoryFloors,
}

/// Runs the benchmark and prints it.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let report = measure(args)?;
    if args.json {
        super::print_json(&report.json())
    } else {
        print!("{}", report.text());
        Ok(())
    }
}

/// Checks the arguments, then measures everything they ask for.
fn measure(args: &BenchArgs) -> anyhow::Result<Report> {
    let sizes = args.sizes()?;
    let presets = args.scenes()?;
    let spp = args.spp()?;
    if let Some(path) = &args.plot
        && presets.is_empty()
    {
        bail!(
            "--plot {}: nothing to plot with --presets none",
            path.display()
        );
    }
    let plan = Plan::new(args.quick);
    let mut cases = Vec::new();
    let mut read_floors = Vec::new();
    for &n in &sizes {
        let (timed, floor) = time_tables(n, args.seed, plan)?;
        cases.extend(timed);
        read_floors.push((n, floor));
    }
    let gpu = if args.no_gpu {
        json!({ "adapter": null, "note": "skipped (--no-gpu)" })
    } else {
        gpu_rate::gpu_rate(args.quick, args.seed)
    };
    let side = if args.quick { 64 } else { 128 };
    let renders: Vec<PresetRender> = presets
        .iter()
        .map(|p| render_preset(p, side, spp, args.seed, args.quick))
        .collect::<anyhow::Result<_>>()?;
    let app_renders = app_cpu_renders(&presets, args.seed, args.quick);
    let gpu_renders = if args.no_gpu {
        Vec::new()
    } else {
        gpu_renders(&presets, args.seed, args.quick)
    };
    let plot = match &args.plot {
        Some(path) => Some(write_plot(path, &renders)?),
        None => None,
    };
    let ratios = ratios(&cases);
    let memory = MemoryFloors::measure(args.quick, sizes, read_floors);
    Ok(Report {
        quick: args.quick,
        cases,
        gpu,
        renders,
        app_renders,
        gpu_renders,
        plot,
        ratios,
        memory,
    })
}

impl Report {
    /// The JSON object of `--json`.
    fn json(&self) -> serde_json::Value {
        json!({
            "quick": self.quick,
            "threads": rayon::current_num_threads(),
            "memory_bandwidth": self.memory.json(&self.cases),
            "cases": self.cases,
            "ratios": self.ratios,
            "gpu": self.gpu,
            "renders": self.renders,
            "app_renders": self.app_renders,
            "gpu_renders": self.gpu_renders,
            "plot": self.plot,
        })
    }

    /// The text report.
    fn text(&self) -> String {
        [
            text::cases_text(&self.cases, self.quick),
            text::ratios_text(&self.ratios),
            format!("\nGPU: {}\n", text::gpu_text(&self.gpu)),
            text::renders_text(&self.renders),
            self.memory.text(&self.cases),
            text::app_renders_text(&self.app_renders),
            text::gpu_renders_text(&self.gpu_renders),
            text::plot_text(self.plot.as_ref()),
        ]
        .concat()
    }
}
