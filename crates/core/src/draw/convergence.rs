//! Log-log convergence plot: RMSE against samples per pixel (or against seconds) per
//! scheme, with a dashed reference line of slope −1/2 (Monte Carlo error `∝ 1/√spp`).
//!
//! Both axes span whole decades around the data, with labelled decade ticks and unlabelled
//! ticks at 2…9. Points that cannot sit on a log axis (zero, negative, non-finite) are
//! skipped. The reference line passes through the geometric mean of the series' first points.
//!
//! A zero-variance series ([`zero_variance_series`]: the exact spatial pick on few lights,
//! whose RMSE is the rounding of the reference, about `10^-16` of the signal) is left off
//! the axes, which it would stretch by a dozen decades, and named in the legend instead
//! (`spatial: zero variance, off the plot` with its largest RMSE).

use tiny_skia::Pixmap;

use super::axes::{self, Frame, Scale};
use super::canvas::{self, LegendEntry, Mark};
use super::palette::{self, Rgba8};
use super::{DrawError, Style};
use crate::Scaled;
use crate::render::{SeriesPoint, is_zero_variance_scaled};
use crate::sampler::Scheme;

/// One measurement of a progressive render.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConvergencePoint {
    /// Samples per pixel accumulated so far.
    pub spp: u64,
    /// Root-mean-square error against the reference at that point.
    pub rmse: f64,
    /// Wall-clock seconds spent so far.
    pub seconds: f64,
}

/// One line of the plot.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceSeries {
    /// Legend label.
    pub label: String,
    /// Line colour.
    pub color: Rgba8,
    /// Measurements, in increasing `spp`.
    pub points: Vec<ConvergencePoint>,
}

impl ConvergenceSeries {
    /// A series labelled and coloured after `scheme`.
    pub fn for_scheme(scheme: Scheme, points: Vec<ConvergencePoint>) -> Self {
        Self {
            label: scheme.name().to_owned(),
            color: palette::scheme_color(scheme),
            points,
        }
    }

    /// A scheme's series as the renderers measure it ([`SeriesPoint`]: spp, seconds, RMSE).
    pub fn of_measured(scheme: Scheme, measured: &[SeriesPoint]) -> Self {
        let points = measured
            .iter()
            .map(|p| ConvergencePoint {
                spp: u64::from(p.spp),
                rmse: p.rmse,
                seconds: p.seconds,
            })
            .collect();
        Self::for_scheme(scheme, points)
    }
}

/// What the horizontal axis measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ConvergenceAxis {
    /// Samples per pixel (equal work per sample).
    #[default]
    Spp,
    /// Wall-clock seconds (what the work cost).
    Seconds,
}

impl ConvergenceAxis {
    fn x(self, p: &ConvergencePoint) -> f64 {
        match self {
            ConvergenceAxis::Spp => p.spp as f64,
            ConvergenceAxis::Seconds => p.seconds,
        }
    }
}

/// The plottable `(x, rmse)` pairs of a series: both finite and positive.
fn plottable(series: &ConvergenceSeries, axis: ConvergenceAxis) -> Vec<(f64, f64)> {
    series
        .points
        .iter()
        .map(|p| (axis.x(p), p.rmse))
        .filter(|&(x, y)| x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0)
        .collect()
}

/// The largest finite, non-negative RMSE of a series (`None` when it has none).
fn largest_rmse(series: &ConvergenceSeries) -> Option<f64> {
    series
        .points
        .iter()
        .map(|p| p.rmse)
        .filter(|r| r.is_finite() && *r >= 0.0)
        .reduce(f64::max)
}

/// Which series have zero variance up to rounding: those whose largest squared RMSE is a
/// zero variance next to the largest squared RMSE of all the series
/// ([`is_zero_variance_scaled`]: `max_k RMSE_s² ≤ 10^-12 · max_{s', k} RMSE_{s'}²`). An
/// unbiased series has `MSE = V/spp`, so at equal samples per pixel this compares
/// variances. A lone series, or one with no finite RMSE, is never judged zero-variance.
pub fn zero_variance_series(series: &[ConvergenceSeries]) -> Vec<bool> {
    let largest: Vec<Option<f64>> = series.iter().map(largest_rmse).collect();
    let overall = largest.iter().flatten().copied().fold(0.0, f64::max);
    largest
        .iter()
        .map(|m| {
            // Squared as `Scaled`: an RMSE of `10^200` (a light `10^-100` above a pixel)
            // squares beyond `f64`, where `inf ≤ 10^-12·inf` would call every series exact.
            let square = |x: f64| Scaled::from_f64(x).square();
            m.is_some_and(|m| is_zero_variance_scaled(square(m), square(overall)))
        })
        .collect()
}

