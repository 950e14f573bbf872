//! Drawing primitives over tiny-skia shared by the drawings (rectangles, lines, dots, the
//! legend box), all in pixel coordinates with `y` pointing down.

use tiny_skia::{
    Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Rect, Stroke, StrokeDash, Transform,
};

use super::palette::{Rgba8, ThemeColors};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};

/// Font sizes (pixels per em) used across the drawings.
pub(crate) const TITLE_SIZE: f32 = 18.0;
/// Axis titles, captions, legend entries.
pub(crate) const LABEL_SIZE: f32 = 13.0;
/// Tick labels and in-bar labels.
pub(crate) const TICK_SIZE: f32 = 12.0;

/// A blank canvas of the style's size filled with the theme background.
pub(crate) fn blank(style: &Style) -> Result<Pixmap, DrawError> {
    let mut pixmap = Pixmap::new(style.width, style.height).ok_or(DrawError::Size {
        width: style.width,
        height: style.height,
    })?;
    let [r, g, b, a] = style.theme.colors().background.0;
    pixmap.fill(Color::from_rgba8(r, g, b, a));
    Ok(pixmap)
}

/// An anti-aliased solid paint.
pub(crate) fn paint(color: Rgba8) -> Paint<'static> {
    let mut paint = Paint::default();
    let [r, g, b, a] = color.0;
    paint.set_color_rgba8(r, g, b, a);
    paint.anti_alias = true;
    paint
}

/// The centre of the pixel row/column containing `v`: 1-px lines drawn there are crisp.
pub(crate) fn crisp(v: f32) -> f32 {
    v.floor() + 0.5
}

/// Fills the rectangle `[x, x + w] × [y, y + h]` (nothing when empty).
pub(crate) fn fill_rect(pixmap: &mut Pixmap, x: f32, y: f32, w: f32, h: f32, color: Rgba8) {
    if let Some(rect) = Rect::from_xywh(x, y, w, h) {
        pixmap.fill_rect(rect, &paint(color), Transform::identity(), None);
    }
}

/// Outlines the rectangle `[x, x + w] × [y, y + h]` with a line of `width` pixels.
pub(crate) fn stroke_rect(
    pixmap: &mut Pixmap,
    (x, y, w, h): (f32, f32, f32, f32),
    width: f32,
    color: Rgba8,
) {
    if let Some(rect) = Rect::from_xywh(x, y, w, h) {
        let path = PathBuilder::from_rect(rect);
        let stroke = Stroke {
            width,
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, &paint(color), &stroke, Transform::identity(), None);
    }
}

/// Strokes the polyline through `points`, optionally dashed (`[on, off]` in pixels).
pub(crate) fn polyline(
    pixmap: &mut Pixmap,
    points: &[(f32, f32)],
    width: f32,
    color: Rgba8,
    dash: Option<[f32; 2]>,
) {
    let mut builder = PathBuilder::new();
    for (k, &(x, y)) in points.iter().enumerate() {
        if k == 0 {
            builder.move_to(x, y);
        } else {
            builder.line_to(x, y);
        }
    }
    let Some(path) = builder.finish() else {
        return;
    };
    let stroke = Stroke {
        width,
        line_cap: if dash.is_some() {
            LineCap::Butt
        } else {
            LineCap::Round
        },
        dash: dash.and_then(|[on, off]| StrokeDash::new(vec![on, off], 0.0)),
        ..Stroke::default()
    };
    pixmap.stroke_path(&path, &paint(color), &stroke, Transform::identity(), None);
}

/// Strokes one segment.
pub(crate) fn line(pixmap: &mut Pixmap, a: (f32, f32), b: (f32, f32), width: f32, color: Rgba8) {
    polyline(pixmap, &[a, b], width, color, None);
}

