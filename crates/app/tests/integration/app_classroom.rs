//! The classroom windows driven through the accessibility tree: the walkthrough's numbers on
//! every key step (and after a power changes), the construction stepper's states, and
//! snapshots of both (goldens in `tests/snapshots/`, `UPDATE_SNAPSHOTS=1` to refresh).

use crate::common::{app_harness as harness, click, shows, snapshot_options, wgpu_window};
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;
use lightpick_core::construction::ConstructionEvent;
use lightpick_core::walkthrough::{ColumnPart, StepKind, TableField};

fn assert_shows(harness: &Harness<'_, LightpickApp>, labels: &[&str]) {
    for label in labels {
        assert!(shows(harness, label), "{label:?} is not shown");
    }
}

fn open_walkthrough(harness: &mut Harness<'_, LightpickApp>) {
    // The table panel's header button.
    harness
        .get_by_role_and_label(Role::Button, "Walkthrough")
        .click();
    harness.run();
    assert!(harness.state().state.settings.show_walkthrough);
}

#[test]
fn walkthrough_shows_the_classic_numbers_step_by_step() {
    let mut h = harness();
    assert!(h.state().state.table_highlight.is_none());
    open_walkthrough(&mut h);
    assert_shows(
        &h,
        &[
            "Step 1 of 9",
            "Φ = 2, 5, 20    ΣΦ = 27",
            "f = 0.5·2, 0.4·5, 0.75·20 = 1, 2, 15",
            "exact total L = 1 + 2 + 15 = 18",
        ],
    );
    click(&mut h, "Next →");
    assert_shows(
        &h,
        &[
            "Step 2 of 9",
            "f/pdf = 1/(1/3), 2/(1/3), 15/(1/3) = 3, 6, 45",
            "average = (3 + 6 + 45)/3 = 18",
        ],
    );
    click(&mut h, "Next →");
    assert_shows(&h, &["q = N·p = 6/27, 15/27, 60/27   (mean 1)"]);
    click(&mut h, "Next →");
    assert_shows(
        &h,
        &[
            "Step 4 of 9",
            "threshold = 6/27, 15/27, 1",
            "alias = light 3, 3, 3   (index 2, 2, 2 from 0)",
        ],
    );
    let highlight = h.state().state.table_highlight.clone().expect("highlight");
    for row in 0..3 {
        assert!(highlight.has_cell(row, TableField::Threshold));
        assert!(highlight.has_cell(row, TableField::Alias));
        assert!(!highlight.has_cell(row, TableField::Power));
    }
    click(&mut h, "Next →");
    assert_shows(&h, &["Step 5 of 9", "P(light 1) = 1/3·6/27", "= 2/27"]);
    click(&mut h, "Next →");
    assert_shows(&h, &["P(light 2) = 1/3·15/27", "= 5/27"]);
    click(&mut h, "Next →");
    assert_shows(
        &h,
        &[
            "Step 7 of 9",
            "P(light 3) = 1/3·1 + 1/3·(1 − 6/27) + 1/3·(1 − 15/27)",
            "= 1/3·1 + 1/3·21/27 + 1/3·12/27",
            "= 9/27 + 7/27 + 4/27 = 20/27",
        ],
    );
    let highlight = h.state().state.table_highlight.clone().expect("highlight");
    assert_eq!(
        highlight.columns,
        vec![
            (2, ColumnPart::Own),
            (0, ColumnPart::Alias),
            (1, ColumnPart::Alias)
        ]
    );
    // Back returns to light 2, Next to light 3 again.
    click(&mut h, "← Back");
    assert_shows(&h, &["Step 6 of 9", "= 5/27"]);
    assert!(!shows(&h, "= 9/27 + 7/27 + 4/27 = 20/27"));
    click(&mut h, "Next →");
    click(&mut h, "Next →");
    assert_shows(
        &h,
        &[
            "2/27 + 5/27 + 20/27 = 1",
            "P(light 3)/P(light 1) = 20/27 ÷ 2/27 = 10 = Φ_3/Φ_1",
        ],
    );
    click(&mut h, "Next →");
    assert_shows(
        &h,
        &[
            "Step 9 of 9",
            "27 samples: each column is picked 27/3 = 9 times",
            "column 1: light 1 in 9·6/27 = 2, light 3 in the other 7",
            "column 2: light 2 in 9·15/27 = 5, light 3 in the other 4",
            "samples per light: 2, 5, 20",
            "f/p = 1/(2/27), 2/(5/27), 15/(20/27) = 13.5, 10.8, 20.25",
            "average = (2·13.5 + 5·10.8 + 20·20.25)/27 = (27 + 54 + 405)/27 = 18",
        ],
    );
    // The last step: Next is disabled and changes nothing.
    click(&mut h, "Next →");
    assert_eq!(h.state().state.walkthrough.step, 8);
    // Page Up (a presenter remote) goes back.
    h.key_press(egui::Key::PageUp);
    h.run();
    assert_shows(&h, &["Step 8 of 9"]);
}

