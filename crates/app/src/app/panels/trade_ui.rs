//! The trade-off panel: for the current scene, what each sampling scheme costs and buys — time per
//! sample `T`, variance per sample `V`, efficiency `1/(V̂·T)` (`V̂ = V/Φ²`) — and where each scheme
//! and each samples-per-pixel count sits on the error-against-time plane.
//!
//! The figures come from a small copy of the scene (at most [`TRADE_SIDE`] pixels a side),
//! one fresh [`CpuRenderer`](lightpick_core::render::CpuRenderer) per scheme run to
//! [`TRADE_MAX_SPP`] samples per pixel with
//! [`convergence_series`](lightpick_core::render::convergence_series) (three times, keeping
//! the fastest time of each point), against an exact
//! [`Reference`](lightpick_core::render::Reference). The measurement runs on a background
//! thread in the app (the window never waits for it, even at `10^6` lights) and inline with
//! virtual timings in tests (deterministic snapshots).

use egui::Ui;
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};
use lightpick_core::Scaled;
use lightpick_core::render::SeriesPoint;

use super::log_axes;
use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::rebuild::SYNC_BUILD_LIMIT;
use crate::app::state::trade::{
    TRADE_MAX_SPP, TRADE_SIDE, TradeMeasurement, TradeRow, measure, scheme_label,
};
use crate::numbers;

