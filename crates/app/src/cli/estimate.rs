//! `lightpick estimate`: the one-sample estimator `f(I)/p(I)` averaged over many samples.

use anyhow::bail;
use clap::Args;
use lightpick_core::{
    Construction, LightSampler as _, Rng, Sampler, Scheme, Welford, analytic_moments,
};
use rayon::prelude::*;
use serde_json::json;

use super::input::{PowersArgs, parse_numbers};
use super::sample::check_count;

/// Arguments of `lightpick estimate`.
#[derive(Debug, Args)]
pub struct EstimateArgs {
    /// Where the powers come from.
    #[command(flatten)]
    pub powers: PowersArgs,
    /// Each light's contribution at the shading point, comma separated (e.g. 1,2,15).
    #[arg(long, value_name = "LIST", allow_hyphen_values = true)]
    pub contrib: String,
    /// uniform, alias (or power), alias-one-random, cdf.
    #[arg(long, default_value = "alias")]
    pub scheme: Scheme,
    /// Number of samples.
    #[arg(long, default_value_t = 1_000_000)]
    pub count: u64,
    /// Random seed; sample k uses stream k of this seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// How the alias table is built: `exact` (`f64`, the pmf `p_i` the seed document
    /// gives) or `integer` (the renderers' default; its pmf is the one it realizes exactly).
    #[arg(long, default_value = "exact")]
    pub construction: Construction,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs the estimator and prints its mean, the exact sum and both variances.
pub fn run(args: &EstimateArgs) -> anyhow::Result<()> {
    check_count(args.count)?;
    let powers = args.powers.load()?;
    let contrib = parse_numbers(&args.contrib, false, "--contrib")?;
    if contrib.len() != powers.len() {
        bail!(
            "--contrib has {} values but there are {} lights",
            contrib.len(),
            powers.len()
        );
    }
    if let Some(i) = contrib.iter().position(|f| !f.is_finite()) {
        bail!("--contrib: item {i} is not finite ({})", contrib[i]);
    }
    let sampler = Sampler::try_build_with(args.scheme, &powers, args.construction)?;
    let stats = estimate(&sampler, &contrib, args.count, args.seed);
    let moments = analytic_moments(&contrib, |i| sampler.probability(i));
    let z = if stats.std_error() > 0.0 {
        (stats.mean() - moments.mean) / stats.std_error()
    } else {
        0.0
    };
    if args.json {
        super::print_json(&json!({
            "scheme": args.scheme.name(),
            "construction": args.construction.name(),
            "count": args.count,
            "seed": args.seed,
            "mean": stats.mean(),
            "exact": moments.exact,
            "bias": moments.bias(),
            "variance": stats.variance(),
            "analytic_variance": moments.variance,
            "std_error": stats.std_error(),
            "z_score": z,
        }))
    } else {
        println!(
            "{} samples, scheme {}, seed {}",
            args.count, args.scheme, args.seed
        );
        println!(
            "mean      {:.6} ± {:.6} (standard error)",
            stats.mean(),
            stats.std_error()
        );
        println!("exact     {:.6}", moments.exact);
        if moments.bias() != 0.0 {
            println!(
                "bias      {:.6} (a light with f ≠ 0 is never picked)",
                moments.bias()
            );
        }
        println!(
            "variance  {:.6} per sample (analytic {:.6})",
            stats.variance(),
            moments.variance
        );
        println!("z-score   {z:.3} (mean − expected, in standard errors)");
        Ok(())
    }
}

/// Averages `f(I)/p(I)` over samples `0..count` (sample `k` picks from `Rng::new(seed, k)`).
pub fn estimate(sampler: &Sampler, contrib: &[f64], count: u64, seed: u64) -> Welford {
    let chunks = rayon::current_num_threads().max(1) as u64 * 4;
    let per_chunk = count.div_ceil(chunks);
    (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut w = Welford::new();
            let end = ((c + 1) * per_chunk).min(count);
            for k in (c * per_chunk).min(end)..end {
                let pick = sampler.pick(&mut Rng::new(seed, k));
                w.push(contrib[pick.light as usize] / pick.probability);
            }
            w
        })
        .reduce(Welford::new, |a, b| a.merge(&b))
}
