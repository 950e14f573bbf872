//! The `lightpick` binary: running it (with a private runtime dir, or without a display),
//! reading its JSON, asserting its one-line errors, and reading numbers and GIFs it wrote.

use std::io::Cursor;
use std::path::Path;
use std::process::{Command, Output};

use image::AnimationDecoder as _;
use image::codecs::gif::GifDecoder;

use super::scratch;

/// Runs `lightpick args…`. A private runtime dir is set because, without one, Mesa's Vulkan
/// driver (through libwayland) prints a warning on stderr when a GPU is opened, which would
/// hide whether lightpick itself kept to one error line.
pub fn lightpick(args: &[&str]) -> Output {
    lightpick_with_env(args, &[])
}

/// [`lightpick`] with extra environment variables, e.g. `WGPU_ADAPTER_NAME` to make the GPU
/// context find no adapter.
pub fn lightpick_with_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let runtime = scratch("runtime");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        std::fs::set_permissions(&runtime, std::fs::Permissions::from_mode(0o700)).unwrap();
    }
    Command::new(env!("CARGO_BIN_EXE_lightpick"))
        .args(args)
        .env("XDG_RUNTIME_DIR", &runtime)
        .envs(env.iter().copied())
        .output()
        .expect("run lightpick")
}

/// Runs `lightpick args…` without a display (`DISPLAY` and `WAYLAND_DISPLAY` removed), as
/// on a headless machine: the app cannot open.
pub fn lightpick_headless(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lightpick"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run lightpick")
}

/// Runs a command that must succeed; returns its output.
pub fn run_ok(args: &[&str]) -> Output {
    let out = lightpick(args);
    assert!(
        out.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Runs a command that must succeed and print one JSON object.
pub fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_slice(&run_ok(args).stdout).expect("stdout is one JSON object")
}

/// `bench --quick --no-gpu --sizes 3 extra… --json`: a short bench whose renders `extra`
/// chooses (`--presets`, `--scene`, `--spp`).
pub fn bench_json(extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["bench", "--quick", "--no-gpu", "--sizes", "3"];
    args.extend_from_slice(extra);
    args.push("--json");
    json(&args)
}

/// Asserts exit code 2 and exactly one stderr line, starting with `error:` and containing
/// `needle`, and no panic.
pub fn assert_error(args: &[&str], needle: &str) {
    assert_error_with_env(args, &[], needle);
}

/// [`assert_error`] with extra environment variables.
pub fn assert_error_with_env(args: &[&str], env: &[(&str, &str)], needle: &str) {
    let out = lightpick_with_env(args, env);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(
        lines.len(),
        1,
        "{args:?}: expected one line, got {stderr:?}"
    );
    assert!(lines[0].starts_with("error:"), "{stderr}");
    assert!(
        stderr.contains(needle),
        "{args:?}: {stderr:?} lacks {needle:?}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// A JSON number (a panic names anything else).
pub fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// A JSON array of numbers.
pub fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Decodes every frame of a GIF file.
pub fn gif_frames(path: &Path) -> Vec<image::Frame> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    GifDecoder::new(Cursor::new(bytes))
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap()
}