#[test]
fn walkthrough_numbers_follow_a_changed_power() {
    let mut h = harness();
    open_walkthrough(&mut h);
    for _ in 0..4 {
        click(&mut h, "Next →");
    }
    assert_shows(&h, &["= 2/27"]);
    h.get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(7.0);
    h.run();
    // Powers 7, 5, 20: ΣΦ = 32, threshold 3·7/32 = 21/32, P(light 1) = 7/32; the step stays.
    assert_shows(&h, &["Step 5 of 9", "P(light 1) = 1/3·21/32", "= 7/32"]);
    assert!(!shows(&h, "= 2/27"), "the old probability is still shown");
    for _ in 0..4 {
        click(&mut h, "← Back");
    }
    // f_1 = 0.5·7 = 3.5: the exact total follows.
    assert_shows(
        &h,
        &[
            "f = 0.5·7, 0.4·5, 0.75·20 = 3.5, 2, 15",
            "exact total L = 3.5 + 2 + 15 = 20.5",
        ],
    );
    for _ in 0..8 {
        click(&mut h, "Next →");
    }
    // 32 is not a multiple of 3: 96 samples, 32 per column; the average is 20.5 again.
    assert_shows(
        &h,
        &[
            "96 samples: each column is picked 96/3 = 32 times",
            "samples per light: 21, 15, 60",
        ],
    );
    let step = h
        .state_mut()
        .state
        .walkthrough_lesson()
        .expect("walkthrough")
        .1[8]
        .clone();
    assert_eq!(step.kind, StepKind::Samples);
    assert!(
        step.formulas.last().is_some_and(|f| f.ends_with("= 20.5")),
        "{:?}",
        step.formulas
    );
}

#[test]
fn walkthrough_offers_the_classic_scene_and_restores_the_users_scene() {
    let mut h = harness();
    h.get_by_role_and_label(Role::TextInput, "Powers")
        .set_text_value_accesskit("1, 2, 3, 4");
    h.run();
    click(&mut h, "Apply");
    assert_eq!(h.state().state.built.len(), 4);
    open_walkthrough(&mut h);
    h.get_by_label_contains("this scene has 4");
    assert!(h.state().state.table_highlight.is_none());
    click(&mut h, "Load the classic scene (2, 5, 20)");
    assert_eq!(
        h.state().state.built.scene.powers.as_slice(),
        &[2.0, 5.0, 20.0]
    );
    assert_shows(&h, &["Step 1 of 9"]);
    h.get_by_label_contains("(4 lights) comes back when the walkthrough closes");
    // Closing the walkthrough (the header toggle) brings the user's scene back.
    h.get_by_role_and_label(Role::Button, "Walkthrough").click();
    h.run();
    h.run();
    assert!(!h.state().state.settings.show_walkthrough);
    assert_eq!(
        h.state().state.built.scene.powers.as_slice(),
        &[1.0, 2.0, 3.0, 4.0]
    );
    assert!(h.state().state.table_highlight.is_none());
}

/// The stepper's lists and assigned columns, read from the app.
fn stepper_state(h: &mut Harness<'_, LightpickApp>) -> (Vec<usize>, Vec<usize>, usize) {
    let state = &mut h.state_mut().state;
    let trace = state.stepper_trace().expect("trace");
    let s = &trace.states()[state.stepper.index];
    (s.small.clone(), s.large.clone(), s.assigned_count())
}

