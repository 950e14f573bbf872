//! Scaling every power (or contribution) by `2^k`, `k ∈ [−1000, 1000]`, scales every
//! absolute figure by `2^k` (variances by `2^(2k)`) bit for bit and leaves every relative
//! figure unchanged: the estimators and metrics run in a unit that follows the scale.

use glam::{dvec2, dvec3};
use lightpick_core::point_estimate::{PointEstimator, SchemeRun};
use lightpick_core::render::{CpuRenderer, Reference, efficiency, error_metrics};
use lightpick_core::scene::{ReceiverPlane, Scene};
use lightpick_core::{
    AliasTable, LightPowers, Sampler, Scaled, Scheme, ShadingContext, Uniform, Welford,
    analytic_moments,
};
use proptest::prelude::*;
use std::sync::Arc;

/// `x` and `y` are the same figure up to the factor `2^k`: identical significands and
/// exponents `k` apart (zero stays zero).
fn scaled_by(x: Scaled, y: Scaled, k: i32) -> bool {
    if x.significand() == 0.0 {
        return y.significand() == 0.0;
    }
    x.significand().to_bits() == y.significand().to_bits() && y.exponent() == x.exponent() + k
}

fn pow2(x: f64, k: i32) -> f64 {
    Scaled::new(x, k).to_f64()
}

/// Seven lights at heights 0.5 … 2 over a 6×5 plane, one below it, with powers in
/// `[0.25, 4)` (times `2^±1000` stay normal and finite).
fn scene(powers: &[f64], k: i32) -> Scene {
    let positions = vec![
        dvec3(0.2, 0.3, 0.5),
        dvec3(1.5, 0.4, 1.0),
        dvec3(0.9, 1.7, 2.0),
        dvec3(1.8, 1.8, 0.7),
        dvec3(0.1, 1.1, 1.3),
        dvec3(1.2, 0.9, -0.5),
        dvec3(0.6, 0.6, 0.9),
    ];
    Scene::from_parts(
        "scaled",
        ReceiverPlane {
            min: dvec2(0.0, 0.0),
            max: dvec2(2.0, 2.0),
            width: 6,
            height: 5,
        },
        positions,
        powers.iter().map(|&p| pow2(p, k)).collect(),
    )
    .expect("valid scene")
}

