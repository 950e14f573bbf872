//! The alias-table diagram, drawn the way the classic explanation tells it (e.g. Keith
//! Schwarz, "Darts, Dice, and Coins: Sampling from a Discrete Distribution", 2011):
//!
//! 1. scale each probability by `N`, so the bars `N·pᵢ` have mean height 1 (dashed line);
//! 2. cut the tall bars down and fill the short ones up: `N` columns of height exactly 1,
//!    column `i` holding its own light `i` up to its threshold (bottom) and its alias above.
//!
//! Both panels share one vertical scale, so the dashed mean line runs across both and the
//! unit columns are visibly the bars "levelled" to their mean. Bars taller than the shown
//! range (at most 4) are clipped, with their value written above the clip.
//!
//! With [`TABLE_DETAIL_LIMIT`] lights or more the diagram becomes a summary: columns are
//! thin, unlabelled and two-toned ([`palette::TABLE_OWN`] below the threshold,
//! [`palette::TABLE_ALIAS`] above), and when there are more columns than pixels, adjacent
//! columns are binned and each bin shows its mean `N·pᵢ` and its mean threshold.

mod columns;
mod detailed;
mod labels;
mod legend;
mod summary;

pub use labels::fraction_denominator;

use tiny_skia::Pixmap;

use super::axes::{self, Frame, Scale};
use super::canvas::{self, LABEL_SIZE, TICK_SIZE};
use super::palette::{self, Rgba8, ThemeColors};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};
use crate::alias::AliasTable;
use columns::{bin_means, summary_bins};
use detailed::draw_detailed;
use legend::swatch_row;
use summary::draw_summary;

/// From this many lights on, the diagram is an unlabelled summary.
pub const TABLE_DETAIL_LIMIT: usize = 64;

/// The tallest scaled mass shown before bars are clipped.
const MAX_SHOWN_HEIGHT: f64 = 4.0;

/// Draws the two-panel alias-table diagram of `table`. With `denominator` (see
/// [`fraction_denominator`]) masses and thresholds are labelled as exact fractions.
pub fn table_diagram(
    table: &AliasTable,
    denominator: Option<u64>,
    style: &Style,
) -> Result<Pixmap, DrawError> {
    let n = table.len();
    if n == 0 {
        return Err(DrawError::Empty("the table has no columns"));
    }
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let detailed = n < TABLE_DETAIL_LIMIT;
    let plural = if n == 1 { "light" } else { "lights" };
    canvas::title(
        &mut pixmap,
        &format!("Alias table of {n} {plural}"),
        Some(
            "Scale each pᵢ by N (mean height 1), then level the bars: every column holds its own light and at most one alias",
        ),
        &colors,
    )?;

    let (w, h) = (style.width as f32, style.height as f32);
    let (left, right) = panels(w, h);
    let masses: Vec<f64> = table.pmf_slice().iter().map(|p| p * n as f64).collect();
    let bins = summary_bins(n, right.width);
    // The scale covers what is drawn: binned means in a binned summary.
    let max_mass = if !detailed && bins < n {
        bin_means(&masses, bins).into_iter().fold(1.0, f64::max)
    } else {
        masses.iter().copied().fold(1.0, f64::max)
    };
    let y_max = max_mass.min(MAX_SHOWN_HEIGHT) * 1.12;
    let unit_px = (f64::from(left.height) / y_max) as f32;
    draw_panel_axes(&mut pixmap, (&left, &right), y_max, &colors)?;

    if detailed {
        draw_detailed(
            &mut pixmap,
            table,
            &masses,
            denominator,
            (&left, &right),
            unit_px,
            &colors,
        )?;
    } else {
        draw_summary(
            &mut pixmap,
            table,
            &masses,
            bins,
            (&left, &right),
            unit_px,
            &colors,
        )?;
    }
    draw_mean_line(&mut pixmap, (&left, &right), unit_px, &colors)?;

    // Legend (few lights) and the sampling rule.
    let legend_y = h - 48.0;
    if detailed && n <= palette::LIGHTS.len() {
        let entries: Vec<(Rgba8, String)> = (0..n)
            .map(|i| (palette::light_color(i), format!("light {i}")))
            .collect();
        swatch_row(&mut pixmap, (w / 2.0, legend_y), &entries, &colors)?;
    } else if !detailed {
        let entries = [
            (palette::TABLE_OWN, "own light (below threshold)".to_owned()),
            (palette::TABLE_ALIAS, "alias (above threshold)".to_owned()),
        ];
        swatch_row(&mut pixmap, (w / 2.0, legend_y), &entries, &colors)?;
    }
    text::draw_text(
        &mut pixmap,
        &sampling_rule(table, detailed, bins),
        (w / 2.0, h - 14.0),
        (HAlign::Center, VAlign::Baseline),
        &TextStyle::new(TICK_SIZE, colors.muted),
    )?;
    Ok(pixmap)
}

