//! `lightpick plot animation`: the GIF's frames, its determinism (same bytes for the same
//! arguments, whatever the thread count), its first and last frames against goldens in
//! `tests/snapshots/` (update with `UPDATE_SNAPSHOTS=1`), the RMSE it reports, and its
//! refusals.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use std::path::Path;

use crate::common::{
    assert_error, gif_frames, json, lightpick_with_env, scratch, snapshot_options,
};

/// The tiny animation of these tests: the zeros preset (64 lights, half of power 0: every
/// scheme, the spatial light tree included, is noisy, and each beats the one before), 16×12
/// pixels, 5 frames up to 16 spp.
fn args(out: &Path) -> Vec<String> {
    [
        "plot",
        "animation",
        "--preset",
        "zeros",
        "--width",
        "16",
        "--height",
        "12",
        "--frames",
        "5",
        "--max-spp",
        "16",
        "--delay-ms",
        "100",
        "--hold-ms",
        "1000",
        "--seed",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]
    .map(str::to_owned)
    .to_vec()
}

#[test]
fn animation_frames_are_deterministic_and_converge() {
    let dir = scratch("animation");
    let (a, b) = (dir.join("a.gif"), dir.join("b.gif"));
    let mut with_json = args(&a);
    with_json.push("--json".to_owned());
    let with_json: Vec<&str> = with_json.iter().map(String::as_str).collect();
    let summary = json(&with_json);

    // The same arguments on one thread: the same bytes.
    let single: Vec<String> = args(&b);
    let single: Vec<&str> = single.iter().map(String::as_str).collect();
    let out = lightpick_with_env(&single, &[("RAYON_NUM_THREADS", "1")]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (bytes_a, bytes_b) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(bytes_a.len(), summary["bytes"].as_u64().unwrap() as usize);
    assert!(bytes_a == bytes_b, "the two GIFs differ");

    let frames = gif_frames(&a);
    assert_eq!(frames.len(), 5);
    let (w, h) = (
        summary["frame_width"].as_u64().unwrap() as u32,
        summary["frame_height"].as_u64().unwrap() as u32,
    );
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (w, h));
    }
    // Frame delays: --delay-ms, the last --hold-ms.
    let ms = |f: &image::Frame| {
        let (n, d) = f.delay().numer_denom_ms();
        n / d
    };
    assert_eq!(ms(&frames[0]), 100);
    assert_eq!(ms(&frames[4]), 1000);

    // The summary: frames at 1, 2, 4, 8, 16 spp, each scheme's RMSE lower at the end.
    assert_eq!(
        summary["schemes"],
        serde_json::json!(["uniform", "alias", "spatial"])
    );
    assert_eq!(
        (summary["width"].as_u64(), summary["height"].as_u64()),
        (Some(16), Some(12))
    );
    let series = summary["frames"].as_array().unwrap();
    let spp: Vec<u64> = series.iter().map(|f| f["spp"].as_u64().unwrap()).collect();
    assert_eq!(spp, vec![1, 2, 4, 8, 16]);
    for scheme in ["uniform", "alias", "spatial"] {
        let rmse = |f: &serde_json::Value| f["rmse"][scheme].as_f64().unwrap();
        let (first, last) = (rmse(&series[0]), rmse(&series[4]));
        assert!(
            last < first && last > 0.0,
            "{scheme}: RMSE {first} at 1 spp, {last} at 16"
        );
    }
    // At equal spp, power sampling beats uniform selection and contributions beat powers.
    let last = &series[4]["rmse"];
    let rmse = |scheme: &str| last[scheme].as_f64().unwrap();
    assert!(
        rmse("spatial") < rmse("alias") && rmse("alias") < rmse("uniform"),
        "{last}"
    );
    assert_eq!(summary["reference"]["complete"], true);

    egui_kittest::image_snapshot_options(
        &frames[0].clone().into_buffer(),
        "animation_first_frame",
        &snapshot_options(),
    );
    egui_kittest::image_snapshot_options(
        &frames[4].clone().into_buffer(),
        "animation_last_frame",
        &snapshot_options(),
    );
}

#[test]
fn animation_refuses_bad_input() {
    let dir = scratch("animation-bad");
    let out = dir.join("x.gif");
    let out = out.to_str().unwrap();
    let base = [
        "plot",
        "animation",
        "--preset",
        "worked-example",
        "--out",
        out,
    ];
    let with = |extra: &[&'static str]| {
        let mut v: Vec<&str> = base.to_vec();
        v.extend_from_slice(extra);
        v
    };
    assert_error(
        &with(&["--frames", "0"]),
        "--frames must be between 1 and 240 (got 0)",
    );
    assert_error(&with(&["--frames", "100000"]), "--frames");
    assert_error(
        &with(&["--frames", "30", "--max-spp", "8"]),
        "--frames 30 needs --max-spp of at least 30",
    );
    assert_error(&with(&["--max-spp", "0"]), "--max-spp");
    assert_error(&with(&["--delay-ms", "0"]), "--delay-ms");
    assert_error(&with(&["--hold-ms", "999999"]), "--hold-ms");
    assert_error(
        &with(&["--width", "100000"]),
        "--width must be between 8 and 512",
    );
    assert_error(&with(&["--height", "2"]), "--height");
    assert_error(&with(&["--exposure", "-1"]), "--exposure");
    assert_error(
        &[
            "plot",
            "animation",
            "--scene",
            "/nonexistent/scene.json",
            "--out",
            out,
        ],
        "--scene /nonexistent/scene.json",
    );
    assert_error(
        &["plot", "animation", "--powers", "2,5,20", "--out", out],
        "--powers: plot animation needs light positions",
    );
    assert_error(
        &["plot", "animation", "--preset", "worked-example"],
        "--out",
    );
    assert_error(
        &with(&["--frames", "2", "--max-spp", "2", "--width", "8"])
            .into_iter()
            .map(|a| {
                if a == out {
                    "/nonexistent-dir/x.gif"
                } else {
                    a
                }
            })
            .collect::<Vec<_>>(),
        "--out /nonexistent-dir/x.gif",
    );
    assert!(!Path::new(out).exists(), "nothing is written on a refusal");
}
