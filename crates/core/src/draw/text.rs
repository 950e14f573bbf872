//! Text labels rasterized with `ab_glyph` from a bundled font, so every machine draws the
//! same pixels (no system font lookup).
//!
//! The font is a subset of `DejaVu Sans` (regular and bold; Bitstream Vera licence with
//! public-domain `DejaVu` changes, see `src/draw/fonts/`): Latin-1, Greek, super/subscripts and
//! the few math signs the drawings use (`·`, `χ²`, `−`, `≈`, `≤`, `×`, `√`, `∞`).
//!
//! Glyph coverage is composited source-over in premultiplied alpha straight into the
//! [`Pixmap`]. Vertical text (axis titles) is drawn into a scratch pixmap and turned by an
//! exact quarter turn, so it is as crisp as horizontal text.

use ab_glyph::{Font as _, FontRef, GlyphId, PxScale, ScaleFont as _, point};
use tiny_skia::{FilterQuality, Pixmap, PixmapPaint, PremultipliedColorU8, Transform};

use super::DrawError;
use super::palette::Rgba8;

/// The bundled regular face (a `DejaVu Sans` subset, licence in `fonts/`), also the egui
/// app's fallback for the arrows and math signs its panels write.
pub static REGULAR_FONT: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");
static BOLD: &[u8] = include_bytes!("fonts/DejaVuSans-Bold.ttf");

/// `DejaVu Sans`' cap height as a fraction of the em (1493 / 2048 font units).
const CAP_HEIGHT_EM: f32 = 0.729;

/// Regular or bold face of the bundled font.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Weight {
    /// `DejaVu Sans`.
    #[default]
    Regular,
    /// `DejaVu Sans Bold` (titles).
    Bold,
}

/// Where the anchor point lies horizontally on the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HAlign {
    /// The anchor is the start of the text.
    Left,
    /// The anchor is the middle of the advance width.
    Center,
    /// The anchor is the end of the text.
    Right,
}

/// Where the anchor point lies vertically on the text line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VAlign {
    /// The anchor is the font's ascent line (top of accents).
    Top,
    /// The anchor is half the cap height above the baseline (centres digits and capitals).
    Middle,
    /// The anchor is the baseline.
    Baseline,
    /// The anchor is the font's descent line.
    Bottom,
}

/// How a label looks: pixel size (the em), colour and weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextStyle {
    /// Font size in pixels per em.
    pub size: f32,
    /// Text colour (its alpha scales the glyph coverage).
    pub color: Rgba8,
    /// Regular or bold.
    pub weight: Weight,
}

impl TextStyle {
    /// A regular-weight style.
    pub fn new(size: f32, color: Rgba8) -> Self {
        Self {
            size,
            color,
            weight: Weight::Regular,
        }
    }

    /// The same style in bold.
    #[must_use]
    pub fn bold(self) -> Self {
        Self {
            weight: Weight::Bold,
            ..self
        }
    }
}

/// The size of a line of text in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextExtent {
    /// Advance width (with kerning).
    pub width: f32,
    /// Font ascent above the baseline (positive).
    pub ascent: f32,
    /// Font descent below the baseline (positive).
    pub descent: f32,
}

impl TextExtent {
    /// Line height: ascent plus descent.
    pub fn height(&self) -> f32 {
        self.ascent + self.descent
    }
}

/// The bundled font of `weight`.
pub fn font(weight: Weight) -> Result<FontRef<'static>, DrawError> {
    let bytes = match weight {
        Weight::Regular => REGULAR_FONT,
        Weight::Bold => BOLD,
    };
    FontRef::try_from_slice(bytes).map_err(|_| DrawError::Font)
}

/// Whether the bundled font has a glyph for every character of `text`.
pub fn has_glyphs(text: &str) -> bool {
    font(Weight::Regular).is_ok_and(|f| text.chars().all(|c| f.glyph_id(c) != GlyphId(0)))
}

/// One positioned glyph of a laid-out line: id and pen position relative to the origin.
struct Laid {
    id: GlyphId,
    x: f32,
}