fn powers() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(0.25f64..4.0, 7)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn welford_scales_with_its_unit(
        xs in prop::collection::vec(1e-3f64..1.0, 2..40),
        k in -1000i32..=1000,
    ) {
        let mut plain = Welford::new();
        let mut scaled = Welford::in_unit(k);
        for &x in &xs {
            plain.push(x);
            scaled.push(pow2(x, k));
        }
        prop_assert_eq!(plain.mean_in_unit().to_bits(), scaled.mean_in_unit().to_bits());
        prop_assert!(scaled_by(plain.mean_scaled(), scaled.mean_scaled(), k));
        prop_assert!(scaled_by(plain.std_error_scaled(), scaled.std_error_scaled(), k));
        prop_assert!(scaled_by(plain.variance_scaled(), scaled.variance_scaled(), 2 * k));
        prop_assert!(!scaled.variance().is_nan());
        let log = plain.variance_scaled().log10() + 2.0 * f64::from(k) * std::f64::consts::LOG10_2;
        prop_assert!((scaled.variance_scaled().log10() - log).abs() < 1e-9);
    }

    #[test]
    fn estimates_scale_with_the_contributions(
        powers in powers(),
        f in prop::collection::vec(1e-3f64..1.0, 7),
        k in -1000i32..=1000,
    ) {
        let table = Arc::new(AliasTable::build(&LightPowers::new(powers).expect("valid")));
        let estimator = |contributions: Vec<f64>| {
            let mut e = PointEstimator::new(
                contributions,
                ShadingContext::default(),
                vec![
                    ("uniform", Sampler::Uniform(Uniform::new(7)).into()),
                    ("power", Sampler::Alias(Arc::clone(&table)).into()),
                ],
                5,
            )
            .expect("valid point");
            e.advance(300);
            e
        };
        let a = estimator(f.clone());
        let b = estimator(f.iter().map(|&x| pow2(x, k)).collect());
        prop_assert_eq!(pow2(a.exact(), k).to_bits(), b.exact().to_bits());
        for (la, lb) in a.runs().iter().zip(b.runs()) {
            let (ra, rb) = (la.running(), lb.running());
            prop_assert_eq!(ra.mean_in_unit().to_bits(), rb.mean_in_unit().to_bits());
            prop_assert!(scaled_by(ra.mean_scaled(), rb.mean_scaled(), k));
            prop_assert!(scaled_by(ra.std_error_scaled(), rb.std_error_scaled(), k));
            prop_assert!(scaled_by(la.measured_variance(), lb.measured_variance(), 2 * k));
            prop_assert!(scaled_by(
                la.analytic.variance_scaled,
                lb.analytic.variance_scaled,
                2 * k
            ));
            // The z-score of the running mean against the analytic mean, in the unit.
            let z = |l: &SchemeRun| {
                let w = l.running();
                let unit = Scaled::pow2(-w.unit_exponent());
                (w.mean_in_unit() - (Scaled::from_f64(l.analytic.mean) * unit).to_f64())
                    / (w.std_error_scaled() * unit).to_f64()
            };
            prop_assert_eq!(z(la).to_bits(), z(lb).to_bits());
        }
        let m = analytic_moments(&f, |i| table.pmf(i));
        let ms = analytic_moments(b.contributions(), |i| table.pmf(i));
        prop_assert!(scaled_by(m.variance_scaled, ms.variance_scaled, 2 * k));
    }

    #[test]
    fn render_metrics_scale_with_the_powers(powers in powers(), k in -1000i32..=1000) {
        let base = scene(&powers, 0);
        let scaled = scene(&powers, k);
        let (ra, rb) = (Reference::compute(&base), Reference::compute(&scaled));
        prop_assert_eq!(ra.in_unit(), rb.in_unit());
        prop_assert!(scaled_by(ra.unit(), rb.unit(), k));
        for (&va, &vb) in ra.values().iter().zip(rb.values()) {
            prop_assert_eq!(pow2(va, k).to_bits(), vb.to_bits());
        }
        for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::Spatial] {
            let render = |s: &Scene| {
                let mut r = CpuRenderer::new(s, scheme, 3);
                r.accumulate(6);
                r.accumulator().clone()
            };
            let (aa, ab) = (render(&base), render(&scaled));
            prop_assert_eq!(&aa.sum, &ab.sum, "{}", scheme);
            prop_assert_eq!(&aa.sum_sq, &ab.sum_sq, "{}", scheme);
            for p in 0..aa.sum.len() {
                prop_assert_eq!(pow2(aa.mean(p), k).to_bits(), ab.mean(p).to_bits());
            }
            let (ma, mb) = (error_metrics(&aa, &ra), error_metrics(&ab, &rb));
            prop_assert_eq!(pow2(ma.rmse, k).to_bits(), mb.rmse.to_bits(), "{}", scheme);
            prop_assert_eq!(ma.rel_mse.to_bits(), mb.rel_mse.to_bits());
            let (ea, eb) = (efficiency(&aa, 0.5), efficiency(&ab, 0.5));
            prop_assert!(scaled_by(ea.normalized_variance, eb.normalized_variance, 0));
            prop_assert!(scaled_by(ea.efficiency, eb.efficiency, 0));
            let shift = 2.0 * f64::from(k) * std::f64::consts::LOG10_2;
            prop_assert!((eb.variance_log10 - ea.variance_log10 - shift).abs() < 1e-9);
            prop_assert!(!eb.variance_per_sample.is_nan());
        }
    }
}

