//! End-to-end tests of the spatial (contribution-aware) scheme through the binary:
//! `render --scheme spatial` on both devices, `bench` rows, and the clear refusal of
//! `sample`/`estimate`, which have no shading point.
//!
//! GPU cases fail (never skip) when no adapter is found, unless `LIGHTPICK_SKIP_GPU_TESTS=1`.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use crate::common::{assert_error, bench_json, json as ok_json, num, scratch};

fn render(preset: &str, scheme: &str, device: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "render", "--preset", preset, "--scheme", scheme, "--spp", "16", "--seed", "5", "--width",
        "48", "--height", "48", "--device", device, "--json",
    ];
    args.extend_from_slice(extra);
    ok_json(&args)
}

#[test]
fn render_spatial_on_the_cpu_writes_the_png_and_beats_power_on_spread_lights() {
    let dir = scratch("spatial");
    let (png, stats) = (dir.join("sp.png"), dir.join("sp.json"));
    let v = render(
        "equal",
        "spatial",
        "cpu",
        &[
            "--out",
            png.to_str().unwrap(),
            "--stats",
            stats.to_str().unwrap(),
        ],
    );
    assert_eq!(v["scheme"], "spatial");
    assert_eq!(v["device"], "cpu");
    assert_eq!(v["spp"], 16);
    assert!(num(&v["samples_per_second"]) > 0.0);
    assert_eq!(v["series"].as_array().unwrap().len(), 5);
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (48, 48));
    assert!(stats.exists());
    // 64 equal lights spread over the plane: the tree picks near lights; power sampling
    // picks uniformly. Measured ≈ 16× lower variance, so ≈ 4× lower RMSE; demand 2×.
    let power = render("equal", "power", "cpu", &[]);
    assert!(
        num(&v["rmse"]) * 2.0 < num(&power["rmse"]),
        "spatial {} vs power {}",
        v["rmse"],
        power["rmse"]
    );
}

#[test]
fn render_spatial_on_few_lights_is_exact() {
    let v = render("worked-example", "spatial", "cpu", &[]);
    let power = render("worked-example", "power", "cpu", &[]);
    // Three lights: the exact contribution pick has zero variance; what is left is rounding.
    assert!(
        num(&v["rmse"]) <= 1e-12 * num(&power["rmse"]),
        "{}",
        v["rmse"]
    );
}

#[test]
fn render_spatial_on_the_gpu_agrees_with_the_cpu() {
    if std::env::var_os("LIGHTPICK_SKIP_GPU_TESTS").is_some() {
        eprintln!("GPU case skipped: LIGHTPICK_SKIP_GPU_TESTS is set");
        return;
    }
    for preset in ["heavy-tail", "worked-example"] {
        let cpu = render(preset, "spatial", "cpu", &[]);
        let gpu = render(preset, "spatial", "gpu", &[]);
        assert_eq!(gpu["device"], "gpu");
        let (a, b) = (num(&cpu["rmse"]), num(&gpu["rmse"]));
        if preset == "worked-example" {
            // Both exact: f32 rounding of the sum (≈ 1e-6 of the irradiance) is all there is.
            let power = num(&render(preset, "power", "cpu", &[])["rmse"]);
            assert!(b <= 1e-4 * power, "{preset}: gpu rmse {b}");
        } else {
            // Same picks but for rare f32/f64 branch flips (see gpu_spatial.rs): same RMSE.
            assert!((a - b).abs() <= 1e-3 * a, "{preset}: cpu {a} vs gpu {b}");
        }
    }
}

#[test]
fn sample_and_estimate_refuse_spatial_with_one_error_line() {
    assert_error(
        &[
            "sample", "--powers", "2,5,20", "--scheme", "spatial", "--count", "10",
        ],
        "shading point",
    );
    assert_error(
        &[
            "estimate",
            "--powers",
            "2,5,20",
            "--contrib",
            "1,2,3",
            "--scheme",
            "spatial",
            "--count",
            "10",
        ],
        "shading point",
    );
    assert_error(
        &[
            "render",
            "--preset",
            "worked-example",
            "--scheme",
            "spatiall",
        ],
        "spatial",
    );
}

#[test]
fn bench_rows_include_spatial() {
    let v = bench_json(&["--presets", "equal", "--spp", "8"]);
    let schemes = v["renders"][0]["schemes"].as_array().unwrap();
    let spatial = schemes.iter().find(|s| s["scheme"] == "spatial").unwrap();
    let alias = schemes.iter().find(|s| s["scheme"] == "alias").unwrap();
    for key in [
        "variance_per_sample",
        "seconds_per_sample",
        "efficiency",
        "efficiency_vs_uniform",
        "rmse_at_equal_time",
        "build_seconds",
    ] {
        assert!(num(&spatial[key]).is_finite(), "{key}: {spatial}");
    }
    assert!(num(&spatial["variance_per_sample"]) * 4.0 < num(&alias["variance_per_sample"]));
}

#[test]
fn bench_reports_the_exact_pick_as_zero_variance_with_infinite_efficiency() {
    let v = bench_json(&["--presets", "worked-example", "--spp", "8"]);
    let schemes = v["renders"][0]["schemes"].as_array().unwrap();
    for s in schemes {
        let exact = s["scheme"] == "spatial";
        assert_eq!(s["zero_variance"], exact, "{s}");
        if exact {
            // Infinite efficiency: JSON has no infinity, so null.
            assert!(s["efficiency"].is_null(), "{s}");
            assert!(s["efficiency_vs_uniform"].is_null(), "{s}");
        } else {
            assert!(num(&s["efficiency"]) > 0.0, "{s}");
        }
    }
}
