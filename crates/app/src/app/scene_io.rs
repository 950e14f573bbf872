//! The app's scenes in and out, other than opened files: presets, the session's JSON and
//! saving a scene. (An opened file of any format goes through the core's one loader in
//! `files.rs`; generated scenes are `generated.rs`.)
//!
//! Every scene format question is answered by `lightpick_core::scene`; this module only
//! adapts its errors to one-line messages for the status bar.

use std::path::Path;

use glam::{dvec2, dvec3};
use lightpick_core::scene::{ReceiverPlane, Scene};

/// The preset names, in menu order.
pub fn preset_names() -> Vec<&'static str> {
    lightpick_core::scene::PRESET_NAMES.to_vec()
}

/// The preset `name`, or a message saying why it could not be made.
pub fn preset(name: &str) -> Result<Scene, String> {
    Scene::preset(name).map_err(|e| format!("preset '{name}': {e}"))
}

/// The worked example (powers 2, 5, 20): the app's first scene and its fallback.
pub fn worked_example_scene() -> Scene {
    preset("worked-example").unwrap_or_else(|_| fallback_worked_example())
}

/// A worked example made here, used only if the preset cannot be built.
fn fallback_worked_example() -> Scene {
    Scene::new(
        "worked-example",
        ReceiverPlane {
            min: dvec2(-2.0, -2.0),
            max: dvec2(2.0, 2.0),
            width: 256,
            height: 256,
        },
        vec![
            dvec3(-1.2, 0.8, 0.8),
            dvec3(1.0, 1.0, 1.0),
            dvec3(0.0, -1.0, 1.5),
        ],
        lightpick_core::WorkedExample::powers(),
    )
}

/// Parses scene JSON, or says (in one line) why the text is not a scene.
pub fn from_json_str(text: &str) -> Result<Scene, String> {
    Scene::from_json_str(text).map_err(|e| e.to_string())
}

/// The scene as JSON text.
pub fn to_json(scene: &Scene) -> String {
    scene.to_json()
}

/// Writes the scene as JSON to `path`, atomically: on failure (a full disk, a read-only
/// folder) the old file stays and the message says why.
pub fn save(path: &Path, scene: &Scene) -> Result<(), String> {
    let text = to_json(scene);
    lightpick_core::atomic_file::write_bytes_atomically(path, text.as_bytes()).map_err(|e| {
        format!(
            "cannot write {}: {e} — the old file is unchanged",
            path.display()
        )
    })
}
