//! The pixel inspector's variance is the variance the renderer realizes at that pixel.
//!
//! # Statistical bound
//! At one pixel the renderer's `n` samples are independent draws of a discrete estimate
//! (`f_i/q_i` with probability `q_i`). Its unbiased sample variance `S²` has expectation
//! `σ²` and variance `(μ4 − σ⁴·(n−3)/(n−1))/n`, with `μ4` the exact fourth central moment;
//! the test fails beyond `K = 5` of those standard deviations (and likewise for the mean).

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::{DVec2, DVec3, dvec2, dvec3};
use lightpick_core::inspect::PointInspection;
use lightpick_core::render::CpuRenderer;
use lightpick_core::scene::{ReceiverPlane, Scene, geometry_term, pixel_center};
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::{LightPowers, Scheme};

const K: f64 = 5.0;
const SPP: u32 = 40_000;

fn scene() -> Scene {
    Scene::new(
        "inspect",
        ReceiverPlane {
            min: dvec2(-1.0, -1.0),
            max: dvec2(1.0, 1.0),
            width: 3,
            height: 2,
        },
        vec![
            dvec3(-0.6, 0.3, 0.4),
            dvec3(0.5, -0.4, 0.9),
            dvec3(0.1, 0.7, 0.15),
        ],
        LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap(),
    )
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

/// `q_of(x)`: the scheme's pick pmf at the point `x`.
fn check(scene: &Scene, scheme: Scheme, q_of: impl Fn(DVec2) -> Vec<f64>) {
    let mut renderer = CpuRenderer::new(scene, scheme, 77);
    renderer.accumulate(SPP);
    let acc = renderer.accumulator();
    // The scene's own spatial sampler (cut per tile of its pixels), the one the renderer
    // picks with.
    let spatial = SpatialSampler::for_scene(scene);
    let n = f64::from(SPP);
    for py in 0..scene.plane.height {
        for px in 0..scene.plane.width {
            let x = pixel_center(&scene.plane, px, py);
            let p = (py * scene.plane.width + px) as usize;
            let q = q_of(x);
            let inspection = PointInspection::at_with_spatial(scene, x, &spatial);
            let f: Vec<f64> = scene
                .positions
                .iter()
                .zip(scene.powers.as_slice())
                .map(|(&l, &phi)| phi * geometry_term(l, x))
                .collect();
            let (mean, variance, mu4) = moments(&f, &q);
            let inspected = match scheme {
                Scheme::Uniform => inspection.uniform_variance(),
                Scheme::Spatial => inspection.spatial_variance().unwrap(),
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
    let s = scene();
    check(&s, Scheme::Alias, |_| s.powers.pmf());
}

#[test]
fn uniform_sampling_variance_at_each_pixel_is_the_inspected_one() {
    let s = scene();
    let n = s.light_count();
    check(&s, Scheme::Uniform, |_| vec![1.0 / n as f64; n]);
}

/// 40 lights (a light tree): the spatial pmf depends on the point; the inspector's variance
/// is still the one the renderer realizes at each pixel.
#[test]
fn spatial_sampling_variance_at_each_pixel_is_the_inspected_one() {
    let mut s = scene();
    s.positions = (0..40)
        .map(|k| {
            let t = f64::from(k);
            [
                (0.37 * t).sin() * 1.5,
                (0.23 * t).cos() * 1.2,
                0.2 + 0.02 * t,
            ]
        })
        .map(DVec3::from)
        .collect();
    s.powers = LightPowers::new((0..40).map(|k| 1.0 + f64::from(k % 7)).collect()).unwrap();
    let sampler = SpatialSampler::for_scene(&s);
    assert!(matches!(&sampler, SpatialSampler::Tree(t) if t.tile_cuts().is_some()));
    check(&s, Scheme::Spatial, |x| sampler.pdfs(x));
}

/// Few lights: the spatial scheme is the exact pick, `q = s` at every point, no variance.
#[test]
fn the_exact_spatial_pick_has_no_variance_at_any_pixel() {
    let s = scene();
    let spatial = SpatialSampler::build(&s.positions, &s.powers);
    for (px, py) in [(0, 0), (2, 1), (1, 0)] {
        let x = pixel_center(&s.plane, px, py);
        let inspection = PointInspection::at_with_spatial(&s, x, &spatial);
        for light in &inspection.lights {
            let q = light.spatial.unwrap();
            assert!((q - light.share).abs() <= 1e-15, "light {}", light.index);
        }
        assert!(inspection.spatial_relative_variance.unwrap() <= 1e-14);
        // Without the sampler, no spatial figures.
        assert_eq!(PointInspection::at(&s, x).spatial_relative_variance, None);
    }
}
