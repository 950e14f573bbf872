//! Helpers shared by the tests of the `lightpick` binary and app: [`app`] drives the app
//! through kittest harnesses, [`cli`] runs the binary and reads what it prints; this file
//! holds what both need (scratch files, fixtures, the hang guard, the GPU switch).

#![allow(dead_code, clippy::unwrap_used)] // Each test file uses a subset; a panic is the report.

mod app;
mod cli;
pub mod painted;
pub mod session;

use std::path::PathBuf;
use std::time::Duration;

#[allow(unused_imports)] // Re-exports: each test binary uses a subset.
pub use app::{
    app_harness, click, panel, shows, shows_containing, snapshot_options, step_paused, submit_path,
    wgpu_eframe, wgpu_panel, wgpu_window, window,
};
#[allow(unused_imports)] // Re-exports: each test binary uses a subset.
pub use cli::{
    assert_error, assert_error_with_env, bench_json, gif_frames, json, lightpick,
    lightpick_headless, lightpick_with_env, num, numbers, run_ok,
};

/// How long a test waits for work done on another thread (a reference, a background build,
/// frames of running images) before it declares a hang. A guard, never the thing tested: no
/// verdict depends on how fast the machine is, so the bound is minutes, what a loaded 2-core
/// CI machine needs many times over (the slowest such wait takes seconds idle).
pub const HANG_GUARD: Duration = Duration::from_mins(10);

/// A scratch directory unique to this test process.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lightpick-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `contents` to `file` in the scratch directory `dir` ([`scratch`]) and returns its
/// path.
pub fn scratch_file(dir: &str, file: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = scratch(dir).join(file);
    std::fs::write(&path, contents).unwrap();
    path
}

/// The scene files the tests read (glTF, GLB, CSV), in the workspace's `tests/fixtures`.
pub fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/lights")
}

/// The path of the fixture `name` ([`fixtures`]), as the text a command line takes.
pub fn fixture(name: &str) -> String {
    fixtures().join(name).to_str().unwrap().to_owned()
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
