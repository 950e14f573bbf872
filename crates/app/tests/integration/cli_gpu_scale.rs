//! The GPU past one storage binding, through the binary: `render --device gpu` on a
//! generated scene of `8·10^6` lights (192 MB of lights and alias table, 128 MB of the
//! spatial scheme's lights: two bindings each on lavapipe's 128 MiB), and
//! `sample --device gpu` on `2^25` lights (a 256 MB table), whose counts, chi-square and
//! printed rows must be the CPU's.
//!
//! GPU cases fail (never skip) when no adapter is found, unless `LIGHTPICK_SKIP_GPU_TESTS=1`.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use crate::common::{gpu_expected, json as ok_json, run_ok, scratch, scratch_file};

/// A scene file generating `count` lights in `[-2, 2]² × [0.2, 1]` over a 16×16 image.
fn generated_scene(count: u64) -> std::path::PathBuf {
    let text = format!(
        r#"{{
  "name": "generated-{count}",
  "plane": {{ "min": [-2.0, -2.0], "max": [2.0, 2.0], "width": 16, "height": 16 }},
  "generator": {{
    "count": {count},
    "seed": 8,
    "power": {{ "distribution": "exponential", "mean": 1 }},
    "placement": {{ "min": [-2.0, -2.0, 0.2], "max": [2.0, 2.0, 1.0] }}
  }}
}}"#
    );
    scratch_file("gpu-scale", &format!("generated-{count}.json"), text)
}

#[test]
fn render_on_the_gpu_takes_eight_million_lights_with_the_alias_table_and_the_tree() {
    if !gpu_expected() {
        return;
    }
    let scene = generated_scene(8_000_000);
    let dir = scratch("gpu-scale");
    let render = |scheme: &str| {
        let png = dir.join(format!("eight-million-{scheme}.png"));
        ok_json(&[
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--scheme",
            scheme,
            "--spp",
            "2",
            "--seed",
            "1",
            "--device",
            "gpu",
            "--out",
            png.to_str().unwrap(),
            "--json",
        ])
    };
    let alias = render("alias");
    let spatial = render("spatial");
    for v in [&alias, &spatial] {
        assert_eq!(v["device"], "gpu", "{v}");
        assert_eq!(v["spp"], 2);
        assert_eq!(
            (v["width"].as_u64(), v["height"].as_u64()),
            (Some(16), Some(16))
        );
        let rel = v["rel_mse"].as_f64().unwrap();
        assert!(rel.is_finite() && rel > 0.0, "{v}");
    }
    // The tree's variance is ~10^2 times lower than the alias table's here (one draw of each
    // relative MSE over 256 pixels at 2 spp: measured 0.016 against 5.9).
    let (a, s) = (
        alias["rel_mse"].as_f64().unwrap(),
        spatial["rel_mse"].as_f64().unwrap(),
    );
    assert!(s < a / 10.0, "spatial rel. MSE {s} vs alias {a}");
}

#[test]
fn sample_on_the_gpu_takes_two_to_the_25_lights_and_counts_what_the_cpu_counts() {
    if !gpu_expected() {
        return;
    }
    let n = 1usize << 25;
    // Odd lights zero (but the last), the others 1..5: half the table's columns alias away.
    let mut text = String::with_capacity(2 * n);
    for i in 0..n {
        let p = if i % 2 == 1 && i + 1 != n {
            0
        } else {
            1 + i % 5
        };
        text.push_str(&p.to_string());
        text.push(' ');
    }
    let path = scratch_file("gpu-scale", "powers-2-25.txt", text);
    let sample = |device: &str| {
        let out = run_ok(&[
            "sample",
            "--powers-file",
            path.to_str().unwrap(),
            "--count",
            "2000000",
            "--seed",
            "3",
            "--construction",
            "integer",
            "--device",
            device,
        ]);
        String::from_utf8(out.stdout).unwrap()
    };
    let (cpu, gpu) = (sample("cpu"), sample("gpu"));
    assert!(
        gpu.starts_with(&format!("2000000 samples of {n} lights")),
        "{gpu}"
    );
    assert!(gpu.lines().next().unwrap().ends_with("device gpu"));
    // Everything after the first line (the rows, the chi-square) is the CPU's.
    let rest = |s: &str| s.lines().skip(1).collect::<Vec<_>>().join("\n");
    assert_eq!(rest(&gpu), rest(&cpu));
    assert!(rest(&gpu).contains("chi-square"), "{gpu}");
}
