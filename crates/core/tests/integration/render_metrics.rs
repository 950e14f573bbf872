//! The exact reference (full and subset) and the error metrics, checked against direct
//! evaluations of their formulas.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use crate::common::scenes::preset_at;
use glam::{dvec2, dvec3};
use lightpick_core::render::{
    Accumulator, CpuRenderer, MIN_REFERENCE_PIXELS, REL_MSE_EPSILON, Reference, SeriesPoint,
    cpu_convergence, efficiency, efficiency_of, error_metrics, is_zero_variance_scaled,
    mean_variance_per_sample, rmse, series_spp, subset_pixels,
};
use lightpick_core::scene::{ReceiverPlane, Scene, pixel_center};
use lightpick_core::{Scaled, Scheme};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

// ---------------------------------------------------------------- reference

#[test]
fn full_reference_is_the_sum_over_all_lights() {
    // Includes a light below the plane and one on it, which contribute nothing.
    let scene = Scene::from_parts(
        "mixed",
        ReceiverPlane {
            min: dvec2(-1.0, -1.0),
            max: dvec2(1.0, 1.0),
            width: 7,
            height: 5,
        },
        vec![
            dvec3(0.2, 0.3, 0.5),
            dvec3(-0.7, 0.1, 1.5),
            dvec3(0.0, 0.0, -1.0),
            dvec3(0.5, 0.5, 0.0),
            dvec3(0.9, -0.9, 0.05),
        ],
        vec![2.0, 5.0, 100.0, 100.0, 0.5],
    )
    .unwrap();
    let reference = Reference::compute(&scene);
    assert!(reference.is_complete());
    let image = reference.image().unwrap();
    assert_eq!(image.len(), 35);
    for py in 0..5 {
        for px in 0..7 {
            let exact = scene.exact_irradiance(pixel_center(&scene.plane, px, py));
            let got = image[(py * 7 + px) as usize];
            assert!(rel(got, exact) < 1e-13, "({px},{py}): {got} vs {exact}");
        }
    }
    for name in ["worked-example", "zeros", "extreme-range"] {
        let scene = preset_at(name, 9, 9);
        let reference = Reference::compute(&scene);
        for (p, value) in reference.iter() {
            let x = pixel_center(&scene.plane, p as u32 % 9, p as u32 / 9);
            assert!(rel(value, scene.exact_irradiance(x)) < 1e-12, "{name} {p}");
        }
    }
}

#[test]
fn subset_reference_covers_the_budgeted_pixels_with_identical_values() {
    let scene = preset_at("heavy-tail", 64, 64);
    let full = Reference::compute(&scene);
    assert!(full.is_complete());
    // Budget for 400 pixels of 10^4 lights.
    let subset = Reference::with_budget(&scene, 400 * 10_000);
    assert!(!subset.is_complete());
    assert!(subset.image().is_none());
    let pixels = subset.pixels();
    assert!(
        pixels.len() <= 400 && pixels.len() >= 390,
        "{}",
        pixels.len()
    );
    assert!(pixels.windows(2).all(|w| w[0] < w[1]));
    assert_eq!(pixels, subset_pixels(64, 64, 400).as_slice());
    let full_image = full.image().unwrap();
    for (p, value) in subset.iter() {
        assert_eq!(value, full_image[p], "pixel {p}");
    }
}

#[test]
fn tiny_budgets_still_cover_the_minimum_pixel_count() {
    let scene = preset_at("heavy-tail", 64, 64);
    let subset = Reference::with_budget(&scene, 1);
    let n = subset.pixels().len();
    assert!(
        (MIN_REFERENCE_PIXELS - 8..=MIN_REFERENCE_PIXELS).contains(&n),
        "{n}"
    );
}

#[test]
fn subset_pixels_spread_evenly_over_the_image() {
    // R2 is a low-discrepancy sequence: each of the 16 cells of a 4 × 4 grid holds its
    // share m/16 = 64 up to a few points.
    let (w, h, m) = (512u32, 384u32, 1024usize);
    let pixels = subset_pixels(w, h, m);
    assert!(pixels.len() > 1000);
    let mut cells = [0usize; 16];
    for &p in &pixels {
        let (x, y) = (p % w, p / w);
        cells[(y * 4 / h * 4 + x * 4 / w) as usize] += 1;
    }
    for (i, &c) in cells.iter().enumerate() {
        assert!((56..=72).contains(&c), "cell {i}: {c}");
    }
    // No column or row takes more than a few points (no stride aliasing).
    let mut columns = vec![0usize; w as usize];
    for &p in &pixels {
        columns[(p % w) as usize] += 1;
    }
    assert!(columns.iter().all(|&c| c <= 4));
    assert_eq!(subset_pixels(4, 4, 100), (0..16).collect::<Vec<_>>());
}

