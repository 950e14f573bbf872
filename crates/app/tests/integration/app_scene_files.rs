//! Real light sets in the app: File → Open's file chooser on a glTF file, a file dropped on
//! the window, a bad file (the last good scene stays), names in the panels, the Floor
//! control, and edits that keep each light's spot cone and name.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::common::{app_harness as harness, click, fixtures, scratch};
use egui::accesskit::Role;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::state::MessageKind;

fn status(
    harness: &egui_kittest::Harness<'static, lightpick::app::LightpickApp>,
) -> (String, MessageKind) {
    harness
        .state()
        .state
        .status
        .clone()
        .expect("a status message")
}

/// A file as a native window hands it over when dropped.
#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

fn drop_file(
    harness: &mut egui_kittest::Harness<'static, lightpick::app::LightpickApp>,
    path: PathBuf,
) {
    harness
        .input_mut()
        .dropped_files
        .push(Arc::new(Dropped(path)));
    harness.run();
}

#[test]
fn the_file_chooser_browses_to_a_gltf_and_opens_it() {
    let mut harness = harness();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::O);
    harness.run();
    // Browse: the dialog lists the fixtures folder (scenes only) once told to go there.
    harness.state_mut().state.file_dialog.folder = Some(fixtures());
    harness.state_mut().state.file_dialog.listing = None;
    harness.run();
    assert!(
        harness
            .query_all_by_label_contains("lamps.csv")
            .next()
            .is_some()
    );
    harness.get_by_label_contains("hierarchy.glb").click();
    harness.run();
    assert_eq!(harness.state().state.file_dialog.path, "hierarchy.glb");
    click(&mut harness, "OK");
    let (message, kind) = status(&harness);
    assert_eq!(kind, MessageKind::Success, "{message}");
    assert!(
        message.ends_with(
            "hierarchy.glb: 5 lights: 3 points, 2 spots; skipped 1 directional light 'Sun'"
        ),
        "{message}"
    );
    let state = &harness.state().state;
    assert_eq!(state.built.scene.light_count(), 5);
    assert_eq!(state.built.scene.spot_count(), 2);
    assert!(state.file_dialog.action.is_none(), "the dialog closed");
    // Names in the Lights panel and the table.
    assert!(
        harness
            .query_all_by_label_contains("Spot Node")
            .next()
            .is_some()
    );
}

#[test]
fn a_dropped_file_opens_and_a_bad_one_keeps_the_scene() {
    let mut harness = harness();
    drop_file(&mut harness, fixtures().join("lamps.csv"));
    let (message, kind) = status(&harness);
    assert_eq!(kind, MessageKind::Success, "{message}");
    assert!(message.ends_with("lamps.csv: 3 lights"), "{message}");
    assert_eq!(
        harness.state().state.built.scene.powers.as_slice(),
        &[800.0, 450.0, 120.0]
    );
    // A file that is not a scene: named in the status bar, the CSV scene stays.
    let dir = scratch("app-drop");
    let bad = dir.join("broken.glb");
    std::fs::write(&bad, b"glTF\x02\0\0\0\x08\0\0\0").expect("write");
    drop_file(&mut harness, bad);
    let (message, kind) = status(&harness);
    assert_eq!(kind, MessageKind::Error);
    assert!(
        message.contains("glb: the header's length 8 differs")
            && message.ends_with("nothing changed"),
        "{message}"
    );
    assert_eq!(
        harness.state().state.built.scene.powers.as_slice(),
        &[800.0, 450.0, 120.0]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_floor_control_moves_the_receiver_and_edits_keep_cones_and_names() {
    let mut harness = harness();
    drop_file(&mut harness, fixtures().join("hierarchy.gltf"));
    let before = harness.state().state.built.scene.positions.clone();
    harness
        .get_by_role_and_label(Role::SpinButton, "Floor")
        .set_value_accesskit(1.5);
    harness.run();
    let state = &harness.state().state;
    for (a, b) in state.built.scene.positions.iter().zip(before.iter()) {
        assert_eq!(a.z, b.z - 1.5);
    }
    assert_eq!(state.edit.floor, 1.5);
    // Duplicate the spot (light 2), then change a power: the copy keeps its cone and name,
    // and every light keeps its own.
    click(&mut harness, "duplicate light 2");
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(300.0);
    harness.run();
    let scene = &harness.state().state.built.scene;
    assert_eq!(scene.light_count(), 6);
    assert_eq!(scene.name_of(2), Some("Spot Node"));
    assert_eq!(scene.emission_of(2), scene.emission_of(1));
    assert!(scene.emission_of(2).expect("profiles").spot().is_some());
    assert_eq!(scene.name_of(5), Some("Tilted spot"));
    assert_eq!(scene.powers.as_slice()[0], 300.0);
}
