//! Undo and redo over the scene edits: a drag is one step, a preset, Generate and an opened
//! file are one step each, the Edit menu names them, and Ctrl+Z back to the start restores
//! the first scene bit for bit (Ctrl+Y and Ctrl+Shift+Z forward to the last).

use egui::{Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;
use lightpick::app::state::FileAction;
use lightpick_core::scene::Scene;

use crate::common::painted::light_bits;
use crate::common::{click, fixtures, shows_containing, window};

/// A scene's every number as bits: powers, positions, name and plane.
fn bits(scene: &Scene) -> (Vec<u64>, Vec<[u64; 3]>, String, String) {
    let (powers, positions) = light_bits(scene);
    (
        powers,
        positions,
        scene.name.clone(),
        format!("{:?}", scene.plane),
    )
}

fn scene_bits(harness: &Harness<'_, LightpickApp>) -> (Vec<u64>, Vec<[u64; 3]>, String, String) {
    bits(&harness.state().state.built.scene)
}

/// Drags the pointer from `from` through `to` over several frames, as a hand does.
fn drag(harness: &mut Harness<'static, LightpickApp>, from: Pos2, to: Pos2) {
    harness.hover_at(from);
    let button = |pos, pressed| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::default(),
    };
    harness.event(button(from, true));
    harness.run();
    for k in 1..=6 {
        let pos = from + (to - from) * (k as f32 / 6.0);
        harness.event(Event::PointerMoved(pos));
        harness.run();
    }
    harness.event(button(to, false));
    harness.run();
}

fn key(harness: &mut Harness<'static, LightpickApp>, modifiers: Modifiers, key: Key) {
    harness.key_press_modifiers(modifiers, key);
    harness.run();
}

