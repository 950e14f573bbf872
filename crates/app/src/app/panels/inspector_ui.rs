//! The per-pixel inspector: click a pixel of any image to see, at that point of the plane,
//! each light's pick probability under power and under spatial sampling beside its true
//! share of the irradiance there, and the variance per sample that follows
//! (`Var/E² = Σ s_i²/q_i − 1`, see [`lightpick_core::inspect`]). The spatial sampler is the
//! scene's own, shared (`SceneSamplers`), not a second light tree.

use egui::{Color32, Rect, Response, Sense, Ui, vec2};
use egui_plot::{Bar, BarChart, Legend, Plot};
use lightpick_core::Scheme;
use lightpick_core::inspect::PointInspection;

use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::estimator::EstimatorPoint;
use crate::numbers;

/// The pixel of a `width × height` image under a click on its `response`, if it was
/// clicked.
pub fn clicked_pixel(response: &Response, width: u32, height: u32) -> Option<[u32; 2]> {
    if !response.clicked() {
        return None;
    }
    let pos = response.interact_pointer_pos()?;
    let rect = response.rect;
    let fx = (pos.x - rect.min.x) / rect.width().max(1.0);
    let fy = (pos.y - rect.min.y) / rect.height().max(1.0);
    if !(0.0..=1.0).contains(&fx) || !(0.0..=1.0).contains(&fy) {
        return None;
    }
    let to_index = |f: f32, n: u32| ((f * n as f32) as u32).min(n.saturating_sub(1));
    Some([to_index(fx, width), to_index(fy, height)])
}

/// Draws a small crosshair on an image shown in `rect` at the inspected pixel.
pub fn mark_pixel_ui(ui: &Ui, rect: Rect, pixel: [u32; 2], width: u32, height: u32, dark: bool) {
    if pixel[0] >= width || pixel[1] >= height {
        return;
    }
    let cell = vec2(rect.width() / width as f32, rect.height() / height as f32);
    let center = rect.min
        + vec2(
            (pixel[0] as f32 + 0.5) * cell.x,
            (pixel[1] as f32 + 0.5) * cell.y,
        );
    let arm = 7.0_f32.max(cell.x);
    let painter = ui.painter_at(rect);
    for (color, width) in [(Color32::BLACK, 3.0), (colors::foreground(dark), 1.5)] {
        let stroke = egui::Stroke::new(width, color);
        painter.line_segment([center - vec2(arm, 0.0), center - vec2(2.0, 0.0)], stroke);
        painter.line_segment([center + vec2(2.0, 0.0), center + vec2(arm, 0.0)], stroke);
        painter.line_segment([center - vec2(0.0, arm), center - vec2(0.0, 2.0)], stroke);
        painter.line_segment([center + vec2(0.0, 2.0), center + vec2(0.0, arm)], stroke);
    }
}

/// The inspector window, open while a pixel is selected.
pub fn inspector_window(ctx: &egui::Context, state: &mut AppState) {
    if state.inspector.pixel.is_none() {
        return;
    }
    let mut open = true;
    let shown = egui::Window::new("Pixel inspector")
        .open(&mut open)
        .default_size([520.0, 560.0])
        .default_pos([780.0, 420.0])
        .show(ctx, |ui| inspector_ui(ui, state));
    if std::mem::take(&mut state.inspector.raise)
        && let Some(shown) = shown
    {
        ctx.move_to_top(shown.response.layer_id);
    }
    if !open {
        state.inspector.pixel = None;
    }
}

/// The inspector's contents: the point, the variance of each scheme there, and the lights'
/// pick probabilities beside their shares.
pub fn inspector_ui(ui: &mut Ui, state: &mut AppState) {
    let dark = state.dark();
    let built = std::sync::Arc::clone(&state.built);
    let Some(pixel) = state.inspector.pixel else {
        ui.label("Click a pixel of any image to inspect it.");
        return;
    };
    let Some(inspection) = state.inspector.inspection(&built) else {
        ui.label("The selected pixel is outside the image; click a pixel of any image.");
        return;
    };
    ui.label(format!(
        "pixel ({}, {}) · point x = ({}, {}) · exact irradiance E(x) = {}",
        pixel[0],
        pixel[1],
        numbers::short(inspection.x.x),
        numbers::short(inspection.x.y),
        numbers::short(inspection.irradiance),
    ))
    .on_hover_text("E(x) = Σ Φ_i·max(0, cos θ)/(4π r²), summed over every light");
    if inspection.irradiance <= 0.0 {
        ui.label("No light reaches this point: every estimate is 0, with no variance.");
        return;
    }
    variance_ui(ui, inspection);
    if ui
        .button("Watch the estimate converge here")
        .on_hover_text(
            "Open the estimator at this pixel's point: the running estimate of each scheme, \
             sample by sample, against the exact irradiance",
        )
        .clicked()
    {
        state.estimator.open_at(EstimatorPoint::Pixel(pixel));
        state.estimator.running = true;
    }
    ui.add_space(4.0);
    shares_plot_ui(ui, inspection);
    ui.add_space(4.0);
    let names = state.built.scene.names.as_deref();
    shares_table_ui(ui, inspection, names, dark);
    ui.add_space(4.0);
    super::pick_overlay_ui::pick_overlay_ui(ui, state);
}

