//! Scene files: the JSON format, every `SceneError` variant, the presets and the generator,
//! one file each; the scene texts and checks they share here.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

mod errors;
mod format;
mod generator;
mod presets;

use glam::dvec2;
use lightpick_core::scene::{ReceiverPlane, Scene, SceneError};

pub(super) const PLANE: &str =
    r#""plane": { "min": [-1, -1], "max": [1, 1], "width": 8, "height": 4 }"#;

pub(super) fn lights_scene(lights: &str) -> String {
    format!(r#"{{ "name": "t", {PLANE}, "lights": [{lights}] }}"#)
}

pub(super) fn generator_scene(generator_body: &str) -> String {
    format!(r#"{{ "name": "g", {PLANE}, "generator": {{ {generator_body} }} }}"#)
}

pub(super) const PLACEMENT: &str = r#""placement": { "min": [-1, -1, 0.1], "max": [1, 1, 1] }"#;

pub(super) fn err(text: &str) -> SceneError {
    match Scene::from_json_str(text) {
        Ok(scene) => panic!("accepted: {scene:?}"),
        Err(e) => e,
    }
}

pub(super) fn unit_plane() -> ReceiverPlane {
    ReceiverPlane {
        min: dvec2(-1.0, -1.0),
        max: dvec2(1.0, 1.0),
        width: 4,
        height: 4,
    }
}
