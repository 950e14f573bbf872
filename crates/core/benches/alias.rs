//! Build, rebuild and sample benchmarks of the alias table against its peers, in one run:
//! `rand_distr::WeightedAliasIndex` (alias peer) and `rand::distr::weighted::WeightedIndex`
//! (CDF peer), plus lightpick's own `CdfTable` and `Uniform`, and the spatial sampler
//! (`SpatialSampler`: the exact pick for `N ≤ 16`, the light tree beyond), whose pick needs a
//! shading point (one per iteration, on a fixed cycle of points).
//!
//! Run with `cargo bench -p lightpick-core --bench alias`; `LIGHTPICK_BENCH_SIZES=3,1000`
//! restricts the sizes.

use glam::{DVec2, DVec3, dvec2, dvec3};
use std::hint::black_box;
use std::time::Duration;

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::{AliasTable, CdfTable, Construction, LightPowers, Rng, Uniform};
use rand::SeedableRng as _;
use rand::distr::Distribution as _;
use rand::distr::weighted::WeightedIndex;
use rand::rngs::SmallRng;
use rand_distr::weighted::WeightedAliasIndex;

fn sizes() -> Vec<usize> {
    std::env::var("LIGHTPICK_BENCH_SIZES")
        .ok()
        .and_then(|s| s.split(',').map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![3, 1_000, 1_000_000, 16_000_000])
}

/// Exponentially distributed powers (a realistic spread), reproducible.
fn powers(n: usize) -> Vec<f64> {
    let mut rng = Rng::new(2024, n as u64);
    (0..n).map(|_| -(1.0 - rng.next_unit()).ln()).collect()
}

/// Light positions in `[-2, 2]² × [0.1, 1]`, reproducible.
fn positions(n: usize) -> Vec<DVec3> {
    let mut rng = Rng::new(2025, n as u64);
    (0..n)
        .map(|_| {
            dvec3(
                4.0 * rng.next_unit() - 2.0,
                4.0 * rng.next_unit() - 2.0,
                0.1 + 0.9 * rng.next_unit(),
            )
        })
        .collect()
}

/// 64 shading points on the plane, cycled through by the spatial pick benchmark.
fn points() -> Vec<DVec2> {
    (0..64)
        .map(|k| {
            let t = f64::from(k);
            dvec2((0.7 * t).sin() * 1.8, (0.3 * t).cos() * 1.8)
        })
        .collect()
}

fn configure(
    c: &mut Criterion,
    n: usize,
) -> criterion::BenchmarkGroup<'_, criterion::measurement::WallTime> {
    let mut group = c.benchmark_group(if n >= 1_000_000 { "large" } else { "small" });
    if n >= 1_000_000 {
        group
            .sample_size(10)
            .measurement_time(Duration::from_secs(4));
    } else {
        group.measurement_time(Duration::from_secs(2));
    }
    group.warm_up_time(Duration::from_millis(500));
    group
}

fn build(c: &mut Criterion) {
    for n in sizes() {
        let weights = powers(n);
        let validated = LightPowers::new(weights.clone()).expect("valid powers");
        let mut group = configure(c, n);
        group.bench_with_input(BenchmarkId::new("build/alias", n), &validated, |b, p| {
            b.iter(|| AliasTable::build(black_box(p)));
        });
        // The same table on one thread (rayon's pool of one): the parallel build's baseline.
        let one_thread = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("a one-thread pool");
        group.bench_with_input(BenchmarkId::new("build/alias-1t", n), &validated, |b, p| {
            b.iter(|| one_thread.install(|| AliasTable::build(black_box(p))));
        });
        group.bench_with_input(
            BenchmarkId::new("build/alias-exact", n),
            &validated,
            |b, p| {
                b.iter(|| AliasTable::build_exact(black_box(p)));
            },
        );
        // In place, alternating between two power sets of the same N (no allocation).
        let other = LightPowers::new(powers(n).into_iter().rev().collect()).expect("valid");
        for construction in Construction::ALL {
            let name = format!("rebuild/alias-{construction}");
            let mut table = AliasTable::build_with(&validated, construction);
            let mut flip = false;
            group.bench_function(BenchmarkId::new(name, n), |b| {
                b.iter(|| {
                    flip = !flip;
                    table.rebuild(if flip { &other } else { &validated });
                });
            });
        }
        let mut table = AliasTable::build(&validated);
        let mut flip = false;
        group.bench_function(BenchmarkId::new("rebuild/alias-integer-1t", n), |b| {
            b.iter(|| {
                flip = !flip;
                one_thread.install(|| table.rebuild(if flip { &other } else { &validated }));
            });
        });
        group.bench_with_input(BenchmarkId::new("build/cdf", n), &validated, |b, p| {
            b.iter(|| CdfTable::build(black_box(p)));
        });
        group.bench_with_input(BenchmarkId::new("build/peer-alias", n), &weights, |b, w| {
            b.iter_batched(
                || w.clone(),
                |w| WeightedAliasIndex::new(w).expect("valid"),
                BatchSize::LargeInput,
            );
        });
        group.bench_with_input(BenchmarkId::new("build/peer-cdf", n), &weights, |b, w| {
            b.iter(|| WeightedIndex::new(black_box(w)).expect("valid"));
        });
        let lights = positions(n);
        group.bench_with_input(BenchmarkId::new("build/spatial", n), &validated, |b, p| {
            b.iter(|| SpatialSampler::build(black_box(&lights), black_box(p)));
        });
        group.finish();
    }
}

