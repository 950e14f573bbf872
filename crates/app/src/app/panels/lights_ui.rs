//! The lights panel: one row per light (colour, power drag value and slider, duplicate,
//! remove), presets, randomize, generate `N`, and a powers text field. Rows are virtualized
//! with `ScrollArea::show_rows`, so the `million` preset builds only the visible widgets.

use std::fmt::Write as _;

use egui::{RichText, Sense, Ui, vec2};
use lightpick_core::scene::MAX_LIGHTS;

use crate::app::colors;
use crate::app::generated::PowerShape;
use crate::app::scene_io;
use crate::app::state::AppState;
use crate::app::state::edit::{power_to_text, powers_to_text};
use crate::app::state::settings::SliderScale;

const ROW_HEIGHT: f32 = 22.0;

/// The whole panel.
pub fn lights_ui(ui: &mut Ui, state: &mut AppState) {
    presets_ui(ui, state);
    floor_ui(ui, state);
    ui.separator();
    generate_ui(ui, state);
    ui.separator();
    powers_text_ui(ui, state);
    if let Some(error) = &state.input_error {
        ui.colored_label(colors::error(state.dark()), format!("Error: {error}"));
    }
    ui.separator();
    scale_ui(ui, state);
    ui.add_space(2.0);
    rows_ui(ui, state);
}

fn presets_ui(ui: &mut Ui, state: &mut AppState) {
    ui.horizontal_wrapped(|ui| {
        ui.label("Preset:")
            .on_hover_text("Load one of the bundled scenes");
        for name in scene_io::preset_names() {
            let selected = state.edit.name == name;
            if ui
                .selectable_label(selected, name)
                .on_hover_text(format!("Load the '{name}' scene"))
                .clicked()
            {
                state.load_preset(name);
            }
        }
    });
}

/// The receiver's height (Floor) and the scene's kinds of lights.
fn floor_ui(ui: &mut Ui, state: &mut AppState) {
    ui.horizontal(|ui| {
        let label = ui.label("Floor");
        let mut floor = state.edit.floor;
        let response = ui
            .add(egui::DragValue::new(&mut floor).speed(0.05).max_decimals(4))
            .labelled_by(label.id)
            .on_hover_text(
                "Height of the receiving plane above the scene's ground as loaded (glTF's y = 0): \
                 lights on or below it light nothing",
            );
        if response.changed() {
            state.set_floor(floor);
        }
        let spots = state
            .edit
            .emission
            .as_ref()
            .map_or(0, |e| e.iter().filter(|e| e.spot().is_some()).count());
        let n = state.edit.powers.len();
        if spots > 0 {
            ui.weak(format!("{} points, {spots} spots", n - spots));
        }
    });
}

fn generate_ui(ui: &mut Ui, state: &mut AppState) {
    ui.horizontal(|ui| {
        let label = ui.label("Distribution");
        egui::ComboBox::from_id_salt("power_distribution")
            .selected_text(state.settings.distribution.label())
            .show_ui(ui, |ui| {
                for d in PowerShape::ALL {
                    ui.selectable_value(&mut state.settings.distribution, d, d.label());
                }
            })
            .response
            .labelled_by(label.id)
            .on_hover_text("Distribution of random powers for Randomize and Generate");
    });
    ui.horizontal(|ui| {
        if ui
            .button("Randomize")
            .on_hover_text("Draw new powers for every light from the distribution")
            .clicked()
        {
            state.randomize();
        }
        let label = ui.label("Count");
        ui.add(
            egui::DragValue::new(&mut state.settings.generate_count)
                .range(1..=MAX_LIGHTS)
                .speed(1.0),
        )
        .labelled_by(label.id)
        .on_hover_text(format!(
            "How many lights Generate makes (up to {MAX_LIGHTS}, the scene limit 2^24)"
        ));
        let count = state.settings.generate_count;
        let generate = ui.button("Generate");
        let generate = if count > LARGE_GENERATE {
            generate.on_hover_text(generate_cost_text(count))
        } else {
            generate.on_hover_text("Replace the scene by this many random lights")
        };
        if generate.clicked() {
            let n = state.settings.generate_count;
            state.generate(n);
        }
    });
}

/// Above this many lights Generate says what it will cost before it runs.
const LARGE_GENERATE: usize = 1_000_000;

/// What generating `count` lights costs, scaled from measurements on this 2-core machine:
/// the light tree's `O(N log N)` build (0.22 s at 10^6, 4.7 s at 1.6·10^7 lights) and the
/// app's memory (about 260 bytes per light on `million`).
fn generate_cost_text(count: usize) -> String {
    let millions = count as f64 / 1e6;
    // 0.22 s·m·(1 + 0.08·log2 m) passes through both measurements within 10 %.
    let seconds = 0.22 * millions * (1.0 + 0.08 * millions.log2().max(0.0));
    format!(
        "Replace the scene by {count} random lights: about {seconds:.1} s to build and \
         {:.1} GB of memory (scaled from 0.22 s and ~260 B per light measured at 10^6)",
        260.0 * count as f64 / 1e9
    )
}

