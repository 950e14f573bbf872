//! The estimator view: the running estimate at one shading point, sample by sample, under
//! uniform and power picking (and spatial at a clicked pixel), where the seed
//! document's last claim — "more important values would come first and the result would
//! converge way faster" — can be watched.
//!
//! The plot shows each scheme's running estimate `F̂_n` against the number of samples `n`
//! (log axis) with its `±2σ` band from the running variance (`σ = √(s²/n)`) and the exact
//! value `F` as a line; the table puts the measured per-sample variance beside the analytic
//! one (`Σ f_i²/q_i − F²`: 366 and 14.85 on the worked example) and the samples each scheme needs for
//! a 1 % standard error, `n_1% = Var/(0.01·F)²`, with their ratio. Run / Step / Reset; the
//! streams are seeded (the app's seed), and a change of powers starts the run over with the
//! new contributions.

use egui::{RichText, Ui};
use egui_plot::{Legend, Line, LineStyle, Plot, PlotPoints};
use lightpick_core::Scaled;
use lightpick_core::point_estimate::{PointEstimator, samples_for_relative_error};

use super::log_axes;
use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::estimator::{EstimatorPoint, worked_example_uses_scene};
use crate::numbers;

/// The relative standard error the table's sample counts aim at.
const TARGET_RELATIVE_ERROR: f64 = 0.01;

/// The estimator window (View menu, the walkthrough's last step, the pixel inspector).
pub fn estimator_window(ctx: &egui::Context, state: &mut AppState) {
    if !state.estimator.open {
        return;
    }
    let mut open = true;
    let shown = egui::Window::new("Estimator at one point")
        .open(&mut open)
        .default_size([620.0, 560.0])
        .default_pos([super::walkthrough_ui::right_edge(ctx) - 640.0, 60.0])
        .show(ctx, |ui| estimator_ui(ui, state));
    // Opened by a click (the inspector's "Watch the estimate converge here", the
    // walkthrough): in front of the window the click came from.
    if std::mem::take(&mut state.estimator.raise)
        && let Some(shown) = shown
    {
        ctx.move_to_top(shown.response.layer_id);
    }
    if !open {
        state.estimator.open = false;
        state.estimator.running = false;
    }
    if state.estimator.running {
        ctx.request_repaint();
    }
}

/// The view's contents: the point, the controls, the plot and the table.
pub fn estimator_ui(ui: &mut Ui, state: &mut AppState) {
    let built = std::sync::Arc::clone(&state.built);
    let seed = state.settings.seed;
    if state.estimator.sync(&built, seed).is_none() {
        point_choice_ui(ui, state);
        let problem = state.estimator.problem.clone().unwrap_or_default();
        ui.colored_label(colors::error(state.dark()), problem);
        return;
    }
    state.estimator.run_frame();
    point_choice_ui(ui, state);
    controls_ui(ui, state);
    let dark = state.dark();
    let Some(estimator) = state.estimator.estimator() else {
        return;
    };
    point_sentence_ui(ui, state.estimator.point, estimator, &built, dark);
    ui.add_space(4.0);
    figures_ui(ui, estimator);
    ui.add_space(4.0);
    plot_ui(ui, estimator, dark);
}

/// Which point: the worked example's, or the pixel selected in the images.
fn point_choice_ui(ui: &mut Ui, state: &mut AppState) {
    ui.horizontal(|ui| {
        ui.label("Shading point:");
        let example_selected = state.estimator.point == EstimatorPoint::WorkedExample;
        if ui
            .selectable_label(example_selected, "the worked example's point")
            .on_hover_text("Three lights whose contributions are 1, 2 and 15 at powers 2, 5, 20")
            .clicked()
        {
            state.estimator.open_at(EstimatorPoint::WorkedExample);
        }
        match state.inspector.pixel {
            Some(pixel) => {
                let selected = state.estimator.point == EstimatorPoint::Pixel(pixel);
                if ui
                    .selectable_label(selected, format!("pixel ({}, {})", pixel[0], pixel[1]))
                    .on_hover_text("The pixel selected in the images (click one to change it)")
                    .clicked()
                {
                    state.estimator.open_at(EstimatorPoint::Pixel(pixel));
                }
            }
            None => {
                ui.label(RichText::new("(click a pixel of an image for its point)").weak());
            }
        }
    });
}

