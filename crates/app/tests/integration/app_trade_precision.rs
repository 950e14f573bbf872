//! The speed-against-accuracy and precision panels: a snapshot of each on the worked example
//! (goldens in `tests/snapshots/`, update with `UPDATE_SNAPSHOTS=1`) and what they must say.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::state::trade::{TRADE_SCHEMES, scheme_label};
use lightpick::app::{LightpickApp, PanelKind};

use crate::common::{click, snapshot_options, wgpu_panel, window};

/// One panel over `app`, after a couple of frames (the measurement runs inline in tests).
fn panel(kind: PanelKind, size: [f32; 2], app: LightpickApp) -> Harness<'static, LightpickApp> {
    let mut harness = wgpu_panel(kind, app, size);
    harness.run();
    harness
}

#[test]
fn trade_panel() {
    panel(PanelKind::Trade, [660.0, 560.0], LightpickApp::for_tests())
        .snapshot_options("app_trade", &snapshot_options());
}

#[test]
fn precision_panel() {
    panel(
        PanelKind::Precision,
        [720.0, 460.0],
        LightpickApp::for_tests(),
    )
    .snapshot_options("app_precision", &snapshot_options());
}

#[test]
fn trade_panel_lists_every_scheme_after_measuring() {
    let mut harness = panel(PanelKind::Trade, [660.0, 560.0], LightpickApp::for_tests());
    click(&mut harness, "Measure");
    for scheme in TRADE_SCHEMES {
        // In the figures table and in the plot's legend.
        let label = scheme_label(scheme);
        assert!(
            harness.query_all_by_label(label).next().is_some(),
            "{label} missing"
        );
    }
    let m = harness
        .state()
        .state
        .trade
        .result
        .clone()
        .expect("a measurement");
    assert_eq!(m.generation, harness.state().state.built.generation);
    assert_eq!(m.rows.len(), TRADE_SCHEMES.len());
    let row = |s| {
        m.rows
            .iter()
            .find(|r| r.scheme == s)
            .expect("every scheme measured")
    };
    // With equal (virtual) time per sample, importance sampling beats uniform selection on
    // the worked example, and both alias variants estimate the same pmf.
    let uniform = row(lightpick_core::Scheme::Uniform).efficiency;
    let alias = row(lightpick_core::Scheme::Alias).efficiency;
    assert!(
        alias.efficiency > uniform.efficiency,
        "alias {alias:?} vs uniform {uniform:?}"
    );
    // Three lights: the spatial scheme is the exact contribution pick, zero variance up
    // to rounding.
    let spatial = row(lightpick_core::Scheme::Spatial).efficiency;
    assert!(
        spatial.variance_per_sample <= 1e-12 * uniform.variance_per_sample,
        "spatial {spatial:?}"
    );
    for r in &m.rows {
        assert_eq!(r.series.last().map(|p| p.spp), Some(64));
    }
}

#[test]
fn precision_panel_shows_no_leak_for_the_f64_build_on_zeros() {
    let harness = panel(
        PanelKind::Precision,
        [720.0, 460.0],
        LightpickApp::for_tests_on("zeros"),
    );
    let state = &harness.state().state;
    let m = state.precision.result.as_ref().expect("a measurement");
    assert_eq!(m.generation, state.built.generation);
    assert!(m.report.zero_lights > 0, "the zeros preset has zero lights");
    assert_eq!(m.report.construction.f64_build.zero_leak, 0.0);
    // The f64 leak cell reads exactly "0" (no zero light is ever picked).
    assert!(
        harness.query_all_by_label("0 (0 lights)").next().is_some(),
        "no '0 (0 lights)' leak cell"
    );
    harness.get_by_label_contains("of zero power");
}

#[test]
fn view_menu_windows_open_over_the_whole_app() {
    let mut harness = window(LightpickApp::for_tests(), [1440.0, 900.0]);
    harness.run();
    // Closed by default: the seed layout stays uncluttered.
    assert!(harness.query_by_label("Precision of the table").is_none());
    click(&mut harness, "View");
    click(&mut harness, "Precision");
    harness.get_by_label("Precision of the table");
    assert!(harness.state().state.settings.show_precision);
    let m = harness
        .state()
        .state
        .precision
        .result
        .as_ref()
        .expect("measured");
    assert_eq!(m.report.n, 3);
}
