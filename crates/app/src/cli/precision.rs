//! `lightpick precision`: the precision lab's figures (see `lightpick_core::precision`).

use std::fmt::Write as _;

use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::LightPowers;
use lightpick_core::precision::{
    COLUMN_SWEEP, ColumnPickComparison, Distribution, F32_SPLIT_ERROR, PrecisionReport,
    U32_SPLIT_ERROR, column_pick_sweep,
};
use serde_json::json;

use super::input::PowersArgs;

/// The largest `--n` accepted (`2^28`: a few GiB of tables at most).
pub(crate) const MAX_N: usize = 1 << 28;

/// Arguments of `lightpick precision`.
#[derive(Debug, Args)]
pub struct PrecisionArgs {
    /// Number of lights drawn from each distribution.
    #[arg(long, default_value_t = 1_000_003)]
    pub n: usize,
    /// uniform, exponential, pareto, with-zeros, log-uniform, or all.
    #[arg(long, default_value = "all")]
    pub distribution: String,
    /// Seed of the drawn powers (light i uses stream i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Measure these powers instead of drawn ones.
    #[command(flatten)]
    pub powers: PowersArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Measures and prints the figures.
pub fn run(args: &PrecisionArgs) -> anyhow::Result<()> {
    let reports = measure(args)?;
    let mut sweep_n: Vec<u32> = COLUMN_SWEEP.to_vec();
    if let Some(r) = reports.first()
        && let Ok(n) = u32::try_from(r.n)
        && !sweep_n.contains(&n)
    {
        sweep_n.push(n);
        sweep_n.sort_unstable();
    }
    let sweep = column_pick_sweep(&sweep_n);
    if args.json {
        super::print_json(&json!({
            "seed": args.seed,
            "u32_split_error": U32_SPLIT_ERROR,
            "f32_split_error": F32_SPLIT_ERROR,
            "reports": reports,
            "column_pick": sweep,
        }))
    } else {
        print!("{}", text(&reports, &sweep));
        Ok(())
    }
}

/// The reports: one for `--powers`/`--powers-file`, else one per chosen distribution.
fn measure(args: &PrecisionArgs) -> anyhow::Result<Vec<PrecisionReport>> {
    if args.powers.powers.is_some() || args.powers.powers_file.is_some() {
        let powers = args.powers.load()?;
        return Ok(vec![PrecisionReport::measure(&powers, None)]);
    }
    if args.n == 0 || args.n > MAX_N {
        bail!("--n must be between 1 and {MAX_N} (got {})", args.n);
    }
    let distributions: Vec<Distribution> = if args.distribution == "all" {
        Distribution::ALL.to_vec()
    } else {
        vec![
            args.distribution
                .parse()
                .context("--distribution (or all)")?,
        ]
    };
    distributions
        .into_iter()
        .map(|d| {
            let powers = LightPowers::new(d.powers(args.n, args.seed))
                .with_context(|| format!("{} powers for --n {}", d, args.n))?;
            Ok(PrecisionReport::measure(&powers, Some(d)))
        })
        .collect()
}

/// The text report of `lightpick precision`, its four sections in order.
fn text(reports: &[PrecisionReport], sweep: &[ColumnPickComparison]) -> String {
    let mut out = String::new();
    construction_text(&mut out, reports);
    thresholds_text(&mut out, reports);
    column_pick_text(&mut out, sweep);
    one_random_text(&mut out, reports);
    out
}

/// Section 1: each construction's worst pmf error and its leak onto zero-power lights.
fn construction_text(out: &mut String, reports: &[PrecisionReport]) {
    let _ = writeln!(
        out,
        "1. Table construction: max relative error of the implied pmf, leak onto zero lights; \
         integer: worst |P − p| in units of 2^-32/N (below 1 + a_i), leak"
    );
    let _ = writeln!(
        out,
        "{:>12} {:>9} {:>12} {:>12} {:>13} {:>12} {:>12} {:>14}",
        "powers",
        "N",
        "f64 rel err",
        "f64 leak",
        "integer units",
        "integer leak",
        "f32 rel err",
        "f32 leak"
    );
    for r in reports {
        let (a, b) = (r.construction.f64_build, r.construction.f32_build);
        let int = r.construction.integer_build;
        let _ = writeln!(
            out,
            "{:>12} {:>9} {:>12.3e} {:>12.3e} {:>13.3} {:>12.3e} {:>12.3e} {:>9.3e} ({})",
            name(r),
            r.n,
            a.max_rel_error,
            a.zero_leak,
            r.construction.integer_max_error_units,
            int.zero_leak,
            b.max_rel_error,
            b.zero_leak,
            b.leaking_lights
        );
    }
}

/// Section 2: the u32 and f32 thresholds' pmf errors against their bounds, and lost lights.
fn thresholds_text(out: &mut String, reports: &[PrecisionReport]) {
    let _ = writeln!(
        out,
        "\n2. Thresholds: measured pmf error / bound (u32 bound (1+a_i)·2^-32/N, f32 bound \
         (1+a_i)·1.5·2^-24/N), relative error, lost lights"
    );
    let _ = writeln!(
        out,
        "{:>12} {:>10} {:>12} {:>6} {:>10} {:>12} {:>6}",
        "powers", "u32 /bound", "u32 rel err", "lost", "f32 /bound", "f32 rel err", "lost"
    );
    for r in reports {
        let t = r.thresholds;
        let _ = writeln!(
            out,
            "{:>12} {:>10.4} {:>12.3e} {:>6} {:>10.4} {:>12.3e} {:>6}",
            name(r),
            t.u32_error_over_bound,
            t.u32_max_rel_error,
            t.u32_lost_lights,
            t.f32_error_over_bound,
            t.f32_max_rel_error,
            t.f32_lost_lights
        );
    }
}

/// Section 3: unreachable columns and column frequencies of each column pick.
fn column_pick_text(out: &mut String, sweep: &[ColumnPickComparison]) {
    let _ = writeln!(
        out,
        "\n3. Column pick: unreachable share and max/min column frequency, over every input"
    );
    let _ = writeln!(
        out,
        "{:>10} {:>10} {:>9} {:>12} {:>10} {:>12} {:>13}",
        "N", "f32 unreach", "(share)", "f32 max/min", "mulhi unr", "mulhi max/min", "exact max/min"
    );
    for c in sweep {
        let _ = writeln!(
            out,
            "{:>10} {:>10} {:>9.3e} {:>12.6} {:>10} {:>12.9} {:>13.9}",
            c.n,
            c.f32_pick.unreachable,
            c.f32_pick.unreachable_share,
            c.f32_pick.max_min_ratio,
            c.multiply_high.unreachable,
            c.multiply_high.max_min_ratio,
            c.exact.max_min_ratio
        );
    }
}

/// Section 4: the one-random variant's realized pmf against the two-random picks.
fn one_random_text(out: &mut String, reports: &[PrecisionReport]) {
    let _ = writeln!(
        out,
        "\n4. One random vs two (exact realized pmfs): relative errors against p ('two' is the \
         raw multiply-high pick, 'default' adds the rejection that makes columns exactly \
         uniform), the one-random error over its bound (1+2a_i)·2^-32, total variation \
         distances from p (one, raw two, default)"
    );
    let _ = writeln!(
        out,
        "{:>12} {:>11} {:>13} {:>12} {:>12} {:>12} {:>10} {:>12}",
        "powers",
        "fractions",
        "per column",
        "one vs two",
        "one rel err",
        "two rel err",
        "one /bound",
        "default rel",
    );
    for r in reports {
        let o = r.one_random;
        let _ = writeln!(
            out,
            "{:>12} {:>11} {:>6}..{:<5} {:>12.3e} {:>12.3e} {:>12.3e} {:>10.4} {:>12.3e} \
             {:>10.3e} {:>10.3e} {:>10.3e}",
            name(r),
            o.distinct_fractions,
            o.min_values_per_column,
            o.max_values_per_column,
            o.one_vs_two_max_rel,
            o.one_max_rel_error,
            o.two_max_rel_error,
            o.one_error_over_bound,
            o.exact_max_rel_error,
            o.one_total_variation,
            o.two_total_variation,
            o.exact_total_variation
        );
    }
}

fn name(r: &PrecisionReport) -> &'static str {
    r.distribution.map_or("given", Distribution::name)
}
