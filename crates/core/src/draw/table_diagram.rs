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

use tiny_skia::Pixmap;

use super::axes::{self, Frame, Scale};
use super::canvas::{self, LABEL_SIZE, TICK_SIZE};
use super::palette::{self, Rgba8, ThemeColors};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};
use crate::alias::AliasTable;
use crate::powers::LightPowers;

/// From this many lights on, the diagram is an unlabelled summary.
pub const TABLE_DETAIL_LIMIT: usize = 64;

/// The tallest scaled mass shown before bars are clipped.
const MAX_SHOWN_HEIGHT: f64 = 4.0;

/// The exact denominator for fraction labels: the total power, when every power is a whole
/// number and the total is at most 1000, so fractions stay short (the seed powers 2, 5, 20
/// give 27: labels read `6/27`, `15/27`, `60/27`). `None` otherwise: labels are decimals.
pub fn fraction_denominator(powers: &LightPowers) -> Option<u64> {
    crate::fraction::common_denominator(powers.as_slice(), 1000.0)
}

/// `v` as `k/denominator` when it is one (within rounding), `0` and `1` plainly, else a
/// short decimal.
pub(crate) fn fraction_label(v: f64, denominator: Option<u64>) -> String {
    if let Some(label) = crate::fraction::format_fraction(v, denominator) {
        return label;
    }
    if v >= 10.0 {
        format!("{v:.1}")
    } else if v >= 0.01 {
        format!("{v:.3}")
    } else {
        axes::format_sci(v, 2)
    }
}

/// One drawn column (or bin of columns) of the alias-table panel, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ColumnRects {
    /// Left edge and width.
    pub x: f32,
    pub width: f32,
    /// Top of the own-light part (its bottom is the baseline) and its height.
    pub own_top: f32,
    pub own_height: f32,
    /// Top of the alias part (the column top) and its height.
    pub alias_top: f32,
    pub alias_height: f32,
}

/// Splits a unit column of `unit_px` pixels standing on `baseline` at `threshold`.
pub(crate) fn split_column(
    x: f32,
    width: f32,
    threshold: f64,
    baseline: f32,
    unit_px: f32,
) -> ColumnRects {
    let own_height = threshold as f32 * unit_px;
    ColumnRects {
        x,
        width,
        own_top: baseline - own_height,
        own_height,
        alias_top: baseline - unit_px,
        alias_height: unit_px - own_height,
    }
}

/// Mean of `values` over `bins` contiguous, nearly equal bins.
pub(crate) fn bin_means(values: &[f64], bins: usize) -> Vec<f64> {
    let n = values.len();
    (0..bins)
        .map(|b| {
            let (lo, hi) = (b * n / bins, (b + 1) * n / bins);
            values[lo..hi].iter().sum::<f64>() / (hi - lo).max(1) as f64
        })
        .collect()
}

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

    let masses: Vec<f64> = table.pmf_slice().iter().map(|p| p * n as f64).collect();
    let bins = summary_bins(n, right.width);
    // The scale covers what is drawn: binned means in a binned summary.
    let max_mass = if !detailed && bins < n {
        bin_means(&masses, bins).into_iter().fold(1.0, f64::max)
    } else {
        masses.iter().copied().fold(1.0, f64::max)
    };
    let y_max = max_mass.min(MAX_SHOWN_HEIGHT) * 1.12;
    let scale = Scale::Linear {
        min: 0.0,
        max: y_max,
    };
    let unit_px = (f64::from(left.height) / y_max) as f32;

    let heading = TextStyle::new(LABEL_SIZE, colors.foreground).bold();
    text::draw_text(
        &mut pixmap,
        "1. scaled masses N·pᵢ",
        (left.left, left.top - 12.0),
        (HAlign::Left, VAlign::Baseline),
        &heading,
    )?;
    text::draw_text(
        &mut pixmap,
        "2. alias table: N columns of height 1",
        (right.left, right.top - 12.0),
        (HAlign::Left, VAlign::Baseline),
        &heading,
    )?;
    axes::y_axis(&mut pixmap, &left, &scale, "height", &colors)?;
    axes::y_axis(&mut pixmap, &right, &scale, "", &colors)?;

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

    // The mean line at height 1, across both panels.
    let y1 = canvas::crisp(left.bottom() - unit_px);
    for f in [&left, &right] {
        canvas::polyline(
            &mut pixmap,
            &[(f.left, y1), (f.right(), y1)],
            1.5,
            colors.foreground,
            Some([6.0, 4.0]),
        );
    }
    let mean_label = text::measure("mean = 1", TICK_SIZE, text::Weight::Regular)?;
    canvas::fill_rect(
        &mut pixmap,
        left.left + 3.0,
        y1 - 5.0 - mean_label.height(),
        mean_label.width + 6.0,
        mean_label.height(),
        colors.background.with_alpha(220),
    );
    text::draw_text(
        &mut pixmap,
        "mean = 1",
        (left.left + 6.0, y1 - 5.0),
        (HAlign::Left, VAlign::Bottom),
        &TextStyle::new(TICK_SIZE, colors.foreground),
    )?;

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
    let rule = if detailed {
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
    };
    text::draw_text(
        &mut pixmap,
        &rule,
        (w / 2.0, h - 14.0),
        (HAlign::Center, VAlign::Baseline),
        &TextStyle::new(TICK_SIZE, colors.muted),
    )?;
    Ok(pixmap)
}

