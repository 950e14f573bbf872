//! What the class reads is right: comparisons worded with a factor of at least one and the
//! right direction, sentences whose figures follow the scene, equal time that is equal time,
//! one name for the Trade window, the walkthrough kept at its step, and figures printed with
//! the digits that show their difference.

use lightpick::app::state::BudgetMode;
use lightpick::app::state::estimator::EstimatorPoint;
use lightpick::app::{LightpickApp, PanelKind};
use lightpick::numbers;
use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::pixel_center;

use crate::common::painted::{painted, seed_with_inspector};
use crate::common::{click, panel, shows, shows_containing, step_paused, window};

/// Each "N× word" in `text` whose word is a direction: the factor must be at least 1.
fn assert_factors_at_least_one(text: &str) {
    for (at, _) in text.match_indices("× ") {
        let word: String = text[at + "× ".len()..]
            .chars()
            .take_while(char::is_ascii_alphabetic)
            .collect();
        if !["higher", "lower", "more", "fewer"].contains(&word.as_str()) {
            continue;
        }
        let factor: String = text[..at]
            .chars()
            .rev()
            .take_while(|c| c.is_ascii_digit() || *c == '.')
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .collect();
        let factor: f64 = factor
            .parse()
            .unwrap_or_else(|_| panic!("'{factor}' before × in {text}"));
        assert!(factor >= 1.0, "'{factor}× {word}' in: {text}");
    }
}

#[test]
fn the_inspector_says_higher_where_power_sampling_is_worse() {
    let mut harness = seed_with_inspector([1560.0, 960.0]);
    // A pixel where power picking loses to uniform: under the weak lights, far from light 3.
    let state = &harness.state().state;
    let scene = std::sync::Arc::clone(&state.built.scene);
    let worst = (0..scene.plane.height)
        .flat_map(|y| (0..scene.plane.width).map(move |x| [x, y]))
        .max_by(|a, b| {
            let ratio = |p: &[u32; 2]| {
                let i = PointInspection::at(&scene, pixel_center(&scene.plane, p[0], p[1]));
                i.power_relative_variance / i.uniform_relative_variance
            };
            ratio(a).total_cmp(&ratio(b))
        })
        .expect("pixels");
    harness.state_mut().state.inspector.pixel = Some(worst);
    harness.run();
    let inspection = PointInspection::at(&scene, pixel_center(&scene.plane, worst[0], worst[1]));
    assert!(
        inspection.power_relative_variance > inspection.uniform_relative_variance,
        "the seed has pixels where power picking is worse"
    );
    let expected = numbers::compare(
        inspection.power_relative_variance,
        inspection.uniform_relative_variance,
        "higher",
        "lower",
    );
    assert!(expected.ends_with("× higher"), "{expected}");
    assert!(shows(&harness, &expected), "{expected} is not shown");
    assert!(shows(&harness, "variance vs uniform"));
    assert_factors_at_least_one(&painted(&harness));
}

#[test]
fn the_estimator_counts_samples_in_fewer_with_a_factor_above_one() {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness
        .state_mut()
        .state
        .estimator
        .open_at(EstimatorPoint::WorkedExample);
    harness.run();
    // 366 against 14.85 at the worked example's point: importance needs 24.6× fewer samples.
    assert!(shows(&harness, "24.6× fewer"), "{}", painted(&harness));
    assert!(shows(&harness, "samples vs uniform"));
    assert!(!shows_containing(&harness, "fewer than uniform"));
    assert_factors_at_least_one(&painted(&harness));
}

#[test]
fn the_sentence_under_the_images_follows_an_edit() {
    let mut harness = panel(
        PanelKind::Images,
        LightpickApp::for_tests(),
        [1200.0, 800.0],
    );
    harness.run();
    step_paused(&mut harness, 1);
    let text = painted(&harness);
    assert!(
        text.contains("24.6× lower than uniform's (14.85 against 366.0)"),
        "{text}"
    );
    let state = &mut harness.state_mut().state;
    state.edit.powers_mut()[0] = 7.0;
    state.powers_changed();
    harness.run();
    step_paused(&mut harness, 1);
    let text = painted(&harness);
    assert!(
        text.contains("14.2× lower than uniform's (21.35 against 303.5)"),
        "{text}"
    );
    assert!(
        !text.contains("24.6"),
        "a figure of the old scene is left: {text}"
    );
}

