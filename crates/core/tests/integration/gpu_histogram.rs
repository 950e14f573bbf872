//! GPU pick histograms equal the CPU loop over `Sampler::pick_light`, bin for bin.

use crate::common;

use crate::common::SplitMix;
use lightpick_core::gpu::{GpuError, histogram, histogram_range, histogram_range_split};
use lightpick_core::{LightPowers, Rng, Sampler, Scheme, rejection_threshold};

const GPU_SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::AliasOneRandom];

/// The reference: sample `k` of `first..first + count` picks from `Rng::new(seed, k)`.
fn cpu_counts(sampler: &Sampler, n: usize, first: u64, count: u64, seed: u64) -> Vec<u64> {
    let mut counts = vec![0u64; n];
    for j in 0..count {
        let mut rng = Rng::new(seed, first.wrapping_add(j));
        counts[sampler.pick_light(&mut rng) as usize] += 1;
    }
    counts
}

/// `n` powers spanning many orders of magnitude, about a third of them zero.
fn random_powers(n: usize, seed: u64) -> Vec<f64> {
    let mut draw = SplitMix(seed);
    (0..n)
        .map(|_| {
            if draw.next_f64() < 0.3 {
                0.0
            } else {
                10f64.powf(draw.range(-6.0, 6.0))
            }
        })
        .collect()
}

fn check_equal_counts(powers: &[f64], count: u64, seed: u64) {
    let Some(ctx) = common::context() else {
        return;
    };
    let powers = LightPowers::new(powers.to_vec()).expect("valid powers");
    for scheme in GPU_SCHEMES {
        let sampler = Sampler::build(scheme, &powers);
        let gpu = histogram(ctx, &sampler, count, seed).expect("GPU histogram");
        let cpu = cpu_counts(&sampler, powers.len(), 0, count, seed);
        assert_eq!(gpu.iter().sum::<u64>(), count, "{scheme}: total");
        if let Some(i) = (0..cpu.len()).find(|&i| gpu[i] != cpu[i]) {
            panic!(
                "{scheme}: light {i} counted {} on the GPU, {} on the CPU",
                gpu[i], cpu[i]
            );
        }
        if scheme.is_power_proportional() {
            for (i, &p) in powers.as_slice().iter().enumerate() {
                if p == 0.0 {
                    assert_eq!(gpu[i], 0, "{scheme}: zero-power light {i} was picked");
                }
            }
        }
    }
}

#[test]
fn seed_powers_count_exactly_like_the_cpu() {
    // Three bins: the workgroup-memory path.
    check_equal_counts(&[2.0, 5.0, 20.0], 300_000, 7);
}

#[test]
fn random_powers_with_zeros_count_exactly_like_the_cpu() {
    // 3000 bins: more than the 2048 workgroup bins, so the global-atomics path.
    check_equal_counts(&random_powers(3000, 11), 400_000, 12345);
}

#[test]
fn a_thousand_lights_with_zeros_count_exactly_like_the_cpu() {
    // 1000 bins: the workgroup-memory path with many bins.
    check_equal_counts(&random_powers(1000, 5), 200_000, u64::MAX - 3);
}

/// `N = ⌈2^32/2000⌉ = 2 147 484`: `t = 2^32 mod N = 2 146 780` is almost `N`, so Lemire's
/// column pick rejects a first draw with probability `t/2^32 ≈ 5·10⁻⁴`, the most a table
/// this size allows. 10^6 samples hit the loop about 500 times; the GPU must follow every
/// extra draw exactly as the CPU does, for the uniform and the alias scheme.
#[test]
fn rejected_column_draws_count_exactly_like_the_cpu() {
    let n: u32 = 2_147_484;
    let t = rejection_threshold(n);
    assert_eq!(t, 2_146_780);
    let (count, seed) = (1_000_000u64, 31);
    let rejected = (0..count)
        .filter(|&k| {
            let r = Rng::new(seed, k).next_u32();
            ((u64::from(r) * u64::from(n)) as u32) < t
        })
        .count();
    eprintln!("{rejected} of {count} samples reject their first draw");
    assert!(rejected > 300, "{rejected}");
    check_equal_counts(&random_powers(n as usize, 8), count, seed);
}

#[test]
fn split_dispatches_and_the_64_bit_carry_match_the_cpu() {
    let Some(ctx) = common::context() else {
        return;
    };
    let powers = LightPowers::new(random_powers(257, 3)).expect("valid powers");
    // Samples 2^32 − 5000 .. 2^32 + 5000 − 1 in dispatches of 999: the stream index's low
    // word wraps inside a dispatch, so the WGSL carry into the high word is exercised.
    let first = (1u64 << 32) - 5000;
    for scheme in GPU_SCHEMES {
        let sampler = Sampler::build(scheme, &powers);
        let gpu = histogram_range_split(ctx, &sampler, first, 10_000, 99, 999).expect("split");
        let cpu = cpu_counts(&sampler, powers.len(), first, 10_000, 99);
        assert_eq!(gpu, cpu, "{scheme}: split across the 2^32 boundary");
        // Also across the end of the u64 range, where the index wraps to 0.
        let gpu = histogram_range(ctx, &sampler, u64::MAX - 99, 200, 5).expect("wrap");
        let cpu = cpu_counts(&sampler, powers.len(), u64::MAX - 99, 200, 5);
        assert_eq!(gpu, cpu, "{scheme}: across 2^64");
    }
}

#[test]
fn zero_samples_give_zero_counts() {
    let Some(ctx) = common::context() else {
        return;
    };
    let powers = LightPowers::new(vec![1.0, 2.0]).expect("valid powers");
    let sampler = Sampler::build(Scheme::Alias, &powers);
    assert_eq!(histogram(ctx, &sampler, 0, 1).expect("empty"), vec![0, 0]);
}

#[test]
fn cdf_is_refused_with_a_clear_message() {
    let Some(ctx) = common::context() else {
        return;
    };
    let powers = LightPowers::new(vec![2.0, 5.0, 20.0]).expect("valid powers");
    let sampler = Sampler::build(Scheme::Cdf, &powers);
    let err = histogram(ctx, &sampler, 100, 1).expect_err("cdf has no GPU path");
    assert!(
        matches!(
            err,
            GpuError::UnsupportedScheme {
                scheme: Scheme::Cdf,
                ..
            }
        ),
        "{err:?}"
    );
    let message = err.to_string();
    assert!(
        message.contains("'cdf'") && message.contains("GPU"),
        "{message}"
    );
}
