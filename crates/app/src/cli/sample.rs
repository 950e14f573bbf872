//! `lightpick sample`: draw light indices and test the counts against the pmf.

use std::fmt::Write as _;

use anyhow::bail;
use clap::Args;
use lightpick_core::{
    ChiSquare, Construction, LightPowers, PointFreeSampler as _, Rng, Sampler, Scheme, chi_square,
};
use rayon::prelude::*;
use serde_json::json;

use super::device::{Device, choose};
use super::input::PowersArgs;

/// The largest `--count` accepted (about a minute of CPU sampling on two cores).
pub(crate) const MAX_COUNT: u64 = 100_000_000_000;

/// Arguments of `lightpick sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// Where the powers come from.
    #[command(flatten)]
    pub powers: PowersArgs,
    /// uniform, alias (or power), alias-one-random, cdf.
    #[arg(long, default_value = "alias")]
    pub scheme: Scheme,
    /// Number of samples to draw.
    #[arg(long, default_value_t = 1_000_000)]
    pub count: u64,
    /// Random seed; sample k uses stream k of this seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// How the alias table is built: `exact` (`f64`: the normalized powers `p_i` to within
    /// rounding) or `integer` (the renderers' default; its pmf is the one it realizes exactly).
    #[arg(long, default_value = "exact")]
    pub construction: Construction,
    /// Where to draw the samples (default: the CPU). GPU counts equal CPU counts exactly.
    #[arg(long, value_enum, default_value_t = Device::Cpu)]
    pub device: Device,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Draws the samples and prints the counts and the chi-square test.
pub fn run(args: &SampleArgs) -> anyhow::Result<()> {
    check_count(args.count)?;
    let powers = args.powers.load()?;
    let sampler = Sampler::try_build_with(args.scheme, &powers, args.construction)?;
    let counts = match choose(Some(args.device), true)? {
        None => count_cpu(&sampler, args.count, args.seed),
        Some(ctx) => lightpick_core::gpu::histogram(&ctx, &sampler, args.count, args.seed)
            .map_err(|e| anyhow::anyhow!("--device gpu: {e}"))?,
    };
    let expected: Vec<f64> = (0..sampler.light_count())
        .map(|i| sampler.probability(i))
        .collect();
    let test = chi_square(&counts, &expected);
    if args.json {
        super::print_json(&json!({
            "scheme": args.scheme.name(),
            "construction": args.construction.name(),
            "device": args.device.name(),
            "count": args.count,
            "seed": args.seed,
            "counts": counts,
            "expected": expected,
            "chi2": test.chi2,
            "dof": test.dof,
            "p_value": test.p_value,
        }))
    } else {
        print!("{}", sample_text(args, &powers, &counts, &expected, test));
        Ok(())
    }
}

/// Refuses a zero or absurd `--count`.
pub(crate) fn check_count(count: u64) -> anyhow::Result<()> {
    if count == 0 || count > MAX_COUNT {
        bail!("--count must be between 1 and {MAX_COUNT} (got {count})");
    }
    Ok(())
}

/// Counts how often each light is picked by samples `0..count` (sample `k` draws from
/// `Rng::new(seed, k)`), in parallel; identical for any thread count. Each chunk of samples
/// counts into its own `N` bins, so there are no more chunks than `count / N` (a chunk's bins
/// never cost more than its samples: 2^25 lights take one chunk, not eight of 256 MB).
pub fn count_cpu(sampler: &Sampler, count: u64, seed: u64) -> Vec<u64> {
    let n = sampler.light_count();
    let chunks = (rayon::current_num_threads().max(1) as u64 * 4).min((count / n as u64).max(1));
    let per_chunk = count.div_ceil(chunks);
    (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut local = vec![0u64; n];
            let end = ((c + 1) * per_chunk).min(count);
            for k in (c * per_chunk).min(end)..end {
                local[sampler.pick_light(&mut Rng::new(seed, k)) as usize] += 1;
            }
            local
        })
        .reduce(
            || vec![0u64; n],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                a
            },
        )
}

fn sample_text(
    args: &SampleArgs,
    powers: &LightPowers,
    counts: &[u64],
    expected: &[f64],
    test: ChiSquare,
) -> String {
    const ROWS: usize = 32;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} samples of {} lights, scheme {}, seed {}, device {}",
        args.count,
        counts.len(),
        args.scheme,
        args.seed,
        args.device.name()
    );
    let _ = writeln!(
        out,
        "{:>7}  {:>12}  {:>12}  {:>12}  {:>12}",
        "light", "power", "expected", "count", "frequency"
    );
    let n = args.count as f64;
    for i in 0..counts.len().min(ROWS) {
        let _ = writeln!(
            out,
            "{:>7}  {:>12}  {:>12.6}  {:>12}  {:>12.6}",
            i,
            powers.as_slice()[i],
            expected[i],
            counts[i],
            counts[i] as f64 / n
        );
    }
    if counts.len() > ROWS {
        let _ = writeln!(out, "… {} more lights (use --json)", counts.len() - ROWS);
    }
    let _ = writeln!(
        out,
        "chi-square {:.4} with {} degrees of freedom: p-value {:.4}",
        test.chi2, test.dof, test.p_value
    );
    out
}