#[test]
fn stepper_walks_vose_on_the_seed() {
    let mut h = harness();
    h.get_by_role_and_label(Role::Button, "Construction")
        .click();
    h.run();
    assert_shows(
        &h,
        &["event 0 of 3", " 1: 6/27 ", " 2: 15/27 ", " 3: 60/27 "],
    );
    assert_eq!(stepper_state(&mut h), (vec![0, 1], vec![2], 0));

    click(&mut h, "Step →");
    assert_shows(&h, &["event 1 of 3", " 2: 15/27 ", " 3: 39/27 "]);
    h.get_by_label_contains(
        "Column 1 (q = 6/27) takes 21/27 from column 3: threshold 6/27, alias 3. \
         Column 3: (60/27 + 6/27) − 1 = 39/27, stays large.",
    );
    assert_eq!(stepper_state(&mut h), (vec![1], vec![2], 1));

    click(&mut h, "Step →");
    h.get_by_label_contains("Column 2 (q = 15/27) takes 12/27 from column 3");
    assert_eq!(stepper_state(&mut h), (vec![], vec![2], 2));
    assert!(!shows(&h, " 3: 39/27 "));

    // Back returns to the previous state, lists and all.
    click(&mut h, "← Back");
    assert_shows(&h, &["event 1 of 3", " 3: 39/27 "]);
    assert_eq!(stepper_state(&mut h), (vec![1], vec![2], 1));

    click(&mut h, "Step →");
    click(&mut h, "Step →");
    assert_shows(&h, &["event 3 of 3"]);
    h.get_by_label_contains("Leftover column 3");
    h.get_by_label_contains("exactly the Table panel's table.");
    assert_eq!(stepper_state(&mut h), (vec![], vec![], 3));
    {
        let state = &mut h.state_mut().state;
        let trace = state.stepper_trace().expect("trace");
        assert_eq!(
            trace.thresholds().as_slice(),
            state.built.table.thresholds()
        );
        assert_eq!(trace.aliases().as_slice(), state.built.table.aliases());
        let last = &trace.states()[3];
        assert!(matches!(
            last.event,
            ConstructionEvent::Leftover { column: 2, .. }
        ));
    }

    click(&mut h, "Reset stepper");
    assert_eq!(stepper_state(&mut h), (vec![0, 1], vec![2], 0));
}

#[test]
fn stepper_play_advances_one_event_per_interval_and_stops_at_the_end() {
    let mut h = harness();
    h.get_by_role_and_label(Role::Button, "Construction")
        .click();
    h.run();
    // Each harness step advances egui's clock by kittest's step of 1/4 s: 2 s per event is
    // 8 steps.
    h.state_mut().state.stepper.seconds_per_step = 2.0;
    h.get_by_label("Play").click();
    h.step();
    assert!(h.state().state.stepper.playing);
    assert_eq!(h.state().state.stepper.index, 0);
    for _ in 0..10 {
        h.step();
    }
    assert_eq!(h.state().state.stepper.index, 1, "one event after 2 s");
    assert!(h.state().state.stepper.playing);
    for _ in 0..40 {
        h.step();
    }
    assert_eq!(h.state().state.stepper.index, 3);
    assert!(!h.state().state.stepper.playing, "playing stops at the end");
    h.run();
    h.get_by_label_contains("exactly the Table panel's table.");
}

#[test]
fn stepper_starts_over_on_a_new_table_and_refuses_huge_ones() {
    let mut h = harness();
    h.get_by_role_and_label(Role::Button, "Construction")
        .click();
    h.run();
    click(&mut h, "Step →");
    h.get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(7.0);
    h.run();
    assert_eq!(h.state().state.stepper.index, 0);
    assert_shows(&h, &[" 1: 21/32 ", " 2: 15/32 ", " 3: 60/32 "]);
    h.get_by_role_and_label(Role::TextInput, "Powers")
        .set_text_value_accesskit(&vec!["1"; 65].join(", "));
    h.run();
    click(&mut h, "Apply");
    h.get_by_label_contains("up to 64 lights; this scene has 65");
}

fn whole_app(dark: bool) -> Harness<'static, LightpickApp> {
    let mut app = LightpickApp::for_tests();
    app.state.settings.dark = dark;
    let mut harness = wgpu_window(app, [1600.0, 1000.0]);
    harness.run();
    harness
}

#[test]
fn walkthrough_snapshot() {
    let mut h = whole_app(true);
    open_walkthrough(&mut h);
    for _ in 0..6 {
        click(&mut h, "Next →");
    }
    assert_shows(&h, &["= 9/27 + 7/27 + 4/27 = 20/27"]);
    h.snapshot_options("classroom_walkthrough", &snapshot_options());
}

#[test]
fn stepper_snapshot() {
    let mut h = whole_app(false);
    h.get_by_role_and_label(Role::Button, "Construction")
        .click();
    h.run();
    click(&mut h, "Step →");
    assert_shows(&h, &["event 1 of 3"]);
    h.snapshot_options("classroom_stepper", &snapshot_options());
}