/// The examples: powers `1e200, 3e200` render with finite RMSE and relMSE, a
/// variance beyond `f64` reported by its `log10`, and the same efficiency as powers `1, 3`.
#[test]
fn huge_powers_report_every_figure() {
    let at = |powers: [f64; 2]| {
        let s = Scene::from_parts(
            "two",
            ReceiverPlane {
                min: dvec2(0.0, 0.0),
                max: dvec2(1.0, 1.0),
                width: 4,
                height: 4,
            },
            vec![dvec3(0.2, 0.2, 0.5), dvec3(0.8, 0.7, 0.8)],
            powers.to_vec(),
        )
        .expect("valid");
        let reference = Reference::compute(&s);
        let mut r = CpuRenderer::new(&s, Scheme::Uniform, 9);
        r.accumulate(8);
        let m = error_metrics(r.accumulator(), &reference);
        let e = efficiency(r.accumulator(), 1.0);
        (m, e)
    };
    let (small, small_e) = at([1.0, 3.0]);
    let (huge, huge_e) = at([1e200, 3e200]);
    assert!(huge.rmse.is_finite() && huge.rmse > 0.0, "{huge:?}");
    assert!(huge.rel_mse.is_finite() && huge.rel_mse > 0.0);
    assert!((huge.rel_mse / small.rel_mse - 1.0).abs() < 1e-12);
    assert!((huge.rmse / small.rmse / 1e200 - 1.0).abs() < 1e-12);
    assert_eq!(huge_e.variance_per_sample, f64::INFINITY);
    assert!((huge_e.variance_log10 - small_e.variance_log10 - 400.0).abs() < 1e-9);
    assert!(((huge_e.efficiency / small_e.efficiency).to_f64() - 1.0).abs() < 1e-12);
    let (tiny, tiny_e) = at([1e-180, 3e-180]);
    assert!(tiny.rmse > 0.0 && (tiny.rel_mse / small.rel_mse - 1.0).abs() < 1e-12);
    assert!((tiny_e.variance_log10 - small_e.variance_log10 + 360.0).abs() < 1e-9);
}

/// A light `10^-150` above a pixel centre: the irradiance there (`≈ 8·10^298` per unit
/// power) fits `f64`, and so do the metrics; `10^-160` does not, and the reference names the
/// pixel and the light.
#[test]
fn lights_next_to_the_plane_are_measured_or_named() {
    let plane = ReceiverPlane {
        min: dvec2(0.0, 0.0),
        max: dvec2(2.0, 2.0),
        width: 2,
        height: 2,
    };
    let with_height = |z: f64| {
        Scene::from_parts(
            "close",
            plane.clone(),
            vec![dvec3(0.5, 1.5, z), dvec3(1.0, 1.0, 1.0)],
            vec![1.0, 1.0],
        )
        .expect("valid")
    };
    let near = with_height(1e-150);
    let reference = Reference::compute(&near);
    assert_eq!(reference.overflow(), None);
    assert!(reference.values().iter().all(|v| v.is_finite()));
    let mut r = CpuRenderer::new(&near, Scheme::Alias, 2);
    r.accumulate(16);
    let m = error_metrics(r.accumulator(), &reference);
    assert!(m.rmse.is_finite() && m.rel_mse.is_finite(), "{m:?}");
    let e = efficiency(r.accumulator(), 1.0);
    assert!(
        e.efficiency.is_finite() && e.efficiency > Scaled::ZERO && !e.variance_log10.is_nan(),
        "{e:?}"
    );

    let touching = with_height(1e-160);
    let overflow = Reference::compute(&touching)
        .overflow()
        .expect("the irradiance under the light exceeds f64");
    // Pixel (0, 0) is the top-left one, centre (0.5, 1.5): right under light 0.
    assert_eq!((overflow.x, overflow.y, overflow.light), (0, 0, 0));
    assert!(overflow.to_string().contains("pixel (0, 0)"));
}
