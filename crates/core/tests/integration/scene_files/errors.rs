//! Every `SceneError` variant, each naming its field.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::{DVec3, dvec3};
use lightpick_core::scene::{MAX_LIGHTS, Scene, SceneError};

use super::{PLACEMENT, PLANE, err, generator_scene, lights_scene, unit_plane};

#[test]
fn io_error_names_the_file() {
    let e = Scene::load("/nonexistent/dir/scene.json").unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }), "{e:?}");
    assert!(
        e.to_string()
            .starts_with("cannot read scene file '/nonexistent/dir/scene.json'"),
        "{e}"
    );
}

#[test]
fn load_reads_a_file() {
    let path = std::env::temp_dir().join(format!("lightpick-scene-{}.json", std::process::id()));
    std::fs::write(&path, Scene::preset("worked-example").unwrap().to_json()).unwrap();
    let scene = Scene::load(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(scene, Scene::preset("worked-example").unwrap());
}

#[test]
fn malformed_json_reports_line_and_column() {
    let text = "{\n  \"name\": \"x\",\n  \"plane\": { \"min\": [0, 0], oops }\n}";
    let e = err(text);
    match &e {
        SceneError::Json { line, column, .. } => {
            assert_eq!(*line, 3);
            assert_eq!(*column, 29); // the `o` of `oops`
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("(line 3, column 29)"), "{e}");
}

#[test]
fn wrong_types_name_the_field_path() {
    let e = err(&lights_scene(
        r#"{ "position": [0, 0, 1], "power": 1 }, { "position": [0, 0, 1], "power": "bright" }"#,
    ));
    assert!(matches!(e, SceneError::Json { .. }), "{e:?}");
    assert!(
        e.to_string().starts_with("lights[1].power: invalid type"),
        "{e}"
    );

    let e = err(
        r#"{ "plane": { "min": [0, 0], "max": [1, 1], "width": -3, "height": 4 }, "lights": [] }"#,
    );
    assert!(
        e.to_string().starts_with("plane.width: invalid value"),
        "{e}"
    );

    let e = err(&lights_scene(r#"{ "position": [0, 1], "power": 1 }"#));
    assert!(
        e.to_string()
            .starts_with("lights[0].position: invalid length 2"),
        "{e}"
    );
}

#[test]
fn unknown_and_missing_fields_are_refused() {
    let e = err(&lights_scene(
        r#"{ "position": [0, 0, 1], "power": 1, "colour": 3 }"#,
    ));
    assert!(e.to_string().contains("unknown field `colour`"), "{e}");
    let e = err(r#"{ "lights": [{ "position": [0, 0, 1], "power": 1 }] }"#);
    assert!(e.to_string().contains("missing field `plane`"), "{e}");
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "gaussian", "mean": 1 }}, {PLACEMENT}"#
    )));
    assert!(
        e.to_string()
            .starts_with("generator.power.distribution: unknown variant `gaussian`"),
        "{e}"
    );
}

#[test]
fn trailing_characters_are_refused() {
    let text = lights_scene(r#"{ "position": [0, 0, 1], "power": 1 }"#) + " }";
    assert!(matches!(err(&text), SceneError::Json { .. }));
}

#[test]
fn unknown_preset_lists_the_known_ones() {
    let e = Scene::preset("nope").unwrap_err();
    assert!(matches!(e, SceneError::UnknownPreset { .. }));
    assert_eq!(
        e.to_string(),
        "unknown preset 'nope' (expected one of: worked-example, equal, dominant, zeros, heavy-tail, million, extreme-range, grid, stage, gallery)"
    );
}

#[test]
fn absurd_sizes_are_out_of_range() {
    let plane = |w: u64, h: u64| {
        format!(
            r#"{{ "plane": {{ "min": [0, 0], "max": [1, 1], "width": {w}, "height": {h} }}, "lights": [{{ "position": [0, 0, 1], "power": 1 }}] }}"#
        )
    };
    let e = err(&plane(0, 4));
    assert!(matches!(e, SceneError::OutOfRange { .. }));
    assert_eq!(
        e.to_string(),
        "plane.width: must be between 1 and 16384 (got 0)"
    );
    let e = err(&plane(4, 100_000_000_000));
    assert_eq!(
        e.to_string(),
        "plane.height: must be between 1 and 16384 (got 100000000000)"
    );
    // Both sides allowed, the product not.
    let e = err(&plane(16384, 16384));
    assert_eq!(
        e.to_string(),
        "plane: 16384 × 16384 = 268435456 pixels exceed the limit of 67108864"
    );

    let e = err(&generator_scene(&format!(
        r#""count": 0, "seed": 1, "power": {{ "distribution": "constant", "value": 1 }}, {PLACEMENT}"#
    )));
    assert_eq!(
        e.to_string(),
        "generator.count: must be between 1 and 16777216 (got 0)"
    );
    let e = err(&generator_scene(&format!(
        r#""count": {}, "seed": 1, "power": {{ "distribution": "constant", "value": 1 }}, {PLACEMENT}"#,
        MAX_LIGHTS + 1
    )));
    assert!(
        e.to_string()
            .starts_with("generator.count: must be between 1 and 16777216"),
        "{e}"
    );

    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "constant", "value": 1 }}, "zero_fraction": 1, {PLACEMENT}"#
    )));
    assert_eq!(
        e.to_string(),
        "generator.zero_fraction: must be between 0 and 1 (exclusive) (got 1)"
    );
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "constant", "value": 1 }}, "dominant": {{ "index": 4, "factor": 10 }}, {PLACEMENT}"#
    )));
    assert_eq!(
        e.to_string(),
        "generator.dominant.index: must be between 0 and 3 (got 4)"
    );
}

