//! The JSON format: what a file says is what the scene holds, and it round-trips exactly;
//! a power edit is checked as a file is.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::{dvec2, dvec3};
use lightpick_core::scene::{PRESET_NAMES, ReceiverPlane, Scene, SceneError};

use super::{PLANE, lights_scene, unit_plane};

#[test]
fn explicit_lights_parse_as_written() {
    let text = lights_scene(
        r#"{ "position": [0.5, -0.25, 1], "power": 2 }, { "position": [0, 0, 2], "power": 0 }"#,
    );
    let scene = Scene::from_json_str(&text).unwrap();
    assert_eq!(scene.name, "t");
    assert_eq!(
        scene.plane,
        ReceiverPlane {
            min: dvec2(-1.0, -1.0),
            max: dvec2(1.0, 1.0),
            width: 8,
            height: 4
        }
    );
    assert_eq!(
        scene.positions[..],
        [dvec3(0.5, -0.25, 1.0), dvec3(0.0, 0.0, 2.0)]
    );
    assert_eq!(scene.powers.as_slice(), &[2.0, 0.0]);
}

#[test]
fn name_defaults_to_untitled() {
    let text = format!(r#"{{ {PLANE}, "lights": [{{ "position": [0, 0, 1], "power": 1 }}] }}"#);
    assert_eq!(Scene::from_json_str(&text).unwrap().name, "untitled");
}

#[test]
fn json_round_trip_is_exact_for_every_preset_but_million() {
    for name in PRESET_NAMES.iter().filter(|&&n| n != "million") {
        let scene = Scene::preset(name).unwrap();
        let text = scene.to_json();
        let back = Scene::from_json_str(&text).unwrap();
        assert_eq!(back, scene, "{name}");
    }
}

#[test]
fn json_round_trip_keeps_awkward_values_and_names() {
    let scene = Scene::from_parts(
        "quote \" and \\ and ünïcode",
        unit_plane(),
        vec![
            dvec3(0.1 + 0.2, -1e-300, 5e-324),
            dvec3(1e300, 1.0 / 3.0, 2.0),
        ],
        vec![f64::MIN_POSITIVE, 1e300],
    )
    .unwrap();
    let back = Scene::from_json_str(&scene.to_json()).unwrap();
    assert_eq!(back, scene);
}

#[test]
fn set_power_validates_and_leaves_the_scene_unchanged_on_error() {
    let mut scene = Scene::preset("worked-example").unwrap();
    scene.set_power(1, 7.5).unwrap();
    assert_eq!(scene.powers.as_slice(), &[2.0, 7.5, 20.0]);
    // 1e308 alone is fine (2 + 7.5 + 1e308 rounds to 1e308); a second one overflows.
    scene.set_power(2, 1e308).unwrap();
    let before = scene.clone();
    let e = scene.set_power(1, 1e308).unwrap_err();
    assert!(matches!(e, SceneError::TotalPowerOverflow { .. }), "{e:?}");
    let e = scene.set_power(0, -1.0).unwrap_err();
    assert_eq!(e.to_string(), "lights[0].power: negative (-1)");
    let e = scene.set_power(3, 1.0).unwrap_err();
    assert_eq!(e.to_string(), "lights[3]: no such light (3 lights)");
    assert_eq!(scene, before);
    let mut single =
        Scene::from_parts("one", unit_plane(), vec![dvec3(0.0, 0.0, 1.0)], vec![1.0]).unwrap();
    let e = single.set_power(0, 0.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "lights: all 1 powers are zero: nothing emits light"
    );
}
