//! The table cases: for each `N`, build time, in-place rebuild and time per pick of the
//! alias table (each construction, on rayon's pool and on one thread, batched, one random,
//! drawing from `SmallRng`), the inverse CDF and uniform picking, beside the peers
//! `rand_distr::weighted::WeightedAliasIndex` and `rand::distr::weighted::WeightedIndex`;
//! and the ratios of each method's times over the alias table's.

use std::hint::black_box;
use std::sync::Arc;

use anyhow::Context as _;
use lightpick_core::precision::Distribution;
use lightpick_core::{AliasTable, CdfTable, Construction, LightPowers, Rng, Sampler, Uniform};
use rand::distr::Distribution as _;
use rand::rngs::SmallRng;
use rand::{Rng as _, SeedableRng as _};
use serde_json::json;

use super::case::Case;
use super::machine::{faults_per_call, random_read_ns};
use super::timing::{Plan, median_ns, median_with_inputs, time_picks};
use super::tree::time_tree;

/// What every timing at one `N` shares.
struct At<'a> {
    /// The powers timed (exponential).
    powers: &'a LightPowers,
    /// Other powers of the same `N`, for in-place rebuilds that change something.
    other: &'a LightPowers,
    seed: u64,
    /// Repetitions of each timing.
    reps: usize,
    /// Builds per repetition.
    build_batch: usize,
    /// Picks per repetition.
    samples: usize,
}

/// The cases at one `N`, in the order they are timed.
struct Rows {
    n: usize,
    /// Rayon's pool: the threads of the integer table's build (`alias`, `alias-batch`);
    /// every other figure comes from one thread.
    pool: usize,
    cases: Vec<Case>,
}

impl Rows {
    /// Adds a case (no page faults yet) and returns it.
    fn push(
        &mut self,
        method: &'static str,
        rng: &'static str,
        build_ns: f64,
        rebuild_ns: Option<f64>,
        sample_ns: f64,
    ) -> &mut Case {
        let threads = if ["alias", "alias-batch"].contains(&method) {
            self.pool
        } else {
            1
        };
        self.cases.push(Case {
            n: self.n,
            method,
            rng,
            build_ns,
            rebuild_ns,
            sample_ns,
            threads,
            build_faults: None,
            rebuild_faults: None,
            bytes_per_light: None,
        });
        let last = self.cases.len() - 1;
        &mut self.cases[last]
    }
}

/// Times every method at `N` lights (exponential powers); also returns the random-read
/// floor of the table's own entries ([`random_read_ns`], one thread).
pub(super) fn time_tables(n: usize, seed: u64, plan: Plan) -> anyhow::Result<(Vec<Case>, f64)> {
    let raw = Distribution::Exponential.powers(n, seed);
    let powers = LightPowers::new(raw.clone()).context("bench powers")?;
    let other = Distribution::Exponential.powers(n, seed ^ 0x5eed);
    let other = LightPowers::new(other).context("bench powers")?;
    let at = At {
        powers: &powers,
        other: &other,
        seed,
        reps: if n >= 4_000_000 { 3 } else { plan.repetitions },
        build_batch: (plan.build_budget / n).max(1),
        samples: plan.samples_per_batch,
    };
    let mut rows = Rows {
        n,
        pool: rayon::current_num_threads(),
        cases: Vec::new(),
    };
    let read_floor = time_alias(&mut rows, &at)?;
    time_cdf_and_uniform(&mut rows, &at, n);
    time_peers(&mut rows, &at, &raw)?;
    rows.cases
        .extend(time_tree(n, &powers, &other, seed, at.reps));
    Ok((rows.cases, read_floor))
}

