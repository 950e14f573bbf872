//! The running estimate at one shading point: unbiased under every rule, its measured
//! variance the analytic one, and the spatial rule exact for few lights. Fixed seeds; bounds
//! of 5 standard deviations from the exact distribution of each estimator.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use glam::{DVec2, DVec3, dvec2, dvec3};
use std::sync::Arc;

use lightpick_core::point_estimate::{PointEstimator, samples_for_relative_error};
use lightpick_core::scene::{Scene, geometry_term};
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::{
    AliasTable, LightPowers, Sampler, SchemeSampler, ShadingContext, Uniform, WorkedExample,
};

/// The exact central moments `(σ², μ4)` of `f_I/q_I` for `I ~ q`.
fn central_moments(f: &[f64], q: &[f64]) -> (f64, f64) {
    let mean: f64 = f.iter().sum();
    let (mut m2, mut m4) = (0.0, 0.0);
    for (fi, qi) in f.iter().zip(q) {
        if *qi > 0.0 {
            let d = fi / qi - mean;
            m2 += qi * d * d;
            m4 += qi * d.powi(4);
        }
    }
    (m2, m4)
}

#[test]
fn seed_point_converges_to_18_with_variances_366_and_14_85() {
    let n = 200_000u64;
    let mut e = PointEstimator::worked_example(2026);
    e.advance(n);
    let f = WorkedExample::CONTRIBUTIONS;
    let qs = [
        vec![1.0 / 3.0; 3],
        vec![2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0],
    ];
    let analytic = [
        WorkedExample::UNIFORM_VARIANCE,
        WorkedExample::POWER_VARIANCE,
    ];
    for ((run, q), var) in e.runs().iter().zip(&qs).zip(analytic) {
        let (m2, m4) = central_moments(&f, q);
        assert!((m2 - var).abs() < 1e-9, "{}: {m2}", run.name);
        assert!((run.analytic.variance - var).abs() < 1e-9);
        let w = run.running();
        let mean_sd = (var / n as f64).sqrt();
        assert!(
            (w.mean() - 18.0).abs() < 5.0 * mean_sd,
            "{}: mean {} vs 18 (σ {mean_sd})",
            run.name,
            w.mean()
        );
        // The sample variance has variance (μ4 − σ⁴)/n to first order.
        let var_sd = ((m4 - var * var) / n as f64).sqrt();
        assert!(
            (w.variance() - var).abs() < 5.0 * var_sd,
            "{}: variance {} vs {var} (σ {var_sd})",
            run.name,
            w.variance()
        );
        // The last point of the series is the running state.
        let last = run.series().last().unwrap();
        assert_eq!(last.samples, n);
        assert_eq!(last.mean, w.mean());
    }
    let [u, a] = [&e.runs()[0], &e.runs()[1]];
    let ratio = samples_for_relative_error(u.analytic.variance_scaled, 18.0, 0.01)
        / samples_for_relative_error(a.analytic.variance_scaled, 18.0, 0.01);
    assert!((ratio - 366.0 / 14.85).abs() < 1e-9, "{ratio}");
}

/// A point of a scene with the three rules (the app's pixel estimator).
fn pixel_estimator(scene: &Scene, x: DVec2, seed: u64) -> PointEstimator {
    let total: f64 = scene.powers.as_slice().iter().sum();
    let contributions = scene
        .positions
        .iter()
        .zip(scene.powers.pmf())
        .map(|(&light_in_world, p)| total * p * geometry_term(light_in_world, x))
        .collect();
    let n = scene.light_count();
    let spatial = Arc::new(SpatialSampler::build(&scene.positions, &scene.powers));
    PointEstimator::new(
        contributions,
        ShadingContext::at(x),
        vec![
            ("uniform", Sampler::Uniform(Uniform::new(n as u32)).into()),
            (
                "power",
                Sampler::Alias(Arc::new(AliasTable::build(&scene.powers))).into(),
            ),
            ("spatial", SchemeSampler::Spatial(spatial)),
        ],
        seed,
    )
    .unwrap()
}

#[test]
fn spatial_rule_is_exact_on_few_lights() {
    let scene = Scene::preset("worked-example").unwrap();
    let mut e = pixel_estimator(&scene, dvec2(0.3, -0.2), 5);
    e.advance(1000);
    let spatial = &e.runs()[2];
    let exact = e.exact();
    // Every sample equals the exact total up to the rounding of p_i·G_i/P(i|x); the
    // analytic variance cancels two terms of size F², each within a few ulps.
    assert!(spatial.analytic.variance <= 1e-12 * exact * exact);
    assert!(spatial.running().variance() <= 1e-24 * exact * exact);
    assert!((spatial.running().mean() - exact).abs() <= 1e-12 * exact);
}

#[test]
fn every_rule_is_unbiased_at_a_pixel_of_a_tree_scene() {
    let positions: Vec<DVec3> = (0..300)
        .map(|i| {
            let t = f64::from(i);
            dvec3(
                (t * 0.37).sin() * 3.0,
                (t * 0.71).cos() * 3.0,
                0.3 + (t * 0.13).sin().abs(),
            )
        })
        .collect();
    let powers = LightPowers::new((0..300).map(|i| 1.0 + f64::from(i % 17)).collect()).unwrap();
    let mut scene = Scene::preset("worked-example").unwrap();
    scene.positions = positions.into();
    scene.powers = powers;
    let n = 100_000u64;
    let mut e = pixel_estimator(&scene, dvec2(0.5, 0.25), 9);
    e.advance(n);
    for run in e.runs() {
        let sd = (run.analytic.variance / n as f64).sqrt();
        assert!(
            (run.running().mean() - e.exact()).abs() < 5.0 * sd,
            "{}: {} vs {} (σ {sd})",
            run.name,
            run.running().mean(),
            e.exact()
        );
    }
    // The tree's rule beats power picking where the geometry varies this much.
    assert!(e.runs()[2].analytic.variance < e.runs()[1].analytic.variance);
}
