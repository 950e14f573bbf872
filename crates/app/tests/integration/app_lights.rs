//! The Lights panel beyond typing a power: duplicate, Randomize, Generate (a virtualized
//! list for large N, built off the UI thread past the synchronous limit), the log slider;
//! and the settings and scene that persist between runs (eframe storage).

use std::time::{Duration, Instant};

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::state::{SYNC_BUILD_LIMIT, SliderScale};
use lightpick::app::{LightpickApp, PanelKind};

use crate::common::session::{MemoryStorage, restored};
use crate::common::{HANG_GUARD, click, panel};

fn lights_panel() -> Harness<'static, LightpickApp> {
    let mut harness = panel(PanelKind::Lights, LightpickApp::for_tests(), [460.0, 600.0]);
    harness.run();
    harness
}

fn powers(harness: &Harness<'static, LightpickApp>) -> Vec<f64> {
    harness.state().state.built.scene.powers.as_slice().to_vec()
}

/// Runs frames until the table has `n` lights (a background build), or fails after
/// [`HANG_GUARD`].
fn run_until_built(harness: &mut Harness<'static, LightpickApp>, n: usize) {
    let deadline = Instant::now() + HANG_GUARD;
    while harness.state().state.built.len() != n {
        assert!(
            Instant::now() < deadline,
            "the {n}-light table never arrived"
        );
        std::thread::sleep(Duration::from_millis(20));
        harness.run();
    }
}

#[test]
fn duplicate_inserts_a_copy_after_the_light_and_rebuilds_the_table() {
    let mut harness = lights_panel();
    click(&mut harness, "duplicate light 2");
    assert_eq!(powers(&harness), [2.0, 5.0, 5.0, 20.0]);
    let state = &harness.state().state;
    assert_eq!(state.edit.positions[1], state.edit.positions[2]);
    let pmf = state.built.table.pmf_slice();
    assert!((pmf[1] - 5.0 / 32.0).abs() < 1e-15 && pmf[1] == pmf[2]);
}

#[test]
fn randomize_draws_new_valid_powers_for_every_light() {
    let mut harness = lights_panel();
    let before = powers(&harness);
    click(&mut harness, "Randomize");
    let after = powers(&harness);
    assert_eq!(after.len(), before.len());
    assert_ne!(after, before);
    assert!(after.iter().all(|p| p.is_finite() && *p >= 0.0));
    let total: f64 = harness.state().state.built.table.pmf_slice().iter().sum();
    assert!((total - 1.0).abs() < 1e-12);
}

#[test]
fn generate_makes_count_lights_and_shows_only_the_visible_rows() {
    let mut harness = lights_panel();
    harness
        .get_by_role_and_label(Role::SpinButton, "Count")
        .set_value_accesskit(5000.0);
    harness.run();
    click(&mut harness, "Generate");
    run_until_built(&mut harness, 5000);
    assert_eq!(harness.state().state.edit.powers.len(), 5000);
    // A virtualized list: a few dozen rows exist as widgets, not 5000.
    let rows = harness
        .query_all_by_label_contains("power slider of light")
        .count();
    assert!((1..100).contains(&rows), "{rows} rows built");
    assert!(harness.query_by_label("power slider of light 1").is_some());
    assert!(
        harness
            .query_by_label("power slider of light 5000")
            .is_none()
    );
}

#[test]
fn generating_past_the_synchronous_limit_keeps_the_table_until_the_new_one_is_built() {
    let mut harness = lights_panel();
    let n = SYNC_BUILD_LIMIT * 2;
    harness.state_mut().state.generate(n);
    harness.run();
    // The window keeps the last good table while the big one builds off the UI thread.
    let len = harness.state().state.built.len();
    assert!(len == 3 || len == n, "{len}");
    run_until_built(&mut harness, n);
    let total: f64 = harness.state().state.built.table.pmf_slice().iter().sum();
    assert!((total - 1.0).abs() < 1e-9);
}

#[test]
fn the_log_slider_sets_small_powers() {
    let mut harness = lights_panel();
    click(&mut harness, "log");
    assert_eq!(
        harness.state().state.settings.slider_scale,
        SliderScale::Log
    );
    harness
        .get_by_label("power slider of light 1")
        .set_value_accesskit(0.001);
    harness.run();
    let p = powers(&harness)[0];
    assert!((p - 0.001).abs() <= 1e-9, "{p}");
}

#[test]
fn settings_and_the_scene_persist_between_runs() {
    let mut harness = lights_panel();
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(7.0);
    harness.run();
    {
        let settings = &mut harness.state_mut().state.settings;
        settings.spp_per_frame = 4;
        settings.dark = false;
        settings.seed = 99;
    }
    let mut storage = MemoryStorage::default();
    eframe::App::save(harness.state_mut(), &mut storage);
    let app = restored(&storage);
    assert_eq!(app.state.built.scene.powers.as_slice(), [7.0, 5.0, 20.0]);
    assert_eq!(
        app.state.built.scene.positions,
        harness.state().state.built.scene.positions
    );
    assert_eq!(app.state.settings.spp_per_frame, 4);
    assert!(!app.state.settings.dark);
    assert_eq!(app.state.settings.seed, 99);
}

#[test]
fn a_corrupt_stored_scene_gives_the_seed_scene_and_says_so() {
    let mut harness = lights_panel();
    let mut storage = MemoryStorage::default();
    eframe::App::save(harness.state_mut(), &mut storage);
    let key = storage
        .0
        .keys()
        .find(|k| storage.0[*k].contains("\"lights\"") || storage.0[*k].contains("positions"))
        .cloned()
        .expect("a stored scene");
    storage.0.insert(key, "{ not json".to_owned());
    let app = restored(&storage);
    assert_eq!(app.state.built.scene.powers.as_slice(), [2.0, 5.0, 20.0]);
    let (message, _) = app.state.status.as_ref().expect("a status message");
    assert!(message.contains("last scene not restored"), "{message}");
}

/// A scene too large to store light by light is kept by name when it is an unedited preset
/// (and restored with its own exposure); once edited it is not kept, and the next run opens
/// the worked example with the worked example's exposure, not the large scene's.
#[test]
fn large_presets_persist_by_name_and_edited_large_scenes_fall_back_to_the_seed() {
    let mut harness = lights_panel();
    harness.state_mut().state.load_preset("million");
    run_until_built(&mut harness, 1_000_000);
    let million_exposure = harness.state().state.settings.exposure;
    let mut storage = MemoryStorage::default();
    eframe::App::save(harness.state_mut(), &mut storage);
    assert!(
        !storage.0.values().any(|v| v.len() > 1_000_000),
        "no light list stored"
    );
    let app = restored(&storage);
    assert_eq!(app.state.built.len(), 1_000_000);
    assert_eq!(app.state.built.scene.name, "million");
    assert_eq!(app.state.settings.exposure, million_exposure);

    // Edit one power: the scene is no longer the preset, and is not kept.
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(3.0);
    harness.run();
    assert_eq!(harness.state().state.unedited_preset, None);
    eframe::App::save(harness.state_mut(), &mut storage);
    let app = restored(&storage);
    assert_eq!(app.state.built.scene.powers.as_slice(), [2.0, 5.0, 20.0]);
    let seed_exposure =
        lightpick::app::state::auto_exposure(&lightpick::app::scene_io::worked_example_scene());
    assert_eq!(app.state.settings.exposure, seed_exposure);
    assert_ne!(seed_exposure, million_exposure);
}