#[test]
fn at_pixels_sorts_and_dedups() {
    let scene = preset_at("worked-example", 8, 8);
    let r = Reference::at_pixels(&scene, vec![5, 3, 5, 63]);
    assert_eq!(r.pixels(), &[3, 5, 63]);
    assert_eq!(r.values().len(), 3);
}

// ---------------------------------------------------------------- metrics

/// A 2 × 1 reference and accumulator with chosen estimates.
fn two_pixels() -> (Reference, Accumulator) {
    let scene = Scene::from_parts(
        "two",
        ReceiverPlane {
            min: dvec2(0.0, 0.0),
            max: dvec2(2.0, 1.0),
            width: 2,
            height: 1,
        },
        vec![dvec3(0.5, 0.5, 1.0), dvec3(1.5, 0.5, 2.0)],
        vec![3.0, 1.0],
    )
    .unwrap();
    let reference = Reference::compute(&scene);
    // Total power 4 and shift 0: the unit is 4.
    let mut acc = Accumulator::new(2, 1, Scaled::from_f64(4.0), 0);
    acc.samples_per_pixel = 4;
    // Normalized samples: pixel 0 saw 1, 2, 3, 4; pixel 1 saw 0.5 four times.
    acc.sum = vec![1.0 + 2.0 + 3.0 + 4.0, 4.0 * 0.5];
    acc.sum_sq = vec![1.0 + 4.0 + 9.0 + 16.0, 4.0 * 0.25];
    (reference, acc)
}

#[test]
fn rmse_and_rel_mse_follow_their_definitions() {
    let (reference, acc) = two_pixels();
    let e = reference.values();
    // Means: pixel 0 = 4·10/4 = 10, pixel 1 = 4·2/4 = 2.
    let d = [10.0 - e[0], 2.0 - e[1]];
    let mean_ref = f64::midpoint(e[0], e[1]);
    let eps = REL_MSE_EPSILON * mean_ref * mean_ref;
    let m = error_metrics(&acc, &reference);
    assert_eq!(m.pixels, 2);
    assert!(rel(m.rmse, f64::midpoint(d[0] * d[0], d[1] * d[1]).sqrt()) < 1e-15);
    let rel_mse = f64::midpoint(
        d[0] * d[0] / (e[0] * e[0] + eps),
        d[1] * d[1] / (e[1] * e[1] + eps),
    );
    assert!(rel(m.rel_mse, rel_mse) < 1e-15);
    assert_eq!(rmse(&acc, &reference), m.rmse);
}

#[test]
fn rel_mse_is_invariant_under_scaling_the_powers() {
    let scene = preset_at("zeros", 16, 16);
    let mut bright = scene.clone();
    bright.powers = lightpick_core::LightPowers::new(
        scene.powers.as_slice().iter().map(|p| p * 1e20).collect(),
    )
    .unwrap();
    let metrics = |s: &Scene| {
        let mut r = CpuRenderer::new(s, Scheme::Alias, 1);
        r.accumulate(4);
        error_metrics(r.accumulator(), &Reference::compute(s))
    };
    let (a, b) = (metrics(&scene), metrics(&bright));
    assert!(
        rel(b.rel_mse, a.rel_mse) < 1e-9,
        "{} {}",
        a.rel_mse,
        b.rel_mse
    );
    assert!(rel(b.rmse, a.rmse * 1e20) < 1e-9);
}

#[test]
fn variance_time_and_efficiency_follow_their_definitions() {
    let (_, acc) = two_pixels();
    // Pixel 0: samples 1..4 → s² = 5/3, times scale² 16; pixel 1: constant → 0.
    let v = mean_variance_per_sample(&acc);
    assert!(rel(v, (16.0 * 5.0 / 3.0) / 2.0) < 1e-14, "{v}");
    let eff = efficiency(&acc, 2.0);
    assert_eq!(eff.variance_per_sample, v);
    assert_eq!(eff.seconds_per_sample, 2.0 / 8.0);
    // V̂ = V/Φ² (Φ = 4): the efficiency in units of the total power.
    assert!(rel(eff.normalized_variance.to_f64(), v / 16.0) < 1e-15);
    assert!(rel(eff.efficiency.to_f64(), 1.0 / (v / 16.0 * 0.25)) < 1e-15);
    assert!((eff.variance_log10 - v.log10()).abs() < 1e-14);
    assert!((eff.normalized_variance_log10 - (v / 16.0).log10()).abs() < 1e-14);
    assert!((eff.efficiency_log10 + (v / 16.0 * 0.25).log10()).abs() < 1e-14);
    // A zero variance (or no time) is an infinite efficiency, never 0 or NaN.
    for infinite in [
        efficiency_of(Scaled::ZERO, 0.25),
        efficiency_of(Scaled::from_f64(v), 0.0),
    ] {
        assert!(
            !infinite.is_finite() && infinite > Scaled::ZERO,
            "{infinite:?}"
        );
        assert_eq!(infinite.log10(), f64::INFINITY);
    }
    // Beyond f64 both ways: V̂ = 10^400 with T = 10^-8 is an efficiency of 10^-392.
    let huge = Scaled::from_f64(1e200).square();
    let tiny = efficiency_of(huge, 1e-8);
    assert_eq!(tiny.to_f64(), 0.0);
    assert!((tiny.log10() + 392.0).abs() < 1e-12, "{tiny:?}");
    assert!((efficiency_of(huge.recip(), 1e-8).log10() - 408.0).abs() < 1e-12);
    assert_eq!(
        mean_variance_per_sample(&Accumulator::new(3, 3, Scaled::from_f64(1.0), 0)),
        0.0
    );
}

