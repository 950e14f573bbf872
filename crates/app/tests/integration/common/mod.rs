//! Helpers shared by the tests of the `lightpick` binary and app.

#![allow(dead_code, clippy::unwrap_used)] // Each test file uses a subset; a panic is the report.

use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::Duration;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;

/// How long a test waits for work done on another thread (a reference, a background build,
/// frames of running images) before it declares a hang. A guard, never the thing tested: no
/// verdict depends on how fast the machine is, so the bound is minutes, what a loaded 2-core
/// CI machine needs many times over (the slowest such wait takes seconds idle).
pub const HANG_GUARD: Duration = Duration::from_mins(10);

/// The whole app on its test scene at the tests' window size (1560×960), one frame run.
pub fn app_harness() -> Harness<'static, LightpickApp> {
    let mut harness = Harness::builder()
        .with_size([1560.0, 960.0])
        .build_ui_state(
            |ui, app: &mut LightpickApp| app.ui(ui),
            LightpickApp::for_tests(),
        );
    harness.run();
    harness
}

/// Whether some node is labelled exactly `label`.
pub fn shows(harness: &Harness<'_, LightpickApp>, label: &str) -> bool {
    harness.query_all_by_label(label).next().is_some()
}

/// A scratch directory unique to this test process.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lightpick-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

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

/// Runs a command that must succeed and print one JSON object.
pub fn json(args: &[&str]) -> serde_json::Value {
    let out = lightpick(args);
    assert!(
        out.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON object")
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

/// Whether GPU cases run: always, unless `LIGHTPICK_SKIP_GPU_TESTS` is set (then the case
/// says it was skipped; CI refuses the variable).
pub fn gpu_expected() -> bool {
    if std::env::var_os("LIGHTPICK_SKIP_GPU_TESTS").is_some() {
        eprintln!("GPU case skipped: LIGHTPICK_SKIP_GPU_TESTS is set");
        return false;
    }
    true
}
