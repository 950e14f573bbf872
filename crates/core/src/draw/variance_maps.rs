//! Per-pixel variance maps of several schemes side by side
//! ([`crate::stats::variance_map::VarianceMap`]), on one shared logarithmic colour scale
//! with a labelled colour bar, each panel captioned with its scheme and its mean variance.
//!
//! # The colour scale
//! The scale is shared by every map shown together ([`VarianceScale::shared`]): its top is
//! the largest finite positive value `V_max` of all of them, and it spans
//! [`VARIANCE_DECADES`] decades below it. A pixel of variance `V` gets the viridis colour of
//!
//! `t = 1 + log₁₀(V / V_max) / D`, clamped to `[0, 1]`,
//!
//! so equal colours mean equal variances across the panels; `V ≤ V_max·10^-D` (the exact
//! spatial pick's zero, up to rounding) is the darkest colour, a non-finite `V` magenta.
//! The app's images panel draws its maps through the same scale ([`variance_rgba`]).

use tiny_skia::{FilterQuality, Pixmap, PixmapPaint, Transform};

use super::canvas::{self, LABEL_SIZE, TICK_SIZE};
use super::image_sheet::{fit_scale, pixmap_from_rgba, viridis};
use super::palette::{self, Rgba8};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};
use crate::sampling::sampler::Scheme;

/// The decades of variance the shared colour scale spans below its top.
pub const VARIANCE_DECADES: f64 = 6.0;

/// The colour of non-finite variances.
const INVALID: Rgba8 = Rgba8::hex(0xFF_00_FF);

/// One logarithmic colour scale shared by several variance maps (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VarianceScale {
    /// `V_max`, the largest finite positive value of the maps (0 when there is none: every
    /// pixel is then the darkest colour).
    pub max: f64,
    /// The decades spanned below `max`.
    pub decades: f64,
}

impl VarianceScale {
    /// The scale over every value of `maps`, [`VARIANCE_DECADES`] deep.
    pub fn shared(maps: &[&[f64]]) -> Self {
        let max = maps
            .iter()
            .flat_map(|m| m.iter())
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, &v| m.max(v));
        Self {
            max,
            decades: VARIANCE_DECADES,
        }
    }

    /// The bottom of the scale, `V_max·10^-D` (0 when the scale is empty).
    pub fn min(&self) -> f64 {
        self.max * 10f64.powf(-self.decades)
    }

    /// `t ∈ [0, 1]` of a variance (module docs); `None` for a non-finite one.
    pub fn unit(&self, v: f64) -> Option<f64> {
        if !v.is_finite() {
            return None;
        }
        if !(v > 0.0 && self.max > 0.0) {
            return Some(0.0);
        }
        Some((1.0 + (v / self.max).log10() / self.decades).clamp(0.0, 1.0))
    }

    /// The colour of a variance.
    pub fn color(&self, v: f64) -> Rgba8 {
        self.unit(v).map_or(INVALID, viridis)
    }
}

/// A map's pixels as straight, opaque `RGBA8` through `scale`.
pub fn variance_rgba(values: &[f64], scale: &VarianceScale) -> Vec<u8> {
    values.iter().flat_map(|&v| scale.color(v).0).collect()
}

/// The mean of a map's values, summed in pixel order (what every caption reports).
pub fn variance_mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.iter().sum::<f64>() / values.len() as f64
}

/// The name a variance panel gives a scheme.
pub fn variance_scheme_name(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Uniform => "uniform",
        Scheme::Spatial => "spatial",
        _ => "power (alias)",
    }
}

/// A panel's caption: `uniform · mean 1.234e-3` (three decimals of the mantissa; the number
/// reads back with `str::parse::<f64>`).
pub fn variance_caption(scheme: Scheme, mean: f64) -> String {
    format!("{} · mean {mean:.3e}", variance_scheme_name(scheme))
}

/// The line that says how the maps were computed: exact, or estimated from `k` samples.
pub fn variance_method_line(exact: bool, samples_per_pixel: u32) -> String {
    if exact {
        "exact: Σ s_i²/q_i − E² at every pixel centre".to_owned()
    } else {
        let plural = if samples_per_pixel == 1 { "" } else { "s" };
        format!("estimated from {samples_per_pixel} sample{plural} per pixel")
    }
}

