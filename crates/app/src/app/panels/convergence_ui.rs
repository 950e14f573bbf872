//! The convergence panel: log-log RMSE against samples per pixel and against seconds for the three
//! schemes (uniform, power, spatial), the `−1/2` slope of Monte Carlo convergence, efficiency
//! `1/(V̂·T)` (`V̂ = Var/Φ²`) and the speed-ups of power and spatial sampling over uniform
//! selection. The exact spatial pick (few lights) has zero variance: its RMSE is rounding only, its
//! efficiency infinite (shown as "∞").

use egui::Ui;
use egui_plot::{Legend, Line, LineStyle, Plot, PlotPoints};
use lightpick_core::{Scaled, Scheme};

use super::log_axes;
use crate::app::colors;
use crate::app::images::{ConvergencePoint, Published, SchemeImage};
use crate::app::state::AppState;
use crate::numbers;

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
    let a = &published.power;
    let sp = &published.spatial;
    let spatial_exact = published.spatial_is_exact();
    figures_ui(
        ui,
        [u, a, sp],
        pixels,
        spatial_exact,
        &published.time_source,
    );
    if u.series.is_empty() && a.series.is_empty() && sp.series.is_empty() {
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
    let power_points = log_points(&a.series);
    let spatial_points = if spatial_exact {
        Vec::new()
    } else {
        log_points(&sp.series)
    };
    if spatial_exact {
        ui.label("spatial: the exact contribution pick (few lights), zero variance: its RMSE is rounding, off the plot")
            .on_hover_text("p(i | x) ∝ p_i·G_i(x) makes every sample equal to the exact irradiance");
    }
    curves_plot_ui(
        ui,
        *axis,
        [uniform_points, power_points, spatial_points],
        state.dark(),
    );
}

/// The log-log plot of the three schemes' curves (`log10` points against `axis`) with the
/// `−1/2` slope through the first uniform point.
fn curves_plot_ui(
    ui: &mut Ui,
    axis: ConvergenceAxis,
    [uniform_points, power_points, spatial_points]: [Vec<[f64; 2]>; 3],
    dark: bool,
) {
    // The −1/2 slope through the first uniform point.
    let slope = uniform_points
        .first()
        .zip(uniform_points.last())
        .map(|(first, last)| {
            let x_end = last[0].max(first[0] + 1.0);
            vec![*first, [x_end, first[1] - 0.5 * (x_end - first[0])]]
        });
    let x_label = match axis {
        ConvergenceAxis::Spp => "samples per pixel (log scale)",
        ConvergenceAxis::Seconds => "render seconds, as T counts them (log scale)",
    };
    log_axes::log_log_plot(Plot::new(("convergence", axis == ConvergenceAxis::Spp)))
        .legend(Legend::default())
        .show_background(false)
        .height(ui.available_height().max(140.0))
        .x_axis_label(x_label)
        .y_axis_label("RMSE (log scale)")
        .show(ui, |plot_ui| {
            plot_ui.line(
                Line::new("uniform", PlotPoints::new(uniform_points))
                    .color(colors::scheme(Scheme::Uniform))
                    .width(2.0),
            );
            plot_ui.line(
                Line::new("power (alias)", PlotPoints::new(power_points))
                    .color(colors::scheme(Scheme::Alias))
                    .width(2.0),
            );
            plot_ui.line(
                Line::new("spatial (by contribution)", PlotPoints::new(spatial_points))
                    .color(colors::scheme(Scheme::Spatial))
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

/// The schemes of the panel, in display order, with their names.
const SCHEMES: [(&str, Scheme); 3] = [
    ("uniform", Scheme::Uniform),
    ("power", Scheme::Alias),
    ("spatial", Scheme::Spatial),
];

/// One row per scheme: variance and time per sample, efficiency `1/(V̂·T)`, and the
/// efficiency and variance ratios over uniform selection. With `spatial_exact` the spatial
/// row is the exact pick: variance 0 by construction (the measured rounding on hover),
/// efficiency ∞.
fn figures_ui(
    ui: &mut Ui,
    images: [&SchemeImage; 3],
    pixels: usize,
    spatial_exact: bool,
    time_source: &str,
) {
    let u = images[0];
    egui::Grid::new("convergence_figures")
        .striped(true)
        .num_columns(5)
        .show(ui, |ui| {
            for (text, tip) in [
                ("scheme", "How each light is picked"),
                (
                    "Var/sample",
                    "Mean per-pixel variance of one sample, in irradiance² units",
                ),
                ("T/sample", time_source),
                (
                    "1/(V/Φ²·T)",
                    "Efficiency: the inverse of variance times time, the variance taken per unit \
                     of total power Φ (the figure of lightpick bench; it does not change when \
                     every power is scaled, and its ratios are those of 1/(Var·T))",
                ),
                (
                    "vs uniform",
                    "Efficiency against uniform selection: how many times less (or more) time \
                     the scheme needs for the same error, and its variance per sample against \
                     uniform's",
                ),
            ] {
                ui.strong(text).on_hover_text(tip);
            }
            ui.end_row();
            for ((name, scheme), image) in SCHEMES.into_iter().zip(images) {
                ui.colored_label(colors::scheme(scheme), name);
                let exact = spatial_exact && scheme == Scheme::Spatial && image.spp > 0;
                let seconds = format!("{} s", numbers::short(image.seconds_per_sample(pixels)));
                if exact {
                    ui.label("0 (exact)").on_hover_text(format!(
                        "Every sample is the exact irradiance; the measured {} is rounding \
                         of the sums",
                        numbers::short_scaled(image.variance)
                    ));
                    ui.label(seconds);
                    ui.label("∞");
                    ui.label("∞ (zero variance)");
                } else {
                    ui.label(numbers::short_scaled(image.variance));
                    ui.label(seconds);
                    ui.label(
                        image
                            .efficiency(pixels)
                            .map_or("–".to_owned(), numbers::short_scaled),
                    );
                    ui.label(if scheme == Scheme::Uniform {
                        "baseline".to_owned()
                    } else {
                        speedup_text(u, image, pixels)
                    });
                }
                ui.end_row();
            }
        });
    ui.label(
        egui::RichText::new(format!("T: {time_source}"))
            .small()
            .color(colors::muted(ui.visuals().dark_mode)),
    )
    .on_hover_text(
        "lightpick bench times the same passes the same way (its GPU rows at the preset's \
         own resolution), so these figures are comparable with it",
    );
}

/// "efficiency 6.91× higher (variance 24.6× lower)": `image` against uniform, each factor
/// `≥ 1` with its direction word ([`numbers::compare`]); "–" before any sample.
fn speedup_text(u: &SchemeImage, image: &SchemeImage, pixels: usize) -> String {
    let speedup = u
        .efficiency(pixels)
        .zip(image.efficiency(pixels))
        .map(|(eu, e)| (e / eu).to_f64());
    // V̂ ratios are V ratios (same scene, same Φ_total), finite whatever the powers and
    // the geometry (each V̂ may lie beyond f64: divided as Scaled).
    let variance_ratio = (u.normalized_variance > Scaled::ZERO)
        .then(|| (image.normalized_variance / u.normalized_variance).to_f64());
    match (speedup, variance_ratio) {
        (Some(s), Some(v)) => format!(
            "efficiency {} (variance {})",
            numbers::compare(s, 1.0, "higher", "lower"),
            numbers::compare(v, 1.0, "higher", "lower")
        ),
        _ => "–".to_owned(),
    }
}
