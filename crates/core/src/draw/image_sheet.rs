//! A comparison sheet: uniform | importance (power) | spatial | reference renders at equal
//! spp (top row) and the per-pixel relative error of each estimate (bottom row), with a
//! colour bar under the reference.
//!
//! # Images
//! Irradiance goes through the one tonemap, [`crate::render::tonemap_rgba8`], at the given
//! exposure or, by default, [`auto_exposure`] of the reference (all four images share it).
//! Images are scaled to fit their cells: by a whole factor with nearest-neighbour sampling
//! when they are smaller than the cell (every rendered pixel stays a crisp square),
//! bilinearly when larger.
//!
//! # The error map
//! Each pixel shows the relative error `e = |estimate − reference| / reference` on a log
//! scale over [`ERROR_LOG10_RANGE`] (`10⁻³` to `10¹`, that is 0.1 % to 1000 %), through the
//! viridis colour map (perceptually uniform, readable with colour-vision deficiencies and in
//! greyscale): `t = (log₁₀ e + 3) / 4`, clamped to `[0, 1]`. An exact pixel (`e = 0`) is the
//! darkest colour. Where the reference is 0, an estimate of 0 counts as exact and any other
//! as the largest error; non-finite values are drawn magenta. See [`error_color`].

use tiny_skia::{FilterQuality, IntSize, Pixmap, PixmapPaint, Transform};

use super::axes;
use super::canvas::{self, LABEL_SIZE, TICK_SIZE};
use super::palette::Rgba8;
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};
use crate::render::tonemap_rgba8;

/// Decades of relative error spanned by the error map: `10⁻³ ..= 10¹`.
pub const ERROR_LOG10_RANGE: (i32, i32) = (-3, 1);

/// Matplotlib's viridis at eleven evenly spaced stops (van der Walt & Smith, 2015).
const VIRIDIS: [u32; 11] = [
    0x44_01_54, 0x48_24_75, 0x41_44_87, 0x35_5F_8D, 0x2A_78_8E, 0x21_91_8C, 0x22_A8_84, 0x44_BF_70,
    0x7A_D1_51, 0xBD_DF_26, 0xFD_E7_25,
];

/// The colour of non-finite error values.
const INVALID: Rgba8 = Rgba8::hex(0xFF_00_FF);

/// The images of a sheet: four renders of the same scene, row-major, `width × height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetImages<'a> {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Irradiance estimated with uniform light selection.
    pub uniform: &'a [f64],
    /// Irradiance estimated with importance (power-proportional) selection.
    pub importance: &'a [f64],
    /// Irradiance estimated with contribution-aware (spatial) selection,
    /// `P(i | x) ∝ p_i·G_i(x)` exactly for few lights or by a light tree
    /// ([`crate::spatial`]).
    pub spatial: &'a [f64],
    /// The exact irradiance.
    pub reference: &'a [f64],
    /// Samples per pixel of the three estimates.
    pub spp: u64,
    /// Tonemap exposure; `None` uses [`auto_exposure`] of the reference.
    pub exposure: Option<f64>,
}

/// The default exposure: `1 / mean` of the reference's positive finite values, so a pixel
/// of mean irradiance maps to `L = 1` (display 0.5 before sRGB encoding); 1 when there are
/// none.
pub fn auto_exposure(reference: &[f64]) -> f64 {
    let (sum, count) = reference
        .iter()
        .filter(|v| v.is_finite() && **v > 0.0)
        .fold((0.0, 0usize), |(s, c), &v| (s + v, c + 1));
    if count == 0 || sum <= 0.0 {
        1.0
    } else {
        count as f64 / sum
    }
}

/// Viridis at `t ∈ [0, 1]` (clamped), linearly interpolated between its stops.
pub fn viridis(t: f64) -> Rgba8 {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let [a, b] = [Rgba8::hex(VIRIDIS[k]), Rgba8::hex(VIRIDIS[k + 1])];
    let mix = |i: usize| (f64::from(a.0[i]) * (1.0 - f) + f64::from(b.0[i]) * f).round() as u8;
    Rgba8::rgb(mix(0), mix(1), mix(2))
}

