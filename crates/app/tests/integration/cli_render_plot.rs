//! End-to-end tests of `lightpick render`, `lightpick plot` and `sample --device gpu`.
//!
//! GPU cases fail (never skip) when no adapter is found, unless `LIGHTPICK_SKIP_GPU_TESTS=1`.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use std::path::Path;

use crate::common::{assert_error, gpu_expected, json as ok_json, run_ok, scratch};

fn png_size(path: &Path) -> (u32, u32) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (img.width(), img.height())
}

#[test]
fn render_on_the_cpu_writes_png_exr_and_stats() {
    let dir = scratch("render");
    let (png, exr, stats) = (dir.join("s.png"), dir.join("s.exr"), dir.join("s.json"));
    let v = ok_json(&[
        "render",
        "--preset",
        "worked-example",
        "--scheme",
        "power",
        "--spp",
        "8",
        "--seed",
        "3",
        "--device",
        "cpu",
        "--width",
        "64",
        "--height",
        "48",
        "--out",
        png.to_str().unwrap(),
        "--hdr",
        exr.to_str().unwrap(),
        "--stats",
        stats.to_str().unwrap(),
        "--json",
    ]);
    for key in [
        "spp",
        "width",
        "height",
        "rmse",
        "rel_mse",
        "seconds",
        "samples_per_second",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["spp"], 8);
    assert_eq!(v["width"], 64);
    assert_eq!(v["device"], "cpu");
    let series = v["series"].as_array().unwrap();
    let spps: Vec<u64> = series.iter().map(|p| p["spp"].as_u64().unwrap()).collect();
    assert_eq!(spps, vec![1, 2, 4, 8]);
    // Power sampling of the seed converges: RMSE at 8 spp is below the 1-spp RMSE.
    assert!(series[3]["rmse"].as_f64().unwrap() < series[0]["rmse"].as_f64().unwrap());
    assert_eq!(png_size(&png), (64, 48));
    assert_eq!(png_size(&exr), (64, 48));
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(written["rmse"], v["rmse"]);
}

#[test]
fn error_map_needs_a_complete_reference() {
    let dir = scratch("errmap");
    let png = dir.join("e.png");
    run_ok(&[
        "render",
        "--preset",
        "worked-example",
        "--spp",
        "2",
        "--device",
        "cpu",
        "--width",
        "32",
        "--height",
        "32",
        "--map",
        "error",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(png_size(&png), (32, 32));
    assert_error(
        &[
            "render",
            "--preset",
            "million",
            "--spp",
            "1",
            "--device",
            "cpu",
            "--width",
            "64",
            "--height",
            "64",
            "--map",
            "error",
            "--out",
            png.to_str().unwrap(),
        ],
        "--map error needs a reference over every pixel",
    );
}

#[test]
fn render_refuses_bad_input() {
    assert_error(
        &["render", "--preset", "worked-example", "--spp", "0"],
        "--spp",
    );
    assert_error(
        &["render", "--preset", "worked-example", "--width", "0"],
        "--width",
    );
    assert_error(
        &["render", "--preset", "worked-example", "--width", "100000"],
        "--width",
    );
    assert_error(&["render"], "no scene given");
    assert_error(
        &["render", "--preset", "worked-example", "--exposure", "-1"],
        "--exposure",
    );
    let dir = scratch("badscene");
    let file = dir.join("bad.json");
    std::fs::write(
        &file,
        r#"{"plane":{"min":[0,0],"max":[1,1],"width":8,"height":8},"lights":[{"position":[0,0,1],"power":-3}]}"#,
    )
    .unwrap();
    assert_error(
        &[
            "render",
            "--scene",
            file.to_str().unwrap(),
            "--device",
            "cpu",
        ],
        "lights[0].power",
    );
    std::fs::write(&file, "{ not json").unwrap();
    assert_error(
        &["table", "--scene", file.to_str().unwrap()],
        file.to_str().unwrap(),
    );
}

#[test]
fn gpu_and_cpu_renders_agree() {
    if !gpu_expected() {
        return;
    }
    let args = |device| {
        ok_json(&[
            "render",
            "--preset",
            "worked-example",
            "--spp",
            "16",
            "--seed",
            "9",
            "--width",
            "48",
            "--height",
            "32",
            "--device",
            device,
            "--json",
        ])
    };
    let (cpu, gpu) = (args("cpu"), args("gpu"));
    assert_eq!(gpu["device"], "gpu");
    // Same picks; the images differ only by f32 rounding (relative ~1e-6), so the RMSE
    // against the same reference agrees far inside 1e-3 relative.
    let (a, b) = (cpu["rmse"].as_f64().unwrap(), gpu["rmse"].as_f64().unwrap());
    assert!((a - b).abs() <= 1e-3 * a, "cpu {a} vs gpu {b}");
}

#[test]
fn gpu_sample_counts_equal_cpu_counts() {
    if !gpu_expected() {
        return;
    }
    for scheme in ["uniform", "alias", "alias-one-random"] {
        let run = |device| {
            ok_json(&[
                "sample", "--preset", "zeros", "--scheme", scheme, "--count", "200000", "--seed",
                "4", "--device", device, "--json",
            ])
        };
        let (cpu, gpu) = (run("cpu"), run("gpu"));
        assert_eq!(gpu["device"], "gpu");
        assert_eq!(cpu["counts"], gpu["counts"], "{scheme}");
    }
    assert_error(
        &[
            "sample", "--powers", "1,2", "--scheme", "cdf", "--device", "gpu",
        ],
        "cdf",
    );
}

#[test]
fn plots_are_written() {
    let dir = scratch("plots");
    let cases: [(&str, &[&str]); 4] = [
        ("table", &["--powers", "2,5,20"]),
        ("histogram", &["--preset", "zeros", "--count", "5000"]),
        ("convergence", &["--preset", "worked-example", "--spp", "8"]),
        (
            "sheet",
            &[
                "--preset",
                "worked-example",
                "--spp",
                "2",
                "--image-width",
                "40",
            ],
        ),
    ];
    for (kind, extra) in cases {
        let out_path = dir.join(format!("{kind}.png"));
        let mut args = vec!["plot", kind];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out_path.to_str().unwrap()]);
        run_ok(&args);
        assert_eq!(png_size(&out_path), (800, 500), "{kind}");
    }
    let out_path = dir.join("bad.png");
    assert_error(
        &[
            "plot",
            "table",
            "--powers",
            "1,nan",
            "--out",
            out_path.to_str().unwrap(),
        ],
        "light 1 is not finite",
    );
    assert_error(
        &[
            "plot",
            "table",
            "--powers",
            "1",
            "--width",
            "5",
            "--out",
            out_path.to_str().unwrap(),
        ],
        "--width",
    );
}

