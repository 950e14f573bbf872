//! Expected pmf beside empirical frequencies, one bar group per light.
//!
//! Each group shows the power pmf `pᵢ` (grey) and, per scheme, the observed frequency
//! `countᵢ / n` in the scheme's colour, with a short dark marker at the frequency the scheme
//! *expects* (`1/N` for uniform, `pᵢ` for the power-proportional schemes). The legend gives
//! each scheme's sample count and its Pearson χ² fit against its own expected pmf
//! ([`crate::chi_square()`]). With more than [`HISTOGRAM_TOP_K`] lights only the
//! `HISTOGRAM_TOP_K` lights of largest `pᵢ` are drawn (the χ² still covers all of them).

use tiny_skia::Pixmap;

use super::axes::{self, Frame, Scale};
use super::canvas::{self, LegendEntry, Mark, TICK_SIZE};
use super::palette::{self, ThemeColors};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};
use crate::chi_square::{ChiSquare, chi_square};
use crate::sampler::Scheme;

/// The most lights drawn; larger sets show the ones with the largest `pᵢ`.
pub const HISTOGRAM_TOP_K: usize = 16;

/// The picks of one scheme: counts per light, the pmf they should follow, and the fit.
#[derive(Clone, Debug, PartialEq)]
pub struct SchemeCounts {
    /// The scheme that picked.
    pub scheme: Scheme,
    /// How often each light was picked.
    pub counts: Vec<u64>,
    /// The pmf the scheme realizes (`1/N` each for uniform, `pᵢ` otherwise).
    pub expected: Vec<f64>,
    /// Pearson's χ² test of `counts` against `expected`.
    pub fit: ChiSquare,
}

impl SchemeCounts {
    /// Bundles counts with the pmf they should follow and computes the χ² fit.
    pub fn new(scheme: Scheme, counts: Vec<u64>, expected: Vec<f64>) -> Result<Self, DrawError> {
        if counts.len() != expected.len() {
            return Err(DrawError::Length {
                what: "counts",
                expected: expected.len(),
                got: counts.len(),
            });
        }
        let fit = chi_square(&counts, &expected);
        Ok(Self {
            scheme,
            counts,
            expected,
            fit,
        })
    }

    /// Total number of picks.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }
}

/// Everything the histogram shows.
#[derive(Clone, Debug, PartialEq)]
pub struct HistogramData {
    /// The power pmf `pᵢ` (drawn grey in every group).
    pub pmf: Vec<f64>,
    /// One entry per scheme, drawn in this order.
    pub schemes: Vec<SchemeCounts>,
}

/// The lights shown: all of them in index order when there are at most `k`, else the `k` of
/// largest `pmf` (ties by index), largest first.
pub(crate) fn shown_lights(pmf: &[f64], k: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..pmf.len()).collect();
    if pmf.len() > k {
        order.sort_by(|&a, &b| pmf[b].total_cmp(&pmf[a]).then(a.cmp(&b)));
        order.truncate(k);
    }
    order
}

/// `n` with thin spaces between groups of three digits (`100 000`).
pub(crate) fn group_digits(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
}

/// A p-value for a legend: 3 decimals, scientific below 0.001, `≈ 0` when it underflowed.
pub(crate) fn format_p(p: f64) -> String {
    if p.is_nan() {
        "p = n/a".to_owned()
    } else if p == 0.0 {
        "p ≈ 0".to_owned()
    } else if p >= 0.001 {
        format!("p = {p:.3}")
    } else {
        format!("p = {}", axes::format_sci(p, 2))
    }
}

