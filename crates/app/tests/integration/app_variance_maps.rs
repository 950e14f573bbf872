//! The images panel's variance maps: turned on with their checkbox on the worked example,
//! they show the core's `VarianceMap` means (exact there): bit for bit those of the app's
//! own samplers, and within the table's quantization of a map built apart from them; a new
//! scene generation recomputes them. On `grid` (1024 lights × 256² pixels, beyond the exact
//! budget) they are estimated on a coarser grid and say so; at a 1024×768 projector the
//! images panel shows them instead of the error maps (golden in `tests/snapshots/`).

use lightpick::app::{LightpickApp, PanelKind};
use lightpick_core::Scheme;
use lightpick_core::stats::variance_map::VarianceMap;

use crate::common::{click, panel, shows_containing, snapshot_options, step_paused, wgpu_window};

const SCHEMES: [(Scheme, &str); 3] = [
    (Scheme::Uniform, "uniform"),
    (Scheme::Alias, "power (alias)"),
    (Scheme::Spatial, "spatial"),
];

fn mean(map: &VarianceMap) -> f64 {
    assert!(map.exact, "small scenes are exact");
    map.values.iter().sum::<f64>() / map.values.len() as f64
}

/// The core's exact mean variance of each scheme over the app's scene, through the app's
/// samplers; checked against maps built apart ([`VarianceMap::compute`]), which differ
/// only by the alias table's quantization of `p_i` (its integer construction, `2^-32`).
fn core_means(state: &lightpick::app::state::AppState) -> [f64; 3] {
    let scene = &state.built.scene;
    SCHEMES.map(|(scheme, _)| {
        let sampler = state.built.samplers.sampler(scheme);
        let shared = mean(&VarianceMap::of_sampler(scene, &sampler, 1 << 40, 2, 1));
        let apart = mean(&VarianceMap::compute(scene, scheme, 2, 1));
        assert!(
            (shared - apart).abs() <= 1e-9 * apart.abs() + 1e-18,
            "{scheme}: {shared} vs {apart}"
        );
        shared
    })
}

/// Asserts the panel's line shows each of `means` as the captions write it.
fn assert_means_shown(harness: &egui_kittest::Harness<'_, LightpickApp>, means: [f64; 3]) {
    for ((_, name), mean) in SCHEMES.iter().zip(means) {
        let text = format!("{name} {mean:.3e}");
        assert!(shows_containing(harness, &text), "{text} is not shown");
    }
}

#[test]
fn variance_maps_show_the_cores_means_and_follow_a_new_generation() {
    let mut harness = panel(
        PanelKind::Images,
        LightpickApp::for_tests(),
        [1200.0, 800.0],
    );
    harness.run();
    step_paused(&mut harness, 1);
    assert!(
        !harness.state().state.settings.show_variance,
        "off by default"
    );
    assert!(!shows_containing(&harness, "Mean variance"));
    click(&mut harness, "variance maps");
    assert!(harness.state().state.settings.show_variance);
    harness.run();

    let scene = harness.state().state.built.scene.clone();
    let maps = harness
        .state()
        .state
        .current_variance_maps()
        .expect("computed inline in tests")
        .clone();
    assert!(maps.exact());
    assert_eq!(maps.size(), [scene.plane.width, scene.plane.height]);
    let means = core_means(&harness.state().state);
    assert_eq!(maps.means(), means, "the core's maps, bit for bit");
    assert_means_shown(&harness, means);
    assert!(shows_containing(
        &harness,
        "exact: Σ s_i²/q_i − E² at every pixel centre"
    ));
    // The exact spatial pick of three lights: zero up to rounding.
    assert!(means[2].abs() < 1e-9 * means[1]);

    // A new generation (light 1's power 2 → 7) recomputes the maps.
    let before = harness.state().state.built.generation;
    {
        let state = &mut harness.state_mut().state;
        state.edit.powers_mut()[0] = 7.0;
        state.powers_changed();
    }
    harness.run();
    step_paused(&mut harness, 1);
    let state = &harness.state().state;
    let generation = state.built.generation;
    assert!(generation > before);
    let maps = state.current_variance_maps().expect("recomputed").clone();
    assert_eq!(maps.generation, generation);
    let new_means = core_means(state);
    assert_eq!(maps.means(), new_means);
    assert_ne!(new_means[1], means[1], "new powers, new power variance");
    assert_means_shown(&harness, new_means);
    let old = format!("power (alias) {:.3e}", means[1]);
    assert!(!shows_containing(&harness, &old), "{old} is still shown");

    // Off again: the line goes.
    click(&mut harness, "variance maps");
    assert!(!shows_containing(&harness, "Mean variance"));
}

#[test]
fn exact_maps_on_a_grid_instead_of_the_error_maps_at_a_projector() {
    let mut app = LightpickApp::for_tests_on("grid");
    app.state.settings.dark = false;
    app.state.settings.show_error = false;
    app.state.settings.show_variance = true;
    app.layout.maximized = Some(PanelKind::Images);
    let mut harness = wgpu_window(app, [1024.0, 768.0]);
    harness.run();
    step_paused(&mut harness, 4);
    let maps = harness
        .state()
        .state
        .current_variance_maps()
        .expect("computed inline in tests")
        .clone();
    // 1024 lights × 256² pixels beyond the exact budget: exact on a 128² grid.
    assert!(maps.exact());
    assert_eq!(maps.size(), [128, 128]);
    assert!(shows_containing(
        &harness,
        "exact: Σ s_i²/q_i − E² at every pixel centre"
    ));
    let means = maps.means();
    assert!(
        means[2] < means[1],
        "spatial below power on the grid: {means:?}"
    );
    assert_means_shown(&harness, means);
    harness.snapshot_options("app_variance_grid_1024x768", &snapshot_options());
}