/// The variance of uniform, power, spatial and ideal picking at the point.
fn variance_ui(ui: &mut Ui, inspection: &PointInspection) {
    ui.label("Variance of one sample here: Var/E² = Σ s_i²/q_i − 1 (zero when q = s)")
        .on_hover_text(
            "s_i: light i's share of E(x); q_i: the probability that the scheme picks it. \
             The estimate f_i/q_i is constant (no noise) exactly when q_i = s_i.",
        );
    let e2 = inspection.irradiance * inspection.irradiance;
    let rows = [
        (
            "uniform (q = 1/N)",
            colors::scheme(Scheme::Uniform),
            Some(inspection.uniform_relative_variance),
        ),
        (
            "power (q = p, alias)",
            colors::scheme(Scheme::Alias),
            Some(inspection.power_relative_variance),
        ),
        (
            "spatial (q = P(i | x))",
            colors::scheme(Scheme::Spatial),
            inspection.spatial_relative_variance,
        ),
        ("ideal (q = s)", colors::reference(), Some(0.0)),
    ];
    egui::Grid::new("inspector_variance")
        .num_columns(4)
        .striped(true)
        .show(ui, |ui| {
            ui.strong("scheme");
            ui.strong("Var/E²");
            ui.strong("Var per sample");
            ui.strong("variance vs uniform")
                .on_hover_text("This scheme's variance per sample against uniform picking's");
            ui.end_row();
            for (name, color, relative) in rows {
                ui.colored_label(color, name);
                let Some(relative) = relative else {
                    ui.label("computing…")
                        .on_hover_text("The scene's spatial sampler is being built");
                    ui.label("");
                    ui.label("");
                    ui.end_row();
                    continue;
                };
                ui.label(numbers::short(relative));
                ui.label(numbers::short(relative * e2));
                let ratio = if name.starts_with("uniform") {
                    "baseline".to_owned()
                } else if relative > 0.0 {
                    numbers::compare(
                        relative,
                        inspection.uniform_relative_variance,
                        "higher",
                        "lower",
                    )
                } else if inspection.uniform_relative_variance > 0.0 {
                    "no noise".to_owned()
                } else {
                    "—".to_owned()
                };
                ui.label(ratio);
                ui.end_row();
            }
        });
    ui.label(format!(
        "power sampling is ½Σ|s − p| = {} away from the ideal pmf at this point",
        numbers::short(inspection.total_variation)
    ))
    .on_hover_text("Total variation distance between the shares and the power pmf");
}