/// What [`variance_sheet`] draws: maps of `width × height` pixels, row by row.
#[derive(Clone, Copy, Debug)]
pub struct VarianceSheet<'a> {
    /// Pixel columns of every map.
    pub width: usize,
    /// Pixel rows of every map.
    pub height: usize,
    /// The maps, one per scheme, left to right.
    pub maps: &'a [(Scheme, &'a [f64])],
    /// Whether the maps are exact (else estimated).
    pub exact: bool,
    /// Samples per pixel behind estimated maps.
    pub samples_per_pixel: u32,
    /// Lights of the scene (for the subtitle).
    pub lights: usize,
}

/// The colour bar's width and the room for its labels, pixels.
const BAR_COLUMN: f32 = 96.0;

/// Draws the maps side by side on one shared scale (module docs), the colour bar at the
/// right, the method line just under them.
pub fn variance_sheet(sheet: &VarianceSheet<'_>, style: &Style) -> Result<Pixmap, DrawError> {
    let (iw, ih) = (sheet.width, sheet.height);
    if iw == 0 || ih == 0 {
        return Err(DrawError::Empty("the maps have no pixels"));
    }
    if sheet.maps.is_empty() {
        return Err(DrawError::Empty("no variance maps"));
    }
    for (_, m) in sheet.maps {
        if m.len() != iw * ih {
            return Err(DrawError::Length {
                what: "variance map",
                expected: iw * ih,
                got: m.len(),
            });
        }
    }
    let values: Vec<&[f64]> = sheet.maps.iter().map(|(_, m)| *m).collect();
    let scale = VarianceScale::shared(&values);
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let (w, h) = (style.width as f32, style.height as f32);
    canvas::title(
        &mut pixmap,
        "Variance of one sample, pixel by pixel",
        Some(&format!(
            "{iw}×{ih} px · {} lights · one log scale for all",
            sheet.lights
        )),
        &colors,
    )?;
    let (margin, gap, top, caption, bottom) = (20.0, 14.0, 72.0, 22.0, 34.0);
    let columns = sheet.maps.len() as f32;
    let cell_w = (w - 2.0 * margin - BAR_COLUMN - columns * gap) / columns;
    let cell_h = h - top - caption - bottom;
    let s = fit_scale(iw, ih, cell_w.max(1.0), cell_h.max(1.0));
    let (dw, dh) = ((iw as f32 * s).round(), (ih as f32 * s).round());
    let y = (top + caption + ((cell_h - dh) / 2.0).max(0.0)).round();
    let paint = PixmapPaint {
        quality: if s >= 1.0 {
            FilterQuality::Nearest
        } else {
            FilterQuality::Bilinear
        },
        ..PixmapPaint::default()
    };
    for (k, (scheme, map)) in sheet.maps.iter().enumerate() {
        let cx = margin + k as f32 * (cell_w + gap);
        let x = (cx + (cell_w - dw) / 2.0).round();
        let image = pixmap_from_rgba(iw, ih, variance_rgba(map, &scale))?;
        pixmap.draw_pixmap(
            0,
            0,
            image.as_ref(),
            &paint,
            Transform::from_row(s, 0.0, 0.0, s, x, y),
            None,
        );
        canvas::stroke_rect(
            &mut pixmap,
            (x - 0.5, y - 0.5, dw + 1.0, dh + 1.0),
            1.0,
            colors.grid,
        );
        text::draw_text(
            &mut pixmap,
            &variance_caption(*scheme, variance_mean(map)),
            (cx + cell_w / 2.0, y - 8.0),
            (HAlign::Center, VAlign::Baseline),
            &TextStyle::new(LABEL_SIZE, palette::scheme_color(*scheme)).bold(),
        )?;
    }
    let bar_x = margin + columns * (cell_w + gap);
    color_bar(&mut pixmap, (bar_x, y), dh, &scale, &colors)?;
    text::draw_text(
        &mut pixmap,
        &variance_method_line(sheet.exact, sheet.samples_per_pixel),
        (margin, (y + dh + 28.0).min(h - 12.0)),
        (HAlign::Left, VAlign::Baseline),
        &TextStyle::new(LABEL_SIZE, colors.foreground),
    )?;
    Ok(pixmap)
}