/// The position in `[0, 1]` of a relative error on the map's log scale.
pub(crate) fn error_unit(estimate: f64, reference: f64) -> Option<f64> {
    if !estimate.is_finite() || !reference.is_finite() {
        return None;
    }
    if estimate == reference {
        return Some(0.0);
    }
    if reference == 0.0 {
        return Some(1.0);
    }
    let e = ((estimate - reference) / reference).abs();
    let (lo, hi) = ERROR_LOG10_RANGE;
    Some(((e.log10() - f64::from(lo)) / f64::from(hi - lo)).clamp(0.0, 1.0))
}

/// The false colour of one pixel's relative error (see the module docs).
pub fn error_color(estimate: f64, reference: f64) -> Rgba8 {
    error_unit(estimate, reference).map_or(INVALID, viridis)
}

/// An opaque pixmap from straight `RGBA8` bytes.
pub(super) fn pixmap_from_rgba(
    width: usize,
    height: usize,
    rgba: Vec<u8>,
) -> Result<Pixmap, DrawError> {
    let size = IntSize::from_wh(width as u32, height as u32).ok_or(DrawError::Size {
        width: width as u32,
        height: height as u32,
    })?;
    // Every pixel is opaque, so straight and premultiplied bytes coincide.
    Pixmap::from_vec(rgba, size).ok_or(DrawError::Size {
        width: width as u32,
        height: height as u32,
    })
}

/// The scale of an `iw × ih` image drawn into a `cw × ch` cell: the largest whole factor
/// when the image fits at least once, else the largest fractional one.
pub(crate) fn fit_scale(iw: usize, ih: usize, cw: f32, ch: f32) -> f32 {
    let s = (cw / iw as f32).min(ch / ih as f32);
    if s >= 1.0 { s.floor() } else { s }
}

/// Columns of the sheet: uniform, importance, spatial, reference (the colour bar below).
const COLUMNS: usize = 4;

/// The colour bar's explanation, under it: (text, bold).
const BAR_NOTES: [(&str, bool); 4] = [
    ("relative error, log scale", true),
    ("|estimate − ref| / ref", false),
    ("darkest: ≤ 0.1 % or exact", false),
    ("magenta: not finite", false),
];
/// Line spacing of [`BAR_NOTES`], pixels.
const NOTE_LINE: f32 = 16.0;

/// Draws the comparison sheet of `images`.
pub fn image_sheet(images: &SheetImages<'_>, style: &Style) -> Result<Pixmap, DrawError> {
    let (iw, ih) = (images.width, images.height);
    if iw == 0 || ih == 0 {
        return Err(DrawError::Empty("the images have no pixels"));
    }
    check_lengths(images)?;
    let exposure = images
        .exposure
        .unwrap_or_else(|| auto_exposure(images.reference));
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let (w, h) = (style.width as f32, style.height as f32);
    canvas::title(
        &mut pixmap,
        &format!("Uniform, power and spatial sampling at {} spp", images.spp),
        Some(&format!(
            "{iw}×{ih} px · Reinhard tonemap, exposure {} · bottom: relative error of each estimate",
            short(exposure)
        )),
        &colors,
    )?;

    let grid = Grid::new(iw, ih, w, h);
    let paint = PixmapPaint {
        quality: if grid.scale >= 1.0 {
            FilterQuality::Nearest
        } else {
            FilterQuality::Bilinear
        },
        ..PixmapPaint::default()
    };
    for (label, rgba, (col, row)) in panels(images, exposure) {
        let (cx, cy) = grid.cell(col, row);
        let x = (cx + (grid.cell_w - grid.dw) / 2.0).round();
        let y = cy.round();
        let image = pixmap_from_rgba(iw, ih, rgba)?;
        pixmap.draw_pixmap(
            0,
            0,
            image.as_ref(),
            &paint,
            Transform::from_row(grid.scale, 0.0, 0.0, grid.scale, x, y),
            None,
        );
        canvas::stroke_rect(
            &mut pixmap,
            (
                x - 0.5,
                y - 0.5,
                grid.dw.round() + 1.0,
                grid.dh.round() + 1.0,
            ),
            1.0,
            colors.grid,
        );
        text::draw_text(
            &mut pixmap,
            &label,
            (cx + grid.cell_w / 2.0, y - 6.0),
            (HAlign::Center, VAlign::Baseline),
            &TextStyle::new(LABEL_SIZE, colors.foreground),
        )?;
    }
    // The colour bar under the reference: as tall as the error maps, less the room its
    // notes take below it before the bottom margin (the cell reaches `cell_h` below its top).
    let (cx, cy) = grid.cell(COLUMNS - 1, 1);
    let notes = BAR_NOTES.len() as f32 * NOTE_LINE + 8.0;
    let bar_h = grid.dh.min(grid.cell_h - notes).round().max(1.0);
    color_bar(&mut pixmap, (cx, cy.round()), bar_h, &colors)?;
    Ok(pixmap)
}

