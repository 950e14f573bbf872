//! The trade-off panel: for the current scene, what each sampling scheme costs and buys —
//! time per sample `T`, variance per sample `V`, efficiency `1/(V·T)` — and where each
//! scheme and each samples-per-pixel count sits on the error-against-time plane.
//!
//! The figures come from a small copy of the scene (at most [`TRADE_SIDE`] pixels a side),
//! one fresh [`CpuRenderer`] per scheme run to [`TRADE_MAX_SPP`] samples per pixel with
//! [`convergence_series`] (three times, keeping the fastest time of each point), against an
//! exact [`Reference`]. The measurement runs on a
//! background thread in the app (the window never waits for it, even at `10^6` lights) and
//! inline with virtual timings in tests (deterministic snapshots).

use egui::Ui;
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};
use lightpick_core::Scheme;
use lightpick_core::render::{
    CpuRenderer, Efficiency, Reference, SeriesPoint, convergence_series, efficiency,
};
use lightpick_core::scene::Scene;

use super::colors;
use super::fractions;
use super::log_axes;
use super::state::{AppState, SYNC_BUILD_LIMIT};

/// The measurement image is at most this many pixels a side.
pub const TRADE_SIDE: u32 = 64;
/// Samples per pixel of each scheme's series (`1, 2, 4, …, 64`).
pub const TRADE_MAX_SPP: u32 = 64;
/// Timed runs of each series (the fastest time of each point is kept).
const TRADE_REPEATS: u32 = 3;
/// Light-pixel evaluations of the measurement's reference (a pixel subset beyond it).
const TRADE_REFERENCE_BUDGET: u64 = 1 << 24;
/// Virtual seconds per pixel sample in inline (test) mode, the engine's figure.
const VIRTUAL_SECONDS_PER_SAMPLE: f64 = 1.0e-8;
/// The schemes measured, in display order.
pub const TRADE_SCHEMES: [Scheme; 5] = [
    Scheme::Uniform,
    Scheme::Cdf,
    Scheme::Alias,
    Scheme::AliasOneRandom,
    Scheme::Spatial,
];

/// The display name of a scheme in this panel.
pub fn scheme_label(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Uniform => "uniform",
        Scheme::Cdf => "cdf (binary search)",
        Scheme::Alias => "alias, two randoms",
        Scheme::AliasOneRandom => "alias, one random",
        Scheme::Spatial => "spatial (by contribution)",
    }
}

/// One scheme's measured figures.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeRow {
    /// The scheme.
    pub scheme: Scheme,
    /// RMSE and cumulative seconds at `1, 2, 4, …` samples per pixel.
    pub series: Vec<SeriesPoint>,
    /// Variance, time and efficiency at the last point.
    pub efficiency: Efficiency,
}

/// Every scheme measured on one scene generation.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeMeasurement {
    /// The scene generation measured.
    pub generation: u64,
    /// Image size measured.
    pub size: [u32; 2],
    /// Pixels the reference covers.
    pub reference_pixels: usize,
    /// Whether the timings are virtual (inline mode).
    pub virtual_time: bool,
    /// One row per scheme of [`TRADE_SCHEMES`].
    pub rows: Vec<TradeRow>,
}

/// The panel's measurement: the latest result and the one being computed (inline mode
/// uses virtual timings).
pub type TradeRun = super::background::Background<TradeMeasurement>;

/// The scene at most [`TRADE_SIDE`] pixels a side (same plane extent, coarser pixels).
fn small_scene(scene: &Scene) -> Scene {
    let mut small = scene.clone();
    let (w, h) = (scene.plane.width.max(1), scene.plane.height.max(1));
    let scale = (f64::from(TRADE_SIDE) / f64::from(w.max(h))).min(1.0);
    small.plane.width = ((f64::from(w) * scale).round() as u32).max(1);
    small.plane.height = ((f64::from(h) * scale).round() as u32).max(1);
    small
}