/// Run / Pause, Step, Reset and the sample count.
fn controls_ui(ui: &mut Ui, state: &mut AppState) {
    let samples = state
        .estimator
        .estimator()
        .map_or(0, PointEstimator::samples);
    ui.horizontal_wrapped(|ui| {
        let run_text = if state.estimator.running {
            "Pause"
        } else {
            "Run"
        };
        if ui
            .button(run_text)
            .on_hover_text("Add samples every frame, about 5 % more each time")
            .clicked()
        {
            state.estimator.running = !state.estimator.running;
        }
        for (label, count) in [("Step +1", 1), ("+10", 10), ("+1000", 1000)] {
            if ui
                .button(label)
                .on_hover_text(format!("Add {count} sample(s) to every scheme"))
                .clicked()
            {
                state.estimator.step(count);
            }
        }
        if ui
            .button("Reset samples")
            .on_hover_text("Start over from sample 0 (the same seeded samples again)")
            .clicked()
        {
            state.estimator.reset();
        }
        ui.label(format!(
            "n = {samples} samples per scheme · seed {}",
            state.settings.seed
        ));
    });
}

/// One sentence naming the point and its exact value.
fn point_sentence_ui(
    ui: &mut Ui,
    point: EstimatorPoint,
    estimator: &PointEstimator,
    built: &crate::app::state::built::Built,
    dark: bool,
) {
    let f = estimator.contributions();
    let text = match point {
        EstimatorPoint::WorkedExample => {
            let listed: Vec<String> = f.iter().map(|v| numbers::short(*v)).collect();
            let whose = if worked_example_uses_scene(built) {
                "the scene's three lights, f_i = Φ_i·g_i with g = 1/2, 2/5, 3/4"
            } else {
                "the classic powers 2, 5, 20 (this scene does not have three lights)"
            };
            format!(
                "The worked example's shading point: contributions f = {} ({whose}); exact total F = {}.",
                listed.join(", "),
                numbers::short(estimator.exact())
            )
        }
        EstimatorPoint::Pixel(pixel) => format!(
            "The centre of pixel ({}, {}): {} lights, f_i = Φ_i·G_i(x); exact irradiance F = {}.",
            pixel[0],
            pixel[1],
            f.len(),
            numbers::short(estimator.exact())
        ),
    };
    ui.label(RichText::new(text).color(colors::foreground(dark)));
}