/// Bars: each listed light's power pmf and spatial pick probability beside its share.
fn shares_plot_ui(ui: &mut Ui, inspection: &PointInspection) {
    let width = 0.27;
    let pmf_color = colors::scheme(Scheme::Alias);
    let spatial_color = colors::scheme(Scheme::Spatial);
    let share_color = colors::reference();
    let bars = |side: f64, value: fn(&lightpick_core::inspect::LightShare) -> f64, color| {
        inspection
            .lights
            .iter()
            .enumerate()
            .map(|(k, l)| {
                Bar::new(k as f64 + 1.0 + side * width, value(l))
                    .width(width)
                    .fill(color)
                    .name(format!("light {}", l.index + 1))
            })
            .collect::<Vec<_>>()
    };
    let has_spatial = inspection.spatial_relative_variance.is_some();
    let labels: Vec<String> = inspection
        .lights
        .iter()
        .map(|l| format!("{}", l.index + 1))
        .collect();
    Plot::new("inspector_shares")
        .legend(Legend::default().position(egui_plot::Corner::RightTop))
        .show_background(false)
        .height(170.0)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .include_y(0.0)
        // Probabilities: grid lines every 0.1, labels every 0.5 (the default decimal spacer
        // labels only whole units on a plot this short, i.e. just "0").
        .y_grid_spacer(egui_plot::uniform_grid_spacer(|_| [0.5, 0.1, 0.02]))
        .y_axis_formatter(|mark, _| format!("{:.1}", mark.value))
        .x_axis_label("light (largest share first)")
        .x_axis_formatter(move |mark, _range| {
            let k = mark.value.round();
            if (mark.value - k).abs() < 1e-6 && k >= 1.0 {
                labels.get(k as usize - 1).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .y_axis_label("probability")
        .show(ui, |plot_ui| {
            plot_ui.bar_chart(
                BarChart::new("pmf p (power)", bars(-1.0, |l| l.pmf, pmf_color)).color(pmf_color),
            );
            if has_spatial {
                plot_ui.bar_chart(
                    BarChart::new(
                        "spatial P(i | x)",
                        bars(0.0, |l| l.spatial.unwrap_or(0.0), spatial_color),
                    )
                    .color(spatial_color),
                );
            }
            plot_ui.bar_chart(
                BarChart::new("share s of E(x)", bars(1.0, |l| l.share, share_color))
                    .color(share_color),
            );
        });
}

/// The listed lights, one row each, and the rest summed.
fn shares_table_ui(
    ui: &mut Ui,
    inspection: &PointInspection,
    names: Option<&[String]>,
    dark: bool,
) {
    // Scenes with spots get the cone term t² of each listed light.
    let cones = inspection.lights.iter().any(|l| l.cone.is_some());
    egui::ScrollArea::vertical()
        .max_height(ui.available_height().max(120.0))
        .show(ui, |ui| {
            egui::Grid::new("inspector_lights")
                .num_columns(if cones { 7 } else { 6 })
                .striped(true)
                .show(ui, |ui| {
                    ui.strong("light");
                    ui.strong("power Φ");
                    ui.strong("pmf p");
                    ui.strong("spatial q").on_hover_text(
                        "P(i | x): the spatial scheme's pick probability at this point",
                    );
                    ui.strong("share s");
                    ui.strong("s / p").on_hover_text(
                        "Above 1: power sampling picks this light too rarely here \
                         (its estimate f/p is large); below 1: too often",
                    );
                    if cones {
                        ui.strong("cone t²").on_hover_text(CONE_TERM_HINT);
                    }
                    ui.end_row();
                    for l in &inspection.lights {
                        ui.horizontal(|ui| {
                            let (swatch, _) =
                                ui.allocate_exact_size(vec2(10.0, 10.0), Sense::hover());
                            ui.painter()
                                .rect_filled(swatch, 2.0, colors::light(l.index));
                            match names.and_then(|n| n.get(l.index)).filter(|n| !n.is_empty()) {
                                Some(name) => ui.label(format!("{} {name}", l.index + 1)),
                                None => ui.label(format!("{}", l.index + 1)),
                            };
                        });
                        ui.label(numbers::short(l.power));
                        ui.label(numbers::short(l.pmf));
                        ui.label(l.spatial.map_or("…".to_owned(), numbers::short));
                        ui.label(numbers::short(l.share));
                        ui.label(if l.pmf > 0.0 {
                            numbers::short(l.share / l.pmf)
                        } else {
                            "—".to_owned()
                        });
                        if cones {
                            ui.label(l.cone.map_or("point".to_owned(), numbers::short));
                        }
                        ui.end_row();
                    }
                    let others = inspection.others;
                    if others.count > 0 {
                        ui.colored_label(colors::muted(dark), format!("{} others", others.count));
                        ui.label("");
                        ui.label(numbers::short(others.pmf));
                        ui.label(others.spatial.map_or("…".to_owned(), numbers::short));
                        ui.label(numbers::short(others.share));
                        ui.label("");
                        ui.end_row();
                    }
                });
        });
}

/// What the inspector's cone column means.
const CONE_TERM_HINT: &str = "The spot's cone term toward this point, \
     t² = clamp((cos α − cos θo)/(cos θi − cos θo), 0, 1)²: 1 inside its inner cone, 0 beyond \
     its outer cone. Power picking ignores it; the spatial scheme's cone bounds weigh it \
     ('point': a light without a spot)";
