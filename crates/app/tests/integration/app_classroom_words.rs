//! What the class reads is right: comparisons worded with a factor of at least one and the
//! right direction, sentences whose figures follow the scene, equal time that is equal time,
//! one name for the Trade window, windows in front of what opened them and beside what they
//! explain, sliders that reach every integer, and no text smaller than the body text.

use egui::Shape;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::state::BudgetMode;
use lightpick::app::state::estimator::EstimatorPoint;
use lightpick::app::{LightpickApp, PanelKind};
use lightpick::numbers;
use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::pixel_center;

use crate::common::{click, panel, shows, shows_containing, step_paused, window};

/// Every piece of text painted in the last frame, with its font size in points.
fn painted_texts<S>(harness: &Harness<'_, S>) -> Vec<(String, f32)> {
    fn collect(shape: &Shape, out: &mut Vec<(String, f32)>) {
        match shape {
            Shape::Text(text) => {
                let job = &text.galley.job;
                for section in &job.sections {
                    let range = section.byte_range.start.0..section.byte_range.end.0;
                    let words = job.text[range].trim();
                    if !words.is_empty() {
                        out.push((words.to_owned(), section.format.font_id.size));
                    }
                }
            }
            Shape::Vec(shapes) => shapes.iter().for_each(|s| collect(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        collect(&clipped.shape, &mut out);
    }
    out
}

/// All the text painted in the last frame, joined.
fn painted<S>(harness: &Harness<'_, S>) -> String {
    painted_texts(harness)
        .into_iter()
        .map(|(t, _)| t)
        .collect::<Vec<_>>()
        .join("\n")
}

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

/// A primary click at `pos`.
fn click_at(harness: &mut Harness<'static, LightpickApp>, pos: egui::Pos2) {
    harness.hover_at(pos);
    for pressed in [true, false] {
        harness.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::default(),
        });
    }
    harness.run();
}

/// The whole app on the seed at `size`, one step rendered, a pixel of the importance image
/// clicked (the inspector opens).
fn seed_with_inspector(size: [f32; 2]) -> Harness<'static, LightpickApp> {
    let mut harness = window(LightpickApp::for_tests(), size);
    harness.run();
    step_paused(&mut harness, 1);
    let caption = harness.get_by_label("Importance (alias)").rect();
    click_at(
        &mut harness,
        egui::pos2(caption.left() + 30.0, caption.bottom() + 30.0),
    );
    assert!(
        harness.state().state.inspector.pixel.is_some(),
        "a pixel is inspected"
    );
    harness
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
        .open_at(EstimatorPoint::Seed);
    harness.run();
    // 366 against 14.85 at the seed's point: importance needs 24.6× fewer samples.
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
    let images = [
        &published.uniform,
        &published.importance,
        &published.spatial,
    ];
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
fn a_linear_slider_reaches_every_integer_power() {
    let mut harness = panel(PanelKind::Lights, LightpickApp::for_tests(), [900.0, 700.0]);
    harness.run();
    let max = harness.state().state.settings.slider_max;
    let rail = harness.get_by_label("power slider of light 1").rect();
    let mut reached = std::collections::BTreeSet::new();
    let steps = (rail.width() * 2.0) as usize;
    for k in 0..=steps {
        let x = rail.left() + rail.width() * k as f32 / steps as f32;
        click_at(&mut harness, egui::pos2(x, rail.center().y));
        let power = harness.state().state.edit.powers[0];
        if power.fract() == 0.0 {
            reached.insert(power as u64);
        }
    }
    let missing: Vec<u64> = (0..=max as u64).filter(|p| !reached.contains(p)).collect();
    assert!(
        missing.is_empty(),
        "powers no drag reaches on 0–{max}: {missing:?}"
    );
}

#[test]
fn a_window_opened_by_a_click_comes_to_the_front() {
    let mut harness = seed_with_inspector([1560.0, 960.0]);
    harness
        .get_by_label("Watch the estimate converge here")
        .click();
    // The estimator may run (it repaints every frame): a few frames, not "until idle".
    harness.run_steps(3);
    assert!(harness.state().state.estimator.open);
    // Back to front.
    let order = harness
        .ctx
        .memory(|m| m.layer_ids().map(|l| l.id).collect::<Vec<_>>());
    let at = |title: &str| {
        order
            .iter()
            .position(|id| *id == egui::Id::unique(Some(title)))
            .unwrap_or_else(|| panic!("{title} has no layer"))
    };
    assert!(
        at("Estimator at one point") > at("Pixel inspector"),
        "the estimator opened behind the inspector"
    );
    // The inspector closes; the estimator still speaks of its pixel, and the pixel stays
    // marked on the images (the chip).
    let pixel = harness.state().state.inspector.pixel.expect("pixel");
    harness.state_mut().state.inspector.pixel = None;
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.estimator.point,
        EstimatorPoint::Pixel(pixel)
    );
    assert!(shows_containing(
        &harness,
        &format!("pixel ({}, {})", pixel[0], pixel[1])
    ));
}

