#![allow(clippy::unwrap_used)]
//! `lightpick precision` and `lightpick bench`: JSON shape, the default path within its
//! documented bounds, and one-line errors with exit code 2. Timings are never asserted.

use crate::common::{assert_error, json, lightpick, num, run_ok, scratch};

#[test]
fn precision_json_reports_every_distribution_within_the_documented_bounds() {
    let v = json(&["precision", "--n", "4099", "--json"]);
    let reports = v["reports"].as_array().unwrap();
    assert_eq!(reports.len(), 5);
    for r in reports {
        assert_eq!(r["n"], 4099);
        let name = r["distribution"].as_str().unwrap();
        assert_eq!(
            num(&r["construction"]["f64_build"]["zero_leak"]),
            0.0,
            "{name}"
        );
        assert!(
            num(&r["construction"]["f64_build"]["max_rel_error"]) < 1e-9,
            "{name}"
        );
        assert!(
            num(&r["thresholds"]["u32_error_over_bound"]) <= 1.0 + 1e-6,
            "{name}"
        );
        assert!(
            num(&r["thresholds"]["f32_error_over_bound"]) <= 1.0 + 1e-6,
            "{name}"
        );
        assert_eq!(r["thresholds"]["u32_lost_lights"], 0, "{name}");
        assert!(
            num(&r["one_random"]["one_error_over_bound"]) < 1.0,
            "{name}"
        );
        assert!(
            num(&r["one_random"]["two_error_over_bound"]) < 1.0,
            "{name}"
        );
        assert_eq!(num(&r["one_random"]["two_zero_leak"]), 0.0, "{name}");
        assert_eq!(r["one_random"]["fraction_step"], 4099);
    }
    let sweep = v["column_pick"].as_array().unwrap();
    assert!(
        sweep.iter().any(|c| c["n"] == 4099),
        "the chosen N joins the sweep"
    );
    for c in sweep {
        let n = c["n"].as_u64().unwrap();
        assert_eq!(c["multiply_high"]["unreachable"], 0, "{n}");
        let f32_unreachable = c["f32_pick"]["unreachable"].as_u64().unwrap();
        if n > 1 << 24 {
            assert!(f32_unreachable >= n - (1 << 24), "{n}: {f32_unreachable}");
        }
    }
    assert_eq!(num(&v["u32_split_error"]), 2f64.powi(-32));
}