/// One row per scheme: estimate, measured and analytic variance, samples for 1 %, ratio.
fn figures_ui(ui: &mut Ui, estimator: &PointEstimator) {
    let exact = estimator.exact();
    let needed = |var: Scaled| samples_for_relative_error(var, exact, TARGET_RELATIVE_ERROR);
    let uniform_variance = estimator
        .runs()
        .first()
        .map_or(Scaled::ZERO, |l| l.analytic.variance_scaled);
    let uniform_needed = (uniform_variance.significand() > 0.0).then(|| needed(uniform_variance));
    egui::Grid::new("estimator_figures")
        .striped(true)
        .num_columns(6)
        .show(ui, |ui| {
            for (text, tip) in [
                ("scheme", "How each sample picks a light"),
                (
                    "estimate ± 2σ",
                    "The running mean F̂_n and twice its standard error √(s²/n)",
                ),
                (
                    "Var measured",
                    "The sample variance s² of one sample so far",
                ),
                (
                    "Var analytic",
                    "Σ f_i²/q_i − F²: the exact variance of one sample",
                ),
                (
                    "n for 1 %",
                    "Samples until the standard error is 1 % of F: Var/(0.01·F)² (analytic)",
                ),
                (
                    "samples vs uniform",
                    "How many times fewer (or more) samples this scheme needs than uniform \
                     picking for the same error",
                ),
            ] {
                ui.strong(text).on_hover_text(tip);
            }
            ui.end_row();
            for run in estimator.runs() {
                let w = run.running();
                ui.colored_label(colors::scheme(run.scheme()), run.name);
                if w.count() == 0 {
                    ui.label("–");
                    ui.label("–");
                } else {
                    ui.label(format!(
                        "{} ± {}",
                        numbers::short_scaled(w.mean_scaled()),
                        numbers::short_scaled(w.std_error_scaled().mul_f64(2.0))
                    ));
                    ui.label(if w.count() < 2 {
                        "–".to_owned()
                    } else {
                        numbers::short_scaled(w.variance_scaled())
                    });
                }
                let variance = run.analytic.variance_scaled;
                // The exact pick's variance is the rounding of zero (the same rule as the
                // Convergence panel's), compared as a ratio: the same at any scale.
                let exact_pick = variance.significand() == 0.0
                    || lightpick_core::render::is_zero_variance(
                        (variance / uniform_variance).to_f64(),
                        1.0,
                    );
                ui.label(if exact_pick {
                    "0 (exact)".to_owned()
                } else {
                    numbers::short_scaled(variance)
                });
                let n = needed(variance);
                ui.label(if exact_pick {
                    "1 (exact)".to_owned()
                } else {
                    format!("{:.0}", n.ceil())
                });
                ui.label(match uniform_needed {
                    _ if exact_pick => "∞ (zero variance)".to_owned(),
                    Some(u) => numbers::compare(n, u, "more", "fewer"),
                    None => "–".to_owned(),
                });
                ui.end_row();
            }
        });
}

/// The running estimates against `log10 n`, their ±2σ bands and the exact value.
fn plot_ui(ui: &mut Ui, estimator: &PointEstimator, dark: bool) {
    let exact = estimator.exact();
    let last_x = (estimator.samples().max(10) as f64).log10();
    Plot::new("estimator_plot")
        .legend(Legend::default())
        .show_background(false)
        // Room for the note under the plot.
        .height(
            (ui.available_height() - 2.0 * ui.text_style_height(&egui::TextStyle::Small))
                .max(220.0),
        )
        .x_grid_spacer(log_axes::log_grid_marks)
        .x_axis_formatter(log_axes::log_tick_label)
        .x_axis_label("samples n (log scale)")
        .y_axis_label("running estimate")
        .include_y(exact)
        .show(ui, |plot_ui| {
            plot_ui.line(
                Line::new(
                    format!("exact F = {}", numbers::short(exact)),
                    PlotPoints::new(vec![[0.0, exact], [last_x, exact]]),
                )
                .color(colors::foreground(dark))
                .width(1.5),
            );
            for run in estimator.runs() {
                let color = colors::scheme(run.scheme());
                let series = run.series();
                let at = |p: &lightpick_core::point_estimate::EstimatePoint, k: f64| {
                    [(p.samples as f64).log10(), p.mean + k * p.std_error]
                };
                let mean: Vec<[f64; 2]> = series.iter().map(|p| at(p, 0.0)).collect();
                // The band starts where the running variance exists (two samples).
                let banded = series.iter().filter(|p| p.samples >= 2);
                let upper: Vec<[f64; 2]> = banded.clone().map(|p| at(p, 2.0)).collect();
                let lower: Vec<[f64; 2]> = banded.map(|p| at(p, -2.0)).collect();
                plot_ui.line(
                    Line::new(run.name, PlotPoints::new(mean))
                        .color(color)
                        .width(2.0),
                );
                // The same name and colour as the mean: one legend entry per scheme.
                for band in [upper, lower] {
                    plot_ui.line(
                        Line::new(run.name, PlotPoints::new(band))
                            .color(color)
                            .style(LineStyle::dashed_loose())
                            .width(1.0),
                    );
                }
            }
        });
    ui.label(
        RichText::new("dashed: ±2σ from the running variance; the x axis counts samples")
            .small()
            .color(colors::muted(dark)),
    );
}
