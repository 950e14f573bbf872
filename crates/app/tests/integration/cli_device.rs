//! The device rules of `render` and `sample` through the binary: an explicit `--device gpu`
//! never falls back silently, the default takes the CPU with a one-line notice when there is
//! no adapter, and a scene the GPU's `f32` cannot hold is refused by name.
//!
//! "No adapter" is forced with wgpu's own override, which the GPU context honours:
//! `WGPU_ADAPTER_NAME` set to a name no adapter has. Cases that need a real adapter fail
//! (never skip) when there is none, unless `LIGHTPICK_SKIP_GPU_TESTS=1`.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use crate::common::{
    assert_error, assert_error_with_env, gpu_expected, json, lightpick_with_env, scratch_file,
};

/// An adapter name no machine has: the GPU context then finds no adapter.
const NO_ADAPTER: [(&str, &str); 1] = [("WGPU_ADAPTER_NAME", "no-such-adapter-lightpick-test")];

#[test]
fn an_explicit_gpu_without_an_adapter_is_an_error() {
    for args in [
        &[
            "render",
            "--preset",
            "worked-example",
            "--spp",
            "1",
            "--width",
            "8",
            "--height",
            "8",
            "--device",
            "gpu",
        ][..],
        &[
            "sample", "--powers", "2,5,20", "--count", "100", "--device", "gpu",
        ][..],
    ] {
        assert_error_with_env(
            args,
            &NO_ADAPTER,
            "--device gpu: WGPU_ADAPTER_NAME is 'no-such-adapter-lightpick-test' but no \
             adapter's name contains it",
        );
    }
}

#[test]
fn the_default_device_falls_back_to_the_cpu_with_one_notice() {
    // `render` defaults to the GPU when an adapter exists.
    let args = [
        "render",
        "--preset",
        "worked-example",
        "--spp",
        "2",
        "--width",
        "8",
        "--height",
        "8",
        "--json",
    ];
    let out = lightpick_with_env(&args, &NO_ADAPTER);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{stderr:?}");
    assert!(
        lines[0].starts_with("notice: no GPU adapter (WGPU_ADAPTER_NAME is ")
            && lines[0].ends_with("); using the CPU"),
        "{stderr}"
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["device"], "cpu");
    // `sample` defaults to the CPU: it opens no GPU and says nothing.
    let out = lightpick_with_env(
        &["sample", "--powers", "2,5,20", "--count", "100", "--json"],
        &NO_ADAPTER,
    );
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["device"], "cpu");
}

/// A scene whose light 1 sits at `z = 1e39`: a finite `f64`, `+inf` as an `f32`.
fn beyond_f32_scene() -> std::path::PathBuf {
    scratch_file(
        "beyond-f32",
        "far.json",
        r#"{ "name": "far", "plane": { "min": [-1, -1], "max": [1, 1], "width": 8, "height": 8 },
            "lights": [ { "position": [0, 0, 1], "power": 1 },
                        { "position": [0, 0, 1e39], "power": 1 } ] }"#,
    )
}

#[test]
fn a_scene_beyond_f32_is_refused_on_the_gpu_and_rendered_on_the_cpu_by_default() {
    let file = beyond_f32_scene();
    let scene = file.to_str().unwrap();
    // The CPU works in f64: the far light contributes ~1e-78 of the near one, nothing NaN.
    let v = json(&[
        "render", "--scene", scene, "--spp", "2", "--device", "cpu", "--json",
    ]);
    assert!(v["rmse"].as_f64().unwrap().is_finite(), "{v}");
    // The default device takes the CPU and says why, in one line (no GPU is opened).
    let out = lightpick_with_env(&["render", "--scene", scene, "--spp", "2", "--json"], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(
        stderr.starts_with("notice: lights[1].position[2] = 1e39 is beyond the f32 range")
            && stderr.trim_end().ends_with("; using the CPU"),
        "{stderr}"
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["device"], "cpu");
    assert!(v["rmse"].as_f64().unwrap().is_finite(), "{v}");
    // An explicit GPU opens the device and gets the renderer's refusal as the error.
    if gpu_expected() {
        assert_error(
            &["render", "--scene", scene, "--spp", "2", "--device", "gpu"],
            "lights[1].position[2] = 1e39 is beyond the f32 range of the GPU \
             (|v| ≤ 3.4028235e38)",
        );
    }
}
