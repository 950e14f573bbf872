//! The detailed drawing of small tables (fewer than [`super::TABLE_DETAIL_LIMIT`] lights):
//! per-light colours, outlines and fraction labels, bar by bar and column by column.

use tiny_skia::Pixmap;

use super::columns::{ColumnRects, split_column};
use super::labels::fraction_label;
use crate::alias::AliasTable;
use crate::draw::DrawError;
use crate::draw::axes::Frame;
use crate::draw::canvas::{self, LABEL_SIZE, TICK_SIZE};
use crate::draw::palette::{self, Rgba8, ThemeColors};
use crate::draw::text::{self, HAlign, TextStyle, VAlign};

/// What every light's bar and column are drawn with: the two panels, their slot widths,
/// the vertical unit and the labels' style.
struct Layout<'a> {
    left: &'a Frame,
    right: &'a Frame,
    slot_l: f32,
    slot_r: f32,
    unit_px: f32,
    /// Index labels on every k-th light.
    index_every: usize,
    denominator: Option<u64>,
    tick: TextStyle,
    colors: &'a ThemeColors,
}

/// Per-light colours, outlines and fraction labels (fewer than [`super::TABLE_DETAIL_LIMIT`]).
pub(super) fn draw_detailed(
    pixmap: &mut Pixmap,
    table: &AliasTable,
    masses: &[f64],
    denominator: Option<u64>,
    (left, right): (&Frame, &Frame),
    unit_px: f32,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let n = masses.len();
    let slot_l = left.width / n as f32;
    let slot_r = right.width / n as f32;
    let layout = Layout {
        left,
        right,
        slot_l,
        slot_r,
        unit_px,
        // Index labels on every k-th column, so that they never collide.
        index_every: (24.0 / slot_r.min(slot_l)).ceil().max(1.0) as usize,
        denominator,
        tick: TextStyle::new(TICK_SIZE, colors.foreground),
        colors,
    };
    for (i, &mass) in masses.iter().enumerate() {
        draw_mass_bar(pixmap, &layout, i, mass)?;
        draw_unit_column(pixmap, &layout, table, i)?;
    }
    let axis_title = TextStyle::new(LABEL_SIZE, colors.foreground);
    text::draw_text(
        pixmap,
        "light i",
        (left.left + left.width / 2.0, left.bottom() + 30.0),
        (HAlign::Center, VAlign::Top),
        &axis_title,
    )?;
    text::draw_text(
        pixmap,
        "column i: own light i below its threshold, alias above",
        (right.left + right.width / 2.0, right.bottom() + 30.0),
        (HAlign::Center, VAlign::Top),
        &axis_title,
    )?;
    Ok(())
}

/// Panel 1: light `i`'s scaled mass as a bar, clipped at the frame top, with its value and
/// index.
fn draw_mass_bar(
    pixmap: &mut Pixmap,
    layout: &Layout<'_>,
    i: usize,
    mass: f64,
) -> Result<(), DrawError> {
    let (left, slot_l, tick) = (layout.left, layout.slot_l, &layout.tick);
    let bar_w = (slot_l * 0.62).min(70.0);
    let x = left.left + slot_l * (i as f32 + 0.5) - bar_w / 2.0;
    let bar_h = (mass as f32 * layout.unit_px).min(left.height);
    canvas::fill_rect(
        pixmap,
        x,
        left.bottom() - bar_h,
        bar_w,
        bar_h,
        palette::light_color(i),
    );
    let label = fraction_label(mass, layout.denominator);
    if bar_h >= left.height {
        // Clipped: the value goes beside the bar's top, with an arrow.
        text::draw_text(
            pixmap,
            &format!("↑ {label}"),
            (x + bar_w + 4.0, left.top + 2.0),
            (HAlign::Left, VAlign::Top),
            tick,
        )?;
    } else if text::measure(&label, TICK_SIZE, text::Weight::Regular)?.width + 2.0 <= slot_l {
        text::draw_text(
            pixmap,
            &label,
            (x + bar_w / 2.0, left.bottom() - bar_h - 4.0),
            (HAlign::Center, VAlign::Bottom),
            tick,
        )?;
    }
    if i.is_multiple_of(layout.index_every) {
        text::draw_text(
            pixmap,
            &i.to_string(),
            (x + bar_w / 2.0, left.bottom() + 8.0),
            (HAlign::Center, VAlign::Top),
            tick,
        )?;
    }
    Ok(())
}

