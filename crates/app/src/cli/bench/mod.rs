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

use std::fmt::Write as _;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::bandwidth::{BUILD_BYTES_PER_LIGHT, Bandwidth};
use super::machine::{faults_per_call, random_read_ns};
use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::draw::{self, ConvergenceAxis, ConvergencePoint, ConvergenceSeries};
use lightpick_core::gpu::{self, GpuContext};
use lightpick_core::precision::Distribution;
use lightpick_core::render::{
    CpuRenderer, Reference, SeriesPoint, convergence_series, efficiency, efficiency_of,
    is_zero_variance_scaled, pool_core_seconds,
};
use lightpick_core::scene::Scene;
use lightpick_core::{
    AliasTable, CdfTable, Construction, LightPowers, Rng, Sampler, Scaled, Scheme, Uniform,
};
use rand::distr::Distribution as _;
use rand::rngs::SmallRng;
use rand::{Rng as _, SeedableRng as _};
use serde::Serialize;
use serde_json::json;

/// `N` of a full run: 3 to `1.6·10^7`.
const FULL_SIZES: [usize; 8] = [
    3, 64, 1000, 10_000, 100_000, 1_000_000, 4_000_000, 16_000_000,
];
/// `N` of a `--quick` run.
const QUICK_SIZES: [usize; 4] = [3, 1000, 100_000, 1_000_000];
/// The largest `N` accepted by `--sizes`.
const MAX_SIZE: usize = 1 << 26;
/// Presets of a `--quick` run (`million` is left out: its reference dominates the run; the
/// two spot scenes stay, for the spatial scheme's figures where power picking fails).
const QUICK_PRESETS: [&str; 8] = [
    "seed",
    "equal",
    "dominant",
    "zeros",
    "heavy-tail",
    "extreme-range",
    "stage",
    "gallery",
];
/// Runs of each render; the fastest is kept.
const RENDER_RUNS: usize = 3;
/// The schemes rendered.
const RENDER_SCHEMES: [Scheme; 5] = [
    Scheme::Uniform,
    Scheme::Alias,
    Scheme::AliasOneRandom,
    Scheme::Cdf,
    Scheme::Spatial,
];

/// Arguments of `lightpick bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// A short run (under a minute in release on two cores): fewer sizes, smaller renders.
    #[arg(long)]
    pub quick: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write a PNG of RMSE against rendering time per scheme (the heavy-tail preset, or
    /// the first one rendered).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Table sizes to time instead of the defaults, comma separated (e.g. `3,1000`).
    #[arg(long, value_name = "LIST")]
    pub sizes: Option<String>,
    /// Presets to render instead of the defaults, comma separated, or `none`.
    #[arg(long, value_name = "LIST")]
    pub presets: Option<String>,
    /// A scene file to render too (lightpick JSON, glTF/GLB, CSV; repeatable), after the
    /// presets; named by its file name.
    #[arg(long, value_name = "FILE")]
    pub scene: Vec<PathBuf>,
    /// The receiver's height for `--scene` files (glTF's y), instead of the file's ground.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub floor: Option<f64>,
    /// Samples per pixel of each render (default 1024, `--quick` 256).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Skip the GPU measurement.
    #[arg(long)]
    pub no_gpu: bool,
    /// Seed of the powers, the samples and the renders.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// One timed method at one `N`.
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// Number of lights.
    pub n: usize,
    /// What was timed (`alias`, `alias-one-random`, `cdf`, `uniform`, `alias+smallrng`,
    /// `rand_distr::WeightedAliasIndex`, `rand::WeightedIndex`).
    pub method: &'static str,
    /// The random generator the samples drew from.
    pub rng: &'static str,
    /// Median build time (powers to a ready table, allocation included), nanoseconds.
    pub build_ns: f64,
    /// Median time to rebuild an existing table of the same `N` in place (no allocation),
    /// nanoseconds, for the methods that can (`alias`, `alias-exact`, and the peer
    /// `rand_distr::WeightedAliasIndex`, which has no in-place rebuild: its build).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rebuild_ns: Option<f64>,
    /// Median time per sample, nanoseconds (for `tree-build`, `tree-refit` and
    /// `app-repower`: one pick of the light tree at a shading point).
    pub sample_ns: f64,
    /// Threads the timed build ran on: rayon's pool for the integer alias table (`alias`,
    /// `alias-batch`) and the light tree (`tree-build`, `tree-refit`), 1 for `alias-1t` and
    /// the sequential constructions and peers (`app-repower`: the pool, for its table and
    /// tree). Picks always run on one thread.
    pub threads: usize,
    /// Minor page faults per build (`alias`, `alias-1t` and the peer alias table; Linux).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub build_faults: Option<f64>,
    /// Minor page faults per in-place rebuild (`alias`, `alias-1t`; Linux).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rebuild_faults: Option<f64>,
}

/// Timing plan: repetitions and batch sizes.
#[derive(Clone, Copy, Debug)]
struct Plan {
    repetitions: usize,
    samples_per_batch: usize,
    build_budget: usize,
}