/// The two panels side by side on a `w × h` canvas: the scaled masses (left) and the
/// alias table (right).
fn panels(w: f32, h: f32) -> (Frame, Frame) {
    let gap = 70.0;
    let panel_w = (w - 70.0 - gap - 30.0) / 2.0;
    let left = Frame {
        left: 70.0,
        top: 96.0,
        width: panel_w,
        height: h - 96.0 - 120.0,
    };
    let right = Frame {
        left: left.right() + gap,
        ..left
    };
    (left, right)
}

/// The panels' headings and their shared vertical axis, from 0 to `y_max`.
fn draw_panel_axes(
    pixmap: &mut Pixmap,
    (left, right): (&Frame, &Frame),
    y_max: f64,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let scale = Scale::Linear {
        min: 0.0,
        max: y_max,
    };
    let heading = TextStyle::new(LABEL_SIZE, colors.foreground).bold();
    text::draw_text(
        pixmap,
        "1. scaled masses N·pᵢ",
        (left.left, left.top - 12.0),
        (HAlign::Left, VAlign::Baseline),
        &heading,
    )?;
    text::draw_text(
        pixmap,
        "2. alias table: N columns of height 1",
        (right.left, right.top - 12.0),
        (HAlign::Left, VAlign::Baseline),
        &heading,
    )?;
    axes::y_axis(pixmap, left, &scale, "height", colors)?;
    axes::y_axis(pixmap, right, &scale, "", colors)?;
    Ok(())
}

/// The dashed mean line at height 1 across both panels, labelled `mean = 1`.
fn draw_mean_line(
    pixmap: &mut Pixmap,
    (left, right): (&Frame, &Frame),
    unit_px: f32,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let y1 = canvas::crisp(left.bottom() - unit_px);
    for f in [left, right] {
        canvas::polyline(
            pixmap,
            &[(f.left, y1), (f.right(), y1)],
            1.5,
            colors.foreground,
            Some([6.0, 4.0]),
        );
    }
    let mean_label = text::measure("mean = 1", TICK_SIZE, text::Weight::Regular)?;
    canvas::fill_rect(
        pixmap,
        left.left + 3.0,
        y1 - 5.0 - mean_label.height(),
        mean_label.width + 6.0,
        mean_label.height(),
        colors.background.with_alpha(220),
    );
    text::draw_text(
        pixmap,
        "mean = 1",
        (left.left + 6.0, y1 - 5.0),
        (HAlign::Left, VAlign::Bottom),
        &TextStyle::new(TICK_SIZE, colors.foreground),
    )?;
    Ok(())
}

/// The line under the diagram: how to sample (detailed), or the table's figures (summary).
fn sampling_rule(table: &AliasTable, detailed: bool, bins: usize) -> String {
    let n = table.len();
    if detailed {
        "To sample: pick a column uniformly, keep its own light with probability = threshold, else take its alias.".to_owned()
    } else {
        let full = table.thresholds().iter().filter(|&&t| t >= 1.0).count();
        let mean = table.thresholds().iter().sum::<f64>() / n as f64;
        format!(
            "N = {n}: {full} {} no alias (threshold 1); mean threshold {mean:.3}{}",
            if full == 1 {
                "column needs"
            } else {
                "columns need"
            },
            if bins < n {
                ". Columns are binned; bins show means."
            } else {
                "."
            }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{LightPowers, WorkedExample};

    #[test]
    fn draws_small_and_large_tables() {
        let style = Style::default();
        let seed = AliasTable::build_exact(&WorkedExample::powers());
        let pm = table_diagram(&seed, Some(27), &style).expect("valid test input");
        assert_eq!((pm.width(), pm.height()), (800, 500));
        let powers: Vec<f64> = (0..5000).map(|i| 1.0 + f64::from(i % 7)).collect();
        let big = AliasTable::build_exact(&LightPowers::new(powers).expect("valid test input"));
        assert!(table_diagram(&big, None, &style).is_ok());
    }
}