/// Lays `text` out on one line from pen position 0.
fn layout(font: &FontRef<'static>, text: &str, size: f32) -> (Vec<Laid>, TextExtent) {
    let scaled = font.as_scaled(PxScale::from(size));
    let mut glyphs = Vec::with_capacity(text.len());
    let mut x = 0.0_f32;
    let mut previous: Option<GlyphId> = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            x += scaled.kern(p, id);
        }
        glyphs.push(Laid { id, x });
        x += scaled.h_advance(id);
        previous = Some(id);
    }
    let extent = TextExtent {
        width: x,
        ascent: scaled.ascent(),
        descent: -scaled.descent(),
    };
    (glyphs, extent)
}

/// Measures `text` at `size` pixels per em in `weight`.
pub fn measure(text: &str, size: f32, weight: Weight) -> Result<TextExtent, DrawError> {
    Ok(layout(&font(weight)?, text, size).1)
}

/// Draws `text` with its anchor point (per `h` and `v`) at `(x, y)`. The pen origin is
/// rounded to whole pixels so equal labels look equal wherever they are placed. Returns the
/// text's extent.
pub fn draw_text(
    pixmap: &mut Pixmap,
    text: &str,
    (x, y): (f32, f32),
    (h, v): (HAlign, VAlign),
    style: &TextStyle,
) -> Result<TextExtent, DrawError> {
    let font = font(style.weight)?;
    let (glyphs, extent) = layout(&font, text, style.size);
    let left = match h {
        HAlign::Left => x,
        HAlign::Center => x - extent.width / 2.0,
        HAlign::Right => x - extent.width,
    };
    let baseline = match v {
        VAlign::Top => y + extent.ascent,
        VAlign::Middle => y + CAP_HEIGHT_EM * style.size / 2.0,
        VAlign::Baseline => y,
        VAlign::Bottom => y - extent.descent,
    };
    let (left, baseline) = (left.round(), baseline.round());
    let scale = PxScale::from(style.size);
    for laid in glyphs {
        let glyph = laid
            .id
            .with_scale_and_position(scale, point(left + laid.x, baseline));
        let Some(outlined) = font.outline_glyph(glyph) else {
            continue; // blank glyphs (space)
        };
        let bounds = outlined.px_bounds();
        let (x0, y0) = (bounds.min.x as i64, bounds.min.y as i64);
        outlined.draw(|gx, gy, coverage| {
            blend(
                pixmap,
                x0 + i64::from(gx),
                y0 + i64::from(gy),
                style.color,
                coverage,
            );
        });
    }
    Ok(extent)
}

/// Draws `text` turned a quarter turn counter-clockwise (reading bottom to top), centred
/// on `(x, y)`: the usual y-axis title.
pub fn draw_text_vertical(
    pixmap: &mut Pixmap,
    text: &str,
    (x, y): (f32, f32),
    style: &TextStyle,
) -> Result<(), DrawError> {
    let extent = measure(text, style.size, style.weight)?;
    let w = extent.width.ceil() as u32 + 2;
    let h = extent.height().ceil() as u32 + 2;
    let mut scratch = Pixmap::new(w, h).ok_or(DrawError::Size {
        width: w,
        height: h,
    })?;
    draw_text(
        &mut scratch,
        text,
        (1.0, 1.0),
        (HAlign::Left, VAlign::Top),
        style,
    )?;
    // (sx, sy) ↦ (tx + sy, ty − sx): a quarter turn counter-clockwise, exact on whole pixels.
    let tx = (x - h as f32 / 2.0).round();
    let ty = (y + w as f32 / 2.0).round();
    let paint = PixmapPaint {
        quality: FilterQuality::Nearest,
        ..PixmapPaint::default()
    };
    pixmap.draw_pixmap(
        0,
        0,
        scratch.as_ref(),
        &paint,
        Transform::from_row(0.0, -1.0, 1.0, 0.0, tx, ty),
        None,
    );
    Ok(())
}

