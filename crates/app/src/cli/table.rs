//! `lightpick table`: the alias table of a set of powers, with its thresholds as exact fractions where the powers allow (6/27, 15/27, 1 for 2, 5, 20).

use std::fmt::Write as _;

use clap::Args;
use lightpick_core::fraction::{common_denominator, format_fraction};
use lightpick_core::{AliasTable, Construction, LightPowers};
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
    /// How the table is built: `exact` (the `f64` construction: exact fractions such as 6/27) or
    /// `integer` (the fast default of the samplers, thresholds `T/2^32`).
    #[arg(long, default_value = "exact")]
    pub construction: Construction,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Builds the table and prints it.
pub fn run(args: &TableArgs) -> anyhow::Result<()> {
    let powers = args.powers.load()?;
    let table = AliasTable::build_with(&powers, args.construction);
    if args.json {
        super::print_json(&table_json(&powers, &table))
    } else {
        print!("{}", table_text(&powers, &table));
        Ok(())
    }
}

/// The JSON form: `n`, `total_power`, `total_power_log10`, `pmf[]`, `threshold[]`,
/// `alias[]`, and the packed GPU thresholds `threshold_u32[]`.
///
/// Every power is a finite `f64` but their sum need not be (two powers of `f64::MAX`):
/// `total_power` is then `null` (JSON has no infinity), and `total_power_log10`, computed
/// without overflow ([`LightPowers::total_log10`]), is always a finite number. The pmf is
/// computed without overflow in every case.
pub(crate) fn table_json(powers: &LightPowers, table: &AliasTable) -> serde_json::Value {
    let total = powers.total();
    json!({
        "n": table.len(),
        "construction": table.construction().name(),
        "total_power": total.is_finite().then_some(total),
        "total_power_log10": powers.total_log10(),
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
        "{} lights, total power {}  (lights numbered from 0: the worked example's light №1 is light 0)",
        table.len(),
        total_text(powers)
    );
    let _ = writeln!(
        out,
        "construction: {}",
        construction_text(table.construction())
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
            power_text(powers.as_slice()[i]),
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

/// What a construction's thresholds are, in one line.
fn construction_text(construction: Construction) -> &'static str {
    match construction {
        Construction::Exact => "exact (f64 Vose; thresholds as exact fractions where they are)",
        Construction::Integer => {
            "integer (the samplers' default; thresholds T/2^32 of masses summing to N·2^32)"
        }
    }
}

/// The total power for people, in the same form as the powers ([`power_text`]: `27`,
/// `1e300`, not 301 digits), or, when the sum exceeds `f64::MAX`, its value from
/// `log10 Σ Φ_i` ([`LightPowers::total_log10`]) with four significant digits:
/// `3.595e308 (exceeds f64)`.
fn total_text(powers: &LightPowers) -> String {
    let total = powers.total();
    if total.is_finite() {
        power_text(total)
    } else {
        format!("{} (exceeds f64)", decimal_from_log10(powers.total_log10()))
    }
}

/// `10^l` written as `m.mmme±d` (four significant digits) without forming `10^l`, which may
/// exceed `f64`: `d = ⌊l⌋`, `m = 10^(l − d) ∈ [1, 10)`.
fn decimal_from_log10(l: f64) -> String {
    let mut d = l.floor();
    let mut m = 10f64.powf(l - d);
    // Rounding to four digits may carry into the next decade (9.9996 → 10.000).
    if (m * 1000.0).round() >= 10_000.0 {
        m /= 10.0;
        d += 1.0;
    }
    format!("{m:.3}e{d}")
}

/// A power as Rust's shortest round-trip `f64` text, in positional form between `10^-4`
/// and `10^15` (`20`, `0.5`) and in scientific form beyond (`1.7976931348623157e308`, not
/// its 309 digits).
fn power_text(power: f64) -> String {
    if power == 0.0 || (1e-4..1e15).contains(&power.abs()) {
        format!("{power}")
    } else {
        format!("{power:e}")
    }
}

/// `6/27 (0.222222)` where the fraction is exact, else the decimal alone (six decimals
/// from `10^-3` up, else six significant digits in scientific form).
fn labelled(value: f64, den: Option<u64>) -> String {
    match format_fraction(value, den) {
        Some(f) if f == "1" || f == "0" => f,
        Some(f) => format!("{f} ({value:.6})"),
        None if value.abs() >= 1e-3 => format!("{value:.6}"),
        None => format!("{value:.6e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_totals_print_in_scientific_form() {
        let powers = LightPowers::new(vec![1e300]).unwrap();
        assert_eq!(total_text(&powers), "1e300");
        let text = table_text(&powers, &AliasTable::build_exact(&powers));
        assert!(text.starts_with("1 lights, total power 1e300 "), "{text}");
        assert!(text.contains("construction: exact"), "{text}");
    }

    #[test]
    fn powers_and_probabilities_read_at_every_scale() {
        assert_eq!(power_text(20.0), "20");
        assert_eq!(power_text(0.5), "0.5");
        assert_eq!(power_text(f64::MAX), "1.7976931348623157e308");
        assert_eq!(power_text(1e-300), "1e-300");
        assert_eq!(labelled(0.5, None), "0.500000");
        assert_eq!(labelled(2.5e-7, None), "2.500000e-7");
    }

    #[test]
    fn seed_text_shows_fractions() {
        let powers = LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap();
        let text = table_text(&powers, &AliasTable::build_exact(&powers));
        assert!(text.contains("6/27 (0.222222)"), "{text}");
        assert!(text.contains("15/27 (0.555556)"), "{text}");
        assert!(text.contains("20/27 (0.740741)"), "{text}");
        assert!(text.starts_with("3 lights, total power 27 "), "{text}");
    }

    #[test]
    fn an_overflowing_total_is_reported_honestly() {
        let powers = LightPowers::new(vec![f64::MAX, f64::MAX]).unwrap();
        let table = AliasTable::build_exact(&powers);
        // Σ = 2·f64::MAX = 3.5953862697246314e308.
        let text = table_text(&powers, &table);
        assert!(
            text.starts_with("2 lights, total power 3.595e308 (exceeds f64) "),
            "{text}"
        );
        let v = table_json(&powers, &table);
        assert_eq!(v["total_power"], serde_json::Value::Null);
        let log10 = v["total_power_log10"].as_f64().unwrap();
        assert!(
            (log10 - (f64::MAX.log10() + 2f64.log10())).abs() < 1e-12,
            "{log10}"
        );
        assert_eq!(v["pmf"], json!([0.5, 0.5]));
        let seed = LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap();
        let v = table_json(&seed, &AliasTable::build_exact(&seed));
        assert_eq!(v["total_power"], json!(27.0));
    }

    #[test]
    fn decimals_from_log10_carry_into_the_next_decade() {
        assert_eq!(decimal_from_log10(2f64.log10() + 300.0), "2.000e300");
        assert_eq!(decimal_from_log10(9.99996f64.log10() + 400.0), "1.000e401");
        assert_eq!(decimal_from_log10(0.0), "1.000e0");
    }
}