#[test]
fn the_stepper_and_precision_open_beside_the_table_at_1024x768() {
    let mut harness = window(LightpickApp::for_tests(), [1024.0, 768.0]);
    harness.run();
    let table = harness
        .state()
        .layout
        .placed
        .iter()
        .find(|(k, _)| *k == PanelKind::Table)
        .map(|(_, r)| *r)
        .expect("the table is shown at 1024×768");
    for title in ["Construction stepper", "Precision"] {
        let settings = &mut harness.state_mut().state.settings;
        if title == "Precision" {
            settings.show_precision = true;
        } else {
            settings.show_stepper = true;
        }
        harness.run();
        harness.run();
        let rect = harness
            .ctx
            .memory(|m| m.area_rect(egui::Id::unique(Some(title))))
            .unwrap_or_else(|| {
                let layers = harness.ctx.memory(|m| m.layer_ids().collect::<Vec<_>>());
                panic!(
                    "{title} is open; layers {layers:?} vs {:?}",
                    egui::Id::unique(Some(title))
                )
            });
        let overlap = rect.intersect(table);
        let covered = if overlap.is_positive() {
            overlap.area() / table.area()
        } else {
            0.0
        };
        assert!(
            covered < 0.1,
            "{title} at {rect:?} covers {covered:.2} of the table {table:?}"
        );
    }
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

#[test]
fn no_text_is_smaller_than_the_body_text_and_the_zoom_scales_it() {
    for size in [[1024.0, 768.0], [1600.0, 1000.0]] {
        let mut harness = window(LightpickApp::for_tests(), size);
        harness.run();
        step_paused(&mut harness, 1);
        let state = &mut harness.state_mut().state;
        state.inspector.pixel = Some([10, 12]);
        state.settings.show_trade = true;
        state.settings.show_precision = true;
        state.settings.show_walkthrough = true;
        state.settings.show_stepper = true;
        state.estimator.open_at(EstimatorPoint::Seed);
        harness.run();
        step_paused(&mut harness, 1);
        let body = egui::TextStyle::Body
            .resolve(&harness.ctx.global_style())
            .size;
        let texts = painted_texts(&harness);
        assert!(texts.len() > 100, "{} texts painted", texts.len());
        let small: Vec<&(String, f32)> = texts.iter().filter(|(_, s)| *s < body).collect();
        assert!(
            small.is_empty(),
            "smaller than body text ({body}) at {size:?}: {small:?}"
        );
    }
    // Ctrl + zooms everything: the points stay, each point gets more pixels.
    let mut harness = window(LightpickApp::for_tests(), [1024.0, 768.0]);
    harness.run();
    let before = harness.ctx.zoom_factor();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Plus);
    harness.run();
    assert!(harness.ctx.zoom_factor() > before, "Ctrl + does not zoom");
}

