//! Windows and text a class can read: a window opened by a click comes to the front and
//! opens beside what it explains, no text is smaller than the body text, the images stay
//! readable on a projector, labels never collide, and the status bar, the powers field and
//! the file dialog say what is true.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::state::estimator::EstimatorPoint;
use lightpick::app::{LightpickApp, PanelKind};

use crate::common::painted::{
    click_at, image_widths, painted, painted_rects, painted_texts, seed_with_inspector,
};
use crate::common::{click, panel, shows_containing, step_paused, window};

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
        state.estimator.open_at(EstimatorPoint::WorkedExample);
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
        // The light tree's tab, a pick stepped to its first node and to its leaf.
        harness.state_mut().layout.select(PanelKind::LightTree);
        harness.state_mut().state.light_tree.select_pixel([10, 12]);
        for stage in [0, 1] {
            harness.state_mut().state.light_tree.stage = stage;
            harness.run();
            let texts = painted_texts(&harness);
            assert!(
                texts.iter().any(|(t, _)| t.contains("One spatial pick")),
                "the light tree is shown"
            );
            let small: Vec<&(String, f32)> = texts.iter().filter(|(_, s)| *s < body).collect();
            assert!(
                small.is_empty(),
                "light tree: smaller than body text ({body}) at {size:?}: {small:?}"
            );
        }
    }
    // Ctrl + zooms everything: the points stay, each point gets more pixels.
    let mut harness = window(LightpickApp::for_tests(), [1024.0, 768.0]);
    harness.run();
    let before = harness.ctx.zoom_factor();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Plus);
    harness.run();
    assert!(harness.ctx.zoom_factor() > before, "Ctrl + does not zoom");
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
    let mut state = lightpick::app::AppState::worked_example();
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
    let next =
        lightpick::app::AppState::new(lightpick::app::scene_io::worked_example_scene(), settings);
    assert_eq!(next.file_dialog.folder.as_deref(), Some(dir.as_path()));
    let _ = std::fs::remove_dir_all(&dir);
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
fn presenter_keys_show_the_shortcuts_the_panels_and_the_presets() {
    let mut harness = window(LightpickApp::for_tests(), [1024.0, 768.0]);
    harness.run();
    harness.key_press(egui::Key::F1);
    harness.run();
    assert!(harness.state().state.settings.show_shortcuts);
    assert!(shows_containing(&harness, "Keyboard shortcuts"));
    for words in [
        "run or pause",
        "undo the last scene edit",
        "show the Images panel",
        "preset 'grid'",
    ] {
        assert!(shows_containing(&harness, words), "{words} is not listed");
    }
    // 4: the Images tab in front (at 1024×768 it shares a column with two others).
    harness.key_press(egui::Key::Num4);
    harness.run();
    assert_eq!(harness.state().layout.recent[0], PanelKind::Images);
    assert!(
        harness
            .state()
            .layout
            .pane_rect(PanelKind::Images)
            .is_some()
    );
    // Alt+8: the eighth preset of the Lights panel's row.
    harness.key_press_modifiers(egui::Modifiers::ALT, egui::Key::Num8);
    harness.run();
    assert_eq!(harness.state().state.built.scene.name, "grid");
    // F1 again closes the list.
    harness.key_press(egui::Key::F1);
    harness.run();
    assert!(!harness.state().state.settings.show_shortcuts);
}

#[test]
fn the_data_behind_the_figures_exports_as_csv() {
    use lightpick::app::state::FileAction;
    let dir = crate::common::scratch("data-export");
    let mut app = LightpickApp::for_tests();
    app.state.settings.show_trade = true;
    app.state.inspector.pixel = Some([100, 120]);
    let mut harness = window(app, [1560.0, 960.0]);
    harness.run();
    step_paused(&mut harness, 4);
    let published = harness.state_mut().published();
    let path = dir.join("lesson.csv");
    let text = path.to_str().expect("utf-8").to_owned();
    harness
        .state_mut()
        .file_action(FileAction::ExportData, &text, published.as_deref());
    let read = |what: &str| {
        std::fs::read_to_string(dir.join(format!("lesson-{what}.csv")))
            .unwrap_or_else(|e| panic!("{what}: {e}"))
    };
    // Convergence: every point of the three series, as the images hold them.
    let convergence = read("convergence");
    let p = published.expect("a frame");
    let points = p.uniform.series.len() + p.power.series.len() + p.spatial.series.len();
    assert_eq!(convergence.lines().count(), 1 + points);
    assert!(convergence.starts_with("scheme,spp,seconds,rmse\n"));
    // Histograms: the three lights, the counts adding up to the picks made.
    let histogram = read("histogram");
    let rows: Vec<Vec<&str>> = histogram
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 3);
    let picks = harness.state().state.sampling.picks;
    let sum = |col: usize| {
        rows.iter()
            .map(|r| r[col].parse::<u64>().expect("a count"))
            .sum::<u64>()
    };
    assert_eq!(sum(2), picks);
    assert_eq!(sum(3), picks);
    // Trade: one row per scheme; inspector: one row per light of the worked example.
    assert_eq!(read("trade").lines().count(), 1 + 5);
    let inspector = read("inspector");
    assert_eq!(
        inspector.lines().filter(|l| !l.starts_with('#')).count(),
        1 + 3
    );
    let (message, _) = harness.state().state.status.clone().expect("a message");
    assert!(message.contains("lesson-convergence.csv"), "{message}");
    let _ = std::fs::remove_dir_all(&dir);
}