/// Refuses an image whose length is not `width · height`.
fn check_lengths(images: &SheetImages<'_>) -> Result<(), DrawError> {
    let expected = images.width * images.height;
    for (what, img) in [
        ("uniform image", images.uniform),
        ("importance image", images.importance),
        ("spatial image", images.spatial),
        ("reference image", images.reference),
    ] {
        if img.len() != expected {
            return Err(DrawError::Length {
                what,
                expected,
                got: img.len(),
            });
        }
    }
    Ok(())
}

/// The sheet's layout: [`COLUMNS`] cells in two rows under the title, each image drawn at
/// `scale` (`dw × dh` pixels) centred in its cell, with its caption above.
struct Grid {
    margin: f32,
    gap: f32,
    caption: f32,
    row_gap: f32,
    cell_w: f32,
    cell_h: f32,
    scale: f32,
    dw: f32,
    dh: f32,
    /// Top of the first row's captions.
    top: f32,
}

impl Grid {
    /// The layout of `iw × ih` images on a `w × h` sheet.
    fn new(iw: usize, ih: usize, w: f32, h: f32) -> Self {
        let (margin, gap, top, caption, row_gap) = (20.0, 16.0, 64.0, 20.0, 12.0);
        let columns = COLUMNS as f32;
        let cell_w = (w - 2.0 * margin - (columns - 1.0) * gap) / columns;
        let cell_h = (h - top - 10.0 - row_gap) / 2.0 - caption;
        let scale = fit_scale(iw, ih, cell_w, cell_h);
        let (dw, dh) = (iw as f32 * scale, ih as f32 * scale);
        // Rows as tall as the drawn images, the pair centred in the space below the title.
        let grid_top = top + ((h - top - 10.0) - (2.0 * (caption + dh) + row_gap)) / 2.0;
        Grid {
            margin,
            gap,
            caption,
            row_gap,
            cell_w,
            cell_h,
            scale,
            dw,
            dh,
            top: grid_top,
        }
    }

    /// The top-left corner of cell `(col, row)`'s image area (below its caption).
    fn cell(&self, col: usize, row: usize) -> (f32, f32) {
        (
            self.margin + col as f32 * (self.cell_w + self.gap),
            self.top + row as f32 * (self.caption + self.dh + self.row_gap) + self.caption,
        )
    }
}

