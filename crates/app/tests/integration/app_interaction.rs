//! The app driven through its accessibility tree (`egui_kittest`), as a user would: typing
//! powers, bad input, a malformed scene file, a single draw, keyboard shortcuts.

use crate::common::{app_harness as harness, click, scratch, shows, submit_path};
use egui::accesskit::Role;
use egui_kittest::kittest::Queryable as _;

/// Types `path` into the open file dialog's Path field and presses OK.

#[test]
fn seed_table_is_shown_with_exact_fractions() {
    let harness = harness();
    for label in ["2/27", "5/27", "20/27", "6/27", "15/27"] {
        assert!(shows(&harness, label), "{label} missing");
    }
    let state = &harness.state().state;
    assert_eq!(state.built.table.aliases(), &[2, 2, 2]);
}

#[test]
fn setting_a_power_through_accesskit_rebuilds_the_table_and_the_pmf() {
    let mut harness = harness();
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(7.0);
    harness.run();
    // Powers 7, 5, 20: total 32; thresholds 3·7/32 = 21/32, 15/32, then 1.
    for label in ["7/32", "5/32", "20/32", "21/32", "15/32"] {
        assert!(shows(&harness, label), "{label} missing after the edit");
    }
    assert!(!shows(&harness, "6/27"), "the old table is still shown");
    let state = &harness.state().state;
    assert_eq!(state.built.scene.powers.as_slice(), &[7.0, 5.0, 20.0]);
    assert_eq!(state.built.table.pmf_slice()[0], 7.0 / 32.0);
    assert_eq!(state.built.table.thresholds()[0], 21.0 / 32.0);
    assert_eq!(
        lightpick::app::panels::table_words::column_sentence(state, 0),
        "column 1 keeps light 1 with probability 21/32, else light 3"
    );
    // The histograms restarted on the new table.
    assert_eq!(state.sampling.generation, state.built.generation);
}

#[test]
fn a_negative_power_is_named_and_the_last_good_table_kept() {
    let mut harness = harness();
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 2")
        .set_value_accesskit(-1.0);
    harness.run();
    harness.get_by_label_contains("light 2: power -1 is negative");
    // The table still shows the worked example, the typed value is kept.
    assert!(shows(&harness, "6/27"));
    let state = &harness.state().state;
    assert_eq!(state.edit.powers[..], [2.0, -1.0, 20.0]);
    assert_eq!(state.built.scene.powers.as_slice(), &[2.0, 5.0, 20.0]);
}

#[test]
fn nan_typed_in_the_powers_field_is_named_and_kept() {
    let mut harness = harness();
    harness
        .get_by_role_and_label(Role::TextInput, "Powers")
        .set_text_value_accesskit("2, NaN, 20");
    harness.run();
    click(&mut harness, "Apply");
    eprintln!(
        "{:?} / {:?}",
        harness.state().state.input_error,
        harness.state().state.powers_text
    );
    harness.get_by_label_contains("light 2: power NaN is not a finite number");
    assert!(shows(&harness, "15/27"), "the last valid table must stay");
    assert_eq!(harness.state().state.powers_text, "2, NaN, 20");
    // A word that is not a number is named too.
    harness
        .get_by_role_and_label(Role::TextInput, "Powers")
        .set_text_value_accesskit("2, five, 20");
    harness.run();
    click(&mut harness, "Apply");
    harness.get_by_label_contains("light 2: 'five' is not a number");
}

