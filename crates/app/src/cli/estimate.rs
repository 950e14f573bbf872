//! `lightpick estimate`: the one-sample estimator `f(I)/p(I)` averaged over many samples.

use anyhow::bail;
use clap::Args;
use lightpick_core::point_estimate::sampled_mean;
use lightpick_core::{
    Construction, PointFreeSampler as _, Sampler, Scaled, Scheme, analytic_moments,
};
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
    /// How the alias table is built: `exact` (`f64`: the normalized powers `p_i` to within
    /// rounding) or `integer` (the renderers' default; its pmf is the one it realizes exactly).
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
    let stats = sampled_mean(&sampler, &contrib, args.count, args.seed);
    let moments = analytic_moments(&contrib, |i| sampler.probability(i));
    // In the samples' unit, so that the z-score is the same at any scale.
    let unit = Scaled::pow2(-stats.unit_exponent());
    let std_error_in_unit = (stats.std_error_scaled() * unit).to_f64();
    let z = if std_error_in_unit > 0.0 {
        (stats.mean_in_unit() - (Scaled::from_f64(moments.mean) * unit).to_f64())
            / std_error_in_unit
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
            "variance": stats.variance_scaled(),
            "variance_log10": stats.variance_scaled().log10(),
            "analytic_variance": moments.variance_scaled,
            "analytic_variance_log10": moments.variance_scaled.log10(),
            "std_error": stats.std_error_scaled(),
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
            fixed6(stats.std_error_scaled())
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
            fixed6(stats.variance_scaled()),
            fixed6(moments.variance_scaled)
        );
        println!("z-score   {z:.3} (mean − expected, in standard errors)");
        Ok(())
    }
}

/// `{:.6}` of a figure that fits `f64`, else its `m.mmmmmme±X` form (a variance of
/// contributions near `10^200`).
fn fixed6(x: Scaled) -> String {
    x.as_f64()
        .map_or_else(|| format!("{x:.6}"), |plain| format!("{plain:.6}"))
}