/// The part of the line through `(u0, v0)` with slope `k` (unit coordinates) that lies
/// in the unit square, as two endpoints; `None` when it misses the square.
pub(crate) fn clip_line(u0: f64, v0: f64, k: f64) -> Option<((f64, f64), (f64, f64))> {
    let v = |u: f64| v0 + k * (u - u0);
    let mut lo: f64 = 0.0;
    let mut hi: f64 = 1.0;
    if k == 0.0 {
        if !(0.0..=1.0).contains(&v0) {
            return None;
        }
    } else {
        // Where the line crosses v = 0 and v = 1.
        let (a, b) = (u0 - v0 / k, u0 + (1.0 - v0) / k);
        lo = lo.max(a.min(b));
        hi = hi.min(a.max(b));
    }
    (lo < hi).then(|| ((lo, v(lo)), (hi, v(hi))))
}

/// Draws the convergence plot of `series` against `axis`.
pub fn convergence(
    series: &[ConvergenceSeries],
    axis: ConvergenceAxis,
    style: &Style,
) -> Result<Pixmap, DrawError> {
    if series.is_empty() {
        return Err(DrawError::Empty("no series"));
    }
    let zero = zero_variance_series(series);
    // Zero-variance series stay off the axes (their RMSE is rounding); the legend names them.
    let data: Vec<Vec<(f64, f64)>> = series
        .iter()
        .zip(&zero)
        .map(|(s, &z)| if z { Vec::new() } else { plottable(s, axis) })
        .collect();
    let (x_lo, x_hi, y_lo, y_hi) = bounds(&data);
    if x_hi == 0.0 {
        return Err(DrawError::Empty("no point with positive x and RMSE"));
    }
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let (w, h) = (style.width as f32, style.height as f32);
    let (title, x_title, per) = match axis {
        ConvergenceAxis::Spp => (
            "Convergence: RMSE vs samples per pixel",
            "samples per pixel (spp)",
            "spp",
        ),
        ConvergenceAxis::Seconds => ("Convergence: RMSE vs render time", "seconds", "time"),
    };
    canvas::title(
        &mut pixmap,
        title,
        Some(&format!(
            "log-log axes; Monte Carlo error falls as 1/√{per}, parallel to the dashed line; lower is better"
        )),
        &colors,
    )?;
    let frame = Frame {
        left: 84.0,
        top: 70.0,
        width: w - 84.0 - 28.0,
        height: h - 70.0 - 72.0,
    };
    let xs = Scale::log_around(x_lo, x_hi);
    let ys = Scale::log_around(y_lo, y_hi);
    axes::y_axis(&mut pixmap, &frame, &ys, "RMSE", &colors)?;
    axes::x_axis(&mut pixmap, &frame, &xs, x_title, &colors)?;

    let reference = colors.muted;
    draw_reference_slope(&mut pixmap, &data, &frame, (&xs, &ys), reference);
    let lines = draw_series(&mut pixmap, series, &data, &frame, (&xs, &ys));
    let entries = legend_entries(series, &zero, reference, per);
    let size = canvas::legend_size(&entries)?;
    canvas::legend(
        &mut pixmap,
        legend_corner(&frame, size, &lines),
        &entries,
        &colors,
    )?;
    Ok(pixmap)
}

/// `(x_lo, x_hi, y_lo, y_hi)` over every point of `data`; `x_hi = 0` when there is none.
fn bounds(data: &[Vec<(f64, f64)>]) -> (f64, f64, f64, f64) {
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::MAX, 0.0_f64, f64::MAX, 0.0_f64);
    for &(x, y) in data.iter().flatten() {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
        y_lo = y_lo.min(y);
        y_hi = y_hi.max(y);
    }
    (x_lo, x_hi, y_lo, y_hi)
}

/// The pixel of the unit-square point `(u, v)` of `frame` (`v` upwards).
fn to_px(frame: &Frame, u: f64, v: f64) -> (f32, f32) {
    (
        frame.left + u as f32 * frame.width,
        frame.bottom() - v as f32 * frame.height,
    )
}

/// The dashed reference slope −1/2 through the geometric mean of the series' first
/// points, so it runs between (and parallel to) the lines rather than on top of one.
fn draw_reference_slope(
    pixmap: &mut Pixmap,
    data: &[Vec<(f64, f64)>],
    frame: &Frame,
    (xs, ys): (&Scale, &Scale),
    color: Rgba8,
) {
    let firsts: Vec<(f64, f64)> = data.iter().filter_map(|d| d.first().copied()).collect();
    if firsts.is_empty() {
        return;
    }
    let count = firsts.len() as f64;
    let x0 = 10f64.powf(firsts.iter().map(|p| p.0.log10()).sum::<f64>() / count);
    let y0 = 10f64.powf(firsts.iter().map(|p| p.1.log10()).sum::<f64>() / count);
    // One decade right, a factor √10 down: the slope in unit coordinates.
    let k = (ys.unit(y0 / 10f64.sqrt()) - ys.unit(y0)) / (xs.unit(x0 * 10.0) - xs.unit(x0));
    if let Some((a, b)) = clip_line(xs.unit(x0), ys.unit(y0), k) {
        canvas::polyline(
            pixmap,
            &[to_px(frame, a.0, a.1), to_px(frame, b.0, b.1)],
            1.5,
            color,
            Some([7.0, 5.0]),
        );
    }
}