/// Measures every scheme of [`TRADE_SCHEMES`] on a small copy of `scene`.
pub fn measure(generation: u64, scene: &Scene, virtual_time: bool) -> TradeMeasurement {
    let small = small_scene(scene);
    let reference = Reference::with_budget(&small, TRADE_REFERENCE_BUDGET);
    let pixels = small.plane.pixel_count() as f64;
    let rows = TRADE_SCHEMES
        .iter()
        .map(|&scheme| {
            let mut renderer = CpuRenderer::new(&small, scheme, 1);
            let mut series = convergence_series(&mut renderer, &reference, TRADE_MAX_SPP);
            // The same (deterministic) series again: the fastest time of each point, so a
            // cold cache or a busy core does not bend one curve.
            for _ in 1..TRADE_REPEATS {
                renderer.reset();
                let again = convergence_series(&mut renderer, &reference, TRADE_MAX_SPP);
                for (p, q) in series.iter_mut().zip(&again) {
                    p.seconds = p.seconds.min(q.seconds);
                }
            }
            if virtual_time {
                for p in &mut series {
                    p.seconds = f64::from(p.spp) * pixels * VIRTUAL_SECONDS_PER_SAMPLE;
                }
            }
            let seconds = series.last().map_or(0.0, |p| p.seconds);
            TradeRow {
                scheme,
                efficiency: efficiency(renderer.accumulator(), seconds),
                series,
            }
        })
        .collect();
    TradeMeasurement {
        generation,
        size: [small.plane.width, small.plane.height],
        reference_pixels: reference.pixels().len(),
        virtual_time,
        rows,
    }
}

/// The whole panel.
pub fn trade_ui(ui: &mut Ui, state: &mut AppState) {
    state.trade.poll();
    let generation = state.built.generation;
    let stale = state
        .trade
        .result
        .as_ref()
        .is_none_or(|m| m.generation != generation);
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
        ui.heading("Speed against accuracy");
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
    let mut note = format!(
        "{}×{} pixels, reference over {} pixels, {} spp per scheme",
        m.size[0], m.size[1], m.reference_pixels, TRADE_MAX_SPP
    );
    if m.virtual_time {
        note.push_str(" · virtual timings (test mode)");
    }
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

/// The largest variance per sample measured: what a zero variance is judged against.
fn largest_variance(m: &TradeMeasurement) -> f64 {
    m.rows
        .iter()
        .map(|r| r.efficiency.variance_per_sample)
        .fold(0.0f64, f64::max)
}

/// Whether a row is a zero-variance estimator up to rounding (the exact spatial pick).
fn is_exact(row: &TradeRow, largest: f64) -> bool {
    lightpick_core::render::is_zero_variance(row.efficiency.variance_per_sample, largest)
}

/// The table of `T`, `V`, `1/(V·T)` and the final RMSE per scheme. A zero-variance row (the
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
        .fold(0.0f64, f64::max);
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
            ui.strong("1/(V·T) (1/s)").on_hover_text(
                "Efficiency: higher reaches a given error sooner (per second of render time)",
            );
            ui.strong("relative")
                .on_hover_text("Efficiency over the most efficient scheme");
            ui.strong(format!("RMSE @ {TRADE_MAX_SPP} spp"))
                .on_hover_text("Error against the exact image at the last point of the series");
            ui.end_row();
            for row in &m.rows {
                let e = row.efficiency;
                ui.colored_label(colors::scheme(row.scheme), scheme_label(row.scheme));
                ui.label(fractions::short(e.seconds_per_sample * 1e9));
                ui.label(fractions::short(e.variance_per_sample));
                let exact = is_exact(row, largest);
                ui.label(if exact {
                    "∞ (exact)".to_owned()
                } else {
                    fractions::short(e.efficiency)
                });
                let relative = if exact {
                    "∞".to_owned()
                } else if best > 0.0 && e.efficiency.is_finite() {
                    format!("{:.0}%", 100.0 * e.efficiency / best)
                } else {
                    "–".to_owned()
                };
                ui.label(relative);
                ui.label(
                    row.series
                        .last()
                        .map_or("–".to_owned(), |p| fractions::short(p.rmse)),
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
        .x_axis_label("seconds (render time, log scale)")
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