/// Runs the benchmark and prints it.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let sizes = sizes(args)?;
    let presets = presets(args)?;
    let spp = args.spp.unwrap_or(if args.quick { 256 } else { 1024 });
    if spp == 0 {
        bail!("--spp must be at least 1");
    }
    if let Some(path) = &args.plot
        && presets.is_empty()
    {
        bail!(
            "--plot {}: nothing to plot with --presets none",
            path.display()
        );
    }
    let plan = if args.quick {
        Plan {
            repetitions: 5,
            samples_per_batch: 1 << 19,
            build_budget: 1 << 20,
        }
    } else {
        Plan {
            repetitions: 7,
            samples_per_batch: 1 << 21,
            build_budget: 1 << 22,
        }
    };
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
        gpu_rate(args.quick, args.seed)
    };
    let side = if args.quick { 64 } else { 128 };
    let renders: Vec<PresetRender> = presets
        .iter()
        .map(|p| render_preset(p, side, spp, args.seed, args.quick))
        .collect::<anyhow::Result<_>>()?;
    let app_renders = app_cpu_renders(&presets, args.seed, args.quick)?;
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
    // 256 MiB buffers (64 MiB in --quick): far beyond the caches.
    let bandwidth = Bandwidth::measure(if args.quick { 64 << 20 } else { 256 << 20 }, 5);
    let floors: Vec<serde_json::Value> = sizes
        .iter()
        .map(|&n| json!({ "n": n, "build_floor_ns": bandwidth.build_floor_ns(n) }))
        .collect();
    let read_floors_json: Vec<serde_json::Value> = read_floors
        .iter()
        .map(|&(n, ns)| {
            let batch = cases
                .iter()
                .find(|c| c.n == n && c.method == "alias-batch")
                .map(|c| c.sample_ns / ns);
            json!({ "n": n, "random_read_ns": ns, "batch_over_random_read": batch })
        })
        .collect();
    if args.json {
        super::print_json(&json!({
            "quick": args.quick,
            "threads": rayon::current_num_threads(),
            "memory_bandwidth": {
                "copy_gb_per_s": bandwidth.copy_gb_per_s,
                "buffer_bytes": bandwidth.buffer_bytes,
                "build_bytes_per_light": BUILD_BYTES_PER_LIGHT,
                "build_floors": floors,
                "random_read_floors": read_floors_json,
            },
            "cases": cases,
            "ratios": ratios,
            "gpu": gpu,
            "renders": renders,
            "app_renders": app_renders,
            "gpu_renders": gpu_renders,
            "plot": plot,
        }))
    } else {
        print!("{}", text(&cases, &ratios, &gpu, &renders, args.quick));
        println!(
            "\nmemory: copy {:.1} GB/s (read + write, one thread); a table build moves at \
             least {BUILD_BYTES_PER_LIGHT} bytes per light, so no build is faster than:",
            bandwidth.copy_gb_per_s
        );
        for &n in &sizes {
            println!("{n:>9}  {:.3} ms", bandwidth.build_floor_ns(n) / 1e6);
        }
        print!("{}", read_floor_text(&cases, &read_floors));
        print!("{}", app_renders_text(&app_renders));
        print!("{}", gpu_renders_text(&gpu_renders));
        print!("{}", plot_text(plot.as_ref()));
        Ok(())
    }
}

fn sizes(args: &BenchArgs) -> anyhow::Result<Vec<usize>> {
    let Some(list) = &args.sizes else {
        return Ok(if args.quick {
            QUICK_SIZES.to_vec()
        } else {
            FULL_SIZES.to_vec()
        });
    };
    list.split(',')
        .map(|s| {
            let n: usize = s
                .trim()
                .parse()
                .with_context(|| format!("--sizes: '{}' is not a count", s.trim()))?;
            if n == 0 || n > MAX_SIZE {
                bail!("--sizes: each size must be between 1 and {MAX_SIZE} (got {n})");
            }
            Ok(n)
        })
        .collect()
}

/// A scene to render, with the name its rows carry (the preset's, or the file's stem).
struct NamedScene {
    name: String,
    scene: std::sync::Arc<Scene>,
}

/// The presets to render (`--presets`, or the defaults) and then the `--scene` files.
fn presets(args: &BenchArgs) -> anyhow::Result<Vec<NamedScene>> {
    let names: Vec<String> = match &args.presets {
        None if args.quick => QUICK_PRESETS.iter().map(|s| (*s).to_owned()).collect(),
        None if !args.scene.is_empty() => Vec::new(),
        None => lightpick_core::scene::PRESET_NAMES
            .iter()
            .map(|s| (*s).to_owned())
            .collect(),
        Some(list) if list.trim() == "none" => Vec::new(),
        Some(list) => list.split(',').map(|s| s.trim().to_owned()).collect(),
    };
    let mut out = Vec::new();
    for name in names {
        let scene = Scene::preset(&name).with_context(|| format!("--presets '{name}'"))?;
        out.push(NamedScene {
            name,
            scene: std::sync::Arc::new(scene),
        });
    }
    for path in &args.scene {
        let scene = super::input::load_scene_file(path, args.floor)?;
        out.push(NamedScene {
            name: path.file_name().map_or_else(
                || path.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            ),
            scene: std::sync::Arc::new(scene),
        });
    }
    Ok(out)
}