/// Each series as a line with a dot per point; returns the lines in pixels.
fn draw_series(
    pixmap: &mut Pixmap,
    series: &[ConvergenceSeries],
    data: &[Vec<(f64, f64)>],
    frame: &Frame,
    (xs, ys): (&Scale, &Scale),
) -> Vec<Vec<(f32, f32)>> {
    let mut lines: Vec<Vec<(f32, f32)>> = Vec::new();
    for (s, points) in series.iter().zip(data) {
        let px: Vec<(f32, f32)> = points
            .iter()
            .map(|&(x, y)| to_px(frame, xs.unit(x), ys.unit(y)))
            .collect();
        canvas::polyline(pixmap, &px, 2.0, s.color, None);
        for &p in &px {
            canvas::disc(pixmap, p, 3.5, s.color);
        }
        lines.push(px);
    }
    lines
}

/// The legend: each series (a zero-variance one named as off the plot, with its largest
/// RMSE) and the reference slope.
fn legend_entries(
    series: &[ConvergenceSeries],
    zero: &[bool],
    reference: Rgba8,
    per: &str,
) -> Vec<LegendEntry> {
    let mut entries: Vec<LegendEntry> = series
        .iter()
        .zip(zero)
        .map(|(s, &z)| {
            if z {
                LegendEntry {
                    mark: Mark::Swatch(s.color),
                    label: format!("{}: zero variance, off the plot", s.label),
                    detail: Some(format!(
                        "RMSE ≤ {}: rounding only",
                        axes::format_sci(largest_rmse(s).unwrap_or(0.0), 2)
                    )),
                }
            } else {
                LegendEntry {
                    mark: Mark::LineDot(s.color),
                    label: s.label.clone(),
                    detail: None,
                }
            }
        })
        .collect();
    entries.push(LegendEntry {
        mark: Mark::Dashed(reference),
        label: format!("slope −1/2 (∝ 1/√{per})"),
        detail: None,
    });
    entries
}