/// The project's alias samplers, drawing from the project's Rng (as the renderers do): each
/// construction built (allocating), rebuilt in place and picked one at a time; the integer
/// table on one thread, batched, with one random, and drawing from `SmallRng`. Returns the
/// random-read floor of the table's entries.
fn time_alias(rows: &mut Rows, at: &At<'_>) -> anyhow::Result<f64> {
    let integer = time_construction(Construction::Integer, at);
    rows.push(
        "alias",
        "pcg",
        integer.build,
        Some(integer.rebuild),
        integer.sample,
    )
    .set_faults(integer.build_faults, integer.rebuild_faults);
    // The same construction on one thread (the same table, bit for bit).
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .context("a one-thread pool")?;
    let one_thread = single.install(|| time_construction(Construction::Integer, at));
    rows.push(
        "alias-1t",
        "pcg",
        one_thread.build,
        Some(one_thread.rebuild),
        one_thread.sample,
    )
    .set_faults(one_thread.build_faults, one_thread.rebuild_faults);
    drop(one_thread);
    let exact = time_construction(Construction::Exact, at);
    rows.push(
        "alias-exact",
        "pcg",
        exact.build,
        Some(exact.rebuild),
        exact.sample,
    );
    drop(exact);
    let (alias_build, alias_rebuild) = (integer.build, integer.rebuild);
    let table = integer.table;
    let (reps, samples, seed) = (at.reps, at.samples, at.seed);
    let read_floor = random_read_ns(table.packed(), samples.min(1 << 20) as u32, reps);
    // Batched picks into a buffer (the same picks as one at a time on the same stream).
    let mut batch = vec![0u32; samples.min(1 << 16)];
    let batch_sample = median_ns(reps, samples / batch.len(), |rep| {
        let mut rng = Rng::new(seed, rep as u64);
        table.sample_into(&mut batch, &mut rng);
        batch[batch.len() - 1]
    }) / batch.len() as f64;
    rows.push(
        "alias-batch",
        "pcg",
        alias_build,
        Some(alias_rebuild),
        batch_sample,
    );
    let sampler = Sampler::AliasOneRandom(Arc::clone(&table));
    rows.push(
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
    rows.push("alias+smallrng", "SmallRng", alias_build, None, alias_small);
    Ok(read_floor)
}

/// The inverse CDF (build and pick) and uniform picking at `n` lights.
fn time_cdf_and_uniform(rows: &mut Rows, at: &At<'_>, n: usize) {
    let (reps, samples, seed) = (at.reps, at.samples, at.seed);
    let cdf_build = median_ns(reps, at.build_batch, |_| CdfTable::build(at.powers));
    let cdf = Sampler::Cdf(CdfTable::build(at.powers));
    rows.push(
        "cdf",
        "pcg",
        cdf_build,
        None,
        time_picks(&cdf, seed, reps, samples),
    );
    drop(cdf);

    let uniform_build = median_ns(reps, at.build_batch.max(1 << 16), |i| {
        Uniform::new(black_box(n as u32 + (i & 1) as u32))
    });
    let uniform = Sampler::Uniform(Uniform::new(n as u32));
    rows.push(
        "uniform",
        "pcg",
        uniform_build,
        None,
        time_picks(&uniform, seed, reps, samples),
    );
}

/// The peers, drawing from `SmallRng`: `rand_distr`'s alias table (whose rebuild is its
/// build, with its page faults) and `rand`'s weighted index, built from `raw`.
fn time_peers(rows: &mut Rows, at: &At<'_>, raw: &[f64]) -> anyhow::Result<()> {
    use rand::distr::weighted::WeightedIndex;
    use rand_distr::weighted::WeightedAliasIndex;
    let (reps, samples, seed) = (at.reps, at.samples, at.seed);
    // The peer takes its weights by value: each timed build gets a clone made beforehand.
    let wai_build = median_with_inputs(
        reps,
        at.build_batch,
        || raw.to_vec(),
        WeightedAliasIndex::new,
    );
    let wai_faults = {
        let inputs: Vec<Vec<f64>> = (0..3).map(|_| raw.to_vec()).collect();
        let mut inputs = inputs.into_iter();
        faults_per_call(3, || inputs.next().map(WeightedAliasIndex::new))
    };
    let wai = WeightedAliasIndex::new(raw.to_vec())
        .map_err(|e| anyhow::anyhow!("WeightedAliasIndex: {e}"))?;
    let mut small = SmallRng::seed_from_u64(seed);
    let wai_sample = median_ns(reps, samples, |_| wai.sample(&mut small));
    rows.push(
        "rand_distr::WeightedAliasIndex",
        "SmallRng",
        wai_build,
        Some(wai_build),
        wai_sample,
    )
    .build_faults = wai_faults;
    drop(wai);

    let wi_build = median_ns(reps, at.build_batch, |_| WeightedIndex::new(raw));
    let wi = WeightedIndex::new(raw).map_err(|e| anyhow::anyhow!("WeightedIndex: {e}"))?;
    let mut small = SmallRng::seed_from_u64(seed);
    let wi_sample = median_ns(reps, samples, |_| wi.sample(&mut small));
    rows.push("rand::WeightedIndex", "SmallRng", wi_build, None, wi_sample);
    Ok(())
}

/// One construction's timings and its table (built from `powers`).
struct ConstructionTimes {
    build: f64,
    rebuild: f64,
    sample: f64,
    /// Minor page faults per build and per rebuild (Linux).
    build_faults: Option<f64>,
    rebuild_faults: Option<f64>,
    table: Arc<AliasTable>,
}

/// Times a construction: build (allocating), rebuild in place (alternating `other` and
/// `powers`), and one pick at a time from the table rebuilt on `powers`.
fn time_construction(construction: Construction, at: &At<'_>) -> ConstructionTimes {
    let (powers, reps, build_batch) = (at.powers, at.reps, at.build_batch);
    let build = median_ns(reps, build_batch, |_| {
        AliasTable::build_with(powers, construction)
    });
    let build_faults = faults_per_call(3, || AliasTable::build_with(powers, construction));
    let mut table = AliasTable::build_with(powers, construction);
    let inputs = [at.other, powers];
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
    let table = Arc::new(table);
    let sampler = Sampler::Alias(Arc::clone(&table));
    let sample = time_picks(&sampler, at.seed, reps, at.samples);
    ConstructionTimes {
        build,
        rebuild,
        sample,
        build_faults,
        rebuild_faults,
        table,
    }
}

/// Per `N`: how many times slower each peer (and each other project method) is than the
/// alias table, per operation: `build` (peer build over ours), `rebuild` (peer build, which
/// cannot be done in place, over our in-place rebuild), `sample` (one pick; the peers and
/// `alias+smallrng` draw from `SmallRng`, so those ratios compare like with like) and
/// `batch` (one pick over a batched pick of ours). A ratio above 1 means ours is faster.
pub(super) fn ratios(cases: &[Case]) -> Vec<serde_json::Value> {
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