fn powers_text_ui(ui: &mut Ui, state: &mut AppState) {
    // A large scene's powers are not listed; the empty field says so instead of showing
    // example values that could be taken for the scene's own.
    let n = state.edit.powers.len();
    let hint = if n > crate::app::state::edit::POWERS_TEXT_MAX_LIGHTS {
        format!("{n} lights, too many to list: typed powers replace them all")
    } else {
        "type powers, e.g. 2, 5, 20".to_owned()
    };
    ui.horizontal(|ui| {
        let label = ui.label("Powers");
        let response = ui
            .add(
                egui::TextEdit::singleline(&mut state.powers_text)
                    .desired_width(ui.available_width() - 60.0)
                    .hint_text(hint),
            )
            .labelled_by(label.id)
            .on_hover_text(
                "Type powers separated by commas or spaces and press Enter (Apply). \
                 A bad entry is named and the last valid table is kept.",
            );
        let enter = response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui
            .button("Apply")
            .on_hover_text("Use the powers typed in the field")
            .clicked()
            || enter
        {
            state.apply_powers_text();
        }
    });
}

fn scale_ui(ui: &mut Ui, state: &mut AppState) {
    ui.horizontal(|ui| {
        ui.label("Slider")
            .on_hover_text("Scale of the power sliders");
        ui.selectable_value(
            &mut state.settings.slider_scale,
            SliderScale::Linear,
            "linear",
        )
        .on_hover_text("Linear sliders from 0 to the maximum");
        ui.selectable_value(&mut state.settings.slider_scale, SliderScale::Log, "log")
            .on_hover_text("Logarithmic sliders over six decades below the maximum");
        let label = ui.label("max");
        ui.add(
            egui::DragValue::new(&mut state.settings.slider_max)
                .range(1e-300..=1e300)
                .speed(0.1),
        )
        .labelled_by(label.id)
        .on_hover_text("Upper end of the power sliders (typed powers may exceed it)");
        if ui
            .button("+ Add")
            .on_hover_text("Add a light (power 1) at a random position")
            .clicked()
        {
            state.add_light(1.0);
        }
    });
}

/// What the row's tooltip says of light `i`: name, position, and its spot cone and range.
fn light_about(state: &AppState, i: usize) -> String {
    let p = state.edit.positions.get(i).copied().unwrap_or_default();
    let mut text = format!(
        "{} (light {}) at ({:.2}, {:.2}, {:.2})",
        state.edit.display_name(i),
        i + 1,
        p.x,
        p.y,
        p.z
    );
    if let Some(e) = state.edit.emission.as_ref().and_then(|e| e.get(i)) {
        if let Some(s) = e.spot() {
            let a = e.axis();
            let _ = write!(
                text,
                "\nspot toward ({:.2}, {:.2}, {:.2}), cones {:.1}° / {:.1}°",
                a.x,
                a.y,
                a.z,
                s.inner_cone.to_degrees(),
                s.outer_cone.to_degrees()
            );
        }
        if let Some(r) = e.range() {
            let _ = write!(text, "\nrange {}", crate::numbers::short(r));
        }
    }
    text
}

fn rows_ui(ui: &mut Ui, state: &mut AppState) {
    let n = state.edit.powers.len();
    let mut changed = false;
    let mut remove = None;
    let mut duplicate = None;
    egui::ScrollArea::vertical()
        .id_salt("light_rows")
        .auto_shrink([false, false])
        .show_rows(ui, ROW_HEIGHT, n, |ui, rows| {
            for i in rows {
                ui.horizontal(|ui| {
                    let edits = row_ui(ui, state, i);
                    changed |= edits.power;
                    if edits.duplicate {
                        duplicate = Some(i);
                    }
                    if edits.remove {
                        remove = Some(i);
                    }
                });
            }
        });
    if let Some(i) = duplicate {
        state.duplicate_light(i);
    } else if let Some(i) = remove {
        state.remove_light(i);
    } else if changed {
        if n <= 1000 {
            state.powers_text = powers_to_text(&state.edit.powers);
        }
        state.powers_changed();
    }
}

/// What the user did to one light's row this frame.
struct RowEdits {
    /// Its power was changed (and written to the edit).
    power: bool,
    /// "dup" was clicked.
    duplicate: bool,
    /// "del" was clicked.
    remove: bool,
}

