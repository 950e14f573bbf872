//! The legend under the diagram: a centred row of colour swatches with labels.

use tiny_skia::Pixmap;

use crate::draw::DrawError;
use crate::draw::canvas::{self, LABEL_SIZE};
use crate::draw::palette::{Rgba8, ThemeColors};
use crate::draw::text::{self, HAlign, TextStyle, VAlign};

/// Draws a centred row of colour swatches with labels.
pub(super) fn swatch_row(
    pixmap: &mut Pixmap,
    (cx, y): (f32, f32),
    entries: &[(Rgba8, String)],
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let style = TextStyle::new(LABEL_SIZE, colors.foreground);
    let widths = entries
        .iter()
        .map(|(_, label)| Ok(text::measure(label, LABEL_SIZE, text::Weight::Regular)?.width))
        .collect::<Result<Vec<f32>, DrawError>>()?;
    let total: f32 =
        widths.iter().map(|w| w + 20.0).sum::<f32>() + 18.0 * (entries.len() as f32 - 1.0);
    let mut x = (cx - total / 2.0).round();
    for ((color, label), width) in entries.iter().zip(widths) {
        canvas::fill_rect(pixmap, x, y - 7.0, 14.0, 14.0, *color);
        text::draw_text(
            pixmap,
            label,
            (x + 20.0, y),
            (HAlign::Left, VAlign::Middle),
            &style,
        )?;
        x += width + 20.0 + 18.0;
    }
    Ok(())
}