/// Composites `color` with `coverage` source-over onto pixel `(x, y)` (premultiplied).
pub(crate) fn blend(pixmap: &mut Pixmap, x: i64, y: i64, color: Rgba8, coverage: f32) {
    let (width, height) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    if x < 0 || y < 0 || x >= width || y >= height || coverage <= 0.0 {
        return;
    }
    let index = (y * width + x) as usize;
    let [r, g, b, a] = color.0;
    let alpha = f32::from(a) / 255.0 * coverage.min(1.0);
    let dst = pixmap.pixels()[index];
    let keep = 1.0 - alpha;
    let mix = |src: u8, dst: u8| (f32::from(src) * alpha + f32::from(dst) * keep).round();
    let out_a = mix(255, dst.alpha());
    // Premultiplied channels never exceed alpha; rounding must not break that.
    let channel = |src: u8, dst: u8| mix(src, dst).min(out_a) as u8;
    let out = PremultipliedColorU8::from_rgba(
        channel(r, dst.red()),
        channel(g, dst.green()),
        channel(b, dst.blue()),
        out_a as u8,
    );
    if let Some(out) = out {
        pixmap.pixels_mut()[index] = out;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundled_fonts_load_and_cover_the_labels() {
        assert!(font(Weight::Regular).is_ok());
        assert!(font(Weight::Bold).is_ok());
        assert!(has_glyphs(
            "0123456789 abcxyz ABCXYZ / · χ² − ≈ ≤ × √ ∞ ⁻¹²³ Σ % ( ) [ ] = , . : →"
        ));
        assert!(!has_glyphs("漢"));
    }

    #[test]
    fn measure_scales_with_size_and_text() {
        let small = measure("6/27", 10.0, Weight::Regular).expect("valid test input");
        let large = measure("6/27", 20.0, Weight::Regular).expect("valid test input");
        assert!((large.width - 2.0 * small.width).abs() < 0.01);
        assert!(
            measure("6/27 + 1", 10.0, Weight::Regular)
                .expect("valid test input")
                .width
                > small.width
        );
        assert!(small.ascent > 0.0 && small.descent > 0.0);
    }

    #[test]
    fn text_lands_where_anchored() {
        let mut pm = Pixmap::new(100, 40).expect("valid test input");
        let black = Rgba8::rgb(0, 0, 0);
        let style = TextStyle::new(16.0, black);
        let e = draw_text(
            &mut pm,
            "Hi",
            (50.0, 20.0),
            (HAlign::Center, VAlign::Middle),
            &style,
        )
        .expect("valid test input");
        let inked: Vec<(u32, u32)> = (0..40)
            .flat_map(|y| (0..100).map(move |x| (x, y)))
            .filter(|&(x, y)| pm.pixel(x, y).expect("valid test input").alpha() > 128)
            .collect();
        assert!(!inked.is_empty());
        let (min_x, max_x) = inked
            .iter()
            .fold((100, 0), |(lo, hi), &(x, _)| (lo.min(x), hi.max(x)));
        let (min_y, max_y) = inked
            .iter()
            .fold((40, 0), |(lo, hi), &(_, y)| (lo.min(y), hi.max(y)));
        // Ink lies inside the advance box around the anchor, and is centred on it.
        assert!(min_x as f32 >= 50.0 - e.width / 2.0 - 1.0);
        assert!(max_x as f32 <= 50.0 + e.width / 2.0 + 1.0);
        assert!(
            (i64::from(min_y) + i64::from(max_y) - 40).abs() <= 2,
            "{min_y}..{max_y}"
        );
    }

    #[test]
    fn vertical_text_is_taller_than_wide() {
        let mut pm = Pixmap::new(60, 120).expect("valid test input");
        let style = TextStyle::new(14.0, Rgba8::rgb(0, 0, 0));
        draw_text_vertical(&mut pm, "RMSE value", (30.0, 60.0), &style).expect("valid test input");
        let inked: Vec<(u32, u32)> = (0..120)
            .flat_map(|y| (0..60).map(move |x| (x, y)))
            .filter(|&(x, y)| pm.pixel(x, y).expect("valid test input").alpha() > 128)
            .collect();
        let xs = inked.iter().map(|p| p.0);
        let ys = inked.iter().map(|p| p.1);
        let w = xs.clone().max().expect("valid test input") - xs.min().expect("valid test input");
        let h = ys.clone().max().expect("valid test input") - ys.min().expect("valid test input");
        assert!(h > 3 * w, "{w}×{h}");
    }
}
