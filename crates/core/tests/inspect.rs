//! The pixel inspector's variance is the variance the renderer realizes at that pixel.
//!
//! # Statistical bound
//! At one pixel the renderer's `n` samples are independent draws of a discrete estimate
//! (`f_i/q_i` with probability `q_i`). Its unbiased sample variance `S²` has expectation
//! `σ²` and variance `(μ4 − σ⁴·(n−3)/(n−1))/n`, with `μ4` the exact fourth central moment;
//! the test fails beyond `K = 5` of those standard deviations (and likewise for the mean).

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use lightpick_core::inspect::PointInspection;
use lightpick_core::render::CpuRenderer;
use lightpick_core::scene::{ReceiverPlane, Scene, geometry_term, pixel_center};
use lightpick_core::{LightPowers, Scheme};

const K: f64 = 5.0;
const SPP: u32 = 40_000;

fn scene() -> Scene {
    Scene {
        name: "inspect".into(),
        plane: ReceiverPlane {
            min: [-1.0, -1.0],
            max: [1.0, 1.0],
            width: 3,
            height: 2,
        },
        positions: vec![[-0.6, 0.3, 0.4], [0.5, -0.4, 0.9], [0.1, 0.7, 0.15]],
        powers: LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap(),
    }
}

/// Exact mean, variance and fourth central moment of one sample with pick pmf `q`.
fn moments(f: &[f64], q: &[f64]) -> (f64, f64, f64) {
    let mean: f64 = f.iter().sum();
    let central = |k: i32| -> f64 {
        f.iter()
            .zip(q)
            .filter(|&(_, &qi)| qi > 0.0)
            .map(|(&fi, &qi)| qi * (fi / qi - mean).powi(k))
            .sum()
    };
    (mean, central(2), central(4))
}

fn check(scheme: Scheme, q_of: impl Fn(&Scene) -> Vec<f64>) {
    let scene = scene();
    let mut renderer = CpuRenderer::new(&scene, scheme, 77);
    renderer.accumulate(SPP);
    let acc = renderer.accumulator();
    let q = q_of(&scene);
    let n = f64::from(SPP);
    for py in 0..scene.plane.height {
        for px in 0..scene.plane.width {
            let x = pixel_center(&scene.plane, px, py);
            let p = (py * scene.plane.width + px) as usize;
            let inspection = PointInspection::at(&scene, x);
            let f: Vec<f64> = scene
                .positions
                .iter()
                .zip(scene.powers.as_slice())
                .map(|(&l, &phi)| phi * geometry_term(l, x))
                .collect();
            let (mean, variance, mu4) = moments(&f, &q);
            let inspected = match scheme {
                Scheme::Uniform => inspection.uniform_variance(),
                _ => inspection.power_variance(),
            };
            assert!(
                (inspected - variance).abs() <= 1e-12 * variance,
                "{scheme:?} pixel {p}: inspector {inspected} vs exact {variance}"
            );
            let mean_sd = (variance / n).sqrt();
            assert!(
                (acc.mean(p) - mean).abs() <= K * mean_sd,
                "{scheme:?} pixel {p}: mean {} vs {mean} (sd {mean_sd})",
                acc.mean(p)
            );
            let s2_sd = ((mu4 - variance * variance * (n - 3.0) / (n - 1.0)) / n).sqrt();
            let measured = acc.variance_per_sample(p);
            assert!(
                (measured - inspected).abs() <= K * s2_sd,
                "{scheme:?} pixel {p}: measured variance {measured} vs inspector {inspected} \
                 (sd {s2_sd})"
            );
        }
    }
}

#[test]
fn power_sampling_variance_at_each_pixel_is_the_inspected_one() {
    check(Scheme::Alias, |s| s.powers.pmf());
}

#[test]
fn uniform_sampling_variance_at_each_pixel_is_the_inspected_one() {
    check(Scheme::Uniform, |s| {
        vec![1.0 / s.light_count() as f64; s.light_count()]
    });
}
