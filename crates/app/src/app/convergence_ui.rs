//! The convergence panel: log-log RMSE against samples per pixel and against seconds for
//! the three schemes (uniform, importance, spatial), the `−1/2` slope of Monte Carlo
//! convergence, efficiency `1/(Var·T)` and the speed-ups of importance and spatial sampling
//! over uniform selection. The exact spatial pick (few lights) has zero variance: its RMSE
//! is rounding only, its efficiency infinite (shown as "∞").

use egui::Ui;
use egui_plot::{Legend, Line, LineStyle, Plot, PlotPoints};
use lightpick_core::Scheme;

use super::colors;
use super::engine::{ConvergencePoint, Published, SchemeImage};
use super::fractions;
use super::state::AppState;

/// A variance below this fraction of the uniform scheme's is the rounding of a zero-variance
/// estimator (the exact spatial pick): `Σê² − (Σê)²/n` cancels to about `10^-16` relative in
/// `f64`. Such a scheme is shown with an infinite efficiency and left off the plot, whose
/// log axis it would otherwise stretch over sixteen decades.
pub(crate) const ZERO_VARIANCE_RTOL: f64 = 1e-12;

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
    let sp = &published.spatial;
    ui.horizontal_wrapped(|ui| {
        for (name, image) in [("uniform", u), ("importance", a), ("spatial", sp)] {
            let eff = efficiency_text(image, u, pixels);
            ui.label(format!(
                "{name}: Var/sample {} · T/sample {} s · efficiency 1/(Var·T) {eff}",
                fractions::short(image.variance),
                fractions::short(image.seconds_per_sample(pixels)),
            ))
            .on_hover_text("Mean per-pixel variance of one sample, time per pixel sample, and their inverse product");
        }
    });
    for (name, image) in [("importance", a), ("spatial", sp)] {
        ui.label(egui::RichText::new(speedup_text(name, u, image, pixels)).strong())
            .on_hover_text(format!(
                "Efficiency ratio: how much less time {name} sampling needs for the same error"
            ));
    }
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
    let importance_points = log_points(&a.series);
    let spatial_exact = zero_variance(sp, u);
    let spatial_points = if spatial_exact {
        Vec::new()
    } else {
        log_points(&sp.series)
    };
    if spatial_exact {
        ui.label("spatial: the exact contribution pick (few lights), zero variance: its RMSE is rounding, off the plot")
            .on_hover_text("p(i | x) ∝ p_i·G_i(x) makes every sample equal to the exact irradiance");
    }
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

/// Whether `image` has zero variance up to rounding (see [`ZERO_VARIANCE_RTOL`]).
fn zero_variance(image: &SchemeImage, uniform: &SchemeImage) -> bool {
    image.spp >= 2 && is_zero_variance(image.variance, uniform.variance)
}

/// Whether a variance per sample is the rounding of zero next to a `reference` variance
/// (the uniform scheme's, or the largest measured): `v ≤` [`ZERO_VARIANCE_RTOL`]` · reference`.
pub(crate) fn is_zero_variance(variance: f64, reference: f64) -> bool {
    reference > 0.0 && variance <= ZERO_VARIANCE_RTOL * reference
}

/// `1/(Var·T)` of one image: "∞" for zero variance (up to rounding), "–" before any sample.
fn efficiency_text(image: &SchemeImage, uniform: &SchemeImage, pixels: usize) -> String {
    if zero_variance(image, uniform) && uniform.variance > 0.0 {
        return "∞".to_owned();
    }
    image
        .efficiency(pixels)
        .map_or("–".to_owned(), fractions::short)
}

/// "speed-up of NAME over uniform: E× (variance ratio V×)", "∞" for zero variance.
fn speedup_text(name: &str, u: &SchemeImage, image: &SchemeImage, pixels: usize) -> String {
    if zero_variance(image, u) && u.variance > 0.0 {
        return format!("speed-up of {name} over uniform: ∞ (zero variance)");
    }
    let speedup = u
        .efficiency(pixels)
        .zip(image.efficiency(pixels))
        .map(|(eu, e)| e / eu);
    let variance_ratio = (image.variance > 0.0).then(|| u.variance / image.variance);
    format!(
        "speed-up of {name} over uniform: {}× (variance ratio {}×)",
        speedup.map_or("–".to_owned(), fractions::short),
        variance_ratio.map_or("–".to_owned(), fractions::short),
    )
}