fn sample(c: &mut Criterion) {
    for n in sizes() {
        let weights = powers(n);
        let validated = LightPowers::new(weights.clone()).expect("valid powers");
        let alias = AliasTable::build(&validated);
        let cdf = CdfTable::build(&validated);
        let uniform = Uniform::new(n as u32);
        let peer_alias = WeightedAliasIndex::new(weights.clone()).expect("valid");
        let peer_cdf = WeightedIndex::new(&weights).expect("valid");
        let spatial = SpatialSampler::build(&positions(n), &validated);
        drop(weights);
        drop(validated);
        let mut group = configure(c, n);
        // The default pick (exactly uniform column by Lemire's rejection, then the keep test).
        group.bench_function(BenchmarkId::new("sample/alias", n), |b| {
            let mut rng = Rng::new(1, 0);
            b.iter(|| alias.sample(&mut rng));
        });
        // Batched: the same picks as `sample`, 4096 at a time into a buffer.
        group.throughput(criterion::Throughput::Elements(4096));
        group.bench_function(BenchmarkId::new("sample-batch/alias", n), |b| {
            let mut rng = Rng::new(1, 0);
            let mut out = vec![0u32; 4096];
            b.iter(|| {
                alias.sample_into(&mut out, &mut rng);
                out[4095]
            });
        });
        group.throughput(criterion::Throughput::Elements(1));
        // The raw two-draw pick (one multiply-high per column, no rejection).
        group.bench_function(BenchmarkId::new("sample/alias-raw", n), |b| {
            let mut rng = Rng::new(1, 0);
            b.iter(|| alias.sample_u32(rng.next_u32(), rng.next_u32()));
        });
        group.bench_function(BenchmarkId::new("sample/spatial", n), |b| {
            let mut rng = Rng::new(1, 0);
            let at = points();
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) & 63;
                spatial.sample(at[k], &mut rng)
            });
        });
        // Eight shading points at once, their descents interleaved (what the renderer does).
        group.throughput(criterion::Throughput::Elements(8));
        group.bench_function(BenchmarkId::new("sample-many/spatial", n), |b| {
            let at = points();
            let mut k = 0u64;
            b.iter(|| {
                k += 1;
                let first = (k as usize * 8) & 63;
                let batch: [glam::DVec2; 8] = std::array::from_fn(|j| at[(first + j) & 63]);
                let mut rngs: [Rng; 8] = std::array::from_fn(|j| Rng::new(k, j as u64));
                spatial.estimate_many(&batch, &mut rngs)
            });
        });
        group.throughput(criterion::Throughput::Elements(1));
        group.bench_function(BenchmarkId::new("sample/alias-one-random", n), |b| {
            let mut rng = Rng::new(1, 0);
            b.iter(|| alias.sample_one_random(rng.next_u32()));
        });
        group.bench_function(BenchmarkId::new("sample/cdf", n), |b| {
            let mut rng = Rng::new(1, 0);
            b.iter(|| cdf.sample_u32(rng.next_u32()));
        });
        group.bench_function(BenchmarkId::new("sample/uniform", n), |b| {
            let mut rng = Rng::new(1, 0);
            b.iter(|| uniform.sample_u32(rng.next_u32()));
        });
        group.bench_function(BenchmarkId::new("sample/peer-alias", n), |b| {
            let mut rng = SmallRng::seed_from_u64(1);
            b.iter(|| peer_alias.sample(&mut rng));
        });
        group.bench_function(BenchmarkId::new("sample/peer-cdf", n), |b| {
            let mut rng = SmallRng::seed_from_u64(1);
            b.iter(|| peer_cdf.sample(&mut rng));
        });
        group.finish();
    }
}

criterion_group!(benches, build, sample);
criterion_main!(benches);
