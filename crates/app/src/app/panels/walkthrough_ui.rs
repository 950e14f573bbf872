//! The classroom walkthrough: the classic explanation of power-based light picking, retold
//! step by step on the live table ([`lightpick_core::walkthrough`] holds the steps and
//! their numbers).
//!
//! The window shows one step at a time (Back / Next, or Page Up / Page Down as a presenter
//! remote sends them), its formulas with the current powers, and sets
//! [`AppState::table_highlight`] so the table panel outlines the cells and diagram columns
//! the step talks about. The classic has three lights: with another count the window
//! offers to load the worked example (2, 5, 20), keeps the user's scene and restores it when the
//! walkthrough closes (or on request; "Keep the classic scene" forgets it).

use egui::{Key, Modifiers, RichText, Ui};
use lightpick_core::walkthrough::{CLASSIC_GEOMETRY, CLASSIC_POWERS};

use crate::app::state::AppState;
use crate::app::state::estimator::EstimatorPoint;
use crate::app::state::walkthrough::WALKTHROUGH_LIGHTS;

/// Text size of the formulas: readable from the back of a classroom.
pub const FORMULA_SIZE: f32 = 19.0;

/// The Walkthrough window (View menu, or the table panel's button).
pub fn walkthrough_window(ctx: &egui::Context, state: &mut AppState) {
    let mut open = state.settings.show_walkthrough;
    egui::Window::new("Walkthrough")
        .open(&mut open)
        .default_pos([right_edge(ctx) - 540.0, 40.0])
        .default_width(520.0)
        .show(ctx, |ui| walkthrough_ui(ui, state));
    state.settings.show_walkthrough = open;
}

/// Where the classroom windows open: their right edge near the window's right edge, over
/// the Images panel, so the table and its diagram stay visible.
pub fn right_edge(ctx: &egui::Context) -> f32 {
    ctx.content_rect().right() - 12.0
}

/// The window's content: the current step, or the offer to load the classic scene.
pub fn walkthrough_ui(ui: &mut Ui, state: &mut AppState) {
    let Some(walk) = state.walkthrough_lesson() else {
        ui.label(format!(
            "The walkthrough retells the classic explanation, which has {WALKTHROUGH_LIGHTS} \
             lights; this scene has {}.",
            state.built.len()
        ));
        if ui
            .button("Load the classic scene (2, 5, 20)")
            .on_hover_text(
                "Show the classic three lights; your scene is kept and comes back when the \
                 walkthrough closes",
            )
            .clicked()
        {
            state.load_classic();
        }
        saved_scene_ui(ui, state);
        return;
    };
    let (w, steps) = (&walk.0, &walk.1);
    let total = steps.len();
    let k = state.walkthrough.step.min(total - 1);
    let step = &steps[k];
    let next_key = ui.input_mut(|i| i.consume_key(Modifiers::NONE, Key::PageDown));
    let back_key = ui.input_mut(|i| i.consume_key(Modifiers::NONE, Key::PageUp));
    ui.horizontal(|ui| {
        let back = ui
            .add_enabled(k > 0, egui::Button::new(RichText::new("← Back").size(16.0)))
            .on_hover_text("Previous step (Page Up)");
        if (back.clicked() || back_key) && k > 0 {
            state.walkthrough.step = k - 1;
        }
        ui.label(RichText::new(format!("Step {} of {total}", k + 1)).size(16.0))
            .on_hover_text("Where we are in the classic explanation");
        let next = ui
            .add_enabled(
                k + 1 < total,
                egui::Button::new(RichText::new("Next →").size(16.0)),
            )
            .on_hover_text("Next step (Page Down)");
        if (next.clicked() || next_key) && k + 1 < total {
            state.walkthrough.step = k + 1;
        }
    });
    ui.add_space(4.0);
    ui.label(RichText::new(&step.title).size(22.0).strong());
    ui.label(RichText::new(&step.text).size(15.0));
    ui.separator();
    for formula in &step.formulas {
        ui.label(RichText::new(formula).size(FORMULA_SIZE).strong());
    }
    if k + 1 == total {
        ui.add_space(4.0);
        if ui
            .button(RichText::new("Watch it converge →").size(16.0))
            .on_hover_text(
                "Open the estimator at this shading point: the running estimate of uniform \
                 and power picking, sample by sample, against the exact 18",
            )
            .clicked()
        {
            state.estimator.open_at(EstimatorPoint::WorkedExample);
            state.estimator.running = true;
        }
    }
    ui.separator();
    ui.label(
        RichText::new(format!(
            "g = {} stay with their lights: change a power (Lights panel) and every number \
             follows, f = g·Φ.",
            CLASSIC_GEOMETRY
                .map(lightpick_core::walkthrough::number)
                .join(", ")
        ))
        .size(13.0),
    )
    .on_hover_text("The geometry factor g: distance and angle from the light to the point");
    let classic = w.powers.as_slice() == CLASSIC_POWERS.as_slice();
    if !classic
        && state.walkthrough.saved_scene.is_none()
        && ui
            .button("Classic powers 2, 5, 20")
            .on_hover_text("Load the classic scene; yours comes back when the walkthrough closes")
            .clicked()
    {
        state.load_classic();
    }
    saved_scene_ui(ui, state);
}

/// While the user's scene is kept: say so, and offer to restore it now or forget it.
fn saved_scene_ui(ui: &mut Ui, state: &mut AppState) {
    let Some(saved) = &state.walkthrough.saved_scene else {
        return;
    };
    let note = format!(
        "Your scene \"{}\" ({} lights) comes back when the walkthrough closes.",
        saved.name,
        saved.light_count()
    );
    ui.label(RichText::new(note).size(13.0));
    ui.horizontal(|ui| {
        if ui
            .button("Restore my scene")
            .on_hover_text("Bring your scene back now")
            .clicked()
        {
            state.restore_scene();
        }
        if ui
            .button("Keep the classic scene")
            .on_hover_text("Forget your previous scene and keep working on the classic one")
            .clicked()
        {
            state.walkthrough.saved_scene = None;
        }
    });
}