/// Draws the histogram of `data`.
pub fn histogram(data: &HistogramData, style: &Style) -> Result<Pixmap, DrawError> {
    let n = data.pmf.len();
    if n == 0 {
        return Err(DrawError::Empty("no lights"));
    }
    check_lengths(data)?;
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let (w, h) = (style.width as f32, style.height as f32);

    let shown = shown_lights(&data.pmf, HISTOGRAM_TOP_K);
    let totals: Vec<u64> = data.schemes.iter().map(SchemeCounts::total).collect();
    canvas::title(
        &mut pixmap,
        "Expected pmf vs observed frequencies",
        Some(&subtitle(n, shown.len(), &totals)),
        &colors,
    )?;

    // Legend on the right.
    let entries = legend_entries(data, &totals, &colors);
    let (legend_w, _) = canvas::legend_size(&entries)?;
    let frame = Frame {
        left: 76.0,
        top: 76.0,
        width: w - 76.0 - 20.0 - legend_w - 24.0,
        height: h - 76.0 - 72.0,
    };
    canvas::legend(
        &mut pixmap,
        (w - 20.0 - legend_w, frame.top),
        &entries,
        &colors,
    )?;

    // Scale over everything drawn.
    let top = highest_drawn(data, &shown, &totals);
    let scale = Scale::Linear {
        min: 0.0,
        max: if top > 0.0 { top * 1.12 } else { 1.0 },
    };
    axes::y_axis(&mut pixmap, &frame, &scale, "probability", &colors)?;
    draw_bars(
        &mut pixmap,
        data,
        (&shown, &totals),
        &frame,
        &scale,
        &colors,
    )?;
    let y = canvas::crisp(frame.bottom());
    canvas::line(
        &mut pixmap,
        (frame.left, y),
        (frame.right(), y),
        1.0,
        colors.foreground,
    );
    text::draw_text(
        &mut pixmap,
        if shown.len() < n {
            "light i (largest pᵢ first)"
        } else {
            "light i"
        },
        (frame.left + frame.width / 2.0, frame.bottom() + 30.0),
        (HAlign::Center, VAlign::Top),
        &TextStyle::new(canvas::LABEL_SIZE, colors.foreground),
    )?;
    Ok(pixmap)
}

/// Refuses a scheme whose counts or expected probabilities are not one per light.
fn check_lengths(data: &HistogramData) -> Result<(), DrawError> {
    let n = data.pmf.len();
    for s in &data.schemes {
        for (what, len) in [("counts", s.counts.len()), ("expected", s.expected.len())] {
            if len != n {
                return Err(DrawError::Length {
                    what,
                    expected: n,
                    got: len,
                });
            }
        }
    }
    Ok(())
}

/// `N = n lights`, the picks per scheme when all schemes made as many, and how many lights
/// are shown when not all are.
fn subtitle(n: usize, shown: usize, totals: &[u64]) -> String {
    let picks = match totals.first() {
        Some(&t) if totals.iter().all(|&x| x == t) => {
            format!(" · {} picks per scheme", group_digits(t))
        }
        _ => String::new(),
    };
    let which = if shown < n {
        format!(" · showing the {shown} largest pᵢ")
    } else {
        String::new()
    };
    format!("N = {n} lights{picks}{which}")
}

/// The legend: the power pmf, each scheme's observed frequencies with its χ² fit, and the
/// tick marking what each scheme expects.
fn legend_entries(data: &HistogramData, totals: &[u64], colors: &ThemeColors) -> Vec<LegendEntry> {
    let mut entries = vec![LegendEntry {
        mark: Mark::Swatch(palette::REFERENCE),
        label: "power pmf pᵢ".to_owned(),
        detail: None,
    }];
    for (s, &total) in data.schemes.iter().zip(totals) {
        entries.push(LegendEntry {
            mark: Mark::Swatch(palette::scheme_color(s.scheme)),
            label: format!("{}: observed", s.scheme),
            detail: Some(format!(
                "n = {} · χ² = {:.2}, {} dof · {}",
                group_digits(total),
                s.fit.chi2,
                s.fit.dof,
                format_p(s.fit.p_value)
            )),
        });
    }
    if !data.schemes.is_empty() {
        entries.push(LegendEntry {
            mark: Mark::Tick(colors.foreground),
            label: "expected by the scheme".to_owned(),
            detail: None,
        });
    }
    entries
}

