//! The inspector's top views: the plane seen from above three times, each light a dot
//! coloured by the probability that power picking, spatial picking and the ideal pick give
//! it at the inspected pixel (marked), so the class sees where power picking goes wrong.

use egui::{Color32, Sense, Stroke, Ui, pos2, vec2};

use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::pick_overlay::{OVERLAY_MAX_LIGHTS, PickOverlay};
use crate::numbers;

/// Decades of probability the colour scale spans below the largest value shown.
const DECADES: f64 = 4.0;

/// The three top views side by side, with their scale.
pub fn pick_overlay_ui(ui: &mut Ui, state: &mut AppState) {
    let dark = state.dark();
    let built = std::sync::Arc::clone(&state.built);
    let plane = built.scene.plane.clone();
    let Some(overlay) = state.inspector.overlay(&built) else {
        ui.label(format!(
            "Where each scheme picks is drawn light by light up to {OVERLAY_MAX_LIGHTS} lights; \
             the table below lists the lights that matter here."
        ));
        return;
    };
    ui.label("Where each scheme picks at this pixel (seen from above; brighter = likelier)")
        .on_hover_text(format!(
            "Each dot is a light, coloured by its pick probability on a log scale over \
             {DECADES} decades below the largest; the cross is the inspected point"
        ));
    let largest = overlay
        .power
        .iter()
        .chain(&overlay.spatial)
        .chain(&overlay.ideal)
        .fold(0.0f64, |m, &v| m.max(v));
    let gap = ui.spacing().item_spacing.x;
    let side = ((ui.available_width() - 2.0 * gap) / 3.0).clamp(80.0, 240.0);
    let aspect = ((plane.max.y - plane.min.y) / (plane.max.x - plane.min.x)) as f32;
    ui.horizontal_top(|ui| {
        for (title, values) in [
            ("power p_i", &overlay.power),
            ("spatial P(i | x)", &overlay.spatial),
            ("ideal s_i", &overlay.ideal),
        ] {
            ui.vertical(|ui| {
                ui.label(title);
                top_view_ui(ui, overlay, values, (side, side * aspect), largest, dark);
            });
        }
    });
    ui.label(format!(
        "darkest: {} or less · brightest: {}",
        numbers::short(largest * 10f64.powf(-DECADES)),
        numbers::short(largest)
    ));
}

/// One top view of `values` over the plane, `size` points.
fn top_view_ui(
    ui: &mut Ui,
    overlay: &PickOverlay,
    values: &[f64],
    size: (f32, f32),
    largest: f64,
    dark: bool,
) {
    let (response, painter) = ui.allocate_painter(vec2(size.0, size.1), Sense::hover());
    let rect = response.rect;
    painter.rect_stroke(
        rect,
        0.0,
        Stroke::new(1.0, colors::muted(dark)),
        egui::StrokeKind::Inside,
    );
    let (lo, hi) = bounds(overlay);
    let to_screen = |p: glam::DVec2| {
        let t = (p - lo) / (hi - lo);
        // Plane rows run downwards on screen as in the images (y up in the world).
        pos2(
            rect.left() + t.x as f32 * rect.width(),
            rect.bottom() - t.y as f32 * rect.height(),
        )
    };
    // Dimmest first, so the likeliest lights are drawn on top.
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let radius = (size.0 / 60.0).clamp(1.5, 4.0);
    for i in order {
        painter.circle_filled(
            to_screen(overlay.lights[i]),
            radius,
            color(values[i], largest),
        );
    }
    let x = to_screen(overlay.x);
    let stroke = Stroke::new(2.0, colors::highlight(dark));
    painter.line_segment([x - vec2(6.0, 0.0), x + vec2(6.0, 0.0)], stroke);
    painter.line_segment([x - vec2(0.0, 6.0), x + vec2(0.0, 6.0)], stroke);
}

/// The box the views show: the lights and the point, with a margin.
fn bounds(overlay: &PickOverlay) -> (glam::DVec2, glam::DVec2) {
    let (mut lo, mut hi) = (overlay.x, overlay.x);
    for p in &overlay.lights {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let margin = ((hi - lo) * 0.05).max(glam::DVec2::splat(1e-9));
    (lo - margin, hi + margin)
}

/// A probability's colour: viridis over [`DECADES`] decades below `largest`, grey for 0.
fn color(value: f64, largest: f64) -> Color32 {
    if !(value > 0.0 && largest > 0.0) {
        return Color32::from_gray(70);
    }
    let t = (1.0 + (value / largest).log10() / DECADES).clamp(0.0, 1.0);
    let [r, g, b, _] = lightpick_core::draw::viridis(t).0;
    Color32::from_rgb(r, g, b)
}
