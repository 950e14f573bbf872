//! The built-in presets: each loads under its name with the lights it promises.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::dvec2;
use lightpick_core::scene::{PRESET_NAMES, Scene};

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
fn worked_example_preset_has_powers_2_5_20() {
    let scene = Scene::preset("worked-example").unwrap();
    assert_eq!(scene.name, "worked-example");
    assert_eq!(scene.powers.as_slice(), &[2.0, 5.0, 20.0]);
    assert!(scene.positions.iter().all(|p| p[2] > 0.0));
}

/// The former name still opens it (saved sessions and scripts use it), and is no preset of
/// its own in the list.
#[test]
fn former_name_seed_opens_the_worked_example() {
    assert_eq!(
        Scene::preset("seed").unwrap(),
        Scene::preset("worked-example").unwrap()
    );
    assert_eq!(
        Scene::preset_source("seed"),
        Scene::preset_source("worked-example")
    );
    assert!(!lightpick_core::scene::PRESET_NAMES.contains(&"seed"));
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
