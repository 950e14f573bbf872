//! The one palette of lightpick: every colour a drawing or a panel uses comes from here.
//!
//! Colours are plain straight-alpha sRGB bytes ([`Rgba8`]) so that any toolkit can use them
//! (egui: `Color32::from_rgba_unmultiplied(r, g, b, a)`; tiny-skia: `Color::from_rgba8`).
//!
//! * Lights: the first seven take Okabe & Ito's colour-blind-safe palette ("Color Universal
//!   Design", 2008) without its black, the next three Paul Tol's *muted* wine, teal and sand;
//!   beyond ten, hues step by the golden angle so neighbours stay apart ([`light_color`]).
//! * Schemes: one colour each, the same in both themes ([`scheme_color`]); the reference
//!   (exact) solution and expected values are a neutral grey ([`REFERENCE`]).
//! * Themes: background, foreground, muted text and grid for light and dark ([`Theme`]).

use crate::sampler::Scheme;

/// A straight-alpha (not premultiplied) sRGB colour, one byte per channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgba8(pub [u8; 4]);

impl Rgba8 {
    /// An opaque colour from its red, green and blue bytes.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Self {
        Self([r, g, b, 255])
    }

    /// An opaque colour from `0xRRGGBB`.
    pub const fn hex(rgb: u32) -> Self {
        Self([(rgb >> 16) as u8, (rgb >> 8) as u8, rgb as u8, 255])
    }

    /// The same colour with alpha `a`.
    #[must_use]
    pub const fn with_alpha(self, a: u8) -> Self {
        let [r, g, b, _] = self.0;
        Self([r, g, b, a])
    }

    /// The channels `[r, g, b, a]`.
    pub const fn to_array(self) -> [u8; 4] {
        self.0
    }

    /// Relative luminance (WCAG 2, linear-light `0.2126 R + 0.7152 G + 0.0722 B`) in `[0, 1]`.
    pub fn luminance(self) -> f64 {
        let lin = |c: u8| {
            let v = f64::from(c) / 255.0;
            if v <= 0.040_45 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        let [r, g, b, _] = self.0;
        0.2126 * lin(r) + 0.7152 * lin(g) + 0.0722 * lin(b)
    }

    /// Black or white, whichever contrasts more with this colour (for labels drawn on it).
    #[must_use]
    pub fn contrasting_text(self) -> Self {
        // The luminance where black and white text have equal WCAG contrast ratios.
        if self.luminance() > 0.179 {
            Rgba8::rgb(0, 0, 0)
        } else {
            Rgba8::rgb(255, 255, 255)
        }
    }
}

/// The first ten light colours: Okabe–Ito (orange, sky blue, bluish green, blue, vermillion,
/// reddish purple, yellow), then Paul Tol's muted wine, teal and sand.
pub const LIGHTS: [Rgba8; 10] = [
    Rgba8::hex(0xE6_9F_00),
    Rgba8::hex(0x56_B4_E9),
    Rgba8::hex(0x00_9E_73),
    Rgba8::hex(0x00_72_B2),
    Rgba8::hex(0xD5_5E_00),
    Rgba8::hex(0xCC_79_A7),
    Rgba8::hex(0xF0_E4_42),
    Rgba8::hex(0x88_22_55),
    Rgba8::hex(0x44_AA_99),
    Rgba8::hex(0xDD_CC_77),
];

/// The colour of light `i`: [`LIGHTS`] for the first ten, then hues spaced by the golden
/// angle (saturation 0.55, value 0.85), so any two nearby indices differ visibly.
pub fn light_color(i: usize) -> Rgba8 {
    if let Some(&c) = LIGHTS.get(i) {
        return c;
    }
    // Golden-ratio conjugate: successive hues land in the largest gap left so far.
    let hue = ((i - LIGHTS.len()) as f64 * 0.618_033_988_749_895 + 0.11).fract();
    hsv(hue, 0.55, 0.85)
}

/// An opaque colour from hue, saturation and value, each in `[0, 1]`.
fn hsv(h: f64, s: f64, v: f64) -> Rgba8 {
    let h6 = h.rem_euclid(1.0) * 6.0;
    let sector = h6.floor();
    let f = h6 - sector;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let (r, g, b) = match sector as u32 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    let byte = |x: f64| (x * 255.0).round().clamp(0.0, 255.0) as u8;
    Rgba8::rgb(byte(r), byte(g), byte(b))
}

