//! The alias table's accuracy guarantees (docs/numbers.md § Guarantees) on 10^5+ lights of
//! every shape, heavy-tailed log-normal powers with a wide spread included, for both
//! constructions: what the `f64` table implies, what the packed table realizes, and which
//! lights can be sampled.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use lightpick_core::precision::Distribution;
use lightpick_core::{AliasTable, Construction, LightPowers, Rng};

const N: usize = 100_003;

/// Log-normal powers `exp(σ·Z)` (Box–Muller from the project's RNG), with every 17th light
/// at power 0.
fn log_normal(sigma: f64, seed: u64) -> Vec<f64> {
    let mut rng = Rng::new(seed, 0);
    (0..N)
        .map(|i| {
            let u1 = 1.0 - rng.next_unit();
            let u2 = rng.next_unit();
            let z = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
            if i % 17 == 0 { 0.0 } else { (sigma * z).exp() }
        })
        .collect()
}

/// Every input shape the guarantees are proved on, with its name.
fn inputs() -> Vec<(String, Vec<f64>)> {
    let mut sets: Vec<(String, Vec<f64>)> = Distribution::ALL
        .into_iter()
        .map(|d| (d.to_string(), d.powers(N, 11)))
        .collect();
    sets.push(("integers".into(), (1..=N as u32).map(f64::from).collect()));
    for sigma in [2.0, 6.0, 12.0] {
        sets.push((
            format!("log-normal σ={sigma}"),
            log_normal(sigma, sigma as u64),
        ));
    }
    sets
}

/// How many columns alias to each light (self-aliases of full columns not counted).
fn aliased_to(table: &AliasTable) -> Vec<u32> {
    let mut count = vec![0u32; table.len()];
    for (i, e) in table.packed().iter().enumerate() {
        if e.alias as usize != i {
            count[e.alias as usize] += 1;
        }
    }
    count
}

#[test]
fn exact_f64_table_implies_the_pmf_within_1e_minus_12_relative() {
    for (name, values) in inputs() {
        let powers = LightPowers::new(values).unwrap();
        let table = AliasTable::build_exact(&powers);
        let mut worst = 0.0f64;
        for (&got, &p) in table.implied_pmf().iter().zip(table.pmf_slice()) {
            if p > 0.0 {
                worst = worst.max((got - p).abs() / p);
            } else {
                assert_eq!(got, 0.0, "{name}: a zero light has mass");
            }
        }
        eprintln!("{name}: exact f64 table, worst relative error {worst:.2e}");
        assert!(worst <= 1e-12, "{name}: {worst:e}");
    }
}

#[test]
fn packed_tables_realize_the_pmf_within_one_plus_aliases_units() {
    for construction in Construction::ALL {
        for (name, values) in inputs() {
            let powers = LightPowers::new(values.clone()).unwrap();
            let table = AliasTable::build_with(&powers, construction);
            let masses = table.packed_masses();
            assert_eq!(masses.iter().sum::<u64>(), (N as u64) << 32, "{name}");
            let aliases = aliased_to(&table);
            let unit = 1.0 / (N as f64 * 4_294_967_296.0);
            let mut worst_units = 0.0f64;
            for (i, (&m, &p)) in masses.iter().zip(&powers.pmf()).enumerate() {
                // Reachable exactly when positive (every p_i here is representable).
                assert_eq!(m > 0, values[i] > 0.0, "{construction} {name}: light {i}");
                let error = (m as f64 * unit - p).abs();
                // The exact construction adds its f64 table's own error (≤ 1e-12 relative).
                let slack = if construction == Construction::Exact {
                    1e-12
                } else {
                    1e-15
                };
                let bound = f64::from(1 + aliases[i]) * unit + slack * p;
                assert!(
                    error <= bound,
                    "{construction} {name}: light {i} off by {} units, {} aliases",
                    error / unit,
                    aliases[i]
                );
                worst_units = worst_units.max(error / unit);
            }
            eprintln!("{construction} {name}: worst |P − p| = {worst_units:.3} units of 2^-32/N");
            if construction == Construction::Integer {
                // No p_i here is below 2^-32/N, so no light needed a unit from its alias.
                let tiny = powers.pmf().iter().any(|&p| p > 0.0 && p < unit);
                if !tiny {
                    assert!(worst_units < 1.0, "{name}: {worst_units}");
                }
            }
        }
    }
}

#[test]
fn integer_tables_keep_positive_lights_reachable_below_two_to_the_minus_32_over_n() {
    // Half the lights at 10^-300 relative to the rest: every one rounds to mass 0 and takes
    // one unit from its alias.
    let mut values: Vec<f64> = (0..N)
        .map(|i| if i % 2 == 0 { 1e-300 } else { 1.0 })
        .collect();
    values[7] = 0.0;
    let powers = LightPowers::new(values.clone()).unwrap();
    let table = AliasTable::build(&powers);
    let masses = table.packed_masses();
    let aliases = aliased_to(&table);
    let unit = 1.0 / (N as f64 * 4_294_967_296.0);
    for (i, (&m, &p)) in masses.iter().zip(&powers.pmf()).enumerate() {
        assert_eq!(m > 0, values[i] > 0.0, "light {i}");
        assert!(
            (m as f64 * unit - p).abs() <= f64::from(1 + aliases[i]) * unit,
            "light {i}"
        );
    }
}
