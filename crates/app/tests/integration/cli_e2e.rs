//! End-to-end tests of the `lightpick` binary: output, JSON contract, exit codes.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use crate::common::{assert_error, json, lightpick, lightpick_headless, numbers, scratch};

#[test]
fn table_json_is_the_seed_table() {
    let v = json(&["table", "--powers", "2,5,20", "--json"]);
    assert_eq!(v["n"], 3);
    assert_eq!(v["total_power"], 27.0);
    assert_eq!(numbers(&v["threshold"]), vec![6.0 / 27.0, 15.0 / 27.0, 1.0]);
    assert_eq!(v["alias"], serde_json::json!([2, 2, 2]));
    assert_eq!(
        numbers(&v["pmf"]),
        vec![2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]
    );
}

#[test]
fn table_text_shows_the_seed_fractions() {
    let out = lightpick(&["table", "--powers", "2,5,20"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    for needle in ["6/27", "15/27", "2/27", "20/27"] {
        assert!(text.contains(needle), "{text}");
    }
}

#[test]
fn table_reads_a_powers_file() {
    let dir = scratch("e2e");
    let file = dir.join("powers.txt");
    std::fs::write(&file, "2\n5, 20\n").unwrap();
    let v = json(&["table", "--powers-file", file.to_str().unwrap(), "--json"]);
    assert_eq!(v["alias"], serde_json::json!([2, 2, 2]));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sample_counts_fit_the_pmf() {
    for scheme in ["uniform", "alias", "alias-one-random", "cdf"] {
        let v = json(&[
            "sample", "--powers", "2,5,20", "--scheme", scheme, "--count", "100000", "--seed", "7",
            "--json",
        ]);
        assert_eq!(v["scheme"], scheme);
        assert_eq!(v["device"], "cpu");
        let counts: Vec<u64> = v["counts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap())
            .collect();
        assert_eq!(counts.iter().sum::<u64>(), 100_000);
        assert_eq!(v["count"], 100_000);
        assert_eq!(v["dof"], 2);
        // `expected` is the scheme's pmf, and `chi2` is Pearson's statistic of the counts.
        let expected: Vec<f64> = v["expected"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e.as_f64().unwrap())
            .collect();
        let pmf = if scheme == "uniform" {
            [1.0 / 3.0; 3]
        } else {
            [2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]
        };
        for (e, p) in expected.iter().zip(pmf) {
            assert!((e - p).abs() < 1e-15, "{scheme}: expected {e} vs {p}");
        }
        let chi2: f64 = counts
            .iter()
            .zip(&expected)
            .map(|(&c, &p)| (c as f64 - 1e5 * p).powi(2) / (1e5 * p))
            .sum();
        let reported = v["chi2"].as_f64().unwrap();
        assert!(
            (reported - chi2).abs() <= 1e-9 * chi2.max(1.0),
            "{reported} vs {chi2}"
        );
        // Fixed seed, significance 0.001.
        assert!(v["p_value"].as_f64().unwrap() > 1e-3, "{scheme}: {v}");
    }
}

#[test]
fn sample_is_deterministic() {
    let args = [
        "sample",
        "--powers",
        "1,2,3,0,4",
        "--count",
        "5000",
        "--seed",
        "3",
        "--json",
    ];
    assert_eq!(json(&args)["counts"], json(&args)["counts"]);
}

#[test]
fn estimate_averages_to_18() {
    for (scheme, variance) in [("uniform", 366.0), ("alias", 14.85)] {
        let v = json(&[
            "estimate",
            "--powers",
            "2,5,20",
            "--contrib",
            "1,2,15",
            "--scheme",
            scheme,
            "--count",
            "200000",
            "--seed",
            "5",
            "--json",
        ]);
        assert_eq!(v["exact"], 18.0);
        let analytic = v["analytic_variance"].as_f64().unwrap();
        assert!((analytic - variance).abs() < 1e-9, "{scheme}: {analytic}");
        let mean = v["mean"].as_f64().unwrap();
        let se = v["std_error"].as_f64().unwrap();
        assert!((mean - 18.0).abs() <= 5.0 * se, "{scheme}: {mean} ± {se}");
        // The sample variance within 5 standard deviations of its own sampling law:
        // Var(s²) ≈ (μ4 − σ⁴)/n, μ4 the exact fourth central moment of the estimate f_i/q_i.
        let (f, q) = if scheme == "uniform" {
            ([1.0, 2.0, 15.0], [1.0 / 3.0; 3])
        } else {
            ([1.0, 2.0, 15.0], [2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0])
        };
        let mu4: f64 = f
            .iter()
            .zip(q)
            .map(|(fi, qi)| qi * (fi / qi - 18.0_f64).powi(4))
            .sum();
        let s2 = v["variance"].as_f64().unwrap();
        let sd = ((mu4 - variance * variance) / 200_000.0).sqrt();
        assert!(
            (s2 - variance).abs() <= 5.0 * sd,
            "{scheme}: sample variance {s2} vs {variance} (sd {sd})"
        );
        assert!(
            (se - (s2 / 200_000.0).sqrt()).abs() <= 1e-12 * se,
            "{scheme}: {se}"
        );
    }
}

#[test]
fn bad_inputs_exit_2_with_one_error_line() {
    assert_error(&["table", "--powers", "2,-5,20"], "light 1 is negative");
    assert_error(&["table", "--powers", "2,NaN,20"], "light 1 is not finite");
    assert_error(&["table", "--powers", "2,inf"], "light 1 is not finite");
    assert_error(&["table", "--powers", "0,0"], "all 2 powers are zero");
    assert_error(&["table", "--powers", ""], "empty");
    assert_error(
        &["table", "--powers", "2,x"],
        "item 1 ('x') is not a number",
    );
    assert_error(&["table"], "no powers given");
    assert_error(
        &["table", "--powers-file", "/nonexistent/p.txt"],
        "/nonexistent/p.txt",
    );
    assert_error(&["sample", "--powers", "1,2", "--count", "0"], "--count");
    assert_error(&["sample", "--powers", "1,2", "--scheme", "magic"], "magic");
    assert_error(&["sample", "--powers", "1,2", "--count", "-3"], "-3");
    assert_error(
        &["estimate", "--powers", "1,2", "--contrib", "1,2,3"],
        "--contrib has 3 values but there are 2 lights",
    );
    assert_error(&["frobnicate"], "frobnicate");
}

#[test]
fn no_subcommand_without_a_display_exits_2_pointing_to_the_subcommands() {
    let out = lightpick_headless(&[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(
        stderr.starts_with("error:") && stderr.contains("lightpick table"),
        "{stderr}"
    );
}

#[test]
fn clap_errors_name_what_is_wrong_on_one_line() {
    // A missing required argument is named (clap puts it on a second line).
    assert_error(
        &["estimate", "--powers", "2,5,20", "--count", "10"],
        "error: missing required argument --contrib <LIST>",
    );
    // An unknown argument keeps clap's suggestion on the same line.
    assert_error(
        &["table", "--power", "2,5,20"],
        "unexpected argument '--power' found (tip: a similar argument exists: '--powers')",
    );
    // An invalid value names the value, the flag and the accepted values.
    assert_error(
        &["plot", "convergence", "--axis", "spx", "--out", "x.png"],
        "invalid value 'spx' for '--axis <AXIS>' [possible values: spp, seconds]",
    );
    assert_error(
        &["sample", "--powers", "1,2", "--count", "ten"],
        "invalid value 'ten' for '--count <COUNT>'",
    );
}

#[test]
fn powers_files_refuse_empty_items_like_powers_lists() {
    let dir = scratch("e2e-empty");
    let file = dir.join("powers.txt");
    std::fs::write(&file, "2,,20\n").unwrap();
    let path = file.to_str().unwrap();
    assert_error(
        &["table", "--powers-file", path],
        &format!("{path}: item 1 is empty"),
    );
    assert_error(&["table", "--powers", "2,,20"], "--powers: item 1 is empty");
    // White space alone still separates items, and a comma next to it is no empty item.
    std::fs::write(&file, "2 5,\n20\n").unwrap();
    let v = json(&["table", "--powers-file", path, "--json"]);
    assert_eq!(v["n"], 3);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_total_power_beyond_f64_is_reported_honestly() {
    let max = "1.7976931348623157e308,1.7976931348623157e308";
    let v = json(&["table", "--powers", max, "--json"]);
    assert_eq!(numbers(&v["pmf"]), vec![0.5, 0.5]);
    // JSON has no infinity: the total is null, its log10 (2·f64::MAX ≈ 10^308.5557) a number.
    assert!(v["total_power"].is_null(), "{v}");
    let log10 = v["total_power_log10"].as_f64().unwrap();
    assert!(
        (log10 - (f64::MAX.log10() + 2f64.log10())).abs() < 1e-12,
        "{log10}"
    );
    let out = lightpick(&["table", "--powers", max]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(
        text.contains("total power 3.595e308 (exceeds f64)"),
        "{text}"
    );
    assert!(!text.contains("inf"), "{text}");
    let v = json(&["table", "--powers", "2,5,20", "--json"]);
    assert!((v["total_power_log10"].as_f64().unwrap() - 27f64.log10()).abs() < 1e-15);
}

/// A reader that stops early (`| head -c 64`) ends the command quietly: no panic of
/// `print!` on the closed pipe, and a status that is success or the end by `SIGPIPE`, as
/// for `cat` or `yes`. The JSON of a million lights' table is megabytes: far past what the
/// pipe holds, so the command is still writing when the reader goes.
#[test]
fn a_reader_that_stops_early_ends_the_command_quietly() {
    use std::io::Read as _;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_lightpick"))
        .args(["table", "--preset", "million", "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run lightpick");
    let mut head = [0u8; 64];
    let mut stdout = child.stdout.take().expect("its stdout");
    stdout.read_exact(&mut head).expect("the first 64 bytes");
    assert!(
        head.starts_with(b"{"),
        "JSON: {}",
        String::from_utf8_lossy(&head)
    );
    drop(stdout);
    let out = child.wait_with_output().expect("its end");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "a panic: {stderr}");
    assert!(stderr.is_empty(), "nothing on stderr: {stderr}");
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt as _;
        assert!(
            out.status.success() || out.status.signal() == Some(13),
            "ended by {:?}",
            out.status
        );
    }
}

/// `--preset` takes every name its help lists and what the core takes: the worked
/// example's former name `seed` is the worked example.
#[test]
fn preset_takes_the_names_its_help_lists_and_the_former_seed() {
    let help = String::from_utf8(crate::common::run_ok(&["table", "--help"]).stdout).unwrap();
    for name in lightpick_core::scene::PRESET_NAMES {
        assert!(help.contains(name), "--preset's help names {name}: {help}");
    }
    assert!(help.contains("`seed`"), "{help}");
    let former = json(&["table", "--preset", "seed", "--json"]);
    let current = json(&["table", "--preset", "worked-example", "--json"]);
    assert_eq!(former, current);
    assert_eq!(current["n"], 3);
    assert_error(&["table", "--preset", "nope"], "unknown preset 'nope'");
}
