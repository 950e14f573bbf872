//! Scene files: the JSON format, every `SceneError` variant, the presets and the generator.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::{DVec3, dvec2, dvec3};
use lightpick_core::scene::{
    Generator, MAX_LIGHTS, PRESET_NAMES, Placement, PowerDistribution, ReceiverPlane, Scene,
    SceneError,
};

const PLANE: &str = r#""plane": { "min": [-1, -1], "max": [1, 1], "width": 8, "height": 4 }"#;

fn lights_scene(lights: &str) -> String {
    format!(r#"{{ "name": "t", {PLANE}, "lights": [{lights}] }}"#)
}

fn generator_scene(generator_body: &str) -> String {
    format!(r#"{{ "name": "g", {PLANE}, "generator": {{ {generator_body} }} }}"#)
}

const PLACEMENT: &str = r#""placement": { "min": [-1, -1, 0.1], "max": [1, 1, 1] }"#;

fn err(text: &str) -> SceneError {
    match Scene::from_json_str(text) {
        Ok(scene) => panic!("accepted: {scene:?}"),
        Err(e) => e,
    }
}

fn unit_plane() -> ReceiverPlane {
    ReceiverPlane {
        min: dvec2(-1.0, -1.0),
        max: dvec2(1.0, 1.0),
        width: 4,
        height: 4,
    }
}

// ---------------------------------------------------------------- format and round trip

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

// ---------------------------------------------------------------- every error variant

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
    std::fs::write(&path, Scene::preset("seed").unwrap().to_json()).unwrap();
    let scene = Scene::load(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert_eq!(scene, Scene::preset("seed").unwrap());
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
        "unknown preset 'nope' (expected one of: seed, equal, dominant, zeros, heavy-tail, million, extreme-range, grid, stage, gallery)"
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

// ---------------------------------------------------------------- presets

#[test]
fn every_preset_loads_with_its_name() {
    for name in PRESET_NAMES {
        let scene = Scene::preset(name).unwrap();
        assert_eq!(scene.name, name);
        assert_eq!(scene.positions.len(), scene.powers.len());
        assert!(Scene::preset_source(name).is_some());
    }
}

#[test]
fn seed_preset_has_powers_2_5_20() {
    let scene = Scene::preset("seed").unwrap();
    assert_eq!(scene.powers.as_slice(), &[2.0, 5.0, 20.0]);
    assert!(scene.positions.iter().all(|p| p[2] > 0.0));
}

#[test]
fn equal_preset_has_equal_powers() {
    let scene = Scene::preset("equal").unwrap();
    let first = scene.powers.as_slice()[0];
    assert!(scene.light_count() > 1);
    assert!(scene.powers.as_slice().iter().all(|&p| p == first));
}

#[test]
fn dominant_preset_has_one_light_a_million_times_the_rest() {
    let scene = Scene::preset("dominant").unwrap();
    let powers = scene.powers.as_slice();
    let max = scene.powers.max();
    let brightest: Vec<usize> = (0..powers.len()).filter(|&i| powers[i] == max).collect();
    assert_eq!(brightest.len(), 1);
    for (i, &p) in powers.iter().enumerate() {
        if i != brightest[0] {
            assert_eq!(max, 1e6 * p, "light {i}");
        }
    }
}

#[test]
fn zeros_preset_has_exactly_half_its_lights_at_zero() {
    let scene = Scene::preset("zeros").unwrap();
    let n = scene.light_count();
    let zeros = scene
        .powers
        .as_slice()
        .iter()
        .filter(|&&p| p == 0.0)
        .count();
    assert_eq!(n % 2, 0);
    assert_eq!(zeros, n / 2);
    assert!(
        scene
            .powers
            .as_slice()
            .iter()
            .filter(|&&p| p > 0.0)
            .all(|&p| (0.5..2.0).contains(&p))
    );
}

#[test]
fn heavy_tail_preset_is_pareto_with_10k_lights() {
    let scene = Scene::preset("heavy-tail").unwrap();
    assert_eq!(scene.light_count(), 10_000);
    let powers = scene.powers.as_slice();
    // Pareto(scale 1): every power ≥ 1, and P(X > t) = t^-1.2, so among 10^4 draws the
    // maximum exceeds 10^4^(1/1.2)/10 ≈ 215 unless (1 − 215^-1.2)^10^4 ≈ e^-16 happens.
    assert!(powers.iter().all(|&p| p >= 1.0));
    assert!(scene.powers.max() > 215.0, "{}", scene.powers.max());
}

#[test]
fn million_preset_has_a_million_lights() {
    let scene = Scene::preset("million").unwrap();
    assert_eq!(scene.light_count(), 1_000_000);
    assert_eq!((scene.plane.width, scene.plane.height), (512, 512));
    assert!(scene.powers.as_slice().iter().all(|&p| p >= 0.0));
}

#[test]
fn extreme_range_preset_spans_1e_minus_30_to_1e30() {
    let scene = Scene::preset("extreme-range").unwrap();
    let powers = scene.powers.as_slice();
    let min = powers.iter().copied().fold(f64::INFINITY, f64::min);
    let max = scene.powers.max();
    assert!(min >= 1e-30 && max <= 1e30, "{min} {max}");
    // 4096 log-uniform draws over 60 decades: the extremes lie within one decade of the
    // ends unless (1 − 1/60)^4096 ≈ 10^-30 happens.
    assert!(min < 1e-29, "{min}");
    assert!(max > 1e29, "{max}");
    assert!(scene.powers.total().is_finite());
}

#[test]
fn grid_preset_is_1024_unit_lights_low_over_a_16_by_16_plane() {
    let scene = Scene::preset("grid").unwrap();
    assert_eq!(scene.name, "grid");
    assert_eq!(scene.light_count(), 1024);
    assert_eq!(
        (scene.plane.min, scene.plane.max),
        (dvec2(-8.0, -8.0), dvec2(8.0, 8.0))
    );
    assert_eq!((scene.plane.width, scene.plane.height), (256, 256));
    assert!(scene.powers.as_slice().iter().all(|&p| p == 1.0));
    for (i, p) in scene.positions.iter().enumerate() {
        assert!(
            (-8.0..=8.0).contains(&p[0]) && (-8.0..=8.0).contains(&p[1]),
            "light {i}: {p:?}"
        );
        assert!((0.2..=0.4).contains(&p[2]), "light {i}: {p:?}");
    }
    // The lights fill the plane: every 4 × 4 quarter-block of it holds some. 1024 uniform
    // points in 16 cells of 1/16 each: a given cell is empty with probability
    // (15/16)^1024 ≈ 1e-29.
    for cell in 0..16 {
        let (cx, cy) = (
            f64::from(cell % 4) * 4.0 - 8.0,
            f64::from(cell / 4) * 4.0 - 8.0,
        );
        assert!(
            scene
                .positions
                .iter()
                .any(|p| (cx..cx + 4.0).contains(&p[0]) && (cy..cy + 4.0).contains(&p[1])),
            "cell {cell} is empty"
        );
    }
}

// ---------------------------------------------------------------- generator

fn small_generator(seed: u64) -> Generator {
    Generator {
        count: 10_000,
        seed,
        power: PowerDistribution::Exponential { mean: 2.0 },
        zero_fraction: 0.0,
        dominant: None,
        placement: Placement {
            min: dvec3(-1.0, -2.0, 0.5),
            max: dvec3(1.0, 2.0, 0.75),
        },
    }
}

#[test]
fn generation_is_reproducible_and_seed_dependent() {
    let a = small_generator(9).generate().unwrap();
    let b = small_generator(9).generate().unwrap();
    let c = small_generator(10).generate().unwrap();
    assert_eq!(a, b);
    assert_ne!(a.0, c.0);
    assert_ne!(a.1, c.1);
}

#[test]
fn generation_does_not_depend_on_the_thread_count() {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| Scene::preset("heavy-tail").unwrap());
    let three = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| Scene::preset("heavy-tail").unwrap());
    assert_eq!(one, three);
}

#[test]
fn generated_positions_fill_the_placement_box() {
    let g = small_generator(3);
    let (positions, _) = g.generate().unwrap();
    for axis in 0..3 {
        let (lo, hi) = (g.placement.min[axis], g.placement.max[axis]);
        assert!(positions.iter().all(|p| (lo..hi).contains(&p[axis])));
        // The mean of 10^4 uniforms is within 5 standard deviations
        // ((hi − lo)/√12/100) of the centre.
        let mean = positions.iter().map(|p| p[axis]).sum::<f64>() / 1e4;
        let sd = (hi - lo) / 12f64.sqrt() / 100.0;
        assert!(
            (mean - f64::midpoint(lo, hi)).abs() < 5.0 * sd,
            "axis {axis}: {mean}"
        );
    }
}

#[test]
fn generated_powers_follow_their_distribution_means() {
    // Sample means of 10^4 draws within 5 standard errors of the exact mean
    // (uniform: (b−a)/√12, exponential: σ = mean; log-uniform on [1, e²]: mean (e²−1)/2,
    // second moment (e⁴−1)/4).
    let e2 = std::f64::consts::E.powi(2);
    let log_mean = (e2 - 1.0) / 2.0;
    let log_sd = ((e2 * e2 - 1.0) / 4.0 - log_mean * log_mean).sqrt();
    let cases = [
        (
            PowerDistribution::Uniform { min: 1.0, max: 3.0 },
            2.0,
            2.0 / 12f64.sqrt(),
        ),
        (PowerDistribution::Exponential { mean: 2.0 }, 2.0, 2.0),
        (
            PowerDistribution::LogUniform { min: 1.0, max: e2 },
            log_mean,
            log_sd,
        ),
        (PowerDistribution::Constant { value: 4.0 }, 4.0, 0.0),
    ];
    for (power, mean, sd) in cases {
        let g = Generator {
            power: power.clone(),
            ..small_generator(5)
        };
        let (_, powers) = g.generate().unwrap();
        let sample_mean = powers.iter().sum::<f64>() / powers.len() as f64;
        assert!(
            (sample_mean - mean).abs() <= 5.0 * sd / 100.0,
            "{power:?}: {sample_mean} vs {mean}"
        );
    }
}

#[test]
fn dominant_light_is_exempt_from_zeroing() {
    let g = Generator {
        power: PowerDistribution::Constant { value: 1.0 },
        zero_fraction: 0.5,
        dominant: Some(lightpick_core::scene::Dominant {
            index: 1,
            factor: 1e6,
        }),
        ..small_generator(1)
    };
    let (_, powers) = g.generate().unwrap();
    assert_eq!(powers[1], 1e6);
    // Light 1 would have been zeroed (⌊2·0.5⌋ > ⌊1·0.5⌋): one zero fewer than ⌊N/2⌋.
    assert_eq!(powers.iter().filter(|&&p| p == 0.0).count(), 4999);
}

#[test]
fn unknown_distribution_parameters_are_refused() {
    let e = err(&generator_scene(&format!(
        r#""count": 4, "seed": 1, "power": {{ "distribution": "pareto", "scale": 1, "shape": 2, "mean": 3 }}, {PLACEMENT}"#
    )));
    assert!(e.to_string().contains("unknown field `mean`"), "{e}");
    assert_eq!(e.field(), Some("generator.power"));
}

#[test]
fn set_power_validates_and_leaves_the_scene_unchanged_on_error() {
    let mut scene = Scene::preset("seed").unwrap();
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