/// Light `i`'s row: colour, number (red while its power is refused), name, power, and the
/// duplicate and remove buttons.
fn row_ui(ui: &mut Ui, state: &mut AppState, i: usize) -> RowEdits {
    let dark = state.dark();
    let (swatch, _) = ui.allocate_exact_size(vec2(14.0, 14.0), Sense::hover());
    ui.painter().rect_filled(swatch, 3.0, colors::light(i));
    let name = format!("light {}", i + 1);
    let bad = {
        let p = state.edit.powers[i];
        !p.is_finite() || p < 0.0
    };
    let text = RichText::new(format!("{:>3}", i + 1)).monospace();
    let text = if bad {
        text.color(colors::error(dark))
    } else {
        text
    };
    let about = light_about(state, i);
    ui.label(text).on_hover_text(&about);
    if state.edit.names.is_some() {
        let own = state.edit.display_name(i);
        ui.add_sized([84.0, ROW_HEIGHT - 2.0], egui::Label::new(own).truncate())
            .on_hover_text(&about);
    }
    let power = power_ui(ui, state, i, &name);
    let duplicate = ui
        .small_button("dup")
        .on_hover_text(format!("Duplicate {name}"))
        .accessible_name(format!("duplicate {name}"))
        .clicked();
    let remove = ui
        .small_button("del")
        .on_hover_text(format!("Remove {name}"))
        .accessible_name(format!("remove {name}"))
        .clicked();
    RowEdits {
        power,
        duplicate,
        remove,
    }
}

/// Light `i`'s power: a drag value (typed values too) and a slider; returns whether the
/// user changed it (then it is written to the edit).
fn power_ui(ui: &mut Ui, state: &mut AppState, i: usize, name: &str) -> bool {
    let slider_max = state.settings.slider_max;
    let log = state.settings.slider_scale == SliderScale::Log;
    let mut changed = false;
    // Read here, written back (a copy while a scene shares the powers) only
    // when the user changed it.
    let mut power = state.edit.powers[i];
    let p = &mut power;
    let speed = if p.is_finite() {
        (p.abs() * 0.01).max(0.01)
    } else {
        0.01
    };
    // egui compares old and new values to detect edits, and NaN never equals
    // itself: a non-finite power is shown as typed but edited through a
    // finite stand-in, so it stays until the user replaces it.
    let shown = *p;
    let mut stand_in = if shown.is_finite() { shown } else { 0.0 };
    // Seven significant digits at most, in exponent form for extreme powers (1e30 fits
    // its row); the exact value is kept until the user changes it.
    let mut drag_value = egui::DragValue::new(&mut stand_in)
        .speed(speed)
        .custom_formatter(|v, _| power_to_text(v));
    if !shown.is_finite() {
        drag_value = drag_value.custom_formatter(move |_, _| format!("{shown}"));
    }
    let drag = ui
        .add_sized([78.0, ROW_HEIGHT - 2.0], drag_value)
        .accessible_name(format!("power of {name}"))
        .on_hover_text(format!(
            "Power Φ of {name}: drag, or click and type (NaN and negative values are refused)"
        ));
    if drag.changed() {
        *p = stand_in;
        changed = true;
    }
    let mut slider_value = if p.is_finite() {
        p.clamp(0.0, slider_max)
    } else {
        0.0
    };
    let mut slider = egui::Slider::new(&mut slider_value, 0.0..=slider_max)
        .logarithmic(log)
        .smallest_positive(slider_max * 1e-6)
        .show_value(false);
    // Linear: the value under the pointer, snapped below to the finest round step one point
    // of the slider can hold, instead of egui's "simplest number under the pointer" (which
    // jumps 2 → 5 → 6 → 7 on 0–50). Snapped only when the user moves the slider: egui's
    // own `step_by` would round every shown power on every frame.
    let step = (!log).then(|| linear_slider_step(slider_max, ui.spacing().slider_width));
    if step.is_some() {
        slider = slider.smart_aim(false);
    }
    let slider = ui
        .add(slider)
        .accessible_name(format!("power slider of {name}"))
        .on_hover_text(format!("Drag to set the power of {name}"));
    if slider.changed() {
        *p = match step {
            Some(step) => ((slider_value / step).round() * step).min(slider_max),
            None => slider_value,
        };
        changed = true;
    }
    // A drag is one undo step, however many frames it changes the power in.
    if drag.drag_started() || slider.drag_started() {
        state.history.begin_gesture();
    }
    if changed {
        state.edit.powers_mut()[i] = power;
        let how = if drag.dragged() || slider.dragged() {
            "drag"
        } else {
            "power"
        };
        state.history.name_next(format!("{how} of {name}"));
    }
    if drag.drag_stopped() || slider.drag_stopped() {
        state.history.end_gesture();
    }
    changed
}

/// The step of a linear power slider over `0..=max` that is `width` points long: the
/// smallest of `1, 2, 5 × 10^k` that is at least `max / width`, so every step lies under
/// some point of the slider (on `0..=50` over 100 points: 0.5, and every integer power
/// can be reached by dragging). Arrow keys on a focused slider move by one step.
pub fn linear_slider_step(max: f64, width: f32) -> f64 {
    let least = max / f64::from(width.max(1.0));
    if !(least.is_finite() && least > 0.0) {
        return 1.0;
    }
    let decade = 10f64.powf(least.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|step| *step >= least * (1.0 - 1e-12))
        .unwrap_or(10.0 * decade)
}
