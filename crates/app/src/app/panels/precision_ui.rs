//! The precision panel: what each numerical choice of the alias table costs on the current
//! powers, from `lightpick_core::precision` (the figures of `lightpick precision`):
//! `f32` against `f64` construction, `u32` against `f32` thresholds, the column pick
//! `f32(u)·N` against multiply-high, and one random against two.
//!
//! The figures are exact counts over the whole table (`O(N)`, plus `2^24` inputs for the
//! `f32` column pick), so they are computed on a background thread in the app — a second or
//! so at `10^6` lights — and inline in tests.

use std::sync::Arc;

use egui::Ui;

use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::precision::{PrecisionMeasurement, measure};
use crate::app::state::rebuild::SYNC_BUILD_LIMIT;
use crate::numbers;
use lightpick_core::precision::PrecisionReport;

/// The whole panel.
pub fn precision_ui(ui: &mut Ui, state: &mut AppState) {
    measure_ui(ui, state);
    let generation = state.built.generation;
    let dark = state.dark();
    let Some(m) = &state.precision.result else {
        ui.label("press Measure to compute the figures for these powers");
        return;
    };
    let r = &m.report;
    let mut note = format!("{} lights, {} of zero power", r.n, r.zero_lights);
    if m.generation != generation {
        note.push_str(" · scene changed since: press Measure");
    }
    ui.label(egui::RichText::new(note).color(colors::muted(dark)))
        .on_hover_text("The powers these figures were computed for");
    egui::Grid::new("precision_figures")
        .striped(true)
        .spacing([14.0, 3.0])
        .show(ui, |ui| {
            header_row_ui(ui);
            construction_rows_ui(ui, r);
            threshold_rows_ui(ui, r);
            column_pick_rows_ui(ui, m);
            one_random_rows_ui(ui, r);
        });
    ui.add_space(4.0);
    notes_ui(ui, dark);
}