/// The shared scale's bar, `height` pixels tall, labelled at every decade.
fn color_bar(
    pixmap: &mut Pixmap,
    (x, y): (f32, f32),
    height: f32,
    scale: &VarianceScale,
    colors: &super::palette::ThemeColors,
) -> Result<(), DrawError> {
    let bar_w = 18.0;
    super::image_sheet::viridis_bar(pixmap, (x, y, bar_w, height), colors.foreground);
    let tick = TextStyle::new(TICK_SIZE, colors.foreground);
    text::draw_text(
        pixmap,
        "variance",
        (x, y - 8.0),
        (HAlign::Left, VAlign::Baseline),
        &tick.bold(),
    )?;
    if scale.max <= 0.0 {
        text::draw_text(
            pixmap,
            "all 0",
            (x + bar_w + 6.0, y + height),
            (HAlign::Left, VAlign::Bottom),
            &tick,
        )?;
        return Ok(());
    }
    // Ticks at the whole decades inside the scale, labelled 10ⁿ.
    let top = scale.max.log10();
    let bottom = top - scale.decades;
    let mut e = bottom.ceil() as i32;
    while f64::from(e) <= top + 1e-9 {
        let t = (f64::from(e) - bottom) / scale.decades;
        let ty = canvas::crisp(y + (1.0 - t as f32) * (height - 1.0));
        canvas::line(
            pixmap,
            (x + bar_w, ty),
            (x + bar_w + 4.0, ty),
            1.0,
            colors.foreground,
        );
        text::draw_text(
            pixmap,
            &format!("10{}", super::axes::superscript(e)),
            (x + bar_w + 8.0, ty),
            (HAlign::Left, VAlign::Middle),
            &tick,
        )?;
        e += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_is_shared_logarithmic_and_clamped() {
        let a = [1e-2, 0.0, f64::NAN];
        let b = [1e-5, -1e-18, 1e-9];
        let scale = VarianceScale::shared(&[&a, &b]);
        assert_eq!(scale.max, 1e-2);
        assert_eq!(scale.unit(1e-2), Some(1.0));
        assert!((scale.unit(1e-5).expect("finite") - 0.5).abs() < 1e-12);
        assert_eq!(scale.unit(1e-9), Some(0.0), "below the scale: darkest");
        assert_eq!(scale.unit(0.0), Some(0.0));
        assert_eq!(scale.unit(-1e-18), Some(0.0));
        assert_eq!(scale.unit(f64::NAN), None);
        assert_eq!(scale.color(f64::INFINITY), INVALID);
        assert!((scale.min() - 1e-8).abs() < 1e-20);
        let empty = VarianceScale::shared(&[&[0.0, 0.0]]);
        assert_eq!(empty.unit(0.0), Some(0.0));
        assert_eq!(variance_rgba(&[1e-2, 0.0], &scale).len(), 8);
    }

    #[test]
    fn captions_read_back_and_the_mean_is_in_pixel_order() {
        assert_eq!(variance_mean(&[1.0, 2.0, 6.0]), 3.0);
        assert_eq!(variance_mean(&[]), 0.0);
        let caption = variance_caption(Scheme::Alias, 0.001_234_4);
        assert_eq!(caption, "power (alias) · mean 1.234e-3");
        let number: f64 = caption
            .rsplit(' ')
            .next()
            .and_then(|s| s.parse().ok())
            .expect("a number");
        assert!((number - 0.001_234_4).abs() < 1e-6);
        assert_eq!(
            variance_method_line(false, 4),
            "estimated from 4 samples per pixel"
        );
        assert!(variance_method_line(true, 0).starts_with("exact"));
    }

    #[test]
    fn wrong_lengths_are_refused() {
        let map = [1.0; 6];
        let short = [1.0; 5];
        let maps = [(Scheme::Uniform, &map[..]), (Scheme::Spatial, &short[..])];
        let sheet = VarianceSheet {
            width: 3,
            height: 2,
            maps: &maps,
            exact: true,
            samples_per_pixel: 0,
            lights: 3,
        };
        assert!(matches!(
            variance_sheet(&sheet, &Style::default()),
            Err(DrawError::Length {
                expected: 6,
                got: 5,
                ..
            })
        ));
        let maps = [(Scheme::Uniform, &map[..])];
        let ok = VarianceSheet {
            maps: &maps,
            ..sheet
        };
        assert!(variance_sheet(&ok, &Style::default()).is_ok());
    }
}
