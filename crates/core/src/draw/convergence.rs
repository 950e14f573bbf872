//! Log-log convergence plot: RMSE against samples per pixel (or against seconds) per
//! scheme, with a dashed reference line of slope −1/2 (Monte Carlo error `∝ 1/√spp`).
//!
//! Both axes span whole decades around the data, with labelled decade ticks and unlabelled
//! ticks at 2…9. Points that cannot sit on a log axis (zero, negative, non-finite) are
//! skipped. The reference line passes through the geometric mean of the series' first points.

use tiny_skia::Pixmap;

use super::axes::{self, Frame, Scale};
use super::canvas::{self, LegendEntry, Mark};
use super::palette::{self, Rgba8};
use super::{DrawError, Style};
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
    let data: Vec<Vec<(f64, f64)>> = series.iter().map(|s| plottable(s, axis)).collect();
    let all = data.iter().flatten();
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::MAX, 0.0_f64, f64::MAX, 0.0_f64);
    for &(x, y) in all {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
        y_lo = y_lo.min(y);
        y_hi = y_hi.max(y);
    }
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
    let to_px = |u: f64, v: f64| {
        (
            frame.left + u as f32 * frame.width,
            frame.bottom() - v as f32 * frame.height,
        )
    };

    // Reference slope −1/2 through the geometric mean of the series' first points, so it
    // runs between (and parallel to) the lines rather than on top of one.
    let reference = colors.muted;
    let firsts: Vec<(f64, f64)> = data.iter().filter_map(|d| d.first().copied()).collect();
    if !firsts.is_empty() {
        let count = firsts.len() as f64;
        let x0 = 10f64.powf(firsts.iter().map(|p| p.0.log10()).sum::<f64>() / count);
        let y0 = 10f64.powf(firsts.iter().map(|p| p.1.log10()).sum::<f64>() / count);
        // One decade right, a factor √10 down: the slope in unit coordinates.
        let k = (ys.unit(y0 / 10f64.sqrt()) - ys.unit(y0)) / (xs.unit(x0 * 10.0) - xs.unit(x0));
        if let Some((a, b)) = clip_line(xs.unit(x0), ys.unit(y0), k) {
            canvas::polyline(
                &mut pixmap,
                &[to_px(a.0, a.1), to_px(b.0, b.1)],
                1.5,
                reference,
                Some([7.0, 5.0]),
            );
        }
    }

    for (s, points) in series.iter().zip(&data) {
        let px: Vec<(f32, f32)> = points
            .iter()
            .map(|&(x, y)| to_px(xs.unit(x), ys.unit(y)))
            .collect();
        canvas::polyline(&mut pixmap, &px, 2.0, s.color, None);
        for &p in &px {
            canvas::disc(&mut pixmap, p, 3.5, s.color);
        }
    }

    let mut entries: Vec<LegendEntry> = series
        .iter()
        .map(|s| LegendEntry {
            mark: Mark::LineDot(s.color),
            label: s.label.clone(),
            detail: None,
        })
        .collect();
    entries.push(LegendEntry {
        mark: Mark::Dashed(reference),
        label: format!("slope −1/2 (∝ 1/√{per})"),
        detail: None,
    });
    let (lw, _) = canvas::legend_size(&entries)?;
    canvas::legend(
        &mut pixmap,
        (frame.right() - lw - 10.0, frame.top + 10.0),
        &entries,
        &colors,
    )?;
    Ok(pixmap)
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