/// The Measure button and the measurement's start: at once for small tables, on request
/// for large ones.
fn measure_ui(ui: &mut Ui, state: &mut AppState) {
    state.precision.poll();
    let generation = state.built.generation;
    let stale = state.precision.is_stale(generation);
    // Small tables are measured as soon as they change; large ones on request.
    if stale && !state.precision.is_measuring() && state.built.len() <= SYNC_BUILD_LIMIT {
        let scene = Arc::clone(&state.built.scene);
        state
            .precision
            .start(generation, "lightpick-precision", move |_| {
                measure(generation, &scene.powers)
            });
    }
    ui.horizontal(|ui| {
        ui.heading("Precision of the table");
        if ui
            .add_enabled(
                !state.precision.is_measuring(),
                egui::Button::new("Measure"),
            )
            .on_hover_text(
                "Count exactly what each numerical shortcut does to these powers \
                 (in the background; about a second at a million lights)",
            )
            .on_disabled_hover_text("A measurement is running")
            .clicked()
        {
            let scene = Arc::clone(&state.built.scene);
            state
                .precision
                .start(generation, "lightpick-precision", move |_| {
                    measure(generation, &scene.powers)
                });
        }
        if state.precision.is_measuring() {
            ui.spinner().on_hover_text("Measuring in the background");
            // Look for the result even while the app is paused and idle.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
    });
}

/// The grid's column titles.
fn header_row_ui(ui: &mut Ui) {
    ui.strong("question")
        .on_hover_text("Which numerical choice is compared");
    ui.strong("figure").on_hover_text("What is measured");
    ui.strong("careful").on_hover_text(
        "The project's choice (f64 build, u32 thresholds, multiply-high, two randoms)",
    );
    ui.strong("shortcut")
        .on_hover_text("The naive or faster alternative");
    ui.end_row();
}

/// Question 1: the table built in `f64` against `f32`, and the exact build against the
/// integer one.
fn construction_rows_ui(ui: &mut Ui, r: &PrecisionReport) {
    let (a, b) = (r.construction.f64_build, r.construction.f32_build);
    ui.label("1. build in f64 / f32")
        .on_hover_text("The table built in f64 (the project) against a naive f32 Vose build");
    ui.label("leak onto zero lights");
    ui.label(format!(
        "{} ({} lights)",
        numbers::short(a.zero_leak),
        a.leaking_lights
    ))
    .on_hover_text("Probability the f64 table picks a light of zero power");
    ui.label(format!(
        "{} ({} lights)",
        numbers::short(b.zero_leak),
        b.leaking_lights
    ))
    .on_hover_text("Probability the f32 table picks a light of zero power");
    ui.end_row();
    ui.label("");
    ui.label("max relative error");
    ui.label(numbers::short(a.max_rel_error));
    ui.label(numbers::short(b.max_rel_error));
    ui.end_row();
    let int = r.construction.integer_build;
    ui.label("1b. build exact f64 / integer").on_hover_text(
        "The exact f64 construction against the fast integer one (the samplers' default)",
    );
    ui.label("worst error")
        .on_hover_text("The integer table realizes exactly integer masses summing to N·2^32: below 1 unit of 2^-32/N unless some p_i < 2^-32/N (then at most 1 + a_i)");
    ui.label(format!("{} relative", numbers::short(a.max_rel_error)))
        .on_hover_text("The exact f64 table: relative error, as above");
    ui.label(format!(
        "{} × 2^-32/N, leak {}",
        numbers::short(r.construction.integer_max_error_units),
        numbers::short(int.zero_leak)
    ))
    .on_hover_text("The integer table (the samplers' default): absolute error of the pmf it samples, and its probability on zero lights");
    ui.end_row();
}

/// Question 2: thresholds stored as `u32` against `f32`.
fn threshold_rows_ui(ui: &mut Ui, r: &PrecisionReport) {
    let t = r.thresholds;
    ui.label("2. thresholds u32 / f32").on_hover_text(
        "Thresholds stored as 32-bit integers against f32 floats compared with a 24-bit uniform",
    );
    ui.label("pmf error / its bound");
    ui.label(format!(
        "{} (bound {})",
        numbers::short(t.u32_error_over_bound),
        numbers::short(t.u32_bound_max)
    ))
    .on_hover_text(
        "Measured error over (1+a_i)·2^-32/N (at most 1), and the bound's largest value",
    );
    ui.label(format!(
        "{} (bound {})",
        numbers::short(t.f32_error_over_bound),
        numbers::short(t.f32_bound_max)
    ))
    .on_hover_text(
        "Measured error over (1+a_i)·1.5·2^-24/N (at most 1), and the bound's largest value",
    );
    ui.end_row();
    ui.label("");
    ui.label("max relative error · lost lights");
    ui.label(format!(
        "{} · {}",
        numbers::short(t.u32_max_rel_error),
        t.u32_lost_lights
    ));
    ui.label(format!(
        "{} · {}",
        numbers::short(t.f32_max_rel_error),
        t.f32_lost_lights
    ));
    ui.end_row();
}

/// Question 3: the column pick by multiply-high against `f32(u)·N`.
fn column_pick_rows_ui(ui: &mut Ui, m: &PrecisionMeasurement) {
    ui.label("3. column pick").on_hover_text(
        "⌊r·N/2^32⌋ (multiply-high, one draw) against ⌊f32(u)·N⌋ with a 24-bit f32 \
             uniform. The default path also redraws the 2^32 mod N draws that would make \
             columns unequal, so its columns are exactly uniform.",
    );
    ui.label("unreachable columns");
    ui.label(
        m.multiply_high
            .map_or("–".to_owned(), |s| s.unreachable.to_string()),
    );
    ui.label(m.f32_pick.map_or("–".to_owned(), |s| {
        format!(
            "{} ({})",
            s.unreachable,
            numbers::short(s.unreachable_share)
        )
    }))
    .on_hover_text("Columns no f32 uniform reaches, and their share of all columns");
    ui.end_row();
    ui.label("");
    ui.label("max/min column frequency");
    // The same digits on both sides, enough to show how far each is from 1.
    let ratios = [
        m.multiply_high.as_ref().map(|s| s.max_min_ratio),
        m.f32_pick.as_ref().map(|s| s.max_min_ratio),
    ];
    let shown = numbers::near_one(ratios.map(|r| r.unwrap_or(1.0)));
    for (ratio, text) in ratios.iter().zip(shown) {
        ui.label(if ratio.is_some() {
            text
        } else {
            "–".to_owned()
        });
    }
    ui.end_row();
}

/// Question 4: two randoms against one.
fn one_random_rows_ui(ui: &mut Ui, r: &PrecisionReport) {
    let o = r.one_random;
    ui.label("4. two randoms / one").on_hover_text(
        "The default path (an exactly uniform column, then an independent keep draw) \
         against one random whose fraction is reused",
    );
    ui.label("max relative error vs p");
    ui.label(numbers::short(o.exact_max_rel_error));
    ui.label(numbers::short(o.one_max_rel_error));
    ui.end_row();
    ui.label("");
    ui.label("bias (total variation)");
    ui.label(numbers::short(o.exact_total_variation))
        .on_hover_text("½ Σ|P(i) − p_i| of the default path: only the u32 thresholds' rounding");
    ui.label(numbers::short(o.one_total_variation))
        .on_hover_text("½ Σ|P_one(i) − p_i|: how far the realized pmf is from p");
    ui.end_row();
}

/// What each question's figures mean, one small muted paragraph each.
fn notes_ui(ui: &mut Ui, dark: bool) {
    let explain = |ui: &mut Ui, text: &str| {
        ui.label(egui::RichText::new(text).color(colors::muted(dark)).small());
    };
    explain(
        ui,
        "1. An f32 build rounds the sum and every scaled power: leftovers forced to 1 can hand \
         probability to lights that emit nothing. The f64 build keeps zero lights at exactly 0.",
    );
    explain(
        ui,
        "1b. The integer build (the samplers' default, several times faster) makes integer \
         masses summing to N·2^32 and sweeps them exactly: no rounding after that, so its pmf \
         is within 2^-32/N of p_i.",
    );
    explain(
        ui,
        "2. A u32 threshold moves each column's split by at most 2^-32; an f32 threshold with a \
         24-bit uniform by up to 1.5·2^-24, 384 times more, and very dim lights can be lost.",
    );
    explain(
        ui,
        "3. A 24-bit f32 uniform has only 2^24 values: beyond about 16 million lights some \
         columns can never be picked. Multiply-high reaches every column almost equally.",
    );
    explain(
        ui,
        "4. Reusing the column pick's leftover fraction saves a random number; the bias it adds \
         is of the order of 2^-32, far below Monte Carlo noise.",
    );
}
