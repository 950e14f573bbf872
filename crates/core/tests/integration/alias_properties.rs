//! Property tests of the alias table contract (DESIGN.md § Alias table).

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use lightpick_core::{AliasTable, CdfTable, LightPowers};
use proptest::prelude::*;

/// Powers with zeros, tiny and huge magnitudes, never all zero.
fn powers_strategy() -> impl Strategy<Value = Vec<f64>> {
    let power = prop_oneof![
        3 => Just(0.0),
        10 => 0.0f64..1000.0,
        3 => (-300i32..300).prop_map(|e| 10f64.powi(e)),
        1 => Just(f64::MAX),
        1 => Just(f64::from_bits(1)),
    ];
    prop::collection::vec(power, 1..200).prop_filter("not all zero", |v| v.iter().any(|&p| p > 0.0))
}

proptest! {
    // A fixed seed keeps CI reproducible; cases that once failed replay first from
    // `alias_properties.proptest-regressions`. Change the seed to explore further (25 runs
    // of 400 random cases found nothing beyond the replayed one).
    #![proptest_config(ProptestConfig {
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_122),
        ..ProptestConfig::with_cases(1000)
    })]

    #[test]
    fn implied_pmf_equals_pmf(powers in powers_strategy()) {
        let table = AliasTable::build_exact(&LightPowers::new(powers).unwrap());
        let implied = table.implied_pmf();
        for (i, (&got, &want)) in implied.iter().zip(table.pmf_slice()).enumerate() {
            // Within 1e-12 relative to the pmf, or 1e-15/N absolute for entries whose mass
            // is below the rounding floor of a unit-height column.
            let tol = 1e-12 * want + 1e-15 / table.len() as f64;
            prop_assert!((got - want).abs() <= tol, "light {i}: implied {got} vs pmf {want}");
        }
    }

    #[test]
    fn thresholds_in_unit_interval_aliases_in_range(powers in powers_strategy()) {
        let table = AliasTable::build_exact(&LightPowers::new(powers).unwrap());
        let n = table.len() as u32;
        for (&t, &a) in table.thresholds().iter().zip(table.aliases()) {
            prop_assert!((0.0..=1.0).contains(&t), "threshold {t}");
            prop_assert!(a < n, "alias {a} of {n}");
        }
    }

    #[test]
    fn zero_powers_are_never_sampled(powers in powers_strategy()) {
        let lp = LightPowers::new(powers.clone()).unwrap();
        let table = AliasTable::build_exact(&lp);
        for (i, e) in table.packed().iter().enumerate() {
            if powers[i] == 0.0 {
                // Own keep probability is zero …
                prop_assert_eq!(e.threshold, 0);
            }
            // … and no column ever aliases to a zero-power light.
            if e.threshold < u32::MAX {
                prop_assert!(powers[e.alias as usize] > 0.0, "column {i} aliases zero light {}", e.alias);
            }
        }
        let packed_pmf = table.implied_pmf_packed();
        for (i, &p) in powers.iter().enumerate() {
            if p == 0.0 {
                prop_assert_eq!(packed_pmf[i], 0.0);
            }
        }
        let cdf = CdfTable::build(&lp);
        for (i, &p) in powers.iter().enumerate() {
            if p == 0.0 {
                let lo = if i == 0 { 0.0 } else { cdf.cdf()[i - 1] };
                prop_assert_eq!(cdf.cdf()[i], lo, "cdf interval of zero light {} is not empty", i);
            }
        }
    }

    #[test]
    fn packed_pmf_within_quantization_bound(powers in powers_strategy()) {
        let table = AliasTable::build_exact(&LightPowers::new(powers).unwrap());
        let n = table.len();
        let mut aliased_to = vec![0u32; n];
        for (i, e) in table.packed().iter().enumerate() {
            if e.alias as usize != i {
                aliased_to[e.alias as usize] += 1;
            }
        }
        let packed = table.implied_pmf_packed();
        for i in 0..n {
            // Documented bound: (1 + a_i)·2^-32 / N, plus f64 rounding of the f64 table.
            let bound = f64::from(1 + aliased_to[i]) * 2f64.powi(-32) / n as f64
                + 1e-12 * table.pmf(i);
            prop_assert!((packed[i] - table.pmf(i)).abs() <= bound,
                "light {i}: packed {} vs pmf {} (bound {bound})", packed[i], table.pmf(i));
        }
    }

    /// A window of the realized pmf and the groups' probabilities, each from one pass with
    /// memory for what it returns: the window equals the whole pmf's slice bit for bit, and a
    /// group's probability is its lights' exact masses summed (in `u128`) over `N·2^32`.
    #[test]
    fn windows_and_groups_of_the_packed_pmf_match_the_whole(
        powers in powers_strategy(),
        a in 0usize..64,
        b in 0usize..64,
        per in 1usize..9,
    ) {
        let lp = LightPowers::new(powers).unwrap();
        let table = AliasTable::build(&lp);
        let n = table.len();
        let whole = table.implied_pmf_packed();
        let (a, b) = (a.min(n), b.min(n));
        let range = a.min(b)..a.max(b);
        prop_assert_eq!(table.implied_pmf_packed_of(range.clone()), whole[range].to_vec());
        let masses = table.packed_masses();
        let groups = table.packed_group_pmf(per);
        prop_assert_eq!(groups.len(), n.div_ceil(per));
        for (g, &p) in groups.iter().enumerate() {
            let sum: u128 = masses[g * per..((g + 1) * per).min(n)].iter().map(|&m| u128::from(m)).sum();
            prop_assert_eq!(p, sum as f64 / (n as f64 * 4_294_967_296.0), "group {}", g);
        }
    }

    #[test]
    fn integer_table_realizes_its_masses_within_the_bound(powers in powers_strategy()) {
        let lp = LightPowers::new(powers.clone()).unwrap();
        let table = AliasTable::build(&lp);
        let n = table.len();
        let masses = table.packed_masses();
        prop_assert_eq!(masses.iter().sum::<u64>(), (n as u64) << 32);
        let mut aliased_to = vec![0u32; n];
        for (i, e) in table.packed().iter().enumerate() {
            if e.alias as usize != i {
                aliased_to[e.alias as usize] += 1;
            }
            // Zero powers: never kept, never an alias.
            if powers[i] == 0.0 {
                prop_assert_eq!(e.threshold, 0);
            }
            if e.threshold < u32::MAX {
                prop_assert!(powers[e.alias as usize] > 0.0, "column {i} aliases a zero light");
            }
        }
        let unit = 2f64.powi(-32) / n as f64;
        for (i, (&m, &p)) in masses.iter().zip(&lp.pmf()).enumerate() {
            // Reachable exactly when the power is positive.
            prop_assert_eq!(m > 0, powers[i] > 0.0, "light {}", i);
            // (1 + a_i) units, plus the f64 rounding of p_i itself.
            let realized = m as f64 / (n as f64 * 4_294_967_296.0);
            let bound = f64::from(1 + aliased_to[i]) * unit + 1e-15 * p;
            prop_assert!((realized - p).abs() <= bound,
                "light {i}: realized {realized} vs p {p} (bound {bound})");
        }
    }
}