/// Fills a disc of radius `r` centred on `(x, y)`.
pub(crate) fn disc(pixmap: &mut Pixmap, (x, y): (f32, f32), r: f32, color: Rgba8) {
    if let Some(path) = PathBuilder::from_circle(x, y, r) {
        pixmap.fill_path(
            &path,
            &paint(color),
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

/// How a legend entry is marked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Mark {
    /// A filled swatch.
    Swatch(Rgba8),
    /// A solid line with a dot (a plotted series).
    LineDot(Rgba8),
    /// A dashed line.
    Dashed(Rgba8),
    /// A short thick bar (an expected-value marker).
    Tick(Rgba8),
}

/// One legend entry: its mark, its label, and an optional second (muted) line.
pub(crate) struct LegendEntry {
    pub mark: Mark,
    pub label: String,
    pub detail: Option<String>,
}

/// Width and height of the legend box for `entries`.
pub(crate) fn legend_size(entries: &[LegendEntry]) -> Result<(f32, f32), DrawError> {
    let mut width: f32 = 0.0;
    let mut height = 8.0;
    for e in entries {
        let label = text::measure(&e.label, LABEL_SIZE, text::Weight::Regular)?;
        width = width.max(label.width);
        height += 20.0;
        if let Some(detail) = &e.detail {
            width = width.max(text::measure(detail, TICK_SIZE, text::Weight::Regular)?.width);
            height += 16.0;
        }
    }
    Ok((width + 48.0, height))
}

/// Draws a legend box with its top-left corner at `(x, y)`; returns its size.
pub(crate) fn legend(
    pixmap: &mut Pixmap,
    (x, y): (f32, f32),
    entries: &[LegendEntry],
    colors: &ThemeColors,
) -> Result<(f32, f32), DrawError> {
    let (w, h) = legend_size(entries)?;
    fill_rect(pixmap, x, y, w, h, colors.panel);
    stroke_rect(
        pixmap,
        (crisp(x), crisp(y), w.round(), h.round()),
        1.0,
        colors.grid,
    );
    let mut cy = y + 4.0;
    for e in entries {
        let mid = cy + 10.0;
        let (mx, mw) = (x + 8.0, 24.0);
        match e.mark {
            Mark::Swatch(c) => fill_rect(pixmap, mx + 4.0, mid - 6.0, 16.0, 12.0, c),
            Mark::LineDot(c) => {
                line(pixmap, (mx, mid), (mx + mw, mid), 2.0, c);
                disc(pixmap, (mx + mw / 2.0, mid), 3.5, c);
            }
            Mark::Dashed(c) => polyline(
                pixmap,
                &[(mx, mid), (mx + mw, mid)],
                1.5,
                c,
                Some([5.0, 3.0]),
            ),
            Mark::Tick(c) => fill_rect(pixmap, mx + 2.0, mid - 1.5, mw - 4.0, 3.0, c),
        }
        let style = TextStyle::new(LABEL_SIZE, colors.foreground);
        text::draw_text(
            pixmap,
            &e.label,
            (x + 40.0, mid),
            (HAlign::Left, VAlign::Middle),
            &style,
        )?;
        cy += 20.0;
        if let Some(detail) = &e.detail {
            let style = TextStyle::new(TICK_SIZE, colors.muted);
            text::draw_text(
                pixmap,
                detail,
                (x + 40.0, cy + 7.0),
                (HAlign::Left, VAlign::Middle),
                &style,
            )?;
            cy += 16.0;
        }
    }
    Ok((w, h))
}

/// Draws the title (bold, centred) and an optional subtitle (muted) at the top.
pub(crate) fn title(
    pixmap: &mut Pixmap,
    title: &str,
    subtitle: Option<&str>,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let cx = pixmap.width() as f32 / 2.0;
    text::draw_text(
        pixmap,
        title,
        (cx, 12.0),
        (HAlign::Center, VAlign::Top),
        &TextStyle::new(TITLE_SIZE, colors.foreground).bold(),
    )?;
    if let Some(sub) = subtitle {
        text::draw_text(
            pixmap,
            sub,
            (cx, 38.0),
            (HAlign::Center, VAlign::Top),
            &TextStyle::new(LABEL_SIZE, colors.muted),
        )?;
    }
    Ok(())
}