#[test]
fn undo_and_redo_walk_the_edits_back_and_forth_bit_for_bit() {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    let first = scene_bits(&harness);

    // A drag over many frames: one step.
    let rail = harness.get_by_label("power slider of light 1").rect();
    let y = rail.center().y;
    drag(
        &mut harness,
        egui::pos2(rail.left() + 0.1 * rail.width(), y),
        egui::pos2(rail.left() + 0.8 * rail.width(), y),
    );
    let history = &harness.state().state.history;
    assert_eq!(history.undo_len(), 1, "a drag is one step");
    assert_eq!(history.undo_name(), Some("drag of light 1"));
    assert_ne!(harness.state().state.built.scene.powers.as_slice()[0], 2.0);
    let dragged = scene_bits(&harness);

    // A preset, Generate and an opened file: a step each.
    click(&mut harness, "grid");
    assert_eq!(
        harness.state().state.history.undo_name(),
        Some("preset 'grid'")
    );
    harness.state_mut().state.generate(50);
    harness.run();
    assert_eq!(
        harness.state().state.history.undo_name(),
        Some("Generate (50 lights)")
    );
    let generated = scene_bits(&harness);
    let file = fixtures().join("lamps.csv");
    let text = file.to_str().expect("utf-8").to_owned();
    harness
        .state_mut()
        .file_action(FileAction::OpenScene, &text, None);
    harness.run();
    assert_eq!(harness.state().state.history.undo_len(), 4);
    let opened = scene_bits(&harness);

    // The Edit menu names the step.
    click(&mut harness, "Edit");
    assert!(shows_containing(&harness, "Undo open 'lamps.csv'"));
    harness.key_press(Key::Escape);
    harness.run();

    // Back: file → generated → grid → dragged → first.
    key(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(scene_bits(&harness), generated);
    key(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(harness.state().state.built.scene.name, "grid");
    assert_eq!(
        harness.state().state.unedited_preset.as_deref(),
        Some("grid"),
        "the preset comes back as the unedited preset"
    );
    key(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(scene_bits(&harness), dragged);
    key(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(
        scene_bits(&harness),
        first,
        "back to the first scene, bit for bit"
    );
    assert_eq!(harness.state().state.history.undo_len(), 0);
    key(&mut harness, Modifiers::COMMAND, Key::Z);
    assert_eq!(scene_bits(&harness), first, "nothing more to undo");

    // Forward with both redo shortcuts.
    key(&mut harness, Modifiers::COMMAND, Key::Y);
    assert_eq!(scene_bits(&harness), dragged);
    key(&mut harness, Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    key(&mut harness, Modifiers::COMMAND, Key::Y);
    key(&mut harness, Modifiers::COMMAND, Key::Y);
    assert_eq!(scene_bits(&harness), opened);
    assert_eq!(harness.state().state.history.redo_name(), None);

    // A new edit after an undo drops the redo stack.
    key(&mut harness, Modifiers::COMMAND, Key::Z);
    harness.state_mut().state.randomize();
    harness.run();
    assert_eq!(harness.state().state.history.undo_name(), Some("Randomize"));
    assert_eq!(harness.state().state.history.redo_name(), None);
}

#[test]
fn every_edit_of_the_lights_panel_is_one_named_step() {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    let state = &mut harness.state_mut().state;
    state.add_light(4.0);
    state.duplicate_light(0);
    state.remove_light(1);
    state.randomize();
    state.powers_text = "3, 4, 5, 6".to_owned();
    state.apply_powers_text();
    state.set_floor(0.25);
    let mut names = Vec::new();
    while let Some(name) = state.history.undo_name().map(str::to_owned) {
        names.push(name);
        state.undo();
    }
    assert_eq!(
        names,
        [
            "floor 0.25",
            "Apply powers",
            "Randomize",
            "delete light 2",
            "duplicate light 1",
            "add light 4",
        ]
    );
    assert_eq!(state.built.scene.powers.as_slice(), [2.0, 5.0, 20.0]);
    assert_eq!(state.edit.floor, 0.0);
}

#[test]
fn a_power_drag_on_a_large_scene_keeps_only_the_powers_it_changed() {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    harness.state_mut().state.generate(100_000);
    // The build runs on a worker beyond the synchronous limit.
    let deadline = std::time::Instant::now() + crate::common::HANG_GUARD;
    while harness.state().state.built.len() != 100_000 {
        assert!(
            std::time::Instant::now() < deadline,
            "the scene never arrived"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
    let before = harness.state().state.history.heap_bytes();
    let state = &mut harness.state_mut().state;
    state.history.name_next("power of light 7");
    state.edit.powers_mut()[6] = 123.0;
    state.powers_changed();
    while harness.state().state.built.scene.powers.as_slice()[6] != 123.0 {
        assert!(
            std::time::Instant::now() < deadline,
            "the edit never landed"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
    let history = &harness.state().state.history;
    assert_eq!(history.undo_name(), Some("power of light 7"));
    // One changed power: 24 bytes (index, before, after), not 800 kB of powers.
    let grown = history.heap_bytes() - before;
    assert_eq!(grown, 24, "the step keeps {grown} bytes");
}

/// Randomize on a large scene changes every power: the step keeps the powers before and
/// after (shared with the scenes, 8 bytes a light each) instead of 24 bytes per changed
/// light, and undo and redo put each set back bit for bit, with the same geometry.
#[test]
fn randomizing_a_large_scene_keeps_the_powers_not_every_change() {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    let n = 100_000;
    harness.state_mut().state.generate(n);
    let deadline = std::time::Instant::now() + crate::common::HANG_GUARD;
    let settle = |harness: &mut Harness<'_, LightpickApp>, done: &dyn Fn(&Scene) -> bool| {
        while harness.state().state.is_building() || !done(&harness.state().state.built.scene) {
            assert!(
                std::time::Instant::now() < deadline,
                "the build never landed"
            );
            std::thread::sleep(std::time::Duration::from_millis(20));
            harness.step();
        }
    };
    settle(&mut harness, &|s| s.light_count() == n);
    let generated = scene_bits(&harness);
    let before = harness.state().state.history.heap_bytes();
    harness.state_mut().state.randomize();
    settle(&mut harness, &|s| light_bits(s).0 != generated.0);
    let randomized = scene_bits(&harness);
    assert_eq!(harness.state().state.history.undo_name(), Some("Randomize"));
    let grown = harness.state().state.history.heap_bytes() - before;
    assert_eq!(grown, 2 * 8 * n, "the step keeps {grown} bytes");
    harness.state_mut().state.undo();
    settle(&mut harness, &|s| light_bits(s).0 == generated.0);
    assert_eq!(scene_bits(&harness), generated);
    harness.state_mut().state.redo();
    settle(&mut harness, &|s| light_bits(s).0 == randomized.0);
    assert_eq!(scene_bits(&harness), randomized);
}