#[test]
fn a_malformed_scene_file_is_reported_and_the_scene_kept() {
    let dir = scratch("app-open");
    let path = dir.join("broken.json");
    std::fs::write(
        &path,
        "{ \"name\": \"broken\", \"plane\": { \"min\": [0, 0] ",
    )
    .expect("write");

    let mut harness = harness();
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::O);
    harness.run();
    submit_path(&mut harness, &path);

    // The dialog stays open with the reason; the status bar says nothing changed.
    harness.get_by_label_contains("Error: ");
    harness.get_by_label_contains("nothing changed");
    let state = &harness.state().state;
    assert_eq!(state.edit.name, "worked-example");
    assert_eq!(state.built.scene.powers.as_slice(), &[2.0, 5.0, 20.0]);
    assert!(shows(&harness, "6/27"));
    assert!(state.file_dialog.error.is_some());
    // The typed path is kept for correction.
    assert_eq!(state.file_dialog.path, path.to_str().expect("utf-8 path"));

    // A good file replaces the scene.
    std::fs::write(
        &path,
        r#"{"name": "pair", "plane": {"min": [-1, -1], "max": [1, 1], "width": 32, "height": 32},
            "lights": [{"position": [0, 0, 1], "power": 1}, {"position": [0.5, 0, 1], "power": 3}]}"#,
    )
    .expect("write");
    click(&mut harness, "OK");
    let state = &harness.state().state;
    assert_eq!(state.edit.name, "pair");
    assert!(shows(&harness, "3/4"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn draw_one_sample_explains_the_pick() {
    let mut harness = harness();
    click(&mut harness, "Draw one sample");
    let draw = harness
        .state()
        .state
        .sampling
        .last_draw
        .expect("a draw was recorded");
    harness.get_by_label_contains(&format!("U1 = {:.4}", draw.u1));
    let verdict = if draw.kept {
        "keep light"
    } else {
        "alias light"
    };
    harness.get_by_label_contains(verdict);
    // The light is the table's own answer for these two randoms.
    let table = &harness.state().state.built.table;
    assert_eq!(table.sample_u32(draw.r1, draw.r2), draw.light);
}

#[test]
fn space_toggles_pause_and_r_resets() {
    let mut harness = harness();
    assert!(harness.state().state.settings.paused);
    harness.key_press(egui::Key::Space);
    harness.step();
    assert!(!harness.state().state.settings.paused);
    harness.step();
    assert!(harness.state().state.sampling.picks > 0);
    harness.key_press(egui::Key::Space);
    harness.step();
    assert!(harness.state().state.settings.paused);
    harness.key_press(egui::Key::R);
    harness.run();
    assert_eq!(harness.state().state.sampling.picks, 0);
}

#[test]
fn adding_and_removing_lights_keeps_table_and_rows_in_step() {
    let mut harness = harness();
    click(&mut harness, "+ Add");
    assert_eq!(harness.state().state.built.len(), 4);
    click(&mut harness, "remove light 1");
    let state = &harness.state().state;
    assert_eq!(state.built.scene.powers.as_slice(), &[5.0, 20.0, 1.0]);
    assert_eq!(state.edit.positions.len(), 3);
}

#[test]
fn export_writes_png_files_through_the_file_menu() {
    let dir = scratch("app-export");
    let mut harness = harness();
    harness.state_mut().step();
    harness.run();
    for (item, file) in [
        ("Alias-table diagram", "diagram.png"),
        ("Export images", "images.png"),
    ] {
        let path = dir.join(file);
        click(&mut harness, "File");
        if item == "Alias-table diagram" {
            click(&mut harness, "Export figure (PNG)");
        }
        harness.get_by_label_contains(item).click();
        harness.run();
        submit_path(&mut harness, &path);
        let bytes = std::fs::read(&path).expect("the PNG was written");
        assert_eq!(&bytes[1..4], b"PNG", "{file}");
        harness.get_by_label_contains("exported");
    }
    // uniform | importance | spatial | reference over their three error maps.
    let sheet = image::open(dir.join("images.png")).expect("a PNG");
    let plane = &harness.state().state.built.scene.plane;
    // A caption band on top (scheme, spp, RMSE), then the two rows of images.
    assert_eq!(sheet.width(), 4 * plane.width);
    let band = sheet.height() - 2 * plane.height;
    assert!((20..=48).contains(&band), "caption band of {band} px");
    let rgb = sheet.to_rgb8();
    let lit = (0..band)
        .flat_map(|y| (0..plane.width).map(move |x| (x, y)))
        .filter(|&(x, y)| rgb.get_pixel(x, y).0.iter().any(|&c| c > 128))
        .count();
    assert!(
        lit > 20,
        "the uniform column's caption is written ({lit} lit pixels)"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn typing_into_the_drag_value_sets_the_power() {
    let mut harness = harness();
    // A click on a drag value opens it for typing with its text selected.
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 3")
        .click();
    harness.run();
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 3")
        .type_text("47");
    harness.run();
    harness.key_press(egui::Key::Enter);
    harness.run();
    // Powers 2, 5, 47: total 54, thresholds 6/54, 15/54, then 1.
    for label in ["2/54", "5/54", "47/54", "6/54", "15/54"] {
        assert!(shows(&harness, label), "{label} missing after typing");
    }
    assert_eq!(
        harness.state().state.built.scene.powers.as_slice(),
        &[2.0, 5.0, 47.0]
    );
}