/// The zero-variance test at any magnitude: `10^-12` of the reference and below is zero,
/// above is not, whether the reference is `1` or `10^400`; nothing is zero next to 0 or
/// next to itself, even where `f64` would read both as `inf`.
#[test]
fn zero_variance_is_judged_beyond_f64() {
    let huge = Scaled::from_f64(1e200).square();
    for reference in [Scaled::from_f64(1.0), huge, huge.recip()] {
        let at = |f: f64| reference.mul_f64(f);
        assert!(is_zero_variance_scaled(Scaled::ZERO, reference));
        assert!(is_zero_variance_scaled(at(0.9e-12), reference));
        assert!(!is_zero_variance_scaled(at(1.1e-12), reference));
        assert!(!is_zero_variance_scaled(reference, reference));
    }
    assert!(!is_zero_variance_scaled(Scaled::ZERO, Scaled::ZERO));
    assert!(!is_zero_variance_scaled(huge, huge.mul_f64(2.0)));
}

#[test]
#[should_panic(expected = "accumulator 3×3 vs reference 2×1")]
fn metrics_refuse_mismatched_sizes() {
    let (reference, _) = two_pixels();
    error_metrics(
        &Accumulator::new(3, 3, Scaled::from_f64(1.0), 0),
        &reference,
    );
}

// ---------------------------------------------------------------- series

#[test]
fn series_counts_are_powers_of_two_then_the_maximum() {
    assert_eq!(series_spp(0), Vec::<u32>::new());
    assert_eq!(series_spp(1), [1]);
    assert_eq!(series_spp(8), [1, 2, 4, 8]);
    assert_eq!(series_spp(10), [1, 2, 4, 8, 10]);
    let all = series_spp(u32::MAX);
    assert_eq!(all.len(), 33);
    assert_eq!(all[31], 1 << 31);
    assert_eq!(all[32], u32::MAX);
}

#[test]
fn series_points_serialize_with_the_cli_keys() {
    let point = SeriesPoint {
        spp: 4,
        rmse: 0.5,
        seconds: 0.25,
    };
    let json = serde_json::to_value(point).unwrap();
    assert_eq!(
        json,
        serde_json::json!({ "spp": 4, "rmse": 0.5, "seconds": 0.25 })
    );

    let scene = preset_at("worked-example", 8, 8);
    let reference = Reference::compute(&scene);
    let runs = cpu_convergence(&scene, &reference, &[Scheme::Uniform, Scheme::Alias], 1, 5);
    let json = serde_json::to_value(&runs).unwrap();
    assert_eq!(json[0]["scheme"], "uniform");
    assert_eq!(json[1]["scheme"], "alias");
    let spps: Vec<u64> = json[1]["series"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["spp"].as_u64().unwrap())
        .collect();
    assert_eq!(spps, [1, 2, 4, 5]);
}

#[test]
fn a_dark_scene_has_zero_error_not_nan() {
    // Every light below the plane: the exact image and every estimate are exactly 0.
    let scene = Scene::from_parts(
        "dark",
        ReceiverPlane {
            min: dvec2(0.0, 0.0),
            max: dvec2(1.0, 1.0),
            width: 4,
            height: 4,
        },
        vec![dvec3(0.5, 0.5, -1.0), dvec3(0.2, 0.2, -0.1)],
        vec![1.0, 3.0],
    )
    .unwrap();
    let reference = Reference::compute(&scene);
    assert!(reference.values().iter().all(|&v| v == 0.0));
    for scheme in [Scheme::Uniform, Scheme::Alias] {
        let mut r = CpuRenderer::new(&scene, scheme, 1);
        r.accumulate(3);
        let m = error_metrics(r.accumulator(), &reference);
        assert_eq!((m.rmse, m.rel_mse), (0.0, 0.0));
    }
}
