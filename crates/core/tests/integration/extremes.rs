//! The alias table at the extremes of N and of the power range.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use lightpick_core::{AliasTable, LightPowers, PowersError};

fn build(powers: Vec<f64>) -> AliasTable {
    AliasTable::build_exact(&LightPowers::new(powers).unwrap())
}

fn assert_implied_matches(table: &AliasTable) {
    let implied = table.implied_pmf();
    let n = table.len() as f64;
    for (i, (&got, &want)) in implied.iter().zip(table.pmf_slice()).enumerate() {
        assert!(
            (got - want).abs() <= 1e-12 * want + 1e-15 / n,
            "light {i}: implied {got} vs pmf {want}"
        );
    }
}

#[test]
fn one_light() {
    let t = build(vec![1e-300]);
    assert_eq!(t.thresholds(), &[1.0]);
    assert_eq!(t.sample_u32(123, u32::MAX), 0);
}

#[test]
fn two_to_the_twenty_lights() {
    let n: u64 = 1 << 20;
    let powers: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000 + 1) as f64).collect();
    let t = build(powers);
    assert_eq!(t.len() as u64, n);
    assert_implied_matches(&t);
}

#[test]
fn powers_spanning_1e_minus_300_to_1e300() {
    let powers: Vec<f64> = (-300..=300).map(|e| 10f64.powi(e)).collect();
    let t = build(powers);
    assert_implied_matches(&t);
    // The largest light holds essentially all the mass (1e300 / Σ = 0.9 recurring).
    assert!((t.pmf(600) - 0.9).abs() < 1e-15);
    // Shares down to 1e-300 of the largest are representable and stay positive; a share
    // below f64's range (1e-300 / 1e300) underflows to zero and behaves as a zero power.
    for e in 0..=300 {
        assert!(t.pmf(e + 300) > 0.0, "10^{e}");
    }
    assert_eq!(t.pmf(0), 0.0);
    assert_eq!(t.packed()[0].threshold, 0);
    let total: f64 = t.pmf_slice().iter().sum();
    assert!((total - 1.0).abs() < 1e-15);
}

#[test]
fn subnormal_powers() {
    let tiny = f64::from_bits(1);
    let t = build(vec![tiny, 2.0 * tiny, 5.0 * tiny]);
    assert_eq!(t.pmf_slice(), &[1.0 / 8.0, 2.0 / 8.0, 5.0 / 8.0]);
    assert_implied_matches(&t);
}

#[test]
fn near_f64_max_powers() {
    let t = build(vec![f64::MAX, f64::MAX, f64::MAX / 2.0]);
    assert_eq!(t.pmf(0), 0.4);
    assert_implied_matches(&t);
}

#[test]
fn half_the_lights_at_zero_are_never_sampled_exhaustively() {
    // Exhaustive over the column space: every column of a zero light has threshold 0 (no r2
    // keeps it) and no column aliases to one, so no (r1, r2) pair can return it.
    let powers: Vec<f64> = (0..1000)
        .map(|i| if i % 2 == 0 { 0.0 } else { f64::from(i) })
        .collect();
    let t = build(powers);
    for (c, e) in t.packed().iter().enumerate() {
        if c % 2 == 0 {
            assert_eq!(e.threshold, 0, "column {c}");
        }
        assert_eq!(e.alias % 2, 1, "column {c} aliases {}", e.alias);
    }
    assert_implied_matches(&t);
}

#[test]
fn all_equal_needs_no_alias() {
    let t = build(vec![3.0; 1000]);
    assert!(t.thresholds().iter().all(|&x| x == 1.0));
    assert!(
        t.aliases()
            .iter()
            .enumerate()
            .all(|(i, &a)| a as usize == i)
    );
}

#[test]
fn error_variants_are_reported() {
    assert_eq!(LightPowers::new(vec![]), Err(PowersError::Empty));
    assert!(matches!(
        LightPowers::new(vec![1.0, f64::NEG_INFINITY]),
        Err(PowersError::NotFinite { index: 1, .. })
    ));
    assert!(matches!(
        LightPowers::new(vec![-1.0]),
        Err(PowersError::Negative { index: 0, .. })
    ));
    assert_eq!(
        LightPowers::new(vec![0.0; 4]),
        Err(PowersError::AllZero { count: 4 })
    );
}
