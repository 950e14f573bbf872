//! The app's bridge to the one palette, `lightpick_core::draw::palette`: every colour a
//! panel paints comes from there, converted here to [`egui::Color32`]. The few colours the
//! palette does not define (pick highlight, error and success text) are derived here from
//! its theme colours so they stay readable in the light and the dark theme.

use egui::Color32;
use lightpick_core::Scheme;
use lightpick_core::draw::palette::{self, Rgba8};

/// A palette colour as egui's colour.
pub fn to_color32(c: Rgba8) -> Color32 {
    let [r, g, b, a] = c.to_array();
    Color32::from_rgba_unmultiplied(r, g, b, a)
}

fn theme(dark: bool) -> palette::ThemeColors {
    if dark {
        palette::Theme::Dark.colors()
    } else {
        palette::Theme::Light.colors()
    }
}

/// The colour of light `i` (0-based).
pub fn light(i: usize) -> Color32 {
    to_color32(palette::light_color(i))
}

/// Black or white text for a label drawn on light `i`'s colour.
pub fn on_light(i: usize) -> Color32 {
    to_color32(palette::light_color(i).contrasting_text())
}

/// The colour of a sampling scheme in plots and image captions.
pub fn scheme(s: Scheme) -> Color32 {
    to_color32(palette::scheme_color(s))
}

/// Expected values and the reference solution.
pub fn reference() -> Color32 {
    to_color32(palette::REFERENCE)
}

/// Foreground: outlines, guide lines (the `1/N` average), markers of expected values.
pub fn foreground(dark: bool) -> Color32 {
    to_color32(theme(dark).foreground)
}

/// Secondary text and ghost outlines.
pub fn muted(dark: bool) -> Color32 {
    to_color32(theme(dark).muted)
}

/// Grid lines and empty column backgrounds.
pub fn grid(dark: bool) -> Color32 {
    to_color32(theme(dark).grid)
}

/// The highlight of the column picked by "draw one sample": the foreground, so it reads on
/// top of any light colour in either theme.
pub fn pick(dark: bool) -> Color32 {
    foreground(dark)
}

/// Error text: the uniform scheme's vermillion, lightened on dark backgrounds.
pub fn error(dark: bool) -> Color32 {
    let c = to_color32(palette::UNIFORM);
    if dark {
        c.lerp_to_gamma(Color32::WHITE, 0.35)
    } else {
        c
    }
}

/// Success text (a loaded file, a passing chi-square test): the palette's bluish green,
/// lightened on dark backgrounds.
pub fn good(dark: bool) -> Color32 {
    let c = to_color32(palette::CDF);
    if dark {
        c.lerp_to_gamma(Color32::WHITE, 0.35)
    } else {
        c
    }
}

/// The error-map ramp from 0 (background-dark) to 1 (the uniform scheme's vermillion, then
/// white): absolute error per pixel, normalized by the caller.
pub fn error_ramp(t: f64) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0) as f32;
    let hot = to_color32(palette::UNIFORM);
    let dark = to_color32(palette::Theme::Dark.colors().background);
    let c = if t < 0.7 {
        dark.lerp_to_gamma(hot, t / 0.7)
    } else {
        hot.lerp_to_gamma(Color32::WHITE, (t - 0.7) / 0.3)
    };
    [c.r(), c.g(), c.b()]
}

/// The classroom highlight (walkthrough cells and columns, the stepper's current pairing):
/// a bright yellow on dark backgrounds, a deep magenta on light ones, distinct from the first
/// light colours and readable on a projector.
pub fn highlight(dark: bool) -> Color32 {
    if dark {
        Color32::from_rgb(0xFF, 0xE1, 0x4D)
    } else {
        Color32::from_rgb(0xC2, 0x18, 0x5B)
    }
}

/// A veil over what a classroom step does not talk about: the panel background, mostly
/// opaque, so highlighted columns stand out.
pub fn dim(dark: bool) -> Color32 {
    let c = theme(dark).background;
    to_color32(c).gamma_multiply(0.62)
}
