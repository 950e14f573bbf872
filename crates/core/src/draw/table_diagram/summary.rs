//! The summary drawing of large tables: thin two-tone columns on whole pixels, binned when
//! there are more columns than pixels.

use tiny_skia::Pixmap;

use super::columns::{bin_means, pixel_edges, split_column};
use crate::alias::AliasTable;
use crate::draw::DrawError;
use crate::draw::axes::Frame;
use crate::draw::canvas::{self, LABEL_SIZE, TICK_SIZE};
use crate::draw::palette::{self, ThemeColors};
use crate::draw::text::{self, HAlign, TextStyle, VAlign};

/// Thin two-tone columns on whole pixels, binned when there are more columns than pixels.
pub(super) fn draw_summary(
    pixmap: &mut Pixmap,
    table: &AliasTable,
    masses: &[f64],
    bins: usize,
    (left, right): (&Frame, &Frame),
    unit_px: f32,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let n = masses.len();
    let (masses, thresholds) = if bins < n {
        (bin_means(masses, bins), bin_means(table.thresholds(), bins))
    } else {
        (masses.to_vec(), table.thresholds().to_vec())
    };
    let edges_l = pixel_edges(left.left, left.width, bins);
    let edges_r = pixel_edges(right.left, right.width, bins);
    for (b, (&mass, &threshold)) in masses.iter().zip(&thresholds).enumerate() {
        let bar_h = (mass as f32 * unit_px).min(left.height);
        let (x0, x1) = (edges_l[b], edges_l[b + 1]);
        canvas::fill_rect(
            pixmap,
            x0,
            left.bottom() - bar_h,
            x1 - x0,
            bar_h,
            palette::TABLE_OWN,
        );
        let (x0, x1) = (edges_r[b], edges_r[b + 1]);
        let c = split_column(x0, x1 - x0, threshold, right.bottom(), unit_px);
        c.fill(pixmap, palette::TABLE_OWN, palette::TABLE_ALIAS);
    }
    let tick = TextStyle::new(TICK_SIZE, colors.foreground);
    for (f, what) in [(left, "light"), (right, "column")] {
        text::draw_text(
            pixmap,
            "0",
            (f.left, f.bottom() + 8.0),
            (HAlign::Left, VAlign::Top),
            &tick,
        )?;
        text::draw_text(
            pixmap,
            &(n - 1).to_string(),
            (f.right(), f.bottom() + 8.0),
            (HAlign::Right, VAlign::Top),
            &tick,
        )?;
        text::draw_text(
            pixmap,
            &format!("{what} index"),
            (f.left + f.width / 2.0, f.bottom() + 30.0),
            (HAlign::Center, VAlign::Top),
            &TextStyle::new(LABEL_SIZE, colors.foreground),
        )?;
    }
    Ok(())
}