/// The sheet's panels, each a caption, its RGBA8 pixels and its cell `(col, row)`: the
/// three estimates and the reference tonemapped at `exposure`, then the estimates' error
/// maps.
fn panels(images: &SheetImages<'_>, exposure: f64) -> [(String, Vec<u8>, (usize, usize)); 7] {
    let error = |est: &[f64]| -> Vec<u8> {
        est.iter()
            .zip(images.reference)
            .flat_map(|(&e, &r)| error_color(e, r).0)
            .collect()
    };
    let spp = images.spp;
    [
        (
            format!("uniform · {spp} spp"),
            tonemap_rgba8(images.uniform, exposure),
            (0, 0),
        ),
        (
            format!("power · {spp} spp"),
            tonemap_rgba8(images.importance, exposure),
            (1, 0),
        ),
        (
            format!("spatial · {spp} spp"),
            tonemap_rgba8(images.spatial, exposure),
            (2, 0),
        ),
        (
            "reference (exact)".to_owned(),
            tonemap_rgba8(images.reference, exposure),
            (3, 0),
        ),
        ("error, uniform".to_owned(), error(images.uniform), (0, 1)),
        ("error, power".to_owned(), error(images.importance), (1, 1)),
        ("error, spatial".to_owned(), error(images.spatial), (2, 1)),
    ]
}

/// The error map's colour bar with decade labels to its right and its notes below it.
fn color_bar(
    pixmap: &mut Pixmap,
    (x, y): (f32, f32),
    height: f32,
    colors: &super::palette::ThemeColors,
) -> Result<(), DrawError> {
    let bar_w = 22.0;
    let bar_x = x + 12.0;
    viridis_bar(pixmap, (bar_x, y, bar_w, height), colors.foreground);
    let (lo, hi) = ERROR_LOG10_RANGE;
    let tick = TextStyle::new(TICK_SIZE, colors.foreground);
    for e in lo..=hi {
        let t = f64::from(e - lo) / f64::from(hi - lo);
        let ty = canvas::crisp(y + (1.0 - t as f32) * (height - 1.0));
        canvas::line(
            pixmap,
            (bar_x + bar_w, ty),
            (bar_x + bar_w + 4.0, ty),
            1.0,
            colors.foreground,
        );
        let percent = match e {
            -3 => "0.1 %".to_owned(),
            _ if e >= -2 => format!("{} %", 10f64.powi(e + 2)),
            _ => format!("10{} %", axes::superscript(e + 2)),
        };
        text::draw_text(
            pixmap,
            &percent,
            (bar_x + bar_w + 8.0, ty),
            (HAlign::Left, VAlign::Middle),
            &tick,
        )?;
    }
    for (k, (line, bold)) in BAR_NOTES.iter().enumerate() {
        let style = TextStyle::new(
            TICK_SIZE,
            if *bold {
                colors.foreground
            } else {
                colors.muted
            },
        );
        let style = if *bold { style.bold() } else { style };
        text::draw_text(
            pixmap,
            line,
            (bar_x, y + height + 8.0 + NOTE_LINE * (k as f32 + 0.5)),
            (HAlign::Left, VAlign::Middle),
            &style,
        )?;
    }
    Ok(())
}