/// Panel 2: column `i` of the table, a unit column split at its threshold (own light below,
/// alias above), outlined, with its index and the labels that fit.
fn draw_unit_column(
    pixmap: &mut Pixmap,
    layout: &Layout<'_>,
    table: &AliasTable,
    i: usize,
) -> Result<(), DrawError> {
    let (right, slot_r, unit_px) = (layout.right, layout.slot_r, layout.unit_px);
    let foreground = layout.colors.foreground;
    let col_w = (slot_r * 0.8).min(90.0);
    let cx = right.left + slot_r * (i as f32 + 0.5);
    let threshold = table.thresholds()[i];
    let alias = table.aliases()[i] as usize;
    let c = split_column(cx - col_w / 2.0, col_w, threshold, right.bottom(), unit_px);
    let (color, alias_color) = (palette::light_color(i), palette::light_color(alias));
    c.fill(pixmap, color, alias_color);
    canvas::stroke_rect(
        pixmap,
        (c.x, c.alias_top, c.width, unit_px),
        1.0,
        foreground,
    );
    if threshold > 0.0 && threshold < 1.0 {
        canvas::line(
            pixmap,
            (c.x, c.own_top),
            (c.x + c.width, c.own_top),
            1.5,
            foreground,
        );
    }
    if i.is_multiple_of(layout.index_every) {
        text::draw_text(
            pixmap,
            &i.to_string(),
            (cx, right.bottom() + 8.0),
            (HAlign::Center, VAlign::Top),
            &layout.tick,
        )?;
    }
    label_unit_column(
        pixmap,
        &c,
        cx,
        (threshold, color),
        (alias, alias_color),
        layout.denominator,
    )
}

/// The labels of a unit column, where they fit: its threshold on the own part, `alias j`
/// (or `→j`) and the alias's share on the alias part.
fn label_unit_column(
    pixmap: &mut Pixmap,
    c: &ColumnRects,
    cx: f32,
    (threshold, color): (f64, Rgba8),
    (alias, alias_color): (usize, Rgba8),
    denominator: Option<u64>,
) -> Result<(), DrawError> {
    let fits = |label: &str, height: f32| -> Result<bool, DrawError> {
        // Only columns wide enough for a fraction get any label, so none stands alone.
        Ok(height >= 16.0
            && c.width >= 40.0
            && text::measure(label, TICK_SIZE, text::Weight::Regular)?.width + 6.0 <= c.width)
    };
    let own = fraction_label(threshold, denominator);
    if fits(&own, c.own_height)? {
        text::draw_text(
            pixmap,
            &own,
            (cx, c.own_top + c.own_height / 2.0),
            (HAlign::Center, VAlign::Middle),
            &TextStyle::new(TICK_SIZE, color.contrasting_text()),
        )?;
    }
    let given = format!("alias {alias}");
    let given = if fits(&given, c.alias_height)? {
        given
    } else {
        format!("→{alias}")
    };
    if fits(&given, c.alias_height)? {
        let ink = alias_color.contrasting_text();
        let rest = fraction_label(1.0 - threshold, denominator);
        let two_lines = c.alias_height >= 34.0 && fits(&rest, c.alias_height)?;
        let mid = c.alias_top + c.alias_height / 2.0;
        let first_y = if two_lines { mid - 8.0 } else { mid };
        text::draw_text(
            pixmap,
            &given,
            (cx, first_y),
            (HAlign::Center, VAlign::Middle),
            &TextStyle::new(TICK_SIZE, ink),
        )?;
        if two_lines {
            text::draw_text(
                pixmap,
                &rest,
                (cx, mid + 8.0),
                (HAlign::Center, VAlign::Middle),
                &TextStyle::new(TICK_SIZE, ink),
            )?;
        }
    }
    Ok(())
}
