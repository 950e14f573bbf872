//! The classroom screens as a class sees them, at a 1024×768 projector and at 1600×1000:
//! the inspector on the worked example, the images with their sentence on `grid` and `stage`, equal
//! time on `million`, the Trade and the Precision windows. Golden images in
//! `docs/screenshots/` (the README's pictures); `UPDATE_SNAPSHOTS=1` redraws them.

use egui_kittest::{Harness, SnapshotOptions, SnapshotResults};
use lightpick::app::LightpickApp;
use lightpick::app::state::BudgetMode;

use crate::common::{step_paused, wgpu_window};

/// The screenshots' folder and the tests' snapshot threshold.
fn screenshots() -> SnapshotOptions {
    SnapshotOptions::new().output_path(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/screenshots"
    ))
}

/// The two screens a lesson is given on.
const SCREENS: [([f32; 2], &str); 2] = [
    ([1024.0, 768.0], "1024x768"),
    ([1600.0, 1000.0], "1600x1000"),
];

/// The whole window of `app` at `size`, `steps` frames rendered.
fn screen(app: LightpickApp, size: [f32; 2], steps: usize) -> Harness<'static, LightpickApp> {
    let mut harness = wgpu_window(app, size);
    harness.run();
    step_paused(&mut harness, steps);
    harness
}

#[test]
fn inspector_on_the_seed() {
    let mut results = SnapshotResults::new();
    for (size, name) in SCREENS {
        let mut app = LightpickApp::for_tests();
        app.state.settings.dark = false;
        app.state.inspector.pixel = Some([40, 200]);
        let mut harness = screen(app, size, 8);
        assert!(harness.state().state.inspector.pixel.is_some());
        harness.snapshot_options(format!("inspector-seed-{name}"), &screenshots());
        results.extend_harness(&mut harness);
    }
    results.unwrap();
}

#[test]
fn images_with_their_sentence_on_grid_and_stage() {
    let mut results = SnapshotResults::new();
    for preset in ["grid", "stage"] {
        for (size, name) in SCREENS {
            let mut app = LightpickApp::for_tests_on(preset);
            // The images in front on the small screen (they share a column with the table).
            app.layout.maximized = Some(lightpick::app::PanelKind::Images);
            let mut harness = screen(app, size, 8);
            let sentence = harness
                .state()
                .state
                .current_scene_sentence()
                .expect("the sentence")
                .text
                .clone();
            assert!(
                sentence.starts_with("Least variance per sample here: spatial."),
                "{sentence}"
            );
            harness.snapshot_options(format!("images-{preset}-{name}"), &screenshots());
            results.extend_harness(&mut harness);
        }
    }
    results.unwrap();
}

#[test]
fn equal_time_on_million() {
    let mut app = LightpickApp::for_tests_on("million");
    app.state.settings.budget = BudgetMode::EqualTime;
    app.layout.maximized = Some(lightpick::app::PanelKind::Images);
    let mut harness = screen(app, [1600.0, 1000.0], 3);
    let published = harness.state_mut().published().expect("a frame");
    assert!(
        published.uniform.spp > published.spatial.spp,
        "equal time gives uniform more samples"
    );
    harness.snapshot_options("equal-time-million-1600x1000", &screenshots());
}

#[test]
fn trade_and_precision_windows() {
    let mut results = SnapshotResults::new();
    for (size, name) in SCREENS {
        let mut app = LightpickApp::for_tests();
        app.state.settings.show_trade = true;
        let mut harness = screen(app, size, 1);
        harness.snapshot_options(format!("trade-{name}"), &screenshots());
        results.extend_harness(&mut harness);
        let mut app = LightpickApp::for_tests();
        app.state.settings.show_precision = true;
        let mut harness = screen(app, size, 1);
        harness.snapshot_options(format!("precision-{name}"), &screenshots());
        results.extend_harness(&mut harness);
    }
    results.unwrap();
}

/// The Light tree panel on `grid`, one pick at its first stage (the pixel's tile and its
/// cut of the tree): the README's "Why the spatial scheme wins".
#[test]
fn light_tree_pick_on_grid() {
    let mut results = SnapshotResults::new();
    for (size, name) in SCREENS {
        let mut app = LightpickApp::for_tests_on("grid");
        app.state.settings.dark = false;
        app.layout.maximized = Some(lightpick::app::PanelKind::LightTree);
        app.state.light_tree.select_pixel([72, 194]);
        // The first stage: the pixel's tile and the cut it keeps of the tree.
        app.state.light_tree.stage = 0;
        app.state.light_tree.depth = 2;
        let mut harness = screen(app, size, 2);
        assert!(
            harness
                .state()
                .state
                .light_tree
                .pixel
                .is_some_and(|p| p == [72, 194])
        );
        harness.snapshot_options(format!("light-tree-grid-{name}"), &screenshots());
        results.extend_harness(&mut harness);
    }
    results.unwrap();
}

/// The Light tree panel on `stage` (spots): a node below the tile's cut, its chosen group
/// with its map of what its spots give the floor, the lights coloured by their spatial pick
/// probability.
#[test]
fn light_tree_spot_map_on_stage() {
    let mut app = LightpickApp::for_tests_on("stage");
    app.state.settings.dark = false;
    app.layout.maximized = Some(lightpick::app::PanelKind::LightTree);
    // The first pick near the stage's centre whose descent goes on below the tile's cut:
    // its first node.
    let built = std::sync::Arc::clone(&app.state.built);
    let seed = app.state.settings.seed;
    let (pixel, number) = (0..16)
        .map(|k| [60 + 11 * k, 70 + 5 * (k % 7)])
        .chain((0..640).map(|k| [8 * (k % 32) + 3, 8 * (k / 32) + 5]))
        .find_map(|pixel| {
            app.state.light_tree.select_pixel(pixel);
            (0..20).find_map(|number| {
                app.state.light_tree.number = number;
                let record = app.state.light_tree.pick(&built, seed)?.record.clone()?;
                (!record.steps.is_empty()).then_some((pixel, number))
            })
        })
        .expect("a pick through a node");
    app.state.light_tree.select_pixel(pixel);
    app.state.light_tree.number = number;
    app.state.light_tree.stage = 1;
    app.state.light_tree.coloring = lightpick::app::state::light_tree::TreeColoring::Spatial;
    let mut harness = screen(app, [1024.0, 768.0], 2);
    harness.snapshot_options("light-tree-stage-1024x768", &screenshots());
}