/// Where the legend box of `size` goes: the first of the frame's top-right, bottom-left,
/// top-left and bottom-right corners (10 px in) that covers the fewest points of the
/// plotted `lines` (each segment sampled every 2 px, the box grown by 4 px), so it hides
/// as little of the data as it can; top-right when nothing is in the way.
fn legend_corner(frame: &Frame, (w, h): (f32, f32), lines: &[Vec<(f32, f32)>]) -> (f32, f32) {
    let (left, right) = (frame.left + 10.0, frame.right() - w - 10.0);
    let (top, bottom) = (frame.top + 10.0, frame.bottom() - h - 10.0);
    let candidates = [(right, top), (left, bottom), (left, top), (right, bottom)];
    let covered = |(x, y): (f32, f32)| -> usize {
        let inside = |(px, py): (f32, f32)| {
            px >= x - 4.0 && px <= x + w + 4.0 && py >= y - 4.0 && py <= y + h + 4.0
        };
        lines
            .iter()
            .flat_map(|line| {
                line.windows(2).flat_map(|seg| {
                    let ((ax, ay), (bx, by)) = (seg[0], seg[1]);
                    let steps = ((bx - ax).hypot(by - ay) / 2.0).ceil().max(1.0) as usize;
                    (0..=steps).map(move |k| {
                        let t = k as f32 / steps as f32;
                        (ax + t * (bx - ax), ay + t * (by - ay))
                    })
                })
            })
            .chain(lines.iter().filter(|l| l.len() == 1).map(|l| l[0]))
            .filter(|&p| inside(p))
            .count()
    };
    candidates
        .iter()
        .copied()
        .min_by_key(|&c| covered(c))
        .unwrap_or((right, top))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_keeps_the_segment_inside() {
        // Slope −1/2 through the top-left corner leaves through the right edge at v = 0.5.
        let (a, b) = clip_line(0.0, 1.0, -0.5).expect("valid test input");
        assert_eq!(a, (0.0, 1.0));
        assert!((b.0 - 1.0).abs() < 1e-12 && (b.1 - 0.5).abs() < 1e-12);
        // A steep line is cut by the bottom edge.
        let (_, b) = clip_line(0.0, 1.0, -2.0).expect("valid test input");
        assert!((b.0 - 0.5).abs() < 1e-12 && b.1.abs() < 1e-12);
        // A line above the square misses it.
        assert!(clip_line(0.0, 3.0, -0.5).is_none());
        assert!(clip_line(0.5, 2.0, 0.0).is_none());
    }

    fn series(scheme: Scheme, rmse: &[f64]) -> ConvergenceSeries {
        let points = rmse
            .iter()
            .enumerate()
            .map(|(k, &rmse)| ConvergencePoint {
                spp: 1 << k,
                rmse,
                seconds: 0.1 * f64::from(1u32 << k),
            })
            .collect();
        ConvergenceSeries::for_scheme(scheme, points)
    }

    #[test]
    fn rounding_level_series_are_zero_variance() {
        let uniform = series(Scheme::Uniform, &[0.9, 0.64, 0.45]);
        // A million times lower variance (the dominant preset's scale): still a real curve.
        let alias = series(Scheme::Alias, &[0.9e-3, 0.64e-3, 0.45e-3]);
        // The exact pick: rounding, about 1e-16 of the signal.
        let exact = series(Scheme::Spatial, &[3e-16, 2e-16, 4e-16]);
        let zeros = series(Scheme::Cdf, &[0.0, 0.0, f64::NAN]);
        assert_eq!(
            zero_variance_series(&[uniform.clone(), alias.clone(), exact.clone(), zeros]),
            [false, false, true, true]
        );
        // Next to a light 10^-100 above a pixel the RMSEs near 10^200 square beyond f64:
        // still two real curves, and the exact pick's 10^184 still rounding.
        let near = |scheme, scale: f64| series(scheme, &[0.9 * scale, 0.64 * scale]);
        assert_eq!(
            zero_variance_series(&[
                near(Scheme::Uniform, 1e200),
                near(Scheme::Alias, 3e199),
                near(Scheme::Spatial, 1e184),
            ]),
            [false, false, true]
        );
        // Alone, nothing judges it.
        assert_eq!(zero_variance_series(std::slice::from_ref(&exact)), [false]);
        assert_eq!(
            zero_variance_series(&[series(Scheme::Cdf, &[f64::NAN]), uniform.clone()]),
            [false, false]
        );
        // Drawn without it, the plot is the plot of the others (the axes ignore it) …
        let style = Style::default();
        let with = convergence(
            &[uniform.clone(), alias.clone(), exact],
            ConvergenceAxis::Spp,
            &style,
        )
        .expect("valid test input");
        let without =
            convergence(&[uniform, alias], ConvergenceAxis::Spp, &style).expect("valid test input");
        // … except for its legend entry, drawn in the legend box at the top right.
        let differing_rows: Vec<u32> = (0..style.height)
            .filter(|&y| (0..style.width).any(|x| with.pixel(x, y) != without.pixel(x, y)))
            .collect();
        assert!(!differing_rows.is_empty());
        assert!(
            differing_rows.iter().all(|&y| y < style.height / 2),
            "{differing_rows:?}"
        );
    }

    #[test]
    fn the_legend_avoids_the_data() {
        let frame = Frame {
            left: 0.0,
            top: 0.0,
            width: 400.0,
            height: 300.0,
        };
        let size = (100.0, 60.0);
        // Falling lines leave the top right empty: the legend goes there.
        let falling = vec![vec![(0.0, 0.0), (400.0, 300.0)]];
        assert_eq!(legend_corner(&frame, size, &falling), (290.0, 10.0));
        // A flat line along the top: the bottom left is free.
        let flat = vec![vec![(0.0, 20.0), (400.0, 20.0)]];
        assert_eq!(legend_corner(&frame, size, &flat), (10.0, 230.0));
        assert_eq!(legend_corner(&frame, size, &[]), (290.0, 10.0));
    }

    #[test]
    fn unplottable_points_are_skipped() {
        let s = ConvergenceSeries::for_scheme(
            Scheme::Alias,
            vec![
                ConvergencePoint {
                    spp: 0,
                    rmse: 1.0,
                    seconds: 0.0,
                },
                ConvergencePoint {
                    spp: 4,
                    rmse: 0.5,
                    seconds: 0.1,
                },
                ConvergencePoint {
                    spp: 8,
                    rmse: f64::NAN,
                    seconds: 0.2,
                },
            ],
        );
        assert_eq!(plottable(&s, ConvergenceAxis::Spp), [(4.0, 0.5)]);
        assert_eq!(plottable(&s, ConvergenceAxis::Seconds), [(0.1, 0.5)]);
        assert!(convergence(&[], ConvergenceAxis::Spp, &Style::default()).is_err());
        let empty = ConvergenceSeries::for_scheme(Scheme::Uniform, vec![]);
        assert!(matches!(
            convergence(&[empty], ConvergenceAxis::Spp, &Style::default()),
            Err(DrawError::Empty(_))
        ));
    }
}