/// The median of `repetitions` timings of `batch` calls of `f`, per call, in nanoseconds.
fn median_ns<T>(repetitions: usize, batch: usize, mut f: impl FnMut(usize) -> T) -> f64 {
    let mut times: Vec<f64> = (0..repetitions)
        .map(|rep| {
            let start = Instant::now();
            for i in 0..batch {
                black_box(f(rep * batch + i));
            }
            start.elapsed().as_secs_f64() * 1e9 / batch as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Like [`median_ns`], for an `f` that consumes an input: the `batch` inputs of each
/// repetition are made by `input` before its clock starts.
fn median_with_inputs<I, T>(
    repetitions: usize,
    batch: usize,
    mut input: impl FnMut() -> I,
    mut f: impl FnMut(I) -> T,
) -> f64 {
    let mut times: Vec<f64> = (0..repetitions)
        .map(|_| {
            let inputs: Vec<I> = (0..batch).map(|_| input()).collect();
            let start = Instant::now();
            for x in inputs {
                black_box(f(x));
            }
            start.elapsed().as_secs_f64() * 1e9 / batch as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Times every method at `N` lights (exponential powers); also returns the random-read
/// floor of the table's own entries ([`random_read_ns`], one thread).
fn time_tables(n: usize, seed: u64, plan: Plan) -> anyhow::Result<(Vec<Case>, f64)> {
    let raw = Distribution::Exponential.powers(n, seed);
    let powers = LightPowers::new(raw.clone()).context("bench powers")?;
    let build_batch = (plan.build_budget / n).max(1);
    let reps = if n >= 4_000_000 { 3 } else { plan.repetitions };
    let samples = plan.samples_per_batch;
    let mut cases = Vec::new();
    // The integer table builds on rayon's pool (the rows that report its build); every
    // other figure comes from one thread.
    let pool = rayon::current_num_threads();
    let mut push = |method, rng, build_ns, rebuild_ns, sample_ns| {
        let threads = if ["alias", "alias-batch"].contains(&method) {
            pool
        } else {
            1
        };
        cases.push(Case {
            n,
            method,
            rng,
            build_ns,
            rebuild_ns,
            sample_ns,
            threads,
            build_faults: None,
            rebuild_faults: None,
        });
    };

    // The project's samplers, drawing from the project's Rng (as the renderers do). Each
    // construction: build (allocating), rebuild in place, one pick at a time.
    let other = Distribution::Exponential.powers(n, seed ^ 0x5eed);
    let other = LightPowers::new(other).context("bench powers")?;
    let timed = |construction| {
        time_construction(
            construction,
            &powers,
            &other,
            seed,
            reps,
            build_batch,
            samples,
        )
    };
    let integer = timed(Construction::Integer);
    push(
        "alias",
        "pcg",
        integer.build,
        Some(integer.rebuild),
        integer.sample,
    );
    // The same construction on one thread (the same table, bit for bit).
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .context("a one-thread pool")?;
    let one_thread = single.install(|| timed(Construction::Integer));
    push(
        "alias-1t",
        "pcg",
        one_thread.build,
        Some(one_thread.rebuild),
        one_thread.sample,
    );
    let one_thread_faults = (one_thread.build_faults, one_thread.rebuild_faults);
    drop(one_thread);
    let exact = timed(Construction::Exact);
    push(
        "alias-exact",
        "pcg",
        exact.build,
        Some(exact.rebuild),
        exact.sample,
    );
    drop(exact);
    let (alias_build, alias_rebuild) = (integer.build, integer.rebuild);
    let faults = [
        ("alias", integer.build_faults, integer.rebuild_faults),
        ("alias-1t", one_thread_faults.0, one_thread_faults.1),
    ];
    let table = integer.table;
    let read_floor = random_read_ns(table.packed(), samples.min(1 << 20) as u32, reps);
    // Batched picks into a buffer (the same picks as one at a time on the same stream).
    let mut batch = vec![0u32; samples.min(1 << 16)];
    let batch_sample = median_ns(reps, samples / batch.len(), |rep| {
        let mut rng = Rng::new(seed, rep as u64);
        table.sample_into(&mut batch, &mut rng);
        batch[batch.len() - 1]
    }) / batch.len() as f64;
    push(
        "alias-batch",
        "pcg",
        alias_build,
        Some(alias_rebuild),
        batch_sample,
    );
    let sampler = Sampler::AliasOneRandom(std::sync::Arc::clone(&table));
    push(
        "alias-one-random",
        "pcg",
        alias_build,
        None,
        time_picks(&sampler, seed, reps, samples),
    );
    // The same table drawing from SmallRng, for the comparison with the peers.
    let mut small = SmallRng::seed_from_u64(seed);
    let alias_small = median_ns(reps, samples, |_| {
        let r1 = small.next_u32();
        table.sample_u32(r1, small.next_u32())
    });
    push("alias+smallrng", "SmallRng", alias_build, None, alias_small);
    drop(table);

    let cdf_build = median_ns(reps, build_batch, |_| CdfTable::build(&powers));
    let cdf = Sampler::Cdf(CdfTable::build(&powers));
    push(
        "cdf",
        "pcg",
        cdf_build,
        None,
        time_picks(&cdf, seed, reps, samples),
    );
    drop(cdf);

    let uniform_build = median_ns(reps, build_batch.max(1 << 16), |i| {
        Uniform::new(black_box(n as u32 + (i & 1) as u32))
    });
    let uniform = Sampler::Uniform(Uniform::new(n as u32));
    push(
        "uniform",
        "pcg",
        uniform_build,
        None,
        time_picks(&uniform, seed, reps, samples),
    );

    // The peer takes its weights by value: each timed build gets a clone made beforehand.
    let wai_build = median_with_inputs(
        reps,
        build_batch,
        || raw.clone(),
        rand_distr::weighted::WeightedAliasIndex::new,
    );
    let wai_faults = {
        let inputs: Vec<Vec<f64>> = (0..3).map(|_| raw.clone()).collect();
        let mut inputs = inputs.into_iter();
        faults_per_call(3, || {
            inputs
                .next()
                .map(rand_distr::weighted::WeightedAliasIndex::new)
        })
    };
    let wai = rand_distr::weighted::WeightedAliasIndex::new(raw.clone())
        .map_err(|e| anyhow::anyhow!("WeightedAliasIndex: {e}"))?;
    let mut small = SmallRng::seed_from_u64(seed);
    let wai_sample = median_ns(reps, samples, |_| wai.sample(&mut small));
    push(
        "rand_distr::WeightedAliasIndex",
        "SmallRng",
        wai_build,
        Some(wai_build),
        wai_sample,
    );
    drop(wai);

    let wi_build = median_ns(reps, build_batch, |_| {
        rand::distr::weighted::WeightedIndex::new(&raw)
    });
    let wi = rand::distr::weighted::WeightedIndex::new(&raw)
        .map_err(|e| anyhow::anyhow!("WeightedIndex: {e}"))?;
    let mut small = SmallRng::seed_from_u64(seed);
    let wi_sample = median_ns(reps, samples, |_| wi.sample(&mut small));
    push("rand::WeightedIndex", "SmallRng", wi_build, None, wi_sample);
    for case in &mut cases {
        if let Some(&(_, build, rebuild)) = faults.iter().find(|f| f.0 == case.method) {
            (case.build_faults, case.rebuild_faults) = (build, rebuild);
        } else if case.method == "rand_distr::WeightedAliasIndex" {
            case.build_faults = wai_faults;
        }
    }
    cases.extend(time_tree(n, &powers, &other, seed, reps));
    Ok((cases, read_floor))
}

/// The random-read floor beside the batched pick, and the page faults of the builds.
fn read_floor_text(cases: &[Case], floors: &[(usize, f64)]) -> String {
    let mut out = String::from(
        "\nrandom reads of the table's entries (8 bytes at hashed positions, one thread), \
         beside alias-batch's pick:\n",
    );
    for &(n, ns) in floors {
        let batch = cases
            .iter()
            .find(|c| c.n == n && c.method == "alias-batch")
            .map_or(f64::NAN, |c| c.sample_ns);
        let _ = writeln!(
            out,
            "{n:>9}  {ns:.2} ns per read; alias-batch {batch:.2} ns per pick ({:.2}× the floor)",
            batch / ns
        );
    }
    out.push_str("minor page faults per build / rebuild:\n");
    for c in cases.iter().filter(|c| c.build_faults.is_some()) {
        let rebuild = c
            .rebuild_faults
            .map_or_else(|| "-".to_owned(), |f| format!("{f:.0}"));
        let _ = writeln!(
            out,
            "{:>9}  {:<31} {:>9.0} / {rebuild}",
            c.n,
            c.method,
            c.build_faults.unwrap_or(f64::NAN)
        );
    }
    out
}

/// The light tree at `N` lights spread over a unit square at heights `0.1 … 1`: `tree-build`
/// (layout by positions and lanes, `O(N log N)`), `tree-refit` (new powers, same
/// positions: [`lightpick_core::spatial::LightTree::refit`], `O(N)` bottom up, in `build_ns`)
/// and `app-repower` (the app's whole answer to a power drag, [`time_app_repower`]), each
/// with the time of one pick at a shading point.
fn time_tree(
    n: usize,
    powers: &LightPowers,
    other: &LightPowers,
    seed: u64,
    reps: usize,
) -> Vec<Case> {
    use lightpick_core::spatial::LightTree;
    let unit = |i: usize, salt: u64| {
        f64::from(lightpick_core::pcg_hash(
            (i as u32) ^ (seed as u32) ^ salt as u32,
        )) / f64::from(u32::MAX)
    };
    let positions: Vec<glam::DVec3> = (0..n)
        .map(|i| glam::dvec3(unit(i, 1), unit(i, 2), 0.1 + 0.9 * unit(i, 3)))
        .collect();
    let threads = rayon::current_num_threads();
    let build_ns = median_ns(reps.min(3), 1, |_| LightTree::build(&positions, powers));
    let mut tree = LightTree::build(&positions, powers);
    let refit_ns = median_ns(reps, 1, |rep| {
        tree.refit(if rep % 2 == 0 { other } else { powers });
    });
    let picks = 1 << 16;
    let sample_ns = median_ns(reps, picks, |k| {
        let mut rng = Rng::new(seed, k as u64);
        let x = glam::dvec2(unit(k, 4), unit(k, 5));
        tree.sample(x, &mut rng).map_or(0, |p| p.light)
    });
    let repower_ns = time_app_repower(&positions, powers, other, reps);
    ["tree-build", "tree-refit", "app-repower"]
        .into_iter()
        .zip([build_ns, refit_ns, repower_ns])
        .map(|(method, build_ns)| Case {
            n,
            method,
            rng: "pcg",
            build_ns,
            rebuild_ns: None,
            sample_ns,
            threads,
            build_faults: None,
            rebuild_faults: None,
        })
        .collect()
}

/// The app's answer to a power drag, in `build_ns`: from `AppState::powers_changed` (new
/// powers, same positions) until the rebuilt samplers are installed (validation, the
/// scene's assembly, the table's rebuild and the tree's refit, on the worker thread for
/// large scenes, polled every 0.1 ms as a frame would). The images restart on the next
/// frame.
fn time_app_repower(
    positions: &[glam::DVec3],
    powers: &LightPowers,
    other: &LightPowers,
    reps: usize,
) -> f64 {
    use crate::app::scene_io;
    use crate::app::state::{AppState, Settings};
    let plane = scene_io::seed_scene().plane;
    let scene = scene_io::assemble("bench", plane, positions.to_vec(), powers.clone());
    let mut state = AppState::new(scene, Settings::default());
    let inputs = [other.as_slice(), powers.as_slice()];
    median_ns(reps.min(5), 1, |rep| {
        state.edit.powers_mut().copy_from_slice(inputs[rep % 2]);
        state.powers_changed();
        while state.is_building() {
            std::thread::sleep(std::time::Duration::from_micros(100));
            state.poll_build();
        }
        state.built.generation
    })
}

/// One construction's timings and its table (built from `powers`).
struct ConstructionTimes {
    build: f64,
    rebuild: f64,
    sample: f64,
    /// Minor page faults per build and per rebuild (Linux).
    build_faults: Option<f64>,
    rebuild_faults: Option<f64>,
    table: std::sync::Arc<AliasTable>,
}

/// Times a construction: build (allocating), rebuild in place (alternating `other` and
/// `powers`), and one pick at a time from the table rebuilt on `powers`.
fn time_construction(
    construction: Construction,
    powers: &LightPowers,
    other: &LightPowers,
    seed: u64,
    reps: usize,
    build_batch: usize,
    samples: usize,
) -> ConstructionTimes {
    let build = median_ns(reps, build_batch, |_| {
        AliasTable::build_with(powers, construction)
    });
    let build_faults = faults_per_call(3, || AliasTable::build_with(powers, construction));
    let mut table = AliasTable::build_with(powers, construction);
    let inputs = [other, powers];
    let rebuild = median_ns(reps, build_batch, |i| {
        table.rebuild(inputs[i & 1]);
        table.len()
    });
    let mut k = 0;
    let rebuild_faults = faults_per_call(4, || {
        k += 1;
        table.rebuild(inputs[k & 1]);
    });
    table.rebuild(powers);
    let table = std::sync::Arc::new(table);
    let sampler = Sampler::Alias(std::sync::Arc::clone(&table));
    let sample = time_picks(&sampler, seed, reps, samples);
    ConstructionTimes {
        build,
        rebuild,
        sample,
        build_faults,
        rebuild_faults,
        table,
    }
}

/// Time per pick of `sampler`, drawing from one stream of the project's [`Rng`] per
/// repetition.
fn time_picks(sampler: &Sampler, seed: u64, reps: usize, samples: usize) -> f64 {
    let mut times: Vec<f64> = (0..reps)
        .map(|rep| {
            let mut rng = Rng::new(seed, rep as u64);
            let start = Instant::now();
            let mut acc = 0u32;
            for _ in 0..samples {
                acc = acc.wrapping_add(sampler.pick_light(&mut rng));
            }
            black_box(acc);
            start.elapsed().as_secs_f64() * 1e9 / samples as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Per `N`: how many times slower each peer (and each other project method) is than the
/// alias table, per operation: `build` (peer build over ours), `rebuild` (peer build, which
/// cannot be done in place, over our in-place rebuild), `sample` (one pick; the peers and
/// `alias+smallrng` draw from `SmallRng`, so those ratios compare like with like) and
/// `batch` (one pick over a batched pick of ours). A ratio above 1 means ours is faster.
fn ratios(cases: &[Case]) -> Vec<serde_json::Value> {
    let mut out = Vec::new();
    let mut ns: Vec<usize> = cases.iter().map(|c| c.n).collect();
    ns.dedup();
    for n in ns {
        let of = |m: &str| cases.iter().find(|c| c.n == n && c.method == m);
        let (Some(alias), Some(alias_small), Some(batch)) =
            (of("alias"), of("alias+smallrng"), of("alias-batch"))
        else {
            continue;
        };
        let ratio = |m: &str, base: &Case| {
            of(m).map(|c| {
                json!({
                    "method": m,
                    "build_vs_alias": c.build_ns / alias.build_ns,
                    "rebuild_vs_alias": c.rebuild_ns.map(|r| r / alias.rebuild_ns.unwrap_or(f64::NAN)),
                    "sample_vs_alias": c.sample_ns / base.sample_ns,
                    "sample_vs_alias_batch": c.sample_ns / batch.sample_ns,
                })
            })
        };
        let row: Vec<serde_json::Value> = [
            ratio("rand_distr::WeightedAliasIndex", alias_small),
            ratio("rand::WeightedIndex", alias_small),
            ratio("alias-1t", alias),
            ratio("alias-exact", alias),
            ratio("cdf", alias),
            ratio("alias-one-random", alias),
            ratio("uniform", alias),
        ]
        .into_iter()
        .flatten()
        .collect();
        out.push(json!({ "n": n, "ratios": row }));
    }
    out
}

/// GPU samples per second of the alias histogram, or a note saying why there are none.
fn gpu_rate(quick: bool, seed: u64) -> serde_json::Value {
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
        // The first run compiles the pipeline: not timed.
        if let Err(e) = gpu::histogram(&ctx, &sampler, 1 << 16, seed) {
            return json!({ "adapter": ctx.description(), "note": format!("histogram failed: {e}") });
        }
        let mut times = Vec::new();
        for rep in 0..3u64 {
            let start = Instant::now();
            if let Err(e) = gpu::histogram(&ctx, &sampler, count, seed + rep) {
                return json!({ "adapter": ctx.description(), "note": format!("histogram failed: {e}") });
            }
            times.push(start.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let seconds = times[1];
        rows.push(json!({
            "n": n,
            "method": "alias",
            "count": count,
            "seconds": seconds,
            "samples_per_second": count as f64 / seconds,
        }));
    }
    json!({
        "adapter": ctx.description(),
        "software": ctx.is_software(),
        "note": "includes table upload and readback",
        "cases": rows,
    })
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

/// The efficiency of a zero-variance scheme, with its `log10`: `+inf` (`null` in JSON).
fn infinite_efficiency() -> (Scaled, f64) {
    (Scaled::from_f64(f64::INFINITY), f64::INFINITY)
}

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

fn render_preset(
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
        // The render is deterministic; only its timing varies. Keep the fastest of three
        // runs (the machine may be shared).
        let mut best: Option<(CpuRenderer, Vec<SeriesPoint>)> = None;
        let mut build_seconds = f64::INFINITY;
        let mut core_seconds = f64::INFINITY;
        for _ in 0..RENDER_RUNS {
            let started = Instant::now();
            let mut renderer = CpuRenderer::new(&scene, scheme, seed);
            build_seconds = build_seconds.min(started.elapsed().as_secs_f64());
            // The RMSEs between passes run on this (non-pool) thread: not in the core time.
            let (series, core) =
                pool_core_seconds(|| convergence_series(&mut renderer, &reference, spp));
            core_seconds = core_seconds.min(core);
            let seconds = series.last().map_or(0.0, |p| p.seconds);
            if best
                .as_ref()
                .is_none_or(|(_, b)| b.last().is_some_and(|p| seconds < p.seconds))
            {
                best = Some((renderer, series));
            }
        }
        let Some((renderer, series)) = best else {
            bail!("no render of {name}");
        };
        let samples = f64::from(spp) * f64::from(side) * f64::from(side);
        let seconds = series.last().map_or(0.0, |p| p.seconds);
        let e = efficiency(renderer.accumulator(), seconds);
        let core_efficiency = efficiency_of(e.normalized_variance, core_seconds / samples);
        schemes.push(SchemeRender {
            scheme,
            variance_per_sample: e.variance_per_sample,
            variance_log10: e.variance_log10,
            normalized_variance: e.normalized_variance,
            normalized_variance_log10: e.normalized_variance_log10,
            seconds_per_sample: e.seconds_per_sample,
            core_seconds_per_sample: core_seconds / samples,
            core_efficiency,
            core_efficiency_log10: core_efficiency.log10(),
            efficiency: e.efficiency,
            efficiency_log10: e.efficiency_log10,
            zero_variance: false,
            efficiency_vs_uniform: 0.0,
            rmse: series.last().map_or(0.0, |p| p.rmse),
            rmse_at_equal_time: 0.0,
            build_seconds,
            series,
        });
    }
    let equal_time = schemes
        .iter()
        .filter_map(|s| s.series.last().map(|p| p.seconds))
        .fold(f64::INFINITY, f64::min);
    let uniform_eff = schemes[0].efficiency;
    let uniform_variance = schemes[0].normalized_variance;
    for s in &mut schemes {
        s.rmse_at_equal_time = rmse_at(&s.series, equal_time);
        s.zero_variance = is_zero_variance_scaled(s.normalized_variance, uniform_variance);
        if s.zero_variance {
            (s.efficiency, s.efficiency_log10) = infinite_efficiency();
            (s.core_efficiency, s.core_efficiency_log10) = infinite_efficiency();
        }
        s.efficiency_vs_uniform = (s.efficiency / uniform_eff).to_f64();
    }
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
    pub measured: lightpick_core::render::CpuPassMeasurement,
    /// `1/(V̂·T)` with `T` in core seconds; infinite (`null`) for zero variance, `null`
    /// beyond `f64` too.
    pub efficiency: Scaled,
    /// `log10` of the efficiency, finite whatever its magnitude (`null` when infinite).
    pub efficiency_log10: f64,
    /// Whether `V` is zero up to rounding (the exact spatial pick).
    pub zero_variance: bool,
}

/// The app's CPU images' figures for `presets`: at each preset's own resolution, passes of
/// one sample per pixel (the app's default), core time from the render threads' clocks, the
/// scene's shared table and tree (the app's table construction).
fn app_cpu_renders(
    presets: &[NamedScene],
    seed: u64,
    quick: bool,
) -> anyhow::Result<Vec<AppPresetRender>> {
    let min_seconds = GPU_RENDER_SECONDS[usize::from(quick)];
    presets
        .iter()
        .map(|named| {
            let name = &named.name;
            let scene = std::sync::Arc::clone(&named.scene);
            let samplers = lightpick_core::SceneSamplers::new(
                std::sync::Arc::clone(&scene),
                crate::app::state::construction_for(scene.light_count()),
            );
            let exact_pick = lightpick_core::spatial::uses_exact_pick(scene.light_count());
            let mut schemes: Vec<AppSchemeRender> = GPU_RENDER_SCHEMES
                .iter()
                .map(|&scheme| {
                    let measured = lightpick_core::render::measure_cpu_passes(
                        &samplers,
                        scheme,
                        seed,
                        1,
                        min_seconds,
                        GPU_RENDER_MAX_SPP,
                    );
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
            Ok(AppPresetRender {
                preset: name.clone(),
                size: [scene.plane.width, scene.plane.height],
                threads: rayon::current_num_threads(),
                schemes,
            })
        })
        .collect()
}

/// The app's CPU figures as text.
fn app_renders_text(renders: &[AppPresetRender]) -> String {
    let mut out = String::new();
    for r in renders {
        let _ = writeln!(
            out,
            "\nCPU preset {} as the app renders it ({}×{} px, passes of 1 spp; T = core time \
             per pixel sample: the {} render threads' CPU time)",
            r.preset, r.size[0], r.size[1], r.threads
        );
        let _ = writeln!(
            out,
            "  {:<17} {:>6} {:>12} {:>12} {:>12}",
            "scheme", "spp", "Var/sample", "core ns", "1/(Var·T)"
        );
        for s in &r.schemes {
            let efficiency = if s.zero_variance {
                "inf".to_owned()
            } else {
                format!("{:.4}", s.efficiency)
            };
            let _ = writeln!(
                out,
                "  {:<17} {:>6} {:>12} {:>12.2} {:>12}",
                s.measured.scheme.name(),
                s.measured.spp,
                variance_text(s.measured.variance_per_sample, s.measured.variance_log10),
                s.measured.core_seconds_per_sample * 1e9,
                efficiency
            );
        }
    }
    out
}

/// Pass seconds the GPU renders of one preset and scheme aim at (fewer passes when `--quick`).
const GPU_RENDER_SECONDS: [f64; 2] = [0.5, 0.15];
/// Most samples per pixel of one GPU render.
const GPU_RENDER_MAX_SPP: u32 = 256;
/// The schemes the GPU renders (the app's three images).
const GPU_RENDER_SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

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

/// The GPU renders of `presets` (empty without an adapter): the time per sample the app's
/// GPU images measure, from the device's own clock.
fn gpu_renders(presets: &[NamedScene], seed: u64, quick: bool) -> Vec<GpuPresetRender> {
    let Ok(ctx) = GpuContext::new() else {
        return Vec::new();
    };
    let min_seconds = GPU_RENDER_SECONDS[usize::from(quick)];
    presets
        .iter()
        .map(|named| {
            let (name, scene) = (&named.name, &named.scene);
            let mut out = GpuPresetRender {
                preset: name.clone(),
                adapter: ctx.description(),
                size: [scene.plane.width, scene.plane.height],
                schemes: Vec::new(),
                note: None,
            };
            for scheme in GPU_RENDER_SCHEMES {
                match gpu::measure_passes(
                    &ctx,
                    scene,
                    scheme,
                    seed,
                    1,
                    min_seconds,
                    GPU_RENDER_MAX_SPP,
                ) {
                    Ok(measured) => {
                        let efficiency = efficiency_of(
                            measured.normalized_variance,
                            measured.seconds_per_sample,
                        );
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
        })
        .collect()
}

/// The GPU renders as text: `T` in ns from the device's clock, `V`, efficiency.
fn gpu_renders_text(renders: &[GpuPresetRender]) -> String {
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
            let (efficiency, vs_uniform) = if s.zero_variance {
                ("inf".to_owned(), "inf".to_owned())
            } else {
                (
                    format!("{:.4}", s.efficiency),
                    format!("{:.3e}", s.efficiency_vs_uniform),
                )
            };
            let _ = writeln!(
                out,
                "  {:<17} {:>6} {:>12} {:>12.2} {:>12} {:>9}",
                s.measured.scheme.name(),
                s.measured.spp,
                variance_text(s.measured.variance_per_sample, s.measured.variance_log10),
                s.measured.seconds_per_sample * 1e9,
                efficiency,
                vs_uniform
            );
        }
    }
    out
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

/// What `--plot` drew (`"plot"` in the JSON, `null` without `--plot`).
#[derive(Clone, Debug, Serialize)]
pub struct PlotInfo {
    /// The PNG written.
    pub file: PathBuf,
    /// The preset whose render series it shows.
    pub preset: String,
    /// Schemes left off the axes as zero-variance series
    /// ([`draw::zero_variance_series`]: the exact spatial pick on ≤ 16 lights, whose RMSE
    /// is rounding); the legend names them.
    pub zero_variance: Vec<&'static str>,
}

/// Draws RMSE against seconds per scheme of the heavy-tail render (or the first one), a
/// zero-variance series left off the axes by [`draw::convergence`].
fn write_plot(path: &Path, renders: &[PresetRender]) -> anyhow::Result<PlotInfo> {
    let Some(render) = renders
        .iter()
        .find(|r| r.preset == "heavy-tail")
        .or_else(|| renders.first())
    else {
        bail!("--plot {}: no render to plot", path.display());
    };
    let series: Vec<ConvergenceSeries> = render
        .schemes
        .iter()
        .map(|s| {
            ConvergenceSeries::for_scheme(
                s.scheme,
                s.series
                    .iter()
                    .map(|p| ConvergencePoint {
                        spp: u64::from(p.spp),
                        rmse: p.rmse,
                        seconds: p.seconds,
                    })
                    .collect(),
            )
        })
        .collect();
    let pixmap = draw::convergence(&series, ConvergenceAxis::Seconds, &draw::Style::default())
        .with_context(|| format!("--plot: drawing {}", render.preset))?;
    draw::write_png(&pixmap, path).with_context(|| format!("--plot {}", path.display()))?;
    let zero_variance = render
        .schemes
        .iter()
        .zip(draw::zero_variance_series(&series))
        .filter(|(_, zero)| *zero)
        .map(|(s, _)| s.scheme.name())
        .collect();
    Ok(PlotInfo {
        file: path.to_owned(),
        preset: render.preset.clone(),
        zero_variance,
    })
}

fn text(
    cases: &[Case],
    ratios: &[serde_json::Value],
    gpu: &serde_json::Value,
    renders: &[PresetRender],
    quick: bool,
) -> String {
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
    let _ = writeln!(out, "\nGPU: {}", gpu_text(gpu));
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
            let (efficiency, core_efficiency, vs_uniform) = if s.zero_variance {
                ("inf".to_owned(), "inf".to_owned(), "inf".to_owned())
            } else {
                (
                    format!("{:.4}", s.efficiency),
                    format!("{:.4}", s.core_efficiency),
                    format!("{:.3e}", s.efficiency_vs_uniform),
                )
            };
            let _ = writeln!(
                out,
                "  {:<17} {:>12} {:>12.2} {:>10.2} {:>12} {:>12} {:>9} {:>12.4e} {:>14.4e} {:>10.3}{}",
                s.scheme.name(),
                variance_text(s.variance_per_sample, s.variance_log10),
                s.seconds_per_sample * 1e9,
                s.core_seconds_per_sample * 1e9,
                efficiency,
                core_efficiency,
                vs_uniform,
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

/// The line naming the plot written, if any.
fn plot_text(plot: Option<&PlotInfo>) -> String {
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

fn gpu_text(gpu: &serde_json::Value) -> String {
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
