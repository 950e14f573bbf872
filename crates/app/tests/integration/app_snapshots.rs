//! Snapshots of every panel on the worked example (goldens in `tests/snapshots/`), rendered
//! with wgpu (lavapipe without a GPU). Update with `UPDATE_SNAPSHOTS=1`.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::panels::layout;
use lightpick::app::{LightpickApp, PanelKind};

use crate::common::{click, snapshot_options, step_paused, wgpu_panel, wgpu_window};

/// One panel of the worked example after `steps` paused single steps.
fn panel(kind: PanelKind, size: [f32; 2], steps: usize) -> Harness<'static, LightpickApp> {
    let mut harness = wgpu_panel(kind, LightpickApp::for_tests(), size);
    harness.run();
    step_paused(&mut harness, steps);
    harness
}

#[test]
fn lights_panel() {
    panel(PanelKind::Lights, [460.0, 320.0], 0).snapshot_options("app_lights", &snapshot_options());
}

#[test]
fn table_panel() {
    panel(PanelKind::Table, [620.0, 420.0], 0).snapshot_options("app_table", &snapshot_options());
}

#[test]
fn sampling_panel() {
    let mut harness = panel(PanelKind::Sampling, [620.0, 400.0], 5);
    assert_eq!(harness.state().state.sampling.picks, 1000);
    harness.snapshot_options("app_sampling", &snapshot_options());
}

#[test]
fn images_panel() {
    let mut harness = panel(PanelKind::Images, [600.0, 420.0], 64);
    let published = harness.state_mut().published().expect("a frame");
    assert_eq!(published.uniform.spp, 64);
    assert_eq!(published.power.spp, 64);
    // Importance sampling ends closer to the reference than uniform selection.
    let (u, a) = (
        published.uniform.rmse.expect("rmse"),
        published.power.rmse.expect("rmse"),
    );
    assert!(a < u, "power RMSE {a} vs uniform {u}");
    // Three lights: the spatial image is the exact contribution pick, exact up to rounding.
    assert_eq!(published.spatial.spp, 64);
    let s = published.spatial.rmse.expect("rmse");
    assert!(s <= 1e-12 * a, "spatial RMSE {s}");
    harness.snapshot_options("app_images", &snapshot_options());
}

#[test]
fn convergence_panel() {
    panel(PanelKind::Convergence, [620.0, 380.0], 8)
        .snapshot_options("app_convergence", &snapshot_options());
}

#[test]
fn controls_bar() {
    panel(PanelKind::Controls, [900.0, 40.0], 0)
        .snapshot_options("app_controls", &snapshot_options());
}

#[test]
fn whole_app() {
    let mut harness = wgpu_window(LightpickApp::for_tests(), [1280.0, 800.0]);
    harness.run();
    harness.snapshot_options("app_whole", &snapshot_options());
}

/// The whole window at `size` on the worked example after eight paused steps (images, curves
/// and histograms drawn).
fn window(size: [f32; 2]) -> Harness<'static, LightpickApp> {
    let mut harness = wgpu_window(LightpickApp::for_tests(), size);
    harness.run();
    step_paused(&mut harness, 8);
    harness
}

/// Every panel the layout drew is at least its least readable size (width and height,
/// below its header); returns the panels drawn.
fn assert_readable(harness: &Harness<'_, LightpickApp>) -> Vec<PanelKind> {
    let layout = &harness.state().layout;
    for &(pane, rect) in &layout.placed {
        assert!(
            rect.width() >= layout::min_width(pane),
            "{pane:?} is {} wide, less than {} ({:?})",
            rect.width(),
            layout::min_width(pane),
            layout.arrangement
        );
        assert!(
            rect.height() >= layout::min_height(pane) + layout::HEADER_HEIGHT - 1.0,
            "{pane:?} is {} high ({:?})",
            rect.height(),
            layout.arrangement
        );
    }
    layout.placed.iter().map(|(p, _)| *p).collect()
}

/// The table's last header cell ("alias") lies whole inside the table panel: no column of
/// the table is cut by the panel beside it.
fn assert_table_whole(harness: &Harness<'_, LightpickApp>) {
    let table = harness
        .state()
        .layout
        .pane_rect(PanelKind::Table)
        .expect("the table is drawn");
    assert!(
        table.width() >= layout::TABLE_MIN_WIDTH,
        "table {} wide",
        table.width()
    );
    for label in ["threshold", "alias"] {
        let cell = harness.get_by_label(label).rect();
        assert!(
            table.contains_rect(cell),
            "the table's {label:?} header {cell:?} is cut (table panel {table:?})"
        );
    }
}

