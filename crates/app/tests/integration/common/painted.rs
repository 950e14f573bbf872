//! What the last frame painted, read back from egui's shapes: the text with its font size and
//! place, and the images' sizes; a click at a point, as a user's pointer makes it; the seed
//! scene with a pixel inspected; a scene's numbers as bits.

use egui::Shape;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;
use lightpick_core::scene::Scene;

use super::{step_paused, window};

/// Calls `visit` on every shape painted in the last frame, nested ones included.
fn each_shape<S>(harness: &Harness<'_, S>, mut visit: impl FnMut(&Shape)) {
    fn walk(shape: &Shape, visit: &mut dyn FnMut(&Shape)) {
        if let Shape::Vec(shapes) = shape {
            for s in shapes {
                walk(s, visit);
            }
        } else {
            visit(shape);
        }
    }
    for clipped in &harness.output().shapes {
        walk(&clipped.shape, &mut visit);
    }
}

/// Every piece of text painted in the last frame, with its font size in points.
pub fn painted_texts<S>(harness: &Harness<'_, S>) -> Vec<(String, f32)> {
    let mut out = Vec::new();
    each_shape(harness, |shape| {
        if let Shape::Text(text) = shape {
            let job = &text.galley.job;
            for section in &job.sections {
                let range = section.byte_range.start.0..section.byte_range.end.0;
                let words = job.text[range].trim();
                if !words.is_empty() {
                    out.push((words.to_owned(), section.format.font_id.size));
                }
            }
        }
    });
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
pub fn painted_rects<S>(harness: &Harness<'_, S>) -> Vec<(String, egui::Rect)> {
    let mut out = Vec::new();
    each_shape(harness, |shape| {
        if let Shape::Text(text) = shape {
            out.push((
                text.galley.job.text.trim().to_owned(),
                text.galley.rect.translate(text.pos.to_vec2()),
            ));
        }
    });
    out
}

/// The widths of the textured rectangles (the images) painted in the last frame.
pub fn image_widths<S>(harness: &Harness<'_, S>) -> Vec<f32> {
    let mut out = Vec::new();
    each_shape(harness, |shape| match shape {
        Shape::Mesh(mesh) if mesh.texture_id != egui::TextureId::default() => {
            let points: Vec<egui::Pos2> = mesh.vertices.iter().map(|v| v.pos).collect();
            out.push(egui::Rect::from_points(&points).width());
        }
        Shape::Rect(rect) if rect.fill_texture_id() != egui::TextureId::default() => {
            out.push(rect.rect.width());
        }
        _ => {}
    });
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

/// The whole app on the worked example at `size`, one step rendered, a pixel of the power image
/// clicked (the inspector opens).
pub fn seed_with_inspector(size: [f32; 2]) -> Harness<'static, LightpickApp> {
    let mut harness = window(LightpickApp::for_tests(), size);
    harness.run();
    step_paused(&mut harness, 1);
    let caption = harness.get_by_label("Power (alias)").rect();
    click_at(
        &mut harness,
        egui::pos2(caption.left() + 30.0, caption.bottom() + 30.0),
    );
    assert!(
        harness.state().state.inspector.pixel.is_some(),
        "a pixel is inspected"
    );
    harness
}

/// A scene's lights as bits: each power and each position's coordinates.
pub fn light_bits(scene: &Scene) -> (Vec<u64>, Vec<[u64; 3]>) {
    (
        scene
            .powers
            .as_slice()
            .iter()
            .map(|p| p.to_bits())
            .collect(),
        scene
            .positions
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect(),
    )
}