/// Uniform selection: vermillion.
pub const UNIFORM: Rgba8 = Rgba8::hex(0xD5_5E_00);
/// Alias table (two randoms, the default): blue.
pub const ALIAS: Rgba8 = Rgba8::hex(0x00_72_B2);
/// Alias table, one random (speed option): sky blue, a lighter sibling of [`ALIAS`].
pub const ALIAS_ONE_RANDOM: Rgba8 = Rgba8::hex(0x56_B4_E9);
/// Inverse CDF: bluish green.
pub const CDF: Rgba8 = Rgba8::hex(0x00_9E_73);
/// Contribution-aware (spatial) selection: reddish purple (Okabe & Ito).
pub const SPATIAL: Rgba8 = Rgba8::hex(0xCC_79_A7);
/// The reference (exact) solution and expected values: neutral grey, legible on both themes.
pub const REFERENCE: Rgba8 = Rgba8::hex(0x8C_8C_8C);

/// Alias-table summaries of many columns (where per-light colours would only be noise):
/// the part of a column that keeps its own light.
pub const TABLE_OWN: Rgba8 = Rgba8::hex(0x00_72_B2);
/// Alias-table summaries of many columns: the part of a column given to its alias.
pub const TABLE_ALIAS: Rgba8 = Rgba8::hex(0xE6_9F_00);

/// The colour of a selection scheme (identical in light and dark themes).
pub fn scheme_color(scheme: Scheme) -> Rgba8 {
    match scheme {
        Scheme::Uniform => UNIFORM,
        Scheme::Alias => ALIAS,
        Scheme::AliasOneRandom => ALIAS_ONE_RANDOM,
        Scheme::Cdf => CDF,
        Scheme::Spatial => SPATIAL,
    }
}

/// Light or dark surroundings for drawings and panels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Theme {
    /// Dark text on white (handouts, the README).
    #[default]
    Light,
    /// Light text on near-black (egui's dark mode).
    Dark,
}

/// The neutral colours of a [`Theme`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ThemeColors {
    /// Canvas background.
    pub background: Rgba8,
    /// Text, axes and outlines.
    pub foreground: Rgba8,
    /// Secondary text (captions, tick labels of minor importance).
    pub muted: Rgba8,
    /// Grid lines.
    pub grid: Rgba8,
    /// Filled boxes behind legends.
    pub panel: Rgba8,
}

impl Theme {
    /// The theme's neutral colours.
    pub const fn colors(self) -> ThemeColors {
        match self {
            Theme::Light => ThemeColors {
                background: Rgba8::hex(0xFF_FF_FF),
                foreground: Rgba8::hex(0x1E_1E_1E),
                muted: Rgba8::hex(0x5F_5F_5F),
                grid: Rgba8::hex(0xE4_E4_E4),
                panel: Rgba8([255, 255, 255, 230]),
            },
            Theme::Dark => ThemeColors {
                background: Rgba8::hex(0x1B_1B_1B),
                foreground: Rgba8::hex(0xE6_E6_E6),
                muted: Rgba8::hex(0xA5_A5_A5),
                grid: Rgba8::hex(0x3A_3A_3A),
                panel: Rgba8([27, 27, 27, 230]),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_lights_are_distinct_and_cycling_stays_defined() {
        for i in 0..LIGHTS.len() {
            for j in 0..i {
                assert_ne!(light_color(i), light_color(j), "{i} vs {j}");
            }
        }
        for i in 10..1000 {
            assert_eq!(light_color(i).0[3], 255);
            assert_ne!(light_color(i), light_color(i + 1), "{i}");
        }
    }

    #[test]
    fn hex_and_luminance() {
        assert_eq!(Rgba8::hex(0x12_34_56).to_array(), [0x12, 0x34, 0x56, 255]);
        assert_eq!(Rgba8::rgb(0, 0, 0).luminance(), 0.0);
        assert!((Rgba8::rgb(255, 255, 255).luminance() - 1.0).abs() < 1e-12);
        assert_eq!(LIGHTS[6].contrasting_text(), Rgba8::rgb(0, 0, 0));
        assert_eq!(LIGHTS[7].contrasting_text(), Rgba8::rgb(255, 255, 255));
    }

    #[test]
    fn schemes_have_distinct_colors() {
        let all = [Scheme::ALL.as_slice(), &[Scheme::Spatial]].concat();
        for (k, a) in all.iter().enumerate() {
            for b in &all[..k] {
                assert_ne!(scheme_color(*a), scheme_color(*b));
            }
            assert_ne!(scheme_color(*a), REFERENCE);
        }
    }
}