#[test]
fn every_preset_gets_its_sentence_from_its_own_scene() {
    for (preset, words) in [
        ("grid", "same power"),
        ("dominant", "holds"),
        ("heavy-tail", "brightest"),
        ("stage", "Spots"),
        ("equal", "same power"),
    ] {
        let mut harness = panel(
            PanelKind::Images,
            LightpickApp::for_tests_on(preset),
            [1200.0, 800.0],
        );
        harness.run();
        step_paused(&mut harness, 1);
        let sentence = harness
            .state()
            .state
            .current_scene_sentence()
            .expect("the sentence of the current scene")
            .clone();
        assert_eq!(sentence.generation, harness.state().state.built.generation);
        assert!(sentence.text.contains(words), "{preset}: {}", sentence.text);
        assert!(shows(&harness, &sentence.text), "{preset}: not on screen");
        assert_factors_at_least_one(&sentence.text);
        // The winner it names has the least variance of the three it computed.
        let [u, p, s] = sentence.variances;
        let least = u.min(p).min(s);
        let named = if s == least {
            "here: spatial"
        } else if p == least {
            "here: power"
        } else {
            "here: uniform"
        };
        assert!(sentence.text.contains(named), "{preset}: {}", sentence.text);
    }
    // On grid, power is no better than uniform and spatial wins by a wide margin.
    let mut harness = panel(
        PanelKind::Images,
        LightpickApp::for_tests_on("grid"),
        [1200.0, 800.0],
    );
    harness.run();
    let [u, p, s] = harness
        .state()
        .state
        .current_scene_sentence()
        .expect("sentence")
        .variances;
    assert!(
        (p / u - 1.0).abs() < 1e-9,
        "equal powers: power is uniform ({p} vs {u})"
    );
    assert!(s < p / 10.0, "spatial {s} vs power {p}");
}

#[test]
fn equal_time_gives_every_scheme_the_same_seconds_and_different_samples() {
    let mut app = LightpickApp::for_tests();
    app.state.settings.budget = BudgetMode::EqualTime;
    let mut harness = panel(PanelKind::Images, app, [1200.0, 800.0]);
    harness.run();
    step_paused(&mut harness, 6);
    let published = harness.state_mut().published().expect("a frame");
    let images = [&published.uniform, &published.power, &published.spatial];
    let seconds: Vec<f64> = images.iter().map(|i| i.seconds).collect();
    let pixels = (published.width * published.height) as f64;
    // Each total within one pass of the dearest scheme (spatial: 40 ns per pixel sample in
    // the inline engine's virtual time) of the others.
    let pass = pixels * 4.0e-8;
    let spread = seconds.iter().copied().fold(f64::MIN, f64::max)
        - seconds.iter().copied().fold(f64::MAX, f64::min);
    assert!(
        spread <= pass * (1.0 + 1e-9),
        "{seconds:?} spread {spread} > {pass}"
    );
    // The cheaper schemes got more samples per pixel: uniform 4×, alias 3.2× spatial's.
    let spp: Vec<u32> = images.iter().map(|i| i.spp).collect();
    assert!(spp[0] > spp[1] && spp[1] > spp[2], "{spp:?}");
    assert!(spp[2] >= 1);
    for image in images {
        let label = format!("spp {}", image.spp);
        assert!(shows_containing(&harness, &label), "{label} not shown");
    }
}

#[test]
fn the_menu_names_the_trade_window_as_the_readme_does() {
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    click(&mut harness, "View");
    assert!(shows(&harness, "Trade"));
    assert!(!shows_containing(&harness, "Speed against accuracy"));
    let readme = include_str!("../../../../README.md");
    assert!(readme.contains("View → **Trade**") || readme.contains("View → Trade"));
}

#[test]
fn classic_powers_keep_the_walkthrough_at_its_step() {
    let mut app = LightpickApp::for_tests();
    app.state.edit.powers_mut()[0] = 7.0;
    app.state.powers_changed();
    app.state.settings.show_walkthrough = true;
    let mut harness = window(app, [1560.0, 960.0]);
    harness.run();
    for _ in 0..8 {
        click(&mut harness, "Next →");
    }
    assert_eq!(harness.state().state.walkthrough.step, 8);
    click(&mut harness, "Classic powers 2, 5, 20");
    assert_eq!(
        harness.state().state.built.scene.powers.as_slice(),
        [2.0, 5.0, 20.0]
    );
    assert_eq!(
        harness.state().state.walkthrough.step,
        8,
        "the class stays at step 9"
    );
    assert!(shows(&harness, "Step 9 of 9"));
}

#[test]
fn precision_prints_both_column_ratios_with_the_same_digits() {
    let mut app = LightpickApp::for_tests();
    app.state.settings.show_precision = true;
    let mut harness = window(app, [1560.0, 960.0]);
    harness.run();
    harness.run();
    let measured = harness
        .state()
        .state
        .precision
        .result
        .clone()
        .expect("measured inline");
    let ratios = [
        measured.multiply_high.as_ref().expect("n").max_min_ratio,
        measured.f32_pick.as_ref().expect("n").max_min_ratio,
    ];
    let [a, b] = numbers::near_one(ratios);
    assert_eq!(a.len(), b.len());
    assert_ne!(
        a, b,
        "the two picks differ at N = 3 and the digits must show it"
    );
    assert!(shows(&harness, &a), "{a}");
    assert!(shows(&harness, &b), "{b}");
}
