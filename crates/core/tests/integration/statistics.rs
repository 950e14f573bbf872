//! Statistical tests of every scheme, with fixed seeds and bounds derived from the math.
//!
//! Chi-square tests are run at significance 0.001: with the seeds fixed, each test is a
//! deterministic check that the realized distribution is not distinguishable from the pmf.
//! Moment tests use 5-sigma bounds computed from the exact distribution of the estimator.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use lightpick_core::{
    AliasTable, LightPowers, PointFreeSampler as _, Rng, Sampler, Scheme, Welford, WorkedExample,
    analytic_moments, chi_square,
};

const ALPHA: f64 = 1e-3;

fn counts(sampler: &Sampler, count: u64, seed: u64) -> Vec<u64> {
    let mut c = vec![0u64; sampler.light_count()];
    for k in 0..count {
        c[sampler.pick_light(&mut Rng::new(seed, k)) as usize] += 1;
    }
    c
}

fn expected(sampler: &Sampler) -> Vec<f64> {
    (0..sampler.light_count())
        .map(|i| sampler.probability(i))
        .collect()
}

fn mixed_powers() -> LightPowers {
    let mut rng = Rng::new(99, 0);
    let powers = (0..500)
        .map(|i| {
            if i % 7 == 0 {
                0.0
            } else {
                (rng.next_unit() * 20.0).exp()
            }
        })
        .collect();
    LightPowers::new(powers).unwrap()
}

#[test]
fn every_scheme_fits_its_pmf_on_the_seed() {
    for scheme in Scheme::ALL {
        let sampler = Sampler::build(scheme, &WorkedExample::powers());
        let c = counts(&sampler, 200_000, 11);
        let test = chi_square(&c, &expected(&sampler));
        assert!(test.p_value > ALPHA, "{scheme}: {test:?} counts {c:?}");
    }
}

#[test]
fn every_scheme_fits_its_pmf_on_mixed_powers_with_zeros() {
    let powers = mixed_powers();
    for scheme in Scheme::ALL {
        let sampler = Sampler::build(scheme, &powers);
        let c = counts(&sampler, 400_000, 5);
        let test = chi_square(&c, &expected(&sampler));
        assert!(test.p_value > ALPHA, "{scheme}: {test:?}");
        if scheme.is_power_proportional() {
            for (i, &p) in powers.as_slice().iter().enumerate() {
                if p == 0.0 {
                    assert_eq!(c[i], 0, "{scheme}: zero-power light {i} was sampled");
                }
            }
        }
    }
}

#[test]
fn the_test_has_power_to_reject_a_wrong_pmf() {
    // Uniform draws tested against the power pmf must be rejected overwhelmingly.
    let uniform = Sampler::build(Scheme::Uniform, &WorkedExample::powers());
    let table = AliasTable::build_exact(&WorkedExample::powers());
    let c = counts(&uniform, 10_000, 3);
    assert!(chi_square(&c, table.pmf_slice()).p_value < 1e-100);
}

#[test]
fn analytic_variances_of_the_seed() {
    let f = WorkedExample::CONTRIBUTIONS;
    let uniform = analytic_moments(&f, |_| 1.0 / 3.0);
    assert_eq!(uniform.exact, WorkedExample::EXACT);
    assert!((uniform.variance - WorkedExample::UNIFORM_VARIANCE).abs() < 1e-12);
    let table = AliasTable::build_exact(&WorkedExample::powers());
    let power = analytic_moments(&f, |i| table.pmf(i));
    assert!((power.mean - 18.0).abs() < 1e-13);
    assert!((power.variance - WorkedExample::POWER_VARIANCE).abs() < 1e-12);
}

/// The estimator takes value `f_i/p_i` with probability `p_i`: its exact mean, variance and
/// fourth central moment give 5-sigma bounds for the sample mean and sample variance.
fn check_estimator(scheme: Scheme, count: u64, seed: u64) {
    let sampler = Sampler::build(scheme, &WorkedExample::powers());
    let f = WorkedExample::CONTRIBUTIONS;
    let mut w = Welford::new();
    for k in 0..count {
        let pick = sampler.pick(&mut Rng::new(seed, k));
        w.push(f[pick.light as usize] / pick.probability);
    }
    let p: Vec<f64> = (0..3).map(|i| sampler.probability(i)).collect();
    let mean: f64 = (0..3).map(|i| f[i]).sum();
    let var: f64 = (0..3).map(|i| p[i] * (f[i] / p[i] - mean).powi(2)).sum();
    let mu4: f64 = (0..3).map(|i| p[i] * (f[i] / p[i] - mean).powi(4)).sum();
    let n = count as f64;
    assert!(
        (w.mean() - WorkedExample::EXACT).abs() <= 5.0 * (var / n).sqrt(),
        "{scheme}: mean {} vs 18",
        w.mean()
    );
    // Var(s²) ≈ (μ4 − σ⁴)/n for large n.
    let var_sd = ((mu4 - var * var) / n).sqrt();
    assert!(
        (w.variance() - var).abs() <= 5.0 * var_sd,
        "{scheme}: variance {} vs {var}",
        w.variance()
    );
}

#[test]
fn seed_estimators_average_to_18_with_the_analytic_variance() {
    check_estimator(Scheme::Uniform, 200_000, 1);
    check_estimator(Scheme::Alias, 200_000, 2);
    check_estimator(Scheme::Cdf, 200_000, 3);
    check_estimator(Scheme::AliasOneRandom, 200_000, 4);
}
