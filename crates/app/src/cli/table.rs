//! `lightpick table`: the alias table of a set of powers, as the seed document shows it.

use std::fmt::Write as _;

use clap::Args;
use lightpick_core::fraction::{common_denominator, format_fraction};
use lightpick_core::{AliasTable, LightPowers};
use serde_json::json;

use super::input::PowersArgs;

/// Rows printed before the text table is cut short (JSON always has every row).
const TEXT_ROWS: usize = 32;

/// Arguments of `lightpick table`.
#[derive(Debug, Args)]
pub struct TableArgs {
    /// Where the powers come from.
    #[command(flatten)]
    pub powers: PowersArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Builds the table and prints it.
pub fn run(args: &TableArgs) -> anyhow::Result<()> {
    let powers = args.powers.load()?;
    let table = AliasTable::build(&powers);
    if args.json {
        super::print_json(&table_json(&powers, &table))
    } else {
        print!("{}", table_text(&powers, &table));
        Ok(())
    }
}

/// The JSON form: `n`, `total_power`, `pmf[]`, `threshold[]`, `alias[]`, and the packed GPU
/// thresholds `threshold_u32[]`.
pub(crate) fn table_json(powers: &LightPowers, table: &AliasTable) -> serde_json::Value {
    json!({
        "n": table.len(),
        "total_power": powers.total(),
        "pmf": table.pmf_slice(),
        "threshold": table.thresholds(),
        "alias": table.aliases(),
        "threshold_u32": table.packed().iter().map(|e| e.threshold).collect::<Vec<_>>(),
    })
}

/// The text form: one row per light (numbered from 0, as the aliases are), fractions over
/// the total power where the powers are integers.
pub(crate) fn table_text(powers: &LightPowers, table: &AliasTable) -> String {
    let den = common_denominator(powers.as_slice(), f64::INFINITY);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{} lights, total power {}  (lights numbered from 0: the seed's light №1 is light 0)",
        table.len(),
        powers.total()
    );
    let _ = writeln!(
        out,
        "{:>7}  {:>12}  {:>22}  {:>22}  {:>6}",
        "light", "power", "pmf", "threshold", "alias"
    );
    for i in 0..table.len().min(TEXT_ROWS) {
        let _ = writeln!(
            out,
            "{:>7}  {:>12}  {:>22}  {:>22}  {:>6}",
            i,
            powers.as_slice()[i],
            labelled(table.pmf(i), den),
            labelled(table.thresholds()[i], den),
            table.aliases()[i],
        );
    }
    if table.len() > TEXT_ROWS {
        let _ = writeln!(
            out,
            "… {} more lights (use --json for every row)",
            table.len() - TEXT_ROWS
        );
    }
    out
}

/// `6/27 (0.222222)` where the fraction is exact, else the decimal alone.
fn labelled(value: f64, den: Option<u64>) -> String {
    match format_fraction(value, den) {
        Some(f) if f == "1" || f == "0" => f,
        Some(f) => format!("{f} ({value:.6})"),
        None => format!("{value:.6e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_text_shows_fractions() {
        let powers = LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap();
        let text = table_text(&powers, &AliasTable::build(&powers));
        assert!(text.contains("6/27 (0.222222)"), "{text}");
        assert!(text.contains("15/27 (0.555556)"), "{text}");
        assert!(text.contains("20/27 (0.740741)"), "{text}");
    }
}