/// Where each painted text stands: its words and the rectangle it covers.
fn painted_rects(harness: &Harness<'_, LightpickApp>) -> Vec<(String, egui::Rect)> {
    fn collect(shape: &Shape, out: &mut Vec<(String, egui::Rect)>) {
        match shape {
            Shape::Text(text) => out.push((
                text.galley.job.text.trim().to_owned(),
                text.galley.rect.translate(text.pos.to_vec2()),
            )),
            Shape::Vec(shapes) => shapes.iter().for_each(|s| collect(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        collect(&clipped.shape, &mut out);
    }
    out
}

#[test]
fn the_one_over_n_label_stays_above_zero_on_a_one_sided_scene() {
    let mut harness = panel(
        PanelKind::Table,
        LightpickApp::for_tests_on("dominant"),
        [700.0, 520.0],
    );
    harness.run();
    let texts = painted_rects(&harness);
    let at = |label: &str| {
        texts
            .iter()
            .find(|(t, _)| t == label)
            .map_or_else(|| panic!("'{label}' is not painted"), |(_, r)| *r)
    };
    let (one_over_n, zero) = (at("1/N"), at("0"));
    assert!(
        one_over_n.bottom() <= zero.top() + 1.0,
        "1/N at {one_over_n:?} overlaps or falls below 0 at {zero:?}"
    );
}

#[test]
fn a_large_scene_shows_no_example_powers_in_the_field() {
    let mut harness = panel(PanelKind::Lights, LightpickApp::for_tests(), [900.0, 700.0]);
    harness.run();
    assert_eq!(harness.state().state.powers_text, "2, 5, 20");
    harness.state_mut().state.generate(2000);
    harness.run();
    assert!(harness.state().state.powers_text.is_empty());
    let text = painted(&harness);
    assert!(text.contains("2000 lights, too many to list"), "{text}");
    assert!(
        !text.contains("2, 5, 20"),
        "example powers look like the scene's: {text}"
    );
}

#[test]
fn the_status_bar_says_paused_instead_of_a_frame_time() {
    let mut state = lightpick::app::AppState::seed();
    state.settings.paused = true;
    let mut harness = Harness::new_ui_state(
        |ui, state: &mut lightpick::app::AppState| {
            lightpick::app::panels::controls_ui::status_ui(ui, state, "CPU renderer", Some(6069.3));
        },
        state,
    );
    harness.run();
    let text = painted(&harness);
    assert!(
        text.contains("paused") && !text.contains("ms/frame"),
        "{text}"
    );
    harness.state_mut().settings.paused = false;
    harness.run();
    assert!(painted(&harness).contains("6069.3 ms/frame"));
}

#[test]
fn file_open_starts_in_the_last_folder_with_no_name_filled_in() {
    use lightpick::app::state::FileAction;
    let dir = crate::common::scratch("open-folder");
    let path = dir.join("kept.json");
    let mut harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    harness.run();
    let text = path.to_str().expect("utf-8").to_owned();
    harness
        .state_mut()
        .file_action(FileAction::SaveScene, &text, None);
    harness
        .state_mut()
        .file_action(FileAction::OpenScene, &text, None);
    let state = &mut harness.state_mut().state;
    assert_eq!(state.file_dialog.folder.as_deref(), Some(dir.as_path()));
    assert_eq!(state.settings.last_folder.as_deref(), Some(dir.as_path()));
    lightpick::app::panels::controls_ui::open_dialog(state, FileAction::OpenScene);
    assert_eq!(state.file_dialog.path, "", "no file name pre-filled");
    // The next session starts there too.
    let settings = state.settings.clone();
    let next = lightpick::app::AppState::new(lightpick::app::scene_io::seed_scene(), settings);
    assert_eq!(next.file_dialog.folder.as_deref(), Some(dir.as_path()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The widths of the textured rectangles (the images) painted in the last frame.
fn image_widths(harness: &Harness<'_, LightpickApp>) -> Vec<f32> {
    fn collect(shape: &Shape, out: &mut Vec<f32>) {
        match shape {
            Shape::Mesh(mesh) if mesh.texture_id != egui::TextureId::default() => {
                let rect = egui::Rect::from_points(
                    &mesh.vertices.iter().map(|v| v.pos).collect::<Vec<_>>(),
                );
                out.push(rect.width());
            }
            Shape::Rect(rect) if rect.fill_texture_id() != egui::TextureId::default() => {
                out.push(rect.rect.width());
            }
            Shape::Vec(shapes) => shapes.iter().for_each(|s| collect(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        collect(&clipped.shape, &mut out);
    }
    out
}

#[test]
fn the_images_stay_readable_on_a_projector_and_when_zoomed() {
    let mut harness = window(LightpickApp::for_tests(), [1024.0, 768.0]);
    harness.run();
    click(&mut harness, "Images");
    step_paused(&mut harness, 1);
    let widths = image_widths(&harness);
    assert!(
        widths.len() >= 6,
        "images and error maps painted: {widths:?}"
    );
    let narrowest = widths.iter().copied().fold(f32::MAX, f32::min);
    assert!(
        narrowest >= 160.0,
        "images {narrowest} points wide at 1024×768: {widths:?}"
    );
    assert!(shows_containing(&harness, "The reference is hidden"));
    // Ctrl + (110 %): the text grows; the panel has fewer points, and the three images
    // keep at least 140 pixels (they were 125 with four abreast before any zoom).
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Plus);
    harness.run();
    step_paused(&mut harness, 1);
    let zoomed = image_widths(&harness)
        .iter()
        .copied()
        .fold(f32::MAX, f32::min);
    let pixels = zoomed * harness.ctx.pixels_per_point();
    assert!(
        pixels >= 140.0,
        "zoomed in, the images are {pixels} px wide"
    );
}
