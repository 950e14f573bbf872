//! What the last frame painted, read back from egui's shapes: the text with its font size and
//! place, and the images' sizes; and a click at a point, as a user's pointer makes it.

use egui::Shape;
use egui_kittest::Harness;
use lightpick::app::LightpickApp;

/// Every piece of text painted in the last frame, with its font size in points.
pub fn painted_texts<S>(harness: &Harness<'_, S>) -> Vec<(String, f32)> {
    fn collect(shape: &Shape, out: &mut Vec<(String, f32)>) {
        match shape {
            Shape::Text(text) => {
                let job = &text.galley.job;
                for section in &job.sections {
                    let range = section.byte_range.start.0..section.byte_range.end.0;
                    let words = job.text[range].trim();
                    if !words.is_empty() {
                        out.push((words.to_owned(), section.format.font_id.size));
                    }
                }
            }
            Shape::Vec(shapes) => shapes.iter().for_each(|s| collect(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        collect(&clipped.shape, &mut out);
    }
    out
}

/// All the text painted in the last frame, joined.
pub fn painted<S>(harness: &Harness<'_, S>) -> String {
    painted_texts(harness)
        .into_iter()
        .map(|(t, _)| t)
        .collect::<Vec<_>>()
        .join("\n")
}

/// Where each painted text stands: its words and the rectangle it covers.
pub fn painted_rects(harness: &Harness<'_, LightpickApp>) -> Vec<(String, egui::Rect)> {
    fn collect(shape: &Shape, out: &mut Vec<(String, egui::Rect)>) {
        match shape {
            Shape::Text(text) => out.push((
                text.galley.job.text.trim().to_owned(),
                text.galley.rect.translate(text.pos.to_vec2()),
            )),
            Shape::Vec(shapes) => shapes.iter().for_each(|s| collect(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        collect(&clipped.shape, &mut out);
    }
    out
}

/// The widths of the textured rectangles (the images) painted in the last frame.
pub fn image_widths(harness: &Harness<'_, LightpickApp>) -> Vec<f32> {
    fn collect(shape: &Shape, out: &mut Vec<f32>) {
        match shape {
            Shape::Mesh(mesh) if mesh.texture_id != egui::TextureId::default() => {
                let rect = egui::Rect::from_points(
                    &mesh.vertices.iter().map(|v| v.pos).collect::<Vec<_>>(),
                );
                out.push(rect.width());
            }
            Shape::Rect(rect) if rect.fill_texture_id() != egui::TextureId::default() => {
                out.push(rect.rect.width());
            }
            Shape::Vec(shapes) => shapes.iter().for_each(|s| collect(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for clipped in &harness.output().shapes {
        collect(&clipped.shape, &mut out);
    }
    out
}

/// A primary click at `pos`.
pub fn click_at(harness: &mut Harness<'static, LightpickApp>, pos: egui::Pos2) {
    harness.hover_at(pos);
    for pressed in [true, false] {
        harness.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::default(),
        });
    }
    harness.run();
}