/// The whole panel.
pub fn trade_ui(ui: &mut Ui, state: &mut AppState) {
    state.trade.poll();
    let generation = state.built.generation;
    let stale = state.trade.is_stale(generation);
    // Small scenes are measured as soon as they change; large ones on request.
    if stale && !state.trade.is_measuring() && state.built.len() <= SYNC_BUILD_LIMIT {
        let scene = std::sync::Arc::clone(&state.built.scene);
        state
            .trade
            .start(generation, "lightpick-trade", move |inline| {
                measure(generation, &scene, inline)
            });
    }
    ui.horizontal(|ui| {
        ui.label("Speed against accuracy, measured for each scheme on this scene");
        if ui
            .add_enabled(!state.trade.is_measuring(), egui::Button::new("Measure"))
            .on_hover_text(format!(
                "Render the scene at most {TRADE_SIDE}×{TRADE_SIDE} pixels with each scheme \
                 up to {TRADE_MAX_SPP} samples per pixel, in the background"
            ))
            .on_disabled_hover_text("A measurement is running")
            .clicked()
        {
            let scene = std::sync::Arc::clone(&state.built.scene);
            state
                .trade
                .start(generation, "lightpick-trade", move |inline| {
                    measure(generation, &scene, inline)
                });
        }
        if state.trade.is_measuring() {
            ui.spinner().on_hover_text("Measuring in the background");
            ui.label("measuring: the images pause until it is done");
            // Look for the result even while the app is paused and idle.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
    });
    let dark = state.dark();
    let Some(m) = &state.trade.result else {
        ui.label("press Measure to time each scheme on this scene");
        return;
    };
    let still_stale = m.generation != generation;
    let clock = if m.virtual_time {
        "virtual timings (test mode)".to_owned()
    } else {
        format!(
            "T = core time per pixel sample (the CPU time of the {} render threads in the \
             passes), as `lightpick bench`'s \"core ns\"",
            m.threads
        )
    };
    let mut note = format!(
        "CPU renderer, {}×{} pixels, reference over {} pixels, {} spp per scheme, measured \
         with the images paused; the plot's points and the table's T are the same timings; \
         {clock}",
        m.size[0], m.size[1], m.reference_pixels, TRADE_MAX_SPP
    );
    if still_stale {
        note.push_str(" · scene changed since: press Measure");
    }
    ui.label(egui::RichText::new(note).color(colors::muted(dark)))
        .on_hover_text("What the figures below were measured on");
    figures_ui(ui, m);
    let largest = largest_variance(m);
    if let Some(row) = m.rows.iter().find(|r| is_exact(r, largest)) {
        ui.label(
            egui::RichText::new(format!(
                "{}: zero variance (the exact pick p(i | x) ∝ p_i·G_i(x)), off the plot",
                scheme_label(row.scheme)
            ))
            .color(colors::muted(dark)),
        );
    }
    plot_ui(ui, m, state.settings.spp_per_frame, dark);
}

/// The largest normalized variance per sample measured (`V̂ = V/Φ_total²`, the same at any
/// scale of the powers): what a zero variance is judged against.
fn largest_variance(m: &TradeMeasurement) -> Scaled {
    m.rows
        .iter()
        .map(|r| r.efficiency.normalized_variance)
        .fold(Scaled::ZERO, larger)
}

/// The larger of two figures (`a` when they are not ordered).
fn larger(a: Scaled, b: Scaled) -> Scaled {
    if b > a { b } else { a }
}

/// Whether a row is a zero-variance estimator up to rounding (the exact spatial pick).
fn is_exact(row: &TradeRow, largest: Scaled) -> bool {
    lightpick_core::render::is_zero_variance_scaled(row.efficiency.normalized_variance, largest)
}

/// The table of `T`, `V`, `1/(V̂·T)` and the final RMSE per scheme. A zero-variance row (the
/// exact spatial pick on few lights) has an infinite efficiency, shown as "∞ (exact)" and left
/// out of the relative column's best.
fn figures_ui(ui: &mut Ui, m: &TradeMeasurement) {
    let largest = largest_variance(m);
    let best = m
        .rows
        .iter()
        .filter(|r| !is_exact(r, largest))
        .map(|r| r.efficiency.efficiency)
        .filter(|e| e.is_finite())
        .fold(Scaled::ZERO, larger);
    egui::Grid::new("trade_figures")
        .striped(true)
        .spacing([14.0, 3.0])
        .show(ui, |ui| {
            ui.strong("scheme")
                .on_hover_text("How the light of each sample is picked");
            ui.strong("T (ns/sample)")
                .on_hover_text("Render time per pixel sample, in nanoseconds");
            ui.strong("V (per sample)").on_hover_text(
                "Mean per-pixel variance of one sample's estimate, in irradiance² units",
            );
            ui.strong("1/(V/Φ²·T) (1/s)").on_hover_text(
                "Efficiency: higher reaches a given error sooner (per second of render time). \
                 V/Φ² is the variance in units of the total power Φ, so the figure does not \
                 change when every power is scaled; its ratios are those of 1/(V·T)",
            );
            ui.strong("relative")
                .on_hover_text("Efficiency over the most efficient scheme");
            ui.strong(format!("RMSE @ {TRADE_MAX_SPP} spp"))
                .on_hover_text("Error against the exact image at the last point of the series");
            ui.end_row();
            for row in &m.rows {
                let e = row.efficiency;
                ui.colored_label(colors::scheme(row.scheme), scheme_label(row.scheme));
                ui.label(numbers::short(e.seconds_per_sample * 1e9));
                ui.label(numbers::short_scaled(Scaled::from_log10(e.variance_log10)));
                let exact = is_exact(row, largest);
                ui.label(if exact {
                    "∞ (exact)".to_owned()
                } else {
                    numbers::short_scaled(e.efficiency)
                });
                let relative = if exact {
                    "∞".to_owned()
                } else if best > Scaled::ZERO && e.efficiency.is_finite() {
                    format!("{:.0}%", 100.0 * (e.efficiency / best).to_f64())
                } else {
                    "–".to_owned()
                };
                ui.label(relative);
                ui.label(
                    row.series
                        .last()
                        .map_or("–".to_owned(), |p| numbers::short(p.rmse)),
                );
                ui.end_row();
            }
        });
}

/// RMSE against seconds, log-log, one curve per scheme; each point is a samples-per-pixel
/// count, and the app's own spp per frame is ringed.
fn plot_ui(ui: &mut Ui, m: &TradeMeasurement, spp_per_frame: u32, dark: bool) {
    let log = |p: &SeriesPoint| {
        (p.rmse > 0.0 && p.seconds > 0.0).then(|| [p.seconds.log10(), p.rmse.log10()])
    };
    log_axes::log_log_plot(Plot::new("trade_plot"))
        .legend(Legend::default())
        .show_background(false)
        .height(ui.available_height().max(160.0))
        .x_axis_label("core seconds (render threads' CPU time, log scale)")
        .y_axis_label("RMSE (irradiance, log scale)")
        .show(ui, |plot_ui| {
            let largest = largest_variance(m);
            // A zero-variance row's RMSE is rounding (~1e-16): off the plot, which it would
            // stretch over sixteen decades (the table lists it).
            for row in m.rows.iter().filter(|r| !is_exact(r, largest)) {
                let points: Vec<[f64; 2]> = row.series.iter().filter_map(log).collect();
                let color = colors::scheme(row.scheme);
                plot_ui.line(
                    Line::new(scheme_label(row.scheme), PlotPoints::new(points.clone()))
                        .color(color)
                        .width(2.0),
                );
                plot_ui.points(
                    Points::new(scheme_label(row.scheme), PlotPoints::new(points))
                        .color(color)
                        .radius(3.0),
                );
            }
            // The app's spp per frame: the nearest measured count on each curve.
            let ringed: Vec<[f64; 2]> = m
                .rows
                .iter()
                .filter(|r| !is_exact(r, largest))
                .filter_map(|row| {
                    row.series
                        .iter()
                        .min_by_key(|p| p.spp.abs_diff(spp_per_frame))
                        .and_then(log)
                })
                .collect();
            plot_ui.points(
                Points::new(
                    format!("spp/frame = {spp_per_frame}"),
                    PlotPoints::new(ringed),
                )
                .color(colors::foreground(dark))
                .filled(false)
                .radius(7.0),
            );
        });
}