#[test]
fn non_finite_values_are_named() {
    let e = Scene::from_parts(
        "nan",
        unit_plane(),
        vec![dvec3(0.0, 0.0, 1.0), dvec3(0.0, f64::NAN, 1.0)],
        vec![1.0, 1.0],
    )
    .unwrap_err();
    assert!(matches!(e, SceneError::NotFinite { .. }));
    assert_eq!(e.to_string(), "lights[1].position[1]: not finite (NaN)");

    let e =
        Scene::from_parts("inf", unit_plane(), vec![DVec3::ZERO], vec![f64::INFINITY]).unwrap_err();
    assert_eq!(e.to_string(), "lights[0].power: not finite (inf)");

    let mut plane = unit_plane();
    plane.max[0] = f64::INFINITY;
    let e = Scene::from_parts("p", plane, vec![DVec3::ZERO], vec![1.0]).unwrap_err();
    assert_eq!(e.to_string(), "plane.max[0]: not finite (inf)");

    // JSON has no infinity: an overflowing literal is a parse error at its field.
    let e = err(&lights_scene(
        r#"{ "position": [0, 0, 1e999], "power": 1 }"#,
    ));
    assert!(
        e.to_string()
            .starts_with("lights[0].position[2]: number out of range"),
        "{e}"
    );
}

#[test]
fn negative_power_names_its_light() {
    let e = err(&lights_scene(
        r#"{ "position": [0, 0, 1], "power": 1 }, { "position": [0, 0, 1], "power": 1 },
           { "position": [0, 0, 1], "power": 1 }, { "position": [0, 0, 1], "power": -1 }"#,
    ));
    assert!(matches!(e, SceneError::Negative { .. }));
    assert_eq!(e.to_string(), "lights[3].power: negative (-1)");
    assert_eq!(e.field(), Some("lights[3].power"));

    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "uniform", "min": -1, "max": 1 }}, {PLACEMENT}"#
    )));
    assert_eq!(e.to_string(), "generator.power.min: negative (-1)");
}

#[test]
fn structural_problems_are_invalid() {
    let both = format!(
        r#"{{ {PLANE}, "lights": [{{ "position": [0, 0, 1], "power": 1 }}], "generator": {{ "count": 4, "seed": 1, "power": {{ "distribution": "constant", "value": 1 }}, {PLACEMENT} }} }}"#
    );
    let e = err(&both);
    assert!(matches!(e, SceneError::Invalid { .. }));
    assert_eq!(
        e.to_string(),
        ".: give either \"lights\" or \"generator\", not both"
    );
    let e = err(&format!("{{ {PLANE} }}"));
    assert_eq!(
        e.to_string(),
        ".: missing light source: give \"lights\" or \"generator\""
    );
    let e = err(&lights_scene(""));
    assert_eq!(e.to_string(), "lights: no lights");
    let e = err(
        r#"{ "plane": { "min": [0, 0], "max": [1, 0], "width": 4, "height": 4 }, "lights": [{ "position": [0, 0, 1], "power": 1 }] }"#,
    );
    assert_eq!(
        e.to_string(),
        "plane.max[1]: must be greater than plane.min[1] (0 ≤ 0)"
    );
    let e = err(&generator_scene(
        r#""count": 4, "seed": 1, "power": { "distribution": "constant", "value": 1 }, "placement": { "min": [0, 0, 2], "max": [1, 1, 1] }"#,
    ));
    assert_eq!(
        e.to_string(),
        "generator.placement.max[2]: must be at least placement.min[2] (1 < 2)"
    );
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "pareto", "scale": 1, "shape": 0 }}, {PLACEMENT}"#
    )));
    assert_eq!(
        e.to_string(),
        "generator.power.shape: must be positive (got 0)"
    );
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "log-uniform", "min": 10, "max": 1 }}, {PLACEMENT}"#
    )));
    assert_eq!(
        e.to_string(),
        "generator.power.max: must be at least min (1 < 10)"
    );
    let e = Scene::from_parts("x", unit_plane(), vec![DVec3::ZERO], vec![1.0, 2.0]).unwrap_err();
    assert_eq!(e.to_string(), "lights: 1 positions but 2 powers");
}

#[test]
fn all_zero_powers_are_refused() {
    let e = err(&lights_scene(
        r#"{ "position": [0, 0, 1], "power": 0 }, { "position": [0, 0, 1], "power": 0 }"#,
    ));
    assert!(matches!(e, SceneError::AllZero { .. }));
    assert_eq!(
        e.to_string(),
        "lights: all 2 powers are zero: nothing emits light"
    );
}

#[test]
fn overflowing_total_power_is_refused() {
    let e = err(&lights_scene(
        r#"{ "position": [0, 0, 1], "power": 1e308 }, { "position": [0, 0, 1], "power": 1e308 }"#,
    ));
    assert!(matches!(e, SceneError::TotalPowerOverflow { .. }));
    assert_eq!(
        e.to_string(),
        "lights: the total power of 2 lights overflows f64"
    );
    // A dominant factor that overflows one power is named by the generated light's index.
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "constant", "value": 1e300 }}, "dominant": {{ "index": 2, "factor": 1e10 }}, {PLACEMENT}"#
    )));
    assert_eq!(e.to_string(), "generator (light 2).power: not finite (inf)");
}