#[test]
fn presets_feed_every_power_command() {
    let v = ok_json(&["table", "--preset", "worked-example", "--json"]);
    assert_eq!(v["alias"], serde_json::json!([2, 2, 2]));
    let v = ok_json(&[
        "estimate",
        "--preset",
        "worked-example",
        "--contrib",
        "1,2,15",
        "--count",
        "1000",
        "--json",
    ]);
    assert_eq!(v["exact"], 18.0);
    assert_error(&["table", "--preset", "nope"], "unknown preset 'nope'");
    assert_error(
        &["table", "--powers", "1", "--preset", "worked-example"],
        "give the powers once",
    );
}

#[test]
fn convergence_plots_the_chosen_schemes_and_the_sheet_has_a_spatial_column() {
    let dir = scratch("schemes");
    let png = dir.join("c.png");
    let out = png.to_str().unwrap();
    // The default list includes spatial, exact (zero variance) on the worked example's three lights:
    // the plot is still drawn, that series off the axes.
    for extra in [
        &[][..],
        &["--schemes", "uniform,spatial"][..],
        &["--schemes", "power,alias-one-random"][..],
        &["--preset", "grid", "--schemes", "alias,spatial"][..],
    ] {
        let mut args = vec!["plot", "convergence", "--spp", "4", "--out", out];
        args.extend_from_slice(extra);
        run_ok(&args);
        assert_eq!(png_size(&png), (800, 500), "{extra:?}");
    }
    assert_error(
        &[
            "plot",
            "convergence",
            "--schemes",
            "uniform,magic",
            "--out",
            out,
        ],
        "unknown scheme 'magic'",
    );
    assert_error(
        &[
            "plot",
            "convergence",
            "--schemes",
            "alias,power",
            "--out",
            out,
        ],
        "--schemes: item 1 ('alias') is already in the list",
    );
    let sheet = dir.join("s.png");
    run_ok(&[
        "plot",
        "sheet",
        "--preset",
        "equal",
        "--spp",
        "2",
        "--image-width",
        "32",
        "--out",
        sheet.to_str().unwrap(),
    ]);
    assert_eq!(png_size(&sheet), (800, 500));
}

#[test]
fn commands_that_need_positions_refuse_bare_powers_clearly() {
    let dir = scratch("bare");
    let file = dir.join("p.txt");
    std::fs::write(&file, "2 5 20").unwrap();
    let file = file.to_str().unwrap();
    let png = dir.join("x.png");
    let png = png.to_str().unwrap();
    for (command, args) in [
        (
            "plot convergence",
            vec!["plot", "convergence", "--out", png],
        ),
        ("plot sheet", vec!["plot", "sheet", "--out", png]),
        ("render", vec!["render", "--device", "cpu"]),
    ] {
        let mut with_list = args.clone();
        with_list.extend_from_slice(&["--powers", "2,5,20"]);
        assert_error(
            &with_list,
            &format!(
                "--powers: {command} needs light positions, which bare powers do not have; \
                 use --scene FILE or --preset NAME"
            ),
        );
        let mut with_file = args;
        with_file.extend_from_slice(&["--powers-file", file]);
        assert_error(&with_file, "--powers-file: ");
    }
}

#[test]
fn the_grid_preset_loads_everywhere_presets_do() {
    let v = ok_json(&["table", "--preset", "grid", "--json"]);
    assert_eq!(v["n"], 1024);
    assert_eq!(v["total_power"], 1024.0);
    let v = ok_json(&[
        "render", "--preset", "grid", "--scheme", "spatial", "--spp", "4", "--width", "16",
        "--height", "16", "--device", "cpu", "--json",
    ]);
    assert_eq!(v["scene"], "grid");
    assert_eq!(v["lights"], 1024);
    let v = ok_json(&[
        "sample", "--preset", "grid", "--count", "1000", "--device", "cpu", "--json",
    ]);
    assert_eq!(v["counts"].as_array().unwrap().len(), 1024);
}