/// Per-light colours, outlines and fraction labels (fewer than [`TABLE_DETAIL_LIMIT`]).
fn draw_detailed(
    pixmap: &mut Pixmap,
    table: &AliasTable,
    masses: &[f64],
    denominator: Option<u64>,
    (left, right): (&Frame, &Frame),
    unit_px: f32,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let n = masses.len();
    let tick = TextStyle::new(TICK_SIZE, colors.foreground);
    let slot_l = left.width / n as f32;
    let slot_r = right.width / n as f32;
    // Index labels on every k-th column, so that they never collide.
    let index_every = (24.0 / slot_r.min(slot_l)).ceil().max(1.0) as usize;
    for (i, &mass) in masses.iter().enumerate() {
        // Panel 1: the scaled mass, clipped at the frame top.
        let bar_w = (slot_l * 0.62).min(70.0);
        let x = left.left + slot_l * (i as f32 + 0.5) - bar_w / 2.0;
        let bar_h = (mass as f32 * unit_px).min(left.height);
        let color = palette::light_color(i);
        canvas::fill_rect(pixmap, x, left.bottom() - bar_h, bar_w, bar_h, color);
        let label = fraction_label(mass, denominator);
        if bar_h >= left.height {
            // Clipped: the value goes beside the bar's top, with an arrow.
            text::draw_text(
                pixmap,
                &format!("↑ {label}"),
                (x + bar_w + 4.0, left.top + 2.0),
                (HAlign::Left, VAlign::Top),
                &tick,
            )?;
        } else if text::measure(&label, TICK_SIZE, text::Weight::Regular)?.width + 2.0 <= slot_l {
            text::draw_text(
                pixmap,
                &label,
                (x + bar_w / 2.0, left.bottom() - bar_h - 4.0),
                (HAlign::Center, VAlign::Bottom),
                &tick,
            )?;
        }
        if i % index_every == 0 {
            text::draw_text(
                pixmap,
                &i.to_string(),
                (x + bar_w / 2.0, left.bottom() + 8.0),
                (HAlign::Center, VAlign::Top),
                &tick,
            )?;
        }

        // Panel 2: the unit column split at the threshold.
        let col_w = (slot_r * 0.8).min(90.0);
        let cx = right.left + slot_r * (i as f32 + 0.5);
        let threshold = table.thresholds()[i];
        let alias = table.aliases()[i] as usize;
        let c = split_column(cx - col_w / 2.0, col_w, threshold, right.bottom(), unit_px);
        canvas::fill_rect(pixmap, c.x, c.own_top, c.width, c.own_height, color);
        let alias_color = palette::light_color(alias);
        canvas::fill_rect(
            pixmap,
            c.x,
            c.alias_top,
            c.width,
            c.alias_height,
            alias_color,
        );
        canvas::stroke_rect(
            pixmap,
            (c.x, c.alias_top, c.width, unit_px),
            1.0,
            colors.foreground,
        );
        if threshold > 0.0 && threshold < 1.0 {
            canvas::line(
                pixmap,
                (c.x, c.own_top),
                (c.x + c.width, c.own_top),
                1.5,
                colors.foreground,
            );
        }
        if i % index_every == 0 {
            text::draw_text(
                pixmap,
                &i.to_string(),
                (cx, right.bottom() + 8.0),
                (HAlign::Center, VAlign::Top),
                &tick,
            )?;
        }
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

/// How many columns the summary draws: all `n` while each gets at least one pixel of
/// `width`, else bins of about two pixels.
pub(crate) fn summary_bins(n: usize, width: f32) -> usize {
    if n as f32 <= width.floor() {
        n
    } else {
        ((width / 2.0).floor() as usize).clamp(1, n)
    }
}

/// The whole-pixel edges of `count` equal slots across `[x, x + width]`: each slot spans
/// `edges[k]..edges[k + 1]`, so adjacent slots neither overlap nor leave gaps.
pub(crate) fn pixel_edges(x: f32, width: f32, count: usize) -> Vec<f32> {
    (0..=count)
        .map(|k| (x + width * k as f32 / count as f32).round())
        .collect()
}

/// Thin two-tone columns on whole pixels, binned when there are more columns than pixels.
fn draw_summary(
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
        canvas::fill_rect(
            pixmap,
            c.x,
            c.own_top,
            c.width,
            c.own_height,
            palette::TABLE_OWN,
        );
        canvas::fill_rect(
            pixmap,
            c.x,
            c.alias_top,
            c.width,
            c.alias_height,
            palette::TABLE_ALIAS,
        );
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

/// Draws a centred row of colour swatches with labels.
fn swatch_row(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SeedExample;

    #[test]
    fn seed_fractions() {
        let powers = SeedExample::powers();
        let d = fraction_denominator(&powers);
        assert_eq!(d, Some(27));
        let table = AliasTable::build_exact(&powers);
        let labels: Vec<String> = table
            .thresholds()
            .iter()
            .map(|&t| fraction_label(t, d))
            .collect();
        assert_eq!(labels, ["6/27", "15/27", "1"]);
        let masses: Vec<String> = table
            .pmf_slice()
            .iter()
            .map(|&p| fraction_label(3.0 * p, d))
            .collect();
        assert_eq!(masses, ["6/27", "15/27", "60/27"]);
        assert_eq!(fraction_label(21.0 / 27.0, d), "21/27");
    }

    #[test]
    fn fractions_fall_back_to_decimals() {
        let powers = LightPowers::new(vec![0.5, 1.5]).expect("valid test input");
        assert_eq!(fraction_denominator(&powers), None);
        assert_eq!(fraction_label(0.5, None), "0.500");
        assert_eq!(fraction_label(1.0, None), "1");
        assert_eq!(fraction_label(0.1, Some(3)), "0.100");
    }

    #[test]
    fn column_split_heights_equal_thresholds() {
        let table = AliasTable::build_exact(&SeedExample::powers());
        let unit_px = 120.0;
        for &t in table.thresholds() {
            let c = split_column(10.0, 40.0, t, 300.0, unit_px);
            assert!((f64::from(c.own_height / unit_px) - t).abs() < 1e-6);
            assert!((c.own_height + c.alias_height - unit_px).abs() < 1e-4);
            // The own part sits on the baseline and the alias part right on top of it.
            assert!((c.own_top + c.own_height - 300.0).abs() < 1e-4);
            assert!((c.alias_top + c.alias_height - c.own_top).abs() < 1e-4);
        }
    }

    #[test]
    fn unit_columns_hold_the_scaled_masses() {
        // Σ over columns of each light's drawn area equals N·pᵢ (in units of column area).
        let table = AliasTable::build_exact(&SeedExample::powers());
        let mut area = [0.0; 3];
        for (i, (&t, &a)) in table.thresholds().iter().zip(table.aliases()).enumerate() {
            let c = split_column(0.0, 1.0, t, 100.0, 100.0);
            area[i] += f64::from(c.own_height) / 100.0;
            area[a as usize] += f64::from(c.alias_height) / 100.0;
        }
        for (got, want) in area.iter().zip([6.0 / 27.0, 15.0 / 27.0, 60.0 / 27.0]) {
            assert!((got - want).abs() < 1e-6, "{got} vs {want}");
        }
    }

    #[test]
    fn bins_average_contiguous_columns() {
        assert_eq!(bin_means(&[1.0, 3.0, 5.0, 7.0], 2), [2.0, 6.0]);
        assert_eq!(bin_means(&[1.0, 2.0, 3.0], 3), [1.0, 2.0, 3.0]);
        let many: Vec<f64> = (0..1000).map(f64::from).collect();
        let means = bin_means(&many, 7);
        assert_eq!(means.len(), 7);
        let total: f64 = (0..7)
            .map(|b| means[b] * ((b + 1) * 1000 / 7 - b * 1000 / 7) as f64)
            .sum();
        assert!((total - many.iter().sum::<f64>()).abs() < 1e-6);
    }

    #[test]
    fn summary_columns_sit_on_whole_pixels() {
        assert_eq!(summary_bins(100, 330.0), 100);
        assert_eq!(summary_bins(330, 330.5), 330);
        assert_eq!(summary_bins(331, 330.0), 165);
        assert_eq!(summary_bins(5000, 330.0), 165);
        let edges = pixel_edges(10.3, 330.0, 200);
        assert_eq!(edges.len(), 201);
        assert!(edges.iter().all(|e| e.fract() == 0.0));
        assert_eq!((edges[0], edges[200]), (10.0, 340.0));
        assert!(
            edges
                .windows(2)
                .all(|w| (1.0..=2.0).contains(&(w[1] - w[0])))
        );
    }

    #[test]
    fn draws_small_and_large_tables() {
        let style = Style::default();
        let seed = AliasTable::build_exact(&SeedExample::powers());
        let pm = table_diagram(&seed, Some(27), &style).expect("valid test input");
        assert_eq!((pm.width(), pm.height()), (800, 500));
        let powers: Vec<f64> = (0..5000).map(|i| 1.0 + f64::from(i % 7)).collect();
        let big = AliasTable::build_exact(&LightPowers::new(powers).expect("valid test input"));
        assert!(table_diagram(&big, None, &style).is_ok());
    }
}
