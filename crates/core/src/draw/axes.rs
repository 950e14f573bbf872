//! Plot frames, linear and log axes, ticks and their labels.

use tiny_skia::Pixmap;

use super::DrawError;
use super::canvas::{self, LABEL_SIZE, TICK_SIZE};
use super::palette::ThemeColors;
use super::text::{self, HAlign, TextStyle, VAlign};

/// The plot area in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    pub left: f32,
    pub top: f32,
    pub width: f32,
    pub height: f32,
}

impl Frame {
    pub fn right(&self) -> f32 {
        self.left + self.width
    }

    pub fn bottom(&self) -> f32 {
        self.top + self.height
    }
}

/// How data values map onto an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Scale {
    /// `min..max` linearly.
    Linear { min: f64, max: f64 },
    /// `10^lo..10^hi` logarithmically (`lo`, `hi` in decades, not necessarily whole).
    Log10 { lo: f64, hi: f64 },
}

/// A tick: its value and, for major ticks, its label.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Tick {
    pub value: f64,
    pub label: Option<String>,
}

impl Scale {
    /// A log scale around `[lo, hi]` (both positive), padded by 5 % of its span on each
    /// side and at least one decade wide.
    pub fn log_around(lo: f64, hi: f64) -> Self {
        let (mut a, mut b) = (lo.log10(), hi.log10());
        if b - a < 1.0 {
            let mid = f64::midpoint(a, b);
            (a, b) = (mid - 0.5, mid + 0.5);
        }
        let pad = 0.05 * (b - a);
        Scale::Log10 {
            lo: a - pad,
            hi: b + pad,
        }
    }

    /// The position of `v` along the axis, 0 at the start and 1 at the end (not clamped).
    pub fn unit(&self, v: f64) -> f64 {
        match *self {
            Scale::Linear { min, max } => (v - min) / (max - min),
            Scale::Log10 { lo, hi } => (v.log10() - lo) / (hi - lo),
        }
    }

    /// Major ticks (labelled) and, on log scales, minor ticks at 2..9 of each decade.
    pub fn ticks(&self) -> Vec<Tick> {
        match *self {
            Scale::Linear { min, max } => {
                let step = nice_step(max - min, 5);
                let first = (min / step).ceil() as i64;
                let last = (max / step + 1e-9).floor() as i64;
                (first..=last)
                    .map(|k| {
                        let value = k as f64 * step;
                        Tick {
                            value,
                            label: Some(format_linear(value, step)),
                        }
                    })
                    .collect()
            }
            Scale::Log10 { lo, hi } => {
                let inside = |v: f64| (lo - 1e-9..=hi + 1e-9).contains(&v.log10());
                let decades = (lo.floor() as i32)..=(hi.ceil() as i32);
                let labelled_decades = decades.clone().filter(|&e| inside(10f64.powi(e))).count();
                // With fewer than two decades in view, 2 and 5 get labels too.
                let label_minor = labelled_decades < 2;
                let mut ticks = Vec::new();
                for e in decades {
                    for m in 1..10 {
                        let value = f64::from(m) * 10f64.powi(e);
                        if !inside(value) {
                            continue;
                        }
                        let label = if m == 1 {
                            Some(pow10_label(e))
                        } else if label_minor && (m == 2 || m == 5) {
                            Some(mantissa_label(m, e))
                        } else {
                            None
                        };
                        ticks.push(Tick { value, label });
                    }
                }
                ticks
            }
        }
    }
}

