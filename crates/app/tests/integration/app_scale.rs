//! The app's and the CLI's figures at every scale of power: the Trade panel's measurement
//! and `lightpick estimate`'s accumulator scale by `2^k` (variances by `2^(2k)`) and keep
//! their relative figures, for `k ∈ [−1000, 1000]`; the CLI prints finite figures for
//! powers near `10^200` and names a pixel whose irradiance exceeds `f64`.

use lightpick::app::state::trade::measure;
use lightpick_core::point_estimate::sampled_mean as estimate;
use lightpick_core::scene::Scene;
use lightpick_core::{Construction, LightPowers, Sampler, Scaled, Scheme};
use proptest::prelude::*;

use crate::common::{json, lightpick, scratch};

fn pow2(x: f64, k: i32) -> f64 {
    Scaled::new(x, k).to_f64()
}

/// The worked-example preset with every power times `2^k` (2, 5, 20 stay normal and finite for
/// `|k| ≤ 1000`).
fn seed_times(k: i32) -> Scene {
    let mut scene = Scene::preset("worked-example").expect("worked-example preset");
    let powers = scene
        .powers
        .as_slice()
        .iter()
        .map(|&p| pow2(p, k))
        .collect();
    scene.powers = LightPowers::new(powers).expect("finite powers");
    scene
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]

    /// The Trade panel (virtual time, so the timings are the same): every row's efficiency
    /// and normalized variance keep their bits, RMSEs scale by `2^k`, `log10 V` by `2k·log10 2`.
    #[test]
    fn trade_panel_figures_follow_the_scale(k in -1000i32..=1000) {
        let (a, b) = (measure(1, &seed_times(0), true), measure(1, &seed_times(k), true));
        for (ra, rb) in a.rows.iter().zip(&b.rows) {
            let (ea, eb) = (ra.efficiency, rb.efficiency);
            for (a, b) in [
                (ea.efficiency, eb.efficiency),
                (ea.normalized_variance, eb.normalized_variance),
            ] {
                prop_assert_eq!(a.significand().to_bits(), b.significand().to_bits());
                prop_assert_eq!(a.exponent(), b.exponent(), "{}", ra.scheme);
            }
            let shift = 2.0 * f64::from(k) * std::f64::consts::LOG10_2;
            prop_assert!((eb.variance_log10 - ea.variance_log10 - shift).abs() < 1e-9);
            for (pa, pb) in ra.series.iter().zip(&rb.series) {
                prop_assert_eq!(pow2(pa.rmse, k).to_bits(), pb.rmse.to_bits());
            }
        }
    }

    /// `lightpick estimate`'s accumulator: the same bits in its unit, the mean and standard
    /// error scaled by `2^k`, the variance by `2^(2k)`.
    #[test]
    fn cli_estimate_follows_the_scale(k in -1000i32..=1000) {
        let powers = LightPowers::new(vec![2.0, 5.0, 20.0]).expect("valid");
        let contrib = [1.0, 2.0, 15.0];
        let scaled: Vec<f64> = contrib.iter().map(|&f| pow2(f, k)).collect();
        for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::Cdf] {
            let sampler = Sampler::try_build_with(scheme, &powers, Construction::Exact)
                .expect("point-free scheme");
            let (a, b) = (estimate(&sampler, &contrib, 5000, 3), estimate(&sampler, &scaled, 5000, 3));
            prop_assert_eq!(a.mean_in_unit().to_bits(), b.mean_in_unit().to_bits());
            prop_assert_eq!(a.variance_in_unit().to_bits(), b.variance_in_unit().to_bits());
            prop_assert_eq!(pow2(a.mean(), k).to_bits(), b.mean().to_bits());
            prop_assert_eq!(pow2(a.std_error(), k).to_bits(), b.std_error().to_bits());
            prop_assert_eq!(
                b.variance_scaled().exponent(),
                a.variance_scaled().exponent() + 2 * k
            );
        }
    }
}

/// The issue's command: every figure present, the variances beyond `f64` given by `log10`.
#[test]
fn estimate_prints_every_figure_for_huge_contributions() {
    let v = json(&[
        "estimate",
        "--powers",
        "1e200,3e200",
        "--contrib",
        "1e199,2e199",
        "--scheme",
        "alias",
        "--count",
        "20000",
        "--json",
    ]);
    let std_error = v["std_error"].as_f64().expect("a finite standard error");
    assert!(std_error > 1e196 && std_error < 1e198, "{v}");
    // Var = Σ f²/p − F² with p = 1/4, 3/4 and f = 1e199, 2e199:
    // (4 + 4/0.75 − 9)·10^398 = (1/3)·10^398.
    let log = v["analytic_variance_log10"].as_f64().expect("log10");
    assert!((log - (1.0f64 / 3.0).log10() - 398.0).abs() < 1e-9, "{v}");
    assert!(
        v["analytic_variance"].is_null(),
        "beyond f64: null with its log10"
    );
    assert!(
        v["variance_log10"]
            .as_f64()
            .is_some_and(|l| (l - log).abs() < 0.1)
    );
    assert!(v["z_score"].as_f64().is_some_and(|z| z.abs() < 5.0), "{v}");
}

/// `render` of powers near `10^200`: finite RMSE and relMSE, the variance by its `log10`;
/// a light `10^-160` above a pixel centre: exit 2 naming the pixel and the light.
#[test]
fn render_reports_huge_powers_and_names_an_overflowing_pixel() {
    let dir = scratch("scale-render");
    let huge = dir.join("huge.json");
    std::fs::write(
        &huge,
        r#"{"name": "huge", "plane": {"min": [0, 0], "max": [2, 2], "width": 8, "height": 8},
           "lights": [{"position": [0.5, 0.5, 0.5], "power": 1e200},
                      {"position": [1.5, 1.2, 0.8], "power": 3e200}]}"#,
    )
    .expect("write scene");
    let v = json(&[
        "render",
        "--scene",
        huge.to_str().expect("utf-8"),
        "--scheme",
        "uniform",
        "--spp",
        "4",
        "--device",
        "cpu",
        "--json",
    ]);
    let rmse = v["rmse"].as_f64().expect("finite RMSE");
    assert!(rmse > 1e190 && rmse.is_finite(), "{v}");
    assert!(
        v["rel_mse"]
            .as_f64()
            .is_some_and(|r| r > 0.0 && r.is_finite()),
        "{v}"
    );
    assert!(v["efficiency"].as_f64().is_some_and(f64::is_finite), "{v}");
    assert!(
        v["variance_log10"].as_f64().is_some_and(|l| l > 390.0),
        "{v}"
    );

    let close = dir.join("close.json");
    // Pixel (1, 2) of a 4×4 plane over [0, 4]²: centre (1.5, 1.5).
    std::fs::write(
        &close,
        r#"{"name": "close", "plane": {"min": [0, 0], "max": [4, 4], "width": 4, "height": 4},
           "lights": [{"position": [3, 3, 1], "power": 1},
                      {"position": [1.5, 1.5, 1e-160], "power": 1}]}"#,
    )
    .expect("write scene");
    let out = lightpick(&[
        "render",
        "--scene",
        close.to_str().expect("utf-8"),
        "--spp",
        "1",
        "--device",
        "cpu",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.starts_with("error:"), "{stderr}");
    assert!(
        stderr.contains("pixel (1, 2)") && stderr.contains("light 1"),
        "{stderr}"
    );
}
