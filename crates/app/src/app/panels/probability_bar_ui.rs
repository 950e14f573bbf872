//! A probability drawn as a bar: the Light tree panel's stages weigh groups and lights with
//! it.

use egui::{Color32, Sense, Ui, vec2};

/// The widest a probability bar is drawn (points).
const BAR_WIDTH: f32 = 140.0;

/// A bar of length `p` of [`BAR_WIDTH`] in `color`, one text line high, in a faint frame.
pub fn bar_ui(ui: &mut Ui, p: f64, color: Color32) {
    let height = ui.text_style_height(&egui::TextStyle::Body);
    let (rect, _) = ui.allocate_exact_size(vec2(BAR_WIDTH, height), Sense::hover());
    let painter = ui.painter();
    painter.rect_stroke(
        rect,
        0.0,
        egui::Stroke::new(1.0, ui.visuals().widgets.noninteractive.bg_stroke.color),
        egui::StrokeKind::Inside,
    );
    let mut filled = rect;
    filled.set_width(BAR_WIDTH * p.clamp(0.0, 1.0) as f32);
    painter.rect_filled(filled, 0.0, color);
}
