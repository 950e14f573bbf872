//! The convergence panel: log-log RMSE against samples per pixel and against seconds for
//! both schemes, the `−1/2` slope of Monte Carlo convergence, efficiency `1/(Var·T)` and the
//! speed-up of importance sampling over uniform selection.

use egui::Ui;
use egui_plot::{Legend, Line, LineStyle, Plot, PlotPoints};
use lightpick_core::Scheme;

use super::colors;
use super::engine::{ConvergencePoint, Published};
use super::fractions;
use super::state::AppState;

/// Which x axis the plot uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConvergenceAxis {
    /// Samples per pixel.
    Spp,
    /// Render seconds.
    Seconds,
}

/// The whole panel.
pub fn convergence_ui(
    ui: &mut Ui,
    state: &AppState,
    published: Option<&Published>,
    axis: &mut ConvergenceAxis,
) {
    ui.horizontal(|ui| {
        ui.heading("Convergence");
        ui.selectable_value(axis, ConvergenceAxis::Spp, "vs spp")
            .on_hover_text("RMSE against samples per pixel (log-log)");
        ui.selectable_value(axis, ConvergenceAxis::Seconds, "vs seconds")
            .on_hover_text("RMSE against render time (log-log): what equal-time comparisons see");
    });
    let Some(published) = published else {
        ui.label("no frames yet");
        return;
    };
    let pixels = published.width as usize * published.height as usize;
    let u = &published.uniform;
    let a = &published.importance;
    ui.horizontal_wrapped(|ui| {
        for (name, image) in [("uniform", u), ("importance", a)] {
            let eff = image.efficiency(pixels).map_or("–".to_owned(), fractions::short);
            ui.label(format!(
                "{name}: Var/sample {} · T/sample {} s · efficiency 1/(Var·T) {eff}",
                fractions::short(image.variance),
                fractions::short(image.seconds_per_sample(pixels)),
            ))
            .on_hover_text("Mean per-pixel variance of one sample, time per pixel sample, and their inverse product");
        }
    });
    let speedup = u
        .efficiency(pixels)
        .zip(a.efficiency(pixels))
        .map(|(eu, ea)| ea / eu);
    let variance_ratio = (a.variance > 0.0).then(|| u.variance / a.variance);
    ui.label(
        egui::RichText::new(format!(
            "speed-up of importance over uniform: {}× (variance ratio {}×)",
            speedup.map_or("–".to_owned(), fractions::short),
            variance_ratio.map_or("–".to_owned(), fractions::short),
        ))
        .strong(),
    )
    .on_hover_text(
        "Efficiency ratio: how much less time importance sampling needs for the same error",
    );
    if u.series.is_empty() && a.series.is_empty() {
        ui.label(
            published
                .reference_note
                .clone()
                .unwrap_or_else(|| "run a few frames to see the curves".to_owned()),
        );
        return;
    }
    let x_of = |p: &ConvergencePoint| match axis {
        ConvergenceAxis::Spp => f64::from(p.spp),
        ConvergenceAxis::Seconds => p.seconds,
    };
    let log_points = |series: &[ConvergencePoint]| -> Vec<[f64; 2]> {
        series
            .iter()
            .filter(|p| p.rmse > 0.0 && x_of(p) > 0.0)
            .map(|p| [x_of(p).log10(), p.rmse.log10()])
            .collect()
    };
    let uniform_points = log_points(&u.series);
    let importance_points = log_points(&a.series);
    // The −1/2 slope through the first uniform point.
    let slope = uniform_points
        .first()
        .zip(uniform_points.last())
        .map(|(first, last)| {
            let x_end = last[0].max(first[0] + 1.0);
            vec![*first, [x_end, first[1] - 0.5 * (x_end - first[0])]]
        });
    let x_label = match axis {
        ConvergenceAxis::Spp => "log10 spp",
        ConvergenceAxis::Seconds => "log10 seconds",
    };
    let dark = state.dark();
    Plot::new(("convergence", *axis == ConvergenceAxis::Spp))
        .legend(Legend::default())
        .show_background(false)
        .height(ui.available_height().max(140.0))
        .x_axis_label(x_label)
        .y_axis_label("log10 RMSE")
        .x_axis_formatter(|mark, _| format!("1e{}", mark.value))
        .y_axis_formatter(|mark, _| format!("1e{}", mark.value))
        .show(ui, |plot_ui| {
            plot_ui.line(
                Line::new("uniform", PlotPoints::new(uniform_points))
                    .color(colors::scheme(Scheme::Uniform))
                    .width(2.0),
            );
            plot_ui.line(
                Line::new("importance (alias)", PlotPoints::new(importance_points))
                    .color(colors::scheme(Scheme::Alias))
                    .width(2.0),
            );
            if let Some(slope) = slope {
                plot_ui.line(
                    Line::new("slope −1/2", PlotPoints::new(slope))
                        .color(colors::muted(dark))
                        .style(LineStyle::dashed_loose()),
                );
            }
        });
}