#[test]
fn window_1024x768() {
    let mut harness = window([1024.0, 768.0]);
    assert_eq!(
        harness.state().layout.arrangement,
        layout::Arrangement::TwoColumns
    );
    let drawn = assert_readable(&harness);
    assert_table_whole(&harness);
    // The lights over the table; the other three are tabs of one column.
    assert!(drawn.contains(&PanelKind::Lights) && drawn.contains(&PanelKind::Table));
    assert_eq!(drawn.len(), 3, "{drawn:?}");
    for tab in ["Sampling", "Images", "Convergence"] {
        assert!(harness.query_by_label(tab).is_some(), "no {tab} tab");
    }
    // Choosing a tab shows that panel, readable too.
    click(&mut harness, "Convergence");
    assert!(assert_readable(&harness).contains(&PanelKind::Convergence));
    click(&mut harness, "Images");
    harness.snapshot_options("app_window_1024x768", &snapshot_options());
}

#[test]
fn window_1280x720() {
    let mut harness = window([1280.0, 720.0]);
    assert_eq!(
        harness.state().layout.arrangement,
        layout::Arrangement::ThreeColumns
    );
    // The table over the histograms; the images and the curves are tabs of one column.
    assert_eq!(
        assert_readable(&harness),
        [
            PanelKind::Lights,
            PanelKind::Table,
            PanelKind::Sampling,
            PanelKind::Images
        ]
    );
    assert_table_whole(&harness);
    click(&mut harness, "Convergence");
    assert!(assert_readable(&harness).contains(&PanelKind::Convergence));
    click(&mut harness, "Images");
    harness.snapshot_options("app_window_1280x720", &snapshot_options());
}

#[test]
fn window_1920x1080() {
    let mut harness = window([1920.0, 1080.0]);
    assert_eq!(assert_readable(&harness).len(), 5);
    assert_table_whole(&harness);
    harness.snapshot_options("app_window_1920x1080", &snapshot_options());
}

#[test]
fn window_table_maximized() {
    let mut harness = window([1024.0, 768.0]);
    click(&mut harness, "Maximize Alias table");
    let layout = &harness.state().layout;
    assert_eq!(layout.maximized, Some(PanelKind::Table));
    let drawn = assert_readable(&harness);
    assert_eq!(drawn, [PanelKind::Table]);
    let table = harness
        .state()
        .layout
        .pane_rect(PanelKind::Table)
        .expect("drawn");
    assert!(table.width() > 950.0, "{table:?}");
    assert_table_whole(&harness);
    harness.snapshot_options("app_window_table_maximized", &snapshot_options());
    // Escape restores every panel; Restore does too.
    harness.key_press(egui::Key::Escape);
    harness.run();
    assert_eq!(harness.state().layout.maximized, None);
    assert_eq!(assert_readable(&harness).len(), 3);
    click(&mut harness, "Maximize Images");
    assert_eq!(harness.state().layout.maximized, Some(PanelKind::Images));
    click(&mut harness, "Restore");
    assert_eq!(harness.state().layout.maximized, None);
}

/// Drags the mouse from `from` to `to` with the primary button held.
fn drag(harness: &mut Harness<'_, LightpickApp>, from: egui::Pos2, to: egui::Pos2) {
    let button = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::NONE,
    };
    harness.event(egui::Event::PointerMoved(from));
    harness.run();
    harness.event(button(from, true));
    harness.run();
    for k in 1..=8 {
        harness.event(egui::Event::PointerMoved(from.lerp(to, k as f32 / 8.0)));
        harness.run();
    }
    harness.event(button(to, false));
    harness.run();
}

/// The edge between `left` and `right`, two panels side by side, halfway down.
fn edge(harness: &Harness<'_, LightpickApp>, left: PanelKind, right: PanelKind) -> egui::Pos2 {
    let layout = &harness.state().layout;
    let (l, r) = (
        layout.pane_rect(left).expect("drawn"),
        layout.pane_rect(right).expect("drawn"),
    );
    egui::pos2(0.5 * (l.right() + r.left()), l.center().y)
}

#[test]
fn columns_dragged_wide_never_squeeze_a_panel() {
    // A presenter widens the lights and the table on a 1920 monitor as far as they go…
    let mut harness = window([1920.0, 1080.0]);
    let from = edge(&harness, PanelKind::Lights, PanelKind::Table);
    drag(&mut harness, from, egui::pos2(1900.0, from.y));
    let from = edge(&harness, PanelKind::Table, PanelKind::Images);
    drag(&mut harness, from, egui::pos2(1910.0, from.y));
    let layout = &harness.state().layout;
    let lights = layout.pane_rect(PanelKind::Lights).expect("drawn");
    assert!(
        lights.width() > 600.0,
        "the drag widened the lights: {lights:?}"
    );
    assert_eq!(assert_readable(&harness).len(), 5);
    // …then the window moves to a 1280×720 projector: every panel keeps its least width.
    harness.set_size(egui::vec2(1280.0, 720.0));
    harness.run();
    assert_eq!(assert_readable(&harness).len(), 4);
    assert_table_whole(&harness);
}
