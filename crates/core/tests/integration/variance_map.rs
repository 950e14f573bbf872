//! The per-pixel variance map (`stats::variance_map`) against a brute-force
//! `Σ s_i²/q_i − E²` written out here, on the worked example's three lights and on twenty
//! random ones (a light tree); the exact spatial pick has no variance; the estimated map
//! agrees with the exact one.

use glam::{DVec2, dvec2, dvec3};
use lightpick_core::scene::{ReceiverPlane, Scene, pixel_center};
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::stats::variance_map::VarianceMap;
use lightpick_core::{PointFreeSampler as _, Sampler, Scheme};

use crate::common::scenes::scattered_random;

/// The worked example's powers 2, 5, 20 over `[-1, 1]²` at three heights, 6 × 5 pixels.
fn worked_example_scene() -> Scene {
    Scene::from_parts(
        "seed",
        ReceiverPlane {
            min: dvec2(-1.0, -1.0),
            max: dvec2(1.0, 1.0),
            width: 6,
            height: 5,
        },
        vec![
            dvec3(-0.6, 0.2, 0.4),
            dvec3(0.5, -0.3, 0.8),
            dvec3(0.1, 0.7, 1.5),
        ],
        vec![2.0, 5.0, 20.0],
    )
    .expect("valid")
}

/// `Σ_{q_i > 0} s_i²/q_i − (Σ_{q_i > 0} s_i)²` at `x`, in plain `f64` loops.
fn brute_force(scene: &Scene, q: &[f64], x: DVec2) -> f64 {
    let pmf = scene.powers.pmf();
    let (mut mean, mut second) = (0.0, 0.0);
    for i in 0..pmf.len() {
        let s = pmf[i] * scene.light_term(i, x);
        if q[i] > 0.0 {
            mean += s;
            second += s * s / q[i];
        }
    }
    (second - mean * mean).max(0.0)
}

/// The pmf `q(x)` of `scheme` at `x`.
fn pmf_of(scene: &Scene, scheme: Scheme, x: DVec2) -> Vec<f64> {
    match Sampler::try_build(scheme, &scene.powers) {
        Ok(sampler) => (0..scene.powers.len())
            .map(|i| sampler.probability(i))
            .collect(),
        Err(_) => SpatialSampler::for_scene(scene).pdfs(x),
    }
}

/// The exact map of `scheme` equals the brute force at every pixel (within `1e-12` of the
/// second moment `V + E²`, where the subtraction's rounding lives).
fn check_exact(scene: &Scene, scheme: Scheme) -> VarianceMap {
    let map = VarianceMap::compute(scene, scheme, 16, 1);
    assert!(map.exact);
    assert_eq!(map.samples_per_pixel, 0);
    assert_eq!(
        (map.width, map.height),
        (scene.plane.width, scene.plane.height)
    );
    assert_eq!(map.values.len(), scene.plane.pixel_count());
    let pmf = scene.powers.pmf();
    for py in 0..map.height {
        for px in 0..map.width {
            let x = pixel_center(&scene.plane, px, py);
            let q = pmf_of(scene, scheme, x);
            let expected = brute_force(scene, &q, x);
            let e: f64 = (0..pmf.len())
                .map(|i| pmf[i] * scene.light_term(i, x))
                .sum();
            let got = map.at(px, py);
            assert!(
                (got - expected).abs() <= 1e-12 * (expected + e * e),
                "{scheme:?} at ({px}, {py}): {got} vs {expected}"
            );
        }
    }
    map
}

#[test]
fn the_worked_example_matches_the_brute_force() {
    let scene = worked_example_scene();
    let uniform = check_exact(&scene, Scheme::Uniform);
    let power = check_exact(&scene, Scheme::Alias);
    check_exact(&scene, Scheme::Cdf);
    let spatial = check_exact(&scene, Scheme::Spatial);
    // Few lights: the spatial pick is exact, a zero-variance estimator.
    assert!(matches!(
        SpatialSampler::for_scene(&scene),
        SpatialSampler::Exact(_)
    ));
    let pmf = scene.powers.pmf();
    for (k, &v) in spatial.values.iter().enumerate() {
        let x = pixel_center(&scene.plane, k as u32 % 6, k as u32 / 6);
        let e: f64 = (0..3).map(|i| pmf[i] * scene.light_term(i, x)).sum();
        assert!(v <= 1e-12 * e * e, "pixel {k}: {v} against E² = {}", e * e);
    }
    // Somewhere the two power-blind schemes are noisy.
    assert!(uniform.values.iter().all(|&v| v > 0.0));
    assert!(power.values.iter().any(|&v| v > 0.0));
}

#[test]
fn twenty_random_lights_match_the_brute_force() {
    // 20 lights: beyond the exact pick, so the spatial scheme is a light tree.
    let mut scene = scattered_random(20, 77, 1.0, 2.0);
    scene.plane.width = 9;
    scene.plane.height = 7;
    assert!(matches!(
        SpatialSampler::for_scene(&scene),
        SpatialSampler::Tree(_)
    ));
    let uniform = check_exact(&scene, Scheme::Uniform);
    let power = check_exact(&scene, Scheme::Alias);
    let spatial = check_exact(&scene, Scheme::Spatial);
    let mean = |m: &VarianceMap| m.values.iter().sum::<f64>() / m.values.len() as f64;
    assert!(
        mean(&spatial) < mean(&power) && mean(&power) < mean(&uniform),
        "spatial {} power {} uniform {}",
        mean(&spatial),
        mean(&power),
        mean(&uniform)
    );
}

#[test]
fn past_the_budget_the_map_is_estimated_and_agrees() {
    let mut scene = scattered_random(20, 78, 1.0, 1.0);
    scene.plane.width = 8;
    scene.plane.height = 8;
    for scheme in [Scheme::Alias, Scheme::Spatial] {
        let exact = VarianceMap::compute(&scene, scheme, 0, 5);
        let sampled = VarianceMap::with_budget(&scene, scheme, 0, 4096, 5);
        assert!(exact.exact && !sampled.exact);
        assert_eq!(sampled.samples_per_pixel, 4096);
        // Summed over 64 pixels the sample variances' relative error is about
        // √((κ − 1)/4096)/8 (κ the kurtosis of the estimate, below 50 here): ~1.4%.
        let (e, s): (f64, f64) = (exact.values.iter().sum(), sampled.values.iter().sum());
        assert!(
            (s - e).abs() <= 0.05 * e,
            "{scheme:?}: sampled {s} vs exact {e}"
        );
    }
}