/// The highest value drawn for the `shown` lights: pmf, expected and observed frequencies.
fn highest_drawn(data: &HistogramData, shown: &[usize], totals: &[u64]) -> f64 {
    let mut top = 0.0_f64;
    for &i in shown {
        top = top.max(data.pmf[i]);
        for (s, &total) in data.schemes.iter().zip(totals) {
            top = top.max(s.expected[i]);
            if total > 0 {
                top = top.max(s.counts[i] as f64 / total as f64);
            }
        }
    }
    top
}

/// One group of bars per shown light: its pmf, then each scheme's observed frequency with
/// a tick at what the scheme expects, and the light's index below.
fn draw_bars(
    pixmap: &mut Pixmap,
    data: &HistogramData,
    (shown, totals): (&[usize], &[u64]),
    frame: &Frame,
    scale: &Scale,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let to_y = |v: f64| frame.bottom() - scale.unit(v) as f32 * frame.height;
    let slot = frame.width / shown.len() as f32;
    let bars = 1 + data.schemes.len();
    let bar_w = (slot * 0.8 / bars as f32).min(36.0);
    let tick = TextStyle::new(TICK_SIZE, colors.foreground);
    for (g, &i) in shown.iter().enumerate() {
        let cx = frame.left + slot * (g as f32 + 0.5);
        let x0 = cx - bar_w * bars as f32 / 2.0;
        let y = to_y(data.pmf[i]);
        canvas::fill_rect(pixmap, x0, y, bar_w, frame.bottom() - y, palette::REFERENCE);
        for (k, (s, &total)) in data.schemes.iter().zip(totals).enumerate() {
            let x = x0 + bar_w * (k + 1) as f32;
            let freq = if total > 0 {
                s.counts[i] as f64 / total as f64
            } else {
                0.0
            };
            let y = to_y(freq);
            let color = palette::scheme_color(s.scheme);
            canvas::fill_rect(pixmap, x, y, bar_w, frame.bottom() - y, color);
            let ey = to_y(s.expected[i]);
            canvas::fill_rect(
                pixmap,
                x - 1.0,
                ey - 1.5,
                bar_w + 2.0,
                3.0,
                colors.foreground,
            );
        }
        text::draw_text(
            pixmap,
            &i.to_string(),
            (cx, frame.bottom() + 8.0),
            (HAlign::Center, VAlign::Top),
            &tick,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn top_k_keeps_the_largest() {
        assert_eq!(shown_lights(&[0.1, 0.5, 0.4], 16), [0, 1, 2]);
        assert_eq!(shown_lights(&[0.1, 0.5, 0.4, 0.0], 2), [1, 2]);
        assert_eq!(shown_lights(&[0.25; 4], 3), [0, 1, 2]);
    }

    #[test]
    fn number_formats() {
        assert_eq!(group_digits(0), "0");
        assert_eq!(group_digits(999), "999");
        assert_eq!(group_digits(100_000), "100\u{2009}000");
        assert_eq!(group_digits(1_234_567), "1\u{2009}234\u{2009}567");
        assert_eq!(format_p(0.391_6), "p = 0.392");
        assert_eq!(format_p(3.2e-5), "p = 3.2·10⁻⁵");
        assert_eq!(format_p(0.0), "p ≈ 0");
    }

    #[test]
    fn mismatched_lengths_are_refused() {
        let err = SchemeCounts::new(Scheme::Alias, vec![1, 2], vec![0.5; 3])
            .expect_err("must be refused");
        assert!(matches!(
            err,
            DrawError::Length {
                expected: 3,
                got: 2,
                ..
            }
        ));
        let data = HistogramData {
            pmf: vec![0.5; 2],
            schemes: vec![
                SchemeCounts::new(Scheme::Uniform, vec![1; 3], vec![1.0 / 3.0; 3])
                    .expect("valid test input"),
            ],
        };
        assert!(matches!(
            histogram(&data, &Style::default()),
            Err(DrawError::Length { .. })
        ));
        let empty = HistogramData {
            pmf: vec![],
            schemes: vec![],
        };
        assert!(matches!(
            histogram(&empty, &Style::default()),
            Err(DrawError::Empty(_))
        ));
    }
}
