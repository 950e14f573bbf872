//! Snapshots of every panel on the seed scene (goldens in `tests/snapshots/`), rendered
//! with wgpu (lavapipe without a GPU). Update with `UPDATE_SNAPSHOTS=1`.

use egui_kittest::{Harness, SnapshotOptions};
use lightpick::app::{LightpickApp, PanelKind};

fn options() -> SnapshotOptions {
    SnapshotOptions::new().output_path(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/snapshots"))
}

/// One panel of the seed scene after `steps` paused single steps.
fn panel(kind: PanelKind, size: [f32; 2], steps: usize) -> Harness<'static, LightpickApp> {
    let mut harness = Harness::builder().with_size(size).wgpu().build_ui_state(
        move |ui, app: &mut LightpickApp| app.panel_ui(ui, kind),
        LightpickApp::for_tests(),
    );
    harness.run();
    for _ in 0..steps {
        harness.state_mut().step();
        harness.run();
    }
    harness
}

#[test]
fn lights_panel() {
    panel(PanelKind::Lights, [460.0, 320.0], 0).snapshot_options("app_lights", &options());
}

#[test]
fn table_panel() {
    panel(PanelKind::Table, [620.0, 420.0], 0).snapshot_options("app_table", &options());
}

#[test]
fn sampling_panel() {
    let mut harness = panel(PanelKind::Sampling, [620.0, 400.0], 5);
    assert_eq!(harness.state().state.sampling.picks, 1000);
    harness.snapshot_options("app_sampling", &options());
}

#[test]
fn images_panel() {
    let mut harness = panel(PanelKind::Images, [600.0, 420.0], 64);
    let published = harness.state_mut().published().expect("a frame");
    assert_eq!(published.uniform.spp, 64);
    assert_eq!(published.importance.spp, 64);
    // Importance sampling ends closer to the reference than uniform selection.
    let (u, a) = (
        published.uniform.rmse.expect("rmse"),
        published.importance.rmse.expect("rmse"),
    );
    assert!(a < u, "importance RMSE {a} vs uniform {u}");
    // Three lights: the spatial image is the exact contribution pick, exact up to rounding.
    assert_eq!(published.spatial.spp, 64);
    let s = published.spatial.rmse.expect("rmse");
    assert!(s <= 1e-12 * a, "spatial RMSE {s}");
    harness.snapshot_options("app_images", &options());
}

#[test]
fn convergence_panel() {
    panel(PanelKind::Convergence, [620.0, 380.0], 8)
        .snapshot_options("app_convergence", &options());
}

#[test]
fn controls_bar() {
    panel(PanelKind::Controls, [900.0, 40.0], 0).snapshot_options("app_controls", &options());
}

#[test]
fn whole_app() {
    let mut harness = Harness::builder()
        .with_size([1280.0, 800.0])
        .wgpu()
        .build_ui_state(
            |ui, app: &mut LightpickApp| app.ui(ui),
            LightpickApp::for_tests(),
        );
    harness.run();
    harness.snapshot_options("app_whole", &options());
}
