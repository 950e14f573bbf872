//! The app under kittest: harnesses on the whole window or one panel (kittest's own
//! renderer, or wgpu for snapshots and the GPU runs), paused steps, what is shown, clicks
//! and the snapshots' folder.

use egui_kittest::kittest::Queryable as _;
use egui_kittest::{Harness, HarnessBuilder, SnapshotOptions};
use lightpick::app::{LightpickApp, PanelKind};

/// The whole app on its test scene at the tests' window size (1560×960), one frame run.
pub fn app_harness() -> Harness<'static, LightpickApp> {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    harness
}

/// A harness builder of `size`, drawing with wgpu when `wgpu` is set.
fn builder(size: [f32; 2], wgpu: bool) -> HarnessBuilder<LightpickApp> {
    let builder = Harness::builder().with_size(size);
    if wgpu { builder.wgpu() } else { builder }
}

/// The whole window of `app` at `size` (kittest's renderer); no frame run yet.
pub fn window(app: LightpickApp, size: [f32; 2]) -> Harness<'static, LightpickApp> {
    builder(size, false).build_ui_state(|ui, app: &mut LightpickApp| app.ui(ui), app)
}

/// [`window`] drawn with wgpu (snapshots).
pub fn wgpu_window(app: LightpickApp, size: [f32; 2]) -> Harness<'static, LightpickApp> {
    builder(size, true).build_ui_state(|ui, app: &mut LightpickApp| app.ui(ui), app)
}

/// The panel `kind` of `app` at `size` (kittest's renderer); no frame run yet.
pub fn panel(kind: PanelKind, app: LightpickApp, size: [f32; 2]) -> Harness<'static, LightpickApp> {
    builder(size, false).build_ui_state(
        move |ui, app: &mut LightpickApp| app.panel_ui(ui, kind),
        app,
    )
}

/// [`panel`] drawn with wgpu (snapshots, the GPU runs).
pub fn wgpu_panel(
    kind: PanelKind,
    app: LightpickApp,
    size: [f32; 2],
) -> Harness<'static, LightpickApp> {
    builder(size, true).build_ui_state(
        move |ui, app: &mut LightpickApp| app.panel_ui(ui, kind),
        app,
    )
}

/// `steps` single steps of the paused app, each followed by its frames.
pub fn step_paused(harness: &mut Harness<'_, LightpickApp>, steps: usize) {
    for _ in 0..steps {
        harness.state_mut().step();
        harness.run();
    }
}

/// Whether some node is labelled exactly `label`.
pub fn shows(harness: &Harness<'_, LightpickApp>, label: &str) -> bool {
    harness.query_all_by_label(label).next().is_some()
}

/// Whether some node's label contains `text`.
pub fn shows_containing(harness: &Harness<'_, LightpickApp>, text: &str) -> bool {
    harness.query_all_by_label_contains(text).next().is_some()
}

/// Clicks the node labelled `label` and runs the frames that follow.
pub fn click(harness: &mut Harness<'_, LightpickApp>, label: &str) {
    harness.get_by_label(label).click();
    harness.run();
}

/// Types `path` into the open file dialog's Path field and confirms with OK.
pub fn submit_path(harness: &mut Harness<'_, LightpickApp>, path: &std::path::Path) {
    harness
        .get_by_role_and_label(egui::accesskit::Role::TextInput, "Path")
        .set_text_value_accesskit(path.to_str().expect("utf-8 path"));
    harness.run();
    click(harness, "OK");
}

/// Snapshots compare against (and, with `UPDATE_SNAPSHOTS=1`, write) the goldens in
/// `crates/app/tests/snapshots`.
pub fn snapshot_options() -> SnapshotOptions {
    SnapshotOptions::new().output_path(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/snapshots"))
}

/// The whole app as eframe runs it (its wgpu render state: the GPU runs), on kittest's
/// wgpu device at `size`, on the test scene.
pub fn wgpu_eframe(size: [f32; 2]) -> Harness<'static, LightpickApp> {
    builder(size, true).build_eframe(|_cc| LightpickApp::for_tests())
}
