//! The generator: reproducible, independent of the thread count, and faithful to its
//! distributions.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::dvec3;
use lightpick_core::scene::{Generator, Placement, PowerDistribution, Scene};

use super::{PLACEMENT, err, generator_scene};

fn small_generator(seed: u64) -> Generator {
    Generator {
        count: 10_000,
        seed,
        power: PowerDistribution::Exponential { mean: 2.0 },
        zero_fraction: 0.0,
        dominant: None,
        placement: Placement {
            min: dvec3(-1.0, -2.0, 0.5),
            max: dvec3(1.0, 2.0, 0.75),
        },
    }
}

#[test]
fn generation_is_reproducible_and_seed_dependent() {
    let a = small_generator(9).generate().unwrap();
    let b = small_generator(9).generate().unwrap();
    let c = small_generator(10).generate().unwrap();
    assert_eq!(a, b);
    assert_ne!(a.0, c.0);
    assert_ne!(a.1, c.1);
}

#[test]
fn generation_does_not_depend_on_the_thread_count() {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| Scene::preset("heavy-tail").unwrap());
    let three = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| Scene::preset("heavy-tail").unwrap());
    assert_eq!(one, three);
}

#[test]
fn generated_positions_fill_the_placement_box() {
    let g = small_generator(3);
    let (positions, _) = g.generate().unwrap();
    for axis in 0..3 {
        let (lo, hi) = (g.placement.min[axis], g.placement.max[axis]);
        assert!(positions.iter().all(|p| (lo..hi).contains(&p[axis])));
        // The mean of 10^4 uniforms is within 5 standard deviations
        // ((hi − lo)/√12/100) of the centre.
        let mean = positions.iter().map(|p| p[axis]).sum::<f64>() / 1e4;
        let sd = (hi - lo) / 12f64.sqrt() / 100.0;
        assert!(
            (mean - f64::midpoint(lo, hi)).abs() < 5.0 * sd,
            "axis {axis}: {mean}"
        );
    }
}

#[test]
fn generated_powers_follow_their_distribution_means() {
    // Sample means of 10^4 draws within 5 standard errors of the exact mean
    // (uniform: (b−a)/√12, exponential: σ = mean; log-uniform on [1, e²]: mean (e²−1)/2,
    // second moment (e⁴−1)/4).
    let e2 = std::f64::consts::E.powi(2);
    let log_mean = (e2 - 1.0) / 2.0;
    let log_sd = ((e2 * e2 - 1.0) / 4.0 - log_mean * log_mean).sqrt();
    let cases = [
        (
            PowerDistribution::Uniform { min: 1.0, max: 3.0 },
            2.0,
            2.0 / 12f64.sqrt(),
        ),
        (PowerDistribution::Exponential { mean: 2.0 }, 2.0, 2.0),
        (
            PowerDistribution::LogUniform { min: 1.0, max: e2 },
            log_mean,
            log_sd,
        ),
        (PowerDistribution::Constant { value: 4.0 }, 4.0, 0.0),
    ];
    for (power, mean, sd) in cases {
        let g = Generator {
            power: power.clone(),
            ..small_generator(5)
        };
        let (_, powers) = g.generate().unwrap();
        let sample_mean = powers.iter().sum::<f64>() / powers.len() as f64;
        assert!(
            (sample_mean - mean).abs() <= 5.0 * sd / 100.0,
            "{power:?}: {sample_mean} vs {mean}"
        );
    }
}

#[test]
fn dominant_light_is_exempt_from_zeroing() {
    let g = Generator {
        power: PowerDistribution::Constant { value: 1.0 },
        zero_fraction: 0.5,
        dominant: Some(lightpick_core::scene::Dominant {
            index: 1,
            factor: 1e6,
        }),
        ..small_generator(1)
    };
    let (_, powers) = g.generate().unwrap();
    assert_eq!(powers[1], 1e6);
    // Light 1 would have been zeroed (⌊2·0.5⌋ > ⌊1·0.5⌋): one zero fewer than ⌊N/2⌋.
    assert_eq!(powers.iter().filter(|&&p| p == 0.0).count(), 4999);
}

#[test]
fn unknown_distribution_parameters_are_refused() {
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "pareto", "scale": 1, "shape": 2, "mean": 3 }}, {PLACEMENT}"#
    )));
    assert!(e.to_string().contains("unknown field `mean`"), "{e}");
    assert_eq!(e.field(), Some("generator.power"));
}