/// `m·10^e` as a label: plain for `10^-2..10^3`, else `m·10ᵉ`.
pub(crate) fn mantissa_label(m: u32, e: i32) -> String {
    match e {
        -2 => format!("0.0{m}"),
        -1 => format!("0.{m}"),
        0..=3 => (m * 10u32.pow(e as u32)).to_string(),
        _ => format!("{m}·10{}", superscript(e)),
    }
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `target` steps.
pub(crate) fn nice_step(range: f64, target: u32) -> f64 {
    let raw = (range / f64::from(target)).max(f64::MIN_POSITIVE);
    let magnitude = 10f64.powf(raw.log10().floor());
    let fraction = raw / magnitude;
    let nice = if fraction <= 1.0 {
        1.0
    } else if fraction <= 2.0 {
        2.0
    } else if fraction <= 5.0 {
        5.0
    } else {
        10.0
    };
    nice * magnitude
}

/// A tick value with as many decimals as its step needs, and a true minus sign.
pub(crate) fn format_linear(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!(
        "{:.*}",
        decimals,
        if v.abs() < step * 1e-6 { 0.0 } else { v }
    );
    s.replace('-', "−")
}

/// `10^e` as a label: plain for `10^-2..10^3` (`0.01`, `1`, `1000`), else `10⁻³`.
pub(crate) fn pow10_label(e: i32) -> String {
    match e {
        -2 => "0.01".to_owned(),
        -1 => "0.1".to_owned(),
        0..=3 => 10u32.pow(e as u32).to_string(),
        _ => format!("10{}", superscript(e)),
    }
}

/// An integer in superscript digits (`−3` → `⁻³`).
pub(crate) fn superscript(e: i32) -> String {
    let plain = e.unsigned_abs().to_string();
    let digits = plain.chars().map(|c| match c {
        '1' => '¹',
        '2' => '²',
        '3' => '³',
        '4' => '⁴',
        '5' => '⁵',
        '6' => '⁶',
        '7' => '⁷',
        '8' => '⁸',
        '9' => '⁹',
        _ => '⁰',
    });
    let sign = if e < 0 { "⁻" } else { "" };
    sign.chars().chain(digits).collect()
}

/// A number in scientific notation with a `·10ⁿ` exponent (`3.2·10⁻⁵`), `digits` significant.
pub(crate) fn format_sci(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor() as i32;
    let mantissa = v / 10f64.powi(e);
    let m = format!("{:.*}", digits.saturating_sub(1), mantissa);
    // Rounding can carry the mantissa to 10.
    if m.trim_start_matches('-').starts_with("10") {
        return format_sci(v.signum() * 10f64.powi(e + 1), digits);
    }
    format!("{m}·10{}", superscript(e)).replace('-', "−")
}

/// Draws the horizontal grid and the labelled y axis of `scale` along `frame`'s left edge.
pub(crate) fn y_axis(
    pixmap: &mut Pixmap,
    frame: &Frame,
    scale: &Scale,
    title: &str,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let tick_style = TextStyle::new(TICK_SIZE, colors.foreground);
    let mut widest: f32 = 0.0;
    for tick in scale.ticks() {
        let u = scale.unit(tick.value) as f32;
        if !(-1e-4..=1.0001).contains(&u) {
            continue;
        }
        let y = canvas::crisp(frame.bottom() - u * frame.height);
        let major = tick.label.is_some();
        let grid = if major {
            colors.grid
        } else {
            colors.grid.with_alpha(110)
        };
        canvas::line(pixmap, (frame.left, y), (frame.right(), y), 1.0, grid);
        let len = if major { 5.0 } else { 3.0 };
        canvas::line(
            pixmap,
            (frame.left - len, y),
            (frame.left, y),
            1.0,
            colors.foreground,
        );
        if let Some(label) = tick.label {
            let e = text::draw_text(
                pixmap,
                &label,
                (frame.left - 8.0, y),
                (HAlign::Right, VAlign::Middle),
                &tick_style,
            )?;
            widest = widest.max(e.width);
        }
    }
    let x = canvas::crisp(frame.left);
    canvas::line(
        pixmap,
        (x, frame.top),
        (x, frame.bottom()),
        1.0,
        colors.foreground,
    );
    text::draw_text_vertical(
        pixmap,
        title,
        (
            frame.left - 8.0 - widest - 14.0,
            frame.top + frame.height / 2.0,
        ),
        &TextStyle::new(LABEL_SIZE, colors.foreground),
    )
}

/// Draws the vertical grid and the labelled x axis of `scale` along `frame`'s bottom edge.
pub(crate) fn x_axis(
    pixmap: &mut Pixmap,
    frame: &Frame,
    scale: &Scale,
    title: &str,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let tick_style = TextStyle::new(TICK_SIZE, colors.foreground);
    for tick in scale.ticks() {
        let u = scale.unit(tick.value) as f32;
        if !(-1e-4..=1.0001).contains(&u) {
            continue;
        }
        let x = canvas::crisp(frame.left + u * frame.width);
        let major = tick.label.is_some();
        let grid = if major {
            colors.grid
        } else {
            colors.grid.with_alpha(110)
        };
        canvas::line(pixmap, (x, frame.top), (x, frame.bottom()), 1.0, grid);
        let len = if major { 5.0 } else { 3.0 };
        canvas::line(
            pixmap,
            (x, frame.bottom()),
            (x, frame.bottom() + len),
            1.0,
            colors.foreground,
        );
        if let Some(label) = tick.label {
            text::draw_text(
                pixmap,
                &label,
                (x, frame.bottom() + 8.0),
                (HAlign::Center, VAlign::Top),
                &tick_style,
            )?;
        }
    }
    let y = canvas::crisp(frame.bottom());
    canvas::line(
        pixmap,
        (frame.left, y),
        (frame.right(), y),
        1.0,
        colors.foreground,
    );
    text::draw_text(
        pixmap,
        title,
        (frame.left + frame.width / 2.0, frame.bottom() + 30.0),
        (HAlign::Center, VAlign::Top),
        &TextStyle::new(LABEL_SIZE, colors.foreground),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(1.0, 5), 0.2);
        assert_eq!(nice_step(2.5, 5), 0.5);
        assert_eq!(nice_step(0.8, 5), 0.2);
        assert_eq!(nice_step(100.0, 5), 20.0);
        assert!((nice_step(0.074, 5) - 0.02).abs() < 1e-15);
    }

    #[test]
    fn linear_ticks_cover_the_range() {
        let ticks = Scale::Linear { min: 0.0, max: 1.0 }.ticks();
        let labels: Vec<_> = ticks.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
    }

    #[test]
    fn log_scale_maps_decades_evenly() {
        let s = Scale::log_around(1.0, 1000.0);
        let Scale::Log10 { lo, hi } = s else {
            panic!("{s:?}")
        };
        assert!((lo + 0.15).abs() < 1e-12 && (hi - 3.15).abs() < 1e-12);
        let third = (s.unit(10.0) - s.unit(1.0)) - (s.unit(1000.0) - s.unit(100.0));
        assert!(third.abs() < 1e-12);
        assert!((s.unit(10f64.powf(1.5)) - 0.5).abs() < 1e-12);
        let ticks = s.ticks();
        let labels: Vec<_> = ticks.iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["1", "10", "100", "1000"]);
        // 0.8 and 0.9 (≥ 10^-0.15), 1 … 9 in three decades, 1000 (2000 > 10^3.15).
        assert_eq!(ticks.len(), 2 + 27 + 1);
    }

    #[test]
    fn narrow_log_scale_labels_two_and_five() {
        let s = Scale::log_around(0.3, 0.6);
        let labels: Vec<_> = s.ticks().iter().filter_map(|t| t.label.clone()).collect();
        assert_eq!(labels, ["0.2", "0.5", "1"]);
        assert_eq!(mantissa_label(5, 4), "5·10⁴");
    }

    #[test]
    fn labels() {
        assert_eq!(pow10_label(-3), "10⁻³");
        assert_eq!(pow10_label(-1), "0.1");
        assert_eq!(pow10_label(2), "100");
        assert_eq!(pow10_label(12), "10¹²");
        assert_eq!(format_linear(-0.5, 0.5), "−0.5");
        assert_eq!(format_sci(3.24e-5, 2), "3.2·10⁻⁵");
        assert_eq!(format_sci(9.96e-5, 2), "1.0·10⁻⁴");
    }
}
