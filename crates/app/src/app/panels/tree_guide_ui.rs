//! The Light tree panel's guide: five steps on why the spatial scheme wins, in a student's
//! words, ending on the current scene's own variances (the sentence under the images).

use egui::Ui;

use crate::app::state::AppState;
use crate::app::state::light_tree::GUIDE_STEPS;
use crate::numbers;

/// The guide: five steps, with the figures of the current scene.
pub fn guide_ui(ui: &mut Ui, state: &mut AppState) {
    let step = state.light_tree.guide_step.min(GUIDE_STEPS - 1);
    ui.horizontal(|ui| {
        ui.strong(format!(
            "Why the spatial scheme wins ({}/{GUIDE_STEPS})",
            step + 1
        ));
        if ui
            .add_enabled(step > 0, egui::Button::new("Previous"))
            .clicked()
        {
            state.light_tree.guide_step = step - 1;
        }
        if ui
            .add_enabled(step + 1 < GUIDE_STEPS, egui::Button::new("Continue"))
            .clicked()
        {
            state.light_tree.guide_step = step + 1;
        }
    });
    let variances = state.current_scene_sentence().map(|s| s.variances);
    let powers = state.built.scene.powers.as_slice();
    let equal = powers.windows(2).all(|w| w[0] == w[1]);
    let spots = state.built.scene.emission.is_some();
    let text = guide_text(step, variances, state.built.len(), (equal, spots));
    ui.label(text);
}

/// The text of guide step `step`, with the scene's mean variances of one sample (uniform,
/// power, spatial) when known, its number of lights, whether their powers are all equal and
/// whether some have a spot cone or a range.
pub fn guide_text(
    step: usize,
    variances: Option<[f64; 3]>,
    lights: usize,
    (equal_powers, spots): (bool, bool),
) -> String {
    match step {
        0 if equal_powers => format!(
            "Power picking chooses a light by its power alone. Here all {lights} lights have \
             the same power (as on the grid preset), so it picks as uniformly as uniform \
             picking does — yet at any pixel only the few lights nearby matter (G falls as \
             1/r³ for low lights)."
        ),
        0 if spots => format!(
            "Power picking chooses a light by its power alone, the same everywhere. But what \
             one of these {lights} lights gives a pixel depends on where it is (G falls as \
             1/r³ for low lights) and, for a spot, on where it points: the brightest light \
             may give this pixel nothing."
        ),
        0 => format!(
            "Power picking chooses a light by its power alone, the same everywhere. But what \
             one of these {lights} lights gives a pixel depends on where it is: G falls as \
             1/r³ for low lights, so a bright light far away may give this pixel less than a \
             dim one overhead."
        ),
        1 => "The tree groups nearby lights. At each node a group's weight is its \
              representative light (at the group's power-weighted centre, with the group's \
              power) as seen from x, mixed with a small share of plain power so that no group \
              that could light x is ever left out. Near groups weigh more."
            .to_owned(),
        2 => "Click a point of the plane, then Next (Page Down). The first choices are the \
              same all over a small tile of pixels, so each tile keeps them made once: a cut \
              of the tree into groups, and one random number picks a group of it. Below it, \
              at each node one random number picks a group by its weight at x; at the leaf, \
              one more picks a light by its exact contribution."
            .to_owned(),
        3 => "The probability of the light picked is the product of the probabilities of the \
              choices on its path, P(i | x) = P(tile's group) × P(group) × … × P(light in \
              leaf): exactly what the renderer divides by, so the estimate f_i / P stays \
              unbiased."
            .to_owned(),
        _ => match variances {
            Some([uniform, power, spatial]) if spatial > 0.0 => format!(
                "On this scene, averaged over the image, one sample's variance is {} under \
                 uniform picking, {} under power picking and {} under spatial picking: \
                 spatial's is {} than power's.",
                numbers::short(uniform),
                numbers::short(power),
                numbers::short(spatial),
                numbers::compare(spatial, power, "higher", "lower")
            ),
            Some([uniform, power, _]) => format!(
                "On this scene one sample's variance is {} under uniform picking and {} under \
                 power picking; spatial picking is exact here (variance 0): with few lights it \
                 weighs every light at x.",
                numbers::short(uniform),
                numbers::short(power)
            ),
            None => "The variances of this scene are being computed…".to_owned(),
        },
    }
}
