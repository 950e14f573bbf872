//! The WGSL RNG prelude equals the CPU `Rng`, the CPU multiply-high and the CPU exact
//! uniform pick (Lemire's rejection loop included), bit for bit.

use crate::common;

use crate::common::SplitMix;
use lightpick_core::gpu::{probe_mulhi32, probe_pick_uniform, probe_rng};
use lightpick_core::{Rng, Uniform};

const DRAWS: u32 = 8;

#[test]
fn gpu_rng_streams_equal_cpu_bit_for_bit() {
    let Some(ctx) = common::context() else {
        return;
    };
    let seeds = [
        0,
        1,
        42,
        0xdead_beef,
        1 << 32,
        0xffff_ffff_0000_0001,
        u64::MAX,
    ];
    let streams = [
        0,
        1,
        2,
        (1 << 32) - 1,
        1 << 32,
        (1 << 32) + 1,
        (7 << 32) | 0x3039, // a renderer stream: sample 7 of pixel 12345
        1 << 63,
        u64::MAX - 1,
        u64::MAX,
    ];
    let mut pairs: Vec<(u64, u64)> = seeds
        .iter()
        .flat_map(|&seed| streams.iter().map(move |&stream| (seed, stream)))
        .collect();
    let mut draw = SplitMix(2024);
    pairs.extend((0..5000).map(|_| (draw.next_u64(), draw.next_u64())));
    let gpu = probe_rng(ctx, &pairs, DRAWS).expect("probe_rng");
    assert_eq!(gpu.len(), pairs.len() * DRAWS as usize);
    for (i, &(seed, stream)) in pairs.iter().enumerate() {
        let mut rng = Rng::new(seed, stream);
        for d in 0..DRAWS as usize {
            let cpu = rng.next_u32();
            assert_eq!(
                gpu[i * DRAWS as usize + d],
                cpu,
                "draw {d} of seed {seed:#x}, stream {stream:#x}"
            );
        }
    }
    // The streams really differ (a probe that ignored its input would fail here).
    let mut first: Vec<u32> = gpu.iter().step_by(DRAWS as usize).copied().collect();
    first.sort_unstable();
    first.dedup();
    assert!(
        first.len() > pairs.len() * 99 / 100,
        "{} distinct",
        first.len()
    );
}

#[test]
fn gpu_mulhi32_equals_the_64_bit_product() {
    let Some(ctx) = common::context() else {
        return;
    };
    let edges = [
        0u32,
        1,
        2,
        3,
        0xfffe,
        0xffff,
        0x1_0000,
        0x1_0001,
        0x7fff_ffff,
        0x8000_0000,
        0x8000_0001,
        0xffff_0000,
        0xffff_0001,
        0xfffe_ffff,
        u32::MAX - 1,
        u32::MAX,
        1_000_000,
        2_147_483_647,
    ];
    let mut pairs: Vec<(u32, u32)> = edges
        .iter()
        .flat_map(|&a| edges.iter().map(move |&b| (a, b)))
        .collect();
    let mut draw = SplitMix(77);
    pairs.extend((0..20_000).map(|_| {
        let x = draw.next_u64();
        (x as u32, (x >> 32) as u32)
    }));
    let gpu = probe_mulhi32(ctx, &pairs).expect("probe_mulhi32");
    assert_eq!(gpu.len(), pairs.len());
    for (&(a, b), &(hi, lo)) in pairs.iter().zip(&gpu) {
        let product = u64::from(a) * u64::from(b);
        assert_eq!(hi, (product >> 32) as u32, "high word of {a:#x}·{b:#x}");
        assert_eq!(lo, product as u32, "low word of {a:#x}·{b:#x}");
    }
    // u32::MAX² = 2^64 − 2^33 + 1: the high word is 2^32 − 2.
    let max = pairs.iter().position(|&p| p == (u32::MAX, u32::MAX));
    assert_eq!(max.map(|i| gpu[i]), Some((u32::MAX - 1, 1)));
}

#[test]
fn empty_probes_return_nothing() {
    let Some(ctx) = common::context() else {
        return;
    };
    assert!(probe_rng(ctx, &[], 4).expect("empty rng probe").is_empty());
    assert!(
        probe_mulhi32(ctx, &[])
            .expect("empty mulhi probe")
            .is_empty()
    );
}

/// `pick_uniform` in WGSL equals `Uniform::sample` for `N` where Lemire's loop runs often
/// (`N = 2^31 + 1` rejects almost half of all draws, `u32::MAX` only `r = 0`) and for table
/// sizes: the same pick and the same next draw, so the same number of draws was consumed.
#[test]
fn gpu_exact_uniform_pick_equals_cpu_including_rejections() {
    let Some(ctx) = common::context() else {
        return;
    };
    let mut draw = SplitMix(77);
    let pairs: Vec<(u64, u64)> = (0..20_000)
        .map(|_| (draw.next_u64(), draw.next_u64()))
        .collect();
    for n in [
        1u32,
        3,
        5,
        1000,
        1_000_003,
        (1 << 31) + 1,
        (1 << 31) + (1 << 30),
        3_000_000_019,
        u32::MAX,
        1 << 20,
    ] {
        let uniform = Uniform::new(n);
        let t = uniform.rejection_threshold();
        let gpu = probe_pick_uniform(ctx, &pairs, n).expect("probe_pick_uniform");
        let mut rejected = 0usize;
        let mut max_draws = 0usize;
        for (&(seed, stream), &(pick, next)) in pairs.iter().zip(&gpu) {
            let mut rng = Rng::new(seed, stream);
            assert_eq!(
                pick,
                uniform.sample(&mut rng),
                "N {n}, seed {seed:#x}, stream {stream:#x}"
            );
            assert_eq!(
                next,
                rng.next_u32(),
                "N {n}: draws consumed, stream {stream:#x}"
            );
            // How many draws the CPU pick took, counted independently of Uniform::sample.
            let mut count = Rng::new(seed, stream);
            let mut draws = 1;
            while ((u64::from(count.next_u32()) * u64::from(n)) as u32) < t {
                draws += 1;
            }
            rejected += usize::from(draws > 1);
            max_draws = max_draws.max(draws);
        }
        eprintln!(
            "N = {n}: t = {t}, {rejected} of {} picks rejected a draw, at most {max_draws} draws",
            pairs.len()
        );
        if u64::from(t) * 20_000 > 1 << 36 {
            // t/2^32 > 1/3: thousands of picks hit the loop, many more than once.
            assert!(
                rejected > 5000 && max_draws >= 4,
                "N {n}: {rejected}, {max_draws}"
            );
        }
    }
}
