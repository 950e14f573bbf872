//! The app's one rule for text size: nothing the class reads is smaller than body text.
//!
//! egui's `Small` style (9 points) is raised to the body size once, for both themes, so a
//! `.small()` label can never shrink below it; text the panels paint themselves asks for at
//! least [`body_size`]. Everything is in points, so the zoom (Ctrl + / Ctrl −, egui's
//! `zoom_factor`) scales all of it alike.

use egui::{TextStyle, Ui};

/// Raises every text style smaller than `Body` to `Body`'s size, in the dark and the light
/// style alike (call once, on the first frame).
pub fn apply_minimum_text_size(ctx: &egui::Context) {
    ctx.all_styles_mut(|style| {
        let body = style
            .text_styles
            .get(&TextStyle::Body)
            .map_or(13.0, |font| font.size);
        for font in style.text_styles.values_mut() {
            font.size = font.size.max(body);
        }
    });
}

/// The body text's size in points: the least size any text of the app may have.
pub fn body_size(ui: &Ui) -> f32 {
    TextStyle::Body.resolve(ui.style()).size
}