#[test]
fn precision_measures_given_powers_and_prints_text() {
    let v = json(&["precision", "--powers", "2,5,20", "--json"]);
    let reports = v["reports"].as_array().unwrap();
    assert_eq!(reports.len(), 1);
    assert_eq!(reports[0]["n"], 3);
    assert!(reports[0]["distribution"].is_null());
    let out = lightpick(&["precision", "--n", "100", "--distribution", "with-zeros"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for heading in [
        "1. Table construction",
        "2. Thresholds",
        "3. Column pick",
        "4. One random",
    ] {
        assert!(text.contains(heading), "{text}");
    }
    assert!(text.contains("with-zeros"), "{text}");
}

#[test]
fn precision_errors_are_one_line_and_exit_2() {
    assert_error(&["precision", "--n", "0"], "--n must be between 1 and");
    assert_error(
        &["precision", "--distribution", "gauss"],
        "unknown distribution 'gauss'",
    );
    assert_error(&["precision", "--powers", "1,-1"], "negative");
    assert_error(&["precision", "--n", "x"], "invalid value 'x'");
}

#[test]
fn bench_json_has_every_case_and_the_peers() {
    let v = json(&[
        "bench",
        "--quick",
        "--json",
        "--sizes",
        "1000",
        "--presets",
        "worked-example",
        "--spp",
        "8",
        "--no-gpu",
    ]);
    let cases = v["cases"].as_array().unwrap();
    let methods: Vec<&str> = cases
        .iter()
        .map(|c| c["method"].as_str().unwrap())
        .collect();
    for m in [
        "alias",
        "alias-1t",
        "alias-exact",
        "alias-batch",
        "alias-one-random",
        "alias+smallrng",
        "cdf",
        "uniform",
        "rand_distr::WeightedAliasIndex",
        "rand::WeightedIndex",
        "tree-build",
        "tree-refit",
        "tree-refit-cuts",
        "tree-refit-spots",
        "tree-refit-spots-one",
        "app-repower",
        "app-repower-one",
    ] {
        assert!(methods.contains(&m), "{m} missing from {methods:?}");
    }
    for c in cases {
        assert_eq!(c["n"], 1000);
        let threads = c["threads"].as_u64().expect("a thread count per case");
        // Builds on rayon's pool: the light tree and the integer table (whose one-thread
        // twin is `alias-1t`); the rest run on one thread.
        let parallel = c["method"].as_str().is_some_and(|m| {
            m.starts_with("tree-")
                || m.starts_with("app-repower")
                || ["alias", "alias-batch"].contains(&m)
        });
        assert!(threads >= 1 && (parallel || threads == 1), "{c}");
        if c["method"] == "alias-1t" {
            assert_eq!(threads, 1, "{c}");
        }
        assert!(
            num(&c["build_ns"]) > 0.0 && num(&c["sample_ns"]) > 0.0,
            "{c}"
        );
        // The tables that can be rebuilt in place say how long it takes (the peer alias
        // table, which cannot, reports its build); the others carry no rebuild figure.
        let rebuilds = [
            "alias",
            "alias-1t",
            "alias-exact",
            "alias-batch",
            "rand_distr::WeightedAliasIndex",
        ];
        let method = c["method"].as_str().unwrap();
        assert_eq!(
            c.get("rebuild_ns").is_some(),
            rebuilds.contains(&method),
            "{c}"
        );
        if let Some(r) = c.get("rebuild_ns") {
            assert!(num(r) > 0.0, "{c}");
        }
        // The light trees say what they hold per light; nothing else does.
        assert_eq!(
            c.get("bytes_per_light").is_some(),
            ["tree-build", "tree-refit-spots"].contains(&method),
            "{c}"
        );
    }
    let bytes = |method: &str| {
        let case = cases.iter().find(|c| c["method"] == method).unwrap();
        num(&case["bytes_per_light"])
    };
    // By construction: each light's position and power in leaf order (32 bytes) and its
    // scene index (4), and for spots their profiles and each node's maps on top.
    assert!(bytes("tree-build") >= 36.0, "{}", bytes("tree-build"));
    assert!(
        bytes("tree-refit-spots") > bytes("tree-build") + 128.0,
        "{} against {}",
        bytes("tree-refit-spots"),
        bytes("tree-build")
    );
    let memory = &v["memory_bandwidth"];
    assert!(num(&memory["copy_gb_per_s"]) > 0.0, "{memory}");
    assert_eq!(memory["build_floors"][0]["n"], 1000);
    assert!(
        num(&memory["build_floors"][0]["build_floor_ns"]) > 0.0,
        "{memory}"
    );
    let ratios = v["ratios"].as_array().unwrap();
    assert_eq!(ratios[0]["n"], 1000);
    let row = ratios[0]["ratios"].as_array().unwrap();
    assert_eq!(row.len(), 7, "six peers and methods plus alias-1t: {row:?}");
    let peer = row
        .iter()
        .find(|r| r["method"] == "rand_distr::WeightedAliasIndex")
        .unwrap();
    for key in [
        "build_vs_alias",
        "rebuild_vs_alias",
        "sample_vs_alias",
        "sample_vs_alias_batch",
    ] {
        assert!(num(&peer[key]) > 0.0, "{key}: {peer}");
    }
    assert!(v["gpu"]["adapter"].is_null());
    assert!(v["gpu"]["note"].as_str().unwrap().contains("--no-gpu"));
    let render = &v["renders"][0];
    assert_eq!(render["preset"], "worked-example");
    let schemes = render["schemes"].as_array().unwrap();
    assert_eq!(schemes.len(), 5);
    let uniform_var = num(&schemes[0]["variance_per_sample"]);
    for s in schemes {
        let var = num(&s["variance_per_sample"]);
        if s["scheme"] == "spatial" {
            // Three lights: the exact contribution pick, zero variance up to rounding (its
            // efficiency is infinite, `null` in JSON, or huge).
            assert!(var >= 0.0 && var <= 1e-12 * uniform_var, "{s}");
            assert!(
                s["efficiency"].is_null() || num(&s["efficiency"]) > 0.0,
                "{s}"
            );
        } else {
            let eff = num(&s["efficiency"]);
            assert!(var.is_finite() && var > 0.0, "{s}");
            assert!(eff.is_finite() && eff > 0.0, "{s}");
        }
        assert!(num(&s["rmse_at_equal_time"]).is_finite(), "{s}");
        assert!(num(&s["build_seconds"]) >= 0.0, "{s}");
        // 1, 2, 4, 8 spp.
        assert_eq!(s["series"].as_array().unwrap().len(), 4);
    }
}

#[test]
fn bench_writes_the_plot_and_reports_the_gpu() {
    let dir = scratch("bench");
    let png = dir.join("bench.png");
    let out = run_ok(&[
        "bench",
        "--quick",
        "--sizes",
        "3",
        "--presets",
        "worked-example",
        "--spp",
        "4",
        "--plot",
        png.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("GPU: "), "{text}");
    assert!(text.contains("rand_distr::WeightedAliasIndex"), "{text}");
    // The worked example's three lights: the exact spatial pick has zero variance, so its series (RMSE
    // ~1e-16, rounding) stays off the plot's axes, and the text says so.
    assert!(
        text.contains("preset worked-example; spatial: zero variance, left off the axes)"),
        "{text}"
    );
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bench_errors_are_one_line_and_exit_2() {
    assert_error(
        &["bench", "--sizes", "0"],
        "--sizes: each size must be between 1",
    );
    assert_error(&["bench", "--sizes", "3,x"], "--sizes: 'x' is not a count");
    assert_error(
        &["bench", "--sizes", "3", "--presets", "nope"],
        "--presets 'nope'",
    );
    assert_error(&["bench", "--spp", "0"], "--spp must be at least 1");
    assert_error(
        &["bench", "--presets", "none", "--plot", "x.png"],
        "nothing to plot",
    );
}
