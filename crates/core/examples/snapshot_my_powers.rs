//! A deterministic snapshot test of your own powers, the way engineers use lightpick-core
//! in their test suites: build the table, draw a fixed number of picks from a fixed seed,
//! and compare the result with a stored snapshot. Every number is a pure function of the
//! powers and the seed (integer table, counter-based RNG), so the snapshot is the same on
//! every machine; a change means the powers, the seed or the library changed.
//!
//! ```text
//! cargo run -p lightpick-core --example snapshot_my_powers -- 2,5,20
//! UPDATE_SNAPSHOTS=1 cargo run -p lightpick-core --example snapshot_my_powers -- 2,5,20
//! ```
//! The snapshot lives in `$SNAPSHOT_DIR` (default: the system's temporary directory).
//! Exit code 0: matches (or written); 1: differs (the differing lines are printed);
//! 2: bad input.

use std::fmt::Write as _;
use std::process::ExitCode;

use lightpick_core::{AliasTable, LightPowers, Rng, chi_square};

/// Picks drawn for the snapshot, from stream 0 of seed 2026.
const PICKS: usize = 1 << 20;
const SEED: u64 = 2026;

/// The snapshot text: the packed table (what is sampled) and the pick counts.
fn snapshot(powers: &LightPowers) -> String {
    let table = AliasTable::build(powers);
    let mut picks = vec![0u32; PICKS];
    table.sample_into(&mut picks, &mut Rng::new(SEED, 0));
    let mut counts = vec![0u64; table.len()];
    for &light in &picks {
        counts[light as usize] += 1;
    }
    let mut out = format!("lights {}\npicks {PICKS} seed {SEED}\n", table.len());
    for (i, (entry, count)) in table.packed().iter().zip(&counts).enumerate() {
        let _ = writeln!(
            out,
            "column {i}: threshold {} alias {} picks {count}",
            entry.threshold, entry.alias
        );
    }
    // Not part of the comparison's purpose, but a snapshot that disagrees with its own pmf
    // would be worth knowing: the chi-square of the counts against the realized pmf.
    let test = chi_square(&counts, table.pmf_slice());
    let _ = writeln!(
        out,
        "chi2 {:.3} dof {} p {:.3}",
        test.chi2, test.dof, test.p_value
    );
    out
}

fn main() -> ExitCode {
    let arg = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "2,5,20".to_owned());
    let values: Result<Vec<f64>, _> = arg.split(',').map(|s| s.trim().parse::<f64>()).collect();
    let powers = match values
        .map_err(|e| e.to_string())
        .and_then(|v| LightPowers::new(v).map_err(|e| e.to_string()))
    {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: powers '{arg}': {e}");
            return ExitCode::from(2);
        }
    };
    let text = snapshot(&powers);
    let dir = std::env::var_os("SNAPSHOT_DIR").map_or_else(std::env::temp_dir, Into::into);
    let name: String = arg
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .take(64)
        .collect();
    let path = dir.join(format!("lightpick-snapshot-{name}.txt"));
    let update = std::env::var_os("UPDATE_SNAPSHOTS").is_some();
    match std::fs::read_to_string(&path) {
        Ok(stored) if !update => {
            if stored == text {
                println!("snapshot matches: {}", path.display());
                ExitCode::SUCCESS
            } else {
                eprintln!("snapshot differs from {}:", path.display());
                for (old, new) in stored.lines().zip(text.lines()).filter(|(a, b)| a != b) {
                    eprintln!("- {old}\n+ {new}");
                }
                ExitCode::from(1)
            }
        }
        _ => match std::fs::write(&path, &text) {
            Ok(()) => {
                print!("{text}");
                println!("snapshot written: {}", path.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: writing {}: {e}", path.display());
                ExitCode::from(2)
            }
        },
    }
}