/// A positive number with three significant digits, for captions.
fn short(v: f64) -> String {
    if !(0.01..1000.0).contains(&v) {
        axes::format_sci(v, 3)
    } else if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else if v >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// A vertical viridis colour bar filling `(x, y, width, height)`, brightest at the top, in a
/// one-pixel `outline` (the error sheets' and the variance maps' scale).
pub(crate) fn viridis_bar(
    pixmap: &mut Pixmap,
    (x, y, width, height): (f32, f32, f32, f32),
    outline: Rgba8,
) {
    let steps = height.max(1.0) as usize;
    for k in 0..steps {
        let t = 1.0 - (k as f64 + 0.5) / steps as f64;
        canvas::fill_rect(pixmap, x, y + k as f32, width, 1.0, viridis(t));
    }
    canvas::stroke_rect(
        pixmap,
        (x - 0.5, y - 0.5, width + 1.0, height + 1.0),
        1.0,
        outline,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_scale_is_logarithmic_and_clamped() {
        assert_eq!(error_unit(1.0, 1.0), Some(0.0));
        assert!((error_unit(1.001, 1.0).expect("valid test input") - 0.0).abs() < 1e-9);
        assert!((error_unit(1.1, 1.0).expect("valid test input") - 0.5).abs() < 1e-9);
        assert!((error_unit(0.9, 1.0).expect("valid test input") - 0.5).abs() < 1e-9);
        assert_eq!(error_unit(11.0, 1.0), Some(1.0));
        assert_eq!(error_unit(1000.0, 1.0), Some(1.0));
        assert_eq!(error_unit(1e-9, 1.0).map(|t| t > 0.7), Some(true));
        assert_eq!(error_unit(0.0, 0.0), Some(0.0));
        assert_eq!(error_unit(0.5, 0.0), Some(1.0));
        assert_eq!(error_unit(f64::NAN, 1.0), None);
        assert_eq!(error_color(f64::INFINITY, 1.0), INVALID);
    }

    #[test]
    fn viridis_hits_its_stops() {
        assert_eq!(viridis(0.0), Rgba8::hex(0x44_01_54));
        assert_eq!(viridis(0.5), Rgba8::hex(0x21_91_8C));
        assert_eq!(viridis(1.0), Rgba8::hex(0xFD_E7_25));
        assert_eq!(viridis(7.0), viridis(1.0));
        // Monotone in luminance: the map reads in greyscale.
        let lum: Vec<f64> = (0..=20)
            .map(|k| viridis(f64::from(k) / 20.0).luminance())
            .collect();
        assert!(lum.windows(2).all(|w| w[0] < w[1]), "{lum:?}");
    }

    #[test]
    fn exposure_and_fit() {
        assert!((auto_exposure(&[1.0, 3.0, 0.0, f64::NAN]) - 0.5).abs() < 1e-15);
        assert_eq!(auto_exposure(&[0.0, -1.0]), 1.0);
        assert_eq!(fit_scale(48, 32, 242.0, 188.0), 5.0);
        assert_eq!(fit_scale(500, 100, 250.0, 188.0), 0.5);
        assert_eq!(fit_scale(242, 10, 242.0, 188.0), 1.0);
    }

    #[test]
    fn sizes_are_checked() {
        let img = [1.0; 6];
        let sheet = SheetImages {
            width: 3,
            height: 2,
            uniform: &img,
            importance: &img[..5],
            spatial: &img,
            reference: &img,
            spp: 1,
            exposure: None,
        };
        assert!(matches!(
            image_sheet(&sheet, &Style::default()),
            Err(DrawError::Length {
                what: "importance image",
                expected: 6,
                got: 5
            })
        ));
        let ok = SheetImages {
            importance: &img,
            ..sheet
        };
        assert!(image_sheet(&ok, &Style::default()).is_ok());
        let short_spatial = SheetImages {
            spatial: &img[..4],
            ..ok
        };
        assert!(matches!(
            image_sheet(&short_spatial, &Style::default()),
            Err(DrawError::Length {
                what: "spatial image",
                expected: 6,
                got: 4
            })
        ));
    }

    #[test]
    fn captions_and_notes_fit_their_cells_at_the_default_size() {
        // At 800 px, four columns of (800 − 2·20 − 3·16)/4 = 178 px.
        let cell_w = (800.0 - 2.0 * 20.0 - 3.0 * 16.0) / 4.0;
        for label in [
            "uniform · 65536 spp",
            "power · 65536 spp",
            "spatial · 65536 spp",
            "reference (exact)",
            "error, uniform",
            "error, spatial",
        ] {
            let m = text::measure(label, LABEL_SIZE, text::Weight::Regular).expect("font");
            assert!(m.width < cell_w - 8.0, "{label}: {} px", m.width);
        }
        // Notes start 12 px into the colour bar's cell.
        for (line, bold) in BAR_NOTES {
            let weight = if bold {
                text::Weight::Bold
            } else {
                text::Weight::Regular
            };
            let m = text::measure(line, TICK_SIZE, weight).expect("font");
            assert!(m.width < cell_w - 12.0, "{line}: {} px", m.width);
        }
    }
}
