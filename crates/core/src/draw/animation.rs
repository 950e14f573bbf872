//! One frame of a convergence animation: the progressive images of several schemes side by
//! side at the same samples per pixel, each captioned with its label, what it picks by, its
//! samples per pixel and its RMSE against the exact reference.
//!
//! # Layout
//! A title and a subtitle at the top (as every drawing has), then one cell per panel, left
//! to right. Each image is enlarged by the whole factor [`AnimationFrame::zoom`] with
//! nearest-neighbour sampling (every rendered pixel stays a crisp square, noise included)
//! and captioned below with four lines: a swatch in the scheme's colour and the label (bold),
//! the detail (muted), `N spp`, and `RMSE x` (three significant digits, `x·10ⁿ` outside
//! `[0.01, 1000)`). A thin bar along the bottom edge shows how far through the animation
//! the frame is.
//!
//! # Size
//! The frame's size depends only on the image size, the zoom and the number of panels
//! ([`animation_frame_size`]), never on the text, so every frame of an animation has the
//! same size. Cells are at least [`MIN_CELL_WIDTH`] wide so the captions fit under small
//! images.
//!
//! # Images
//! Irradiance goes through the one tonemap, [`crate::render::tonemap_rgba8`], at the frame's
//! exposure (the same for every panel and every frame, so brightness changes are the
//! estimates converging, not the display).

use tiny_skia::{FilterQuality, Pixmap, PixmapPaint, Transform};

use super::axes;
use super::canvas::{self, LABEL_SIZE, TITLE_SIZE};
use super::image_sheet::pixmap_from_rgba;
use super::palette::{Rgba8, ThemeColors};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Theme};
use crate::render::tonemap_rgba8;

/// The narrowest cell: room for the longest caption line (`RMSE 8.88·10⁻¹⁸⁸`, `65536 spp`).
pub const MIN_CELL_WIDTH: u32 = 176;

/// The width a panel's image is enlarged to at least, by [`animation_zoom`].
pub const TARGET_PANEL_WIDTH: u32 = 192;

/// The largest zoom [`animation_zoom`] picks.
pub const MAX_ZOOM: u32 = 8;

/// Space around the cells and between them, pixels.
const MARGIN: u32 = 16;
/// Height of the title and subtitle block above the images.
const TOP: u32 = 62;
/// Caption font size (pixels per em): a little above the plots' labels, for slides.
const CAPTION_SIZE: f32 = 14.0;
/// Distance between caption baselines.
const CAPTION_LINE: u32 = 19;
/// Caption lines under each image.
const CAPTION_LINES: u32 = 4;
/// Gap between an image and its first caption line's top.
const CAPTION_GAP: u32 = 8;
/// Height of the progress bar along the bottom edge and the space above it.
const PROGRESS_BAR: u32 = 4;
const PROGRESS_GAP: u32 = 12;

/// One panel of a frame: a progressive image and its caption.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimationPanel<'a> {
    /// The scheme's name, drawn bold beside a swatch of [`AnimationPanel::color`].
    pub label: &'a str,
    /// A muted second line: what the scheme picks lights by (`1/N each`, `∝ power`).
    pub detail: &'a str,
    /// The scheme's colour ([`crate::draw::palette::scheme_color`]).
    pub color: Rgba8,
    /// Irradiance, row-major, [`AnimationFrame::width`] × [`AnimationFrame::height`].
    pub image: &'a [f64],
    /// Samples per pixel accumulated in `image`.
    pub spp: u64,
    /// RMSE of `image` against the exact reference
    /// ([`crate::render::error_metrics`]).
    pub rmse: f64,
}

/// Everything one frame shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimationFrame<'a> {
    /// Image width in pixels (every panel's).
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Whole-number enlargement of the images (1 ..= [`MAX_ZOOM`]).
    pub zoom: u32,
    /// The panels, left to right.
    pub panels: &'a [AnimationPanel<'a>],
    /// Tonemap exposure shared by every panel.
    pub exposure: f64,
    /// Bold line at the top.
    pub title: &'a str,
    /// Muted line under the title.
    pub subtitle: &'a str,
    /// This frame's position in the animation, `(index, count)` with `index < count`: the
    /// bottom bar is filled to `(index + 1) / count`.
    pub progress: (usize, usize),
}

/// The zoom that enlarges an image `width` pixels wide to at least
/// [`TARGET_PANEL_WIDTH`], at most [`MAX_ZOOM`] (1 for wide images).
pub fn animation_zoom(width: usize) -> u32 {
    let width = width.max(1) as u32;
    TARGET_PANEL_WIDTH.div_ceil(width).clamp(1, MAX_ZOOM)
}

/// The frame size `(width, height)` in pixels for `panels` images of `width × height`
/// pixels enlarged `zoom` times (see the module docs).
pub fn animation_frame_size(width: usize, height: usize, zoom: u32, panels: usize) -> (u32, u32) {
    let (cell_w, image_h) = cell_size(width, height, zoom);
    let n = panels.max(1) as u32;
    let w = 2 * MARGIN + n * cell_w + (n - 1) * MARGIN;
    let h = TOP
        + image_h
        + CAPTION_GAP
        + CAPTION_LINES * CAPTION_LINE
        + PROGRESS_GAP
        + PROGRESS_BAR
        + MARGIN / 2;
    (w, h)
}

/// A cell's width and its image's height for the given image size and zoom.
fn cell_size(width: usize, height: usize, zoom: u32) -> (u32, u32) {
    let (w, h) = (width as u32 * zoom, height as u32 * zoom);
    (w.max(MIN_CELL_WIDTH), h)
}

/// An RMSE for a caption: three significant digits, `x·10ⁿ` outside `[0.01, 1000)`.
pub fn rmse_caption(rmse: f64) -> String {
    let value = if rmse.is_finite() && rmse != 0.0 && !(0.01..1000.0).contains(&rmse.abs()) {
        axes::format_sci(rmse, 3)
    } else if rmse.is_finite() && rmse.abs() >= 100.0 {
        format!("{rmse:.0}")
    } else if rmse.is_finite() && rmse.abs() >= 10.0 {
        format!("{rmse:.1}")
    } else if rmse.is_finite() && rmse.abs() >= 1.0 {
        format!("{rmse:.2}")
    } else if rmse == 0.0 {
        "0".to_owned()
    } else if rmse.is_finite() {
        format!("{rmse:.3}")
    } else {
        format!("{rmse}")
    };
    format!("RMSE {value}")
}

/// Draws one frame of a convergence animation (see the module docs).
pub fn animation_frame(frame: &AnimationFrame<'_>, theme: Theme) -> Result<Pixmap, DrawError> {
    check_frame(frame)?;
    let (iw, ih) = (frame.width, frame.height);
    let (width, height) = animation_frame_size(iw, ih, frame.zoom, frame.panels.len());
    let style = super::Style {
        width,
        height,
        theme,
    };
    let colors = theme.colors();
    let mut pixmap = canvas::blank(&style)?;
    text::draw_text(
        &mut pixmap,
        frame.title,
        (width as f32 / 2.0, 12.0),
        (HAlign::Center, VAlign::Top),
        &TextStyle::new(TITLE_SIZE, colors.foreground).bold(),
    )?;
    text::draw_text(
        &mut pixmap,
        frame.subtitle,
        (width as f32 / 2.0, 38.0),
        (HAlign::Center, VAlign::Top),
        &TextStyle::new(LABEL_SIZE, colors.muted),
    )?;
    for (k, panel) in frame.panels.iter().enumerate() {
        draw_panel(&mut pixmap, frame, k, panel, &colors)?;
    }
    draw_progress(&mut pixmap, frame.progress, (width, height), &colors);
    Ok(pixmap)
}

/// Refuses an empty image, no panels, a zoom beyond `1..=`[`MAX_ZOOM`] and a panel image
/// whose length is not `width · height`.
fn check_frame(frame: &AnimationFrame<'_>) -> Result<(), DrawError> {
    let (iw, ih) = (frame.width, frame.height);
    if iw == 0 || ih == 0 {
        return Err(DrawError::Empty("the images have no pixels"));
    }
    if frame.panels.is_empty() {
        return Err(DrawError::Empty("no panels"));
    }
    if !(1..=MAX_ZOOM).contains(&frame.zoom) {
        return Err(DrawError::Size {
            width: iw as u32 * frame.zoom,
            height: ih as u32 * frame.zoom,
        });
    }
    for panel in frame.panels {
        if panel.image.len() != iw * ih {
            return Err(DrawError::Length {
                what: "panel image",
                expected: iw * ih,
                got: panel.image.len(),
            });
        }
    }
    Ok(())
}

/// Panel `k`: its image tonemapped and enlarged in its cell, outlined, and its captions
/// (swatch and label, detail, spp, RMSE) below it.
fn draw_panel(
    pixmap: &mut Pixmap,
    frame: &AnimationFrame<'_>,
    k: usize,
    panel: &AnimationPanel<'_>,
    colors: &ThemeColors,
) -> Result<(), DrawError> {
    let (iw, ih) = (frame.width, frame.height);
    let zoom = frame.zoom as f32;
    let (cell_w, image_h) = cell_size(iw, ih, frame.zoom);
    let image_w = iw as u32 * frame.zoom;
    let paint = PixmapPaint {
        quality: FilterQuality::Nearest,
        ..PixmapPaint::default()
    };
    let caption = TextStyle::new(CAPTION_SIZE, colors.foreground);
    let cell_x = MARGIN + k as u32 * (cell_w + MARGIN);
    let x = (cell_x + (cell_w - image_w) / 2) as f32;
    let y = TOP as f32;
    let image = pixmap_from_rgba(iw, ih, tonemap_rgba8(panel.image, frame.exposure))?;
    pixmap.draw_pixmap(
        0,
        0,
        image.as_ref(),
        &paint,
        Transform::from_row(zoom, 0.0, 0.0, zoom, x, y),
        None,
    );
    canvas::stroke_rect(
        pixmap,
        (x - 0.5, y - 0.5, image_w as f32 + 1.0, image_h as f32 + 1.0),
        1.0,
        colors.grid,
    );
    // Captions: left-aligned with the image (or the cell, for narrow images).
    let left = cell_x.max(x as u32) as f32;
    let line = |n: u32| (TOP + image_h + CAPTION_GAP + n * CAPTION_LINE) as f32;
    let swatch = 11.0;
    canvas::fill_rect(pixmap, left, line(0) + 4.0, swatch, swatch, panel.color);
    text::draw_text(
        pixmap,
        panel.label,
        (left + swatch + 6.0, line(0)),
        (HAlign::Left, VAlign::Top),
        &caption.bold(),
    )?;
    text::draw_text(
        pixmap,
        panel.detail,
        (left, line(1)),
        (HAlign::Left, VAlign::Top),
        &TextStyle::new(CAPTION_SIZE, colors.muted),
    )?;
    text::draw_text(
        pixmap,
        &format!("{} spp", panel.spp),
        (left, line(2)),
        (HAlign::Left, VAlign::Top),
        &caption,
    )?;
    text::draw_text(
        pixmap,
        &rmse_caption(panel.rmse),
        (left, line(3)),
        (HAlign::Left, VAlign::Top),
        &caption,
    )?;
    Ok(())
}

/// How far through the animation (`(index, count)`): a track and its filled part along the
/// bottom of a `width × height` frame.
fn draw_progress(
    pixmap: &mut Pixmap,
    (index, count): (usize, usize),
    (width, height): (u32, u32),
    colors: &ThemeColors,
) {
    let track_w = (width - 2 * MARGIN) as f32;
    let bar_y = (height - MARGIN / 2 - PROGRESS_BAR) as f32;
    canvas::fill_rect(
        pixmap,
        MARGIN as f32,
        bar_y,
        track_w,
        PROGRESS_BAR as f32,
        colors.grid,
    );
    let done = if count == 0 {
        1.0
    } else {
        ((index + 1).min(count) as f32 / count as f32).clamp(0.0, 1.0)
    };
    canvas::fill_rect(
        pixmap,
        MARGIN as f32,
        bar_y,
        (track_w * done).round(),
        PROGRESS_BAR as f32,
        colors.muted,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::palette::{UNIFORM, scheme_color};
    use crate::sampler::Scheme;

    fn panel(image: &[f64], rmse: f64) -> AnimationPanel<'_> {
        AnimationPanel {
            label: "uniform",
            detail: "1/N each",
            color: UNIFORM,
            image,
            spp: 1,
            rmse,
        }
    }

    #[test]
    fn zoom_reaches_the_target_width_within_bounds() {
        assert_eq!(animation_zoom(96), 2);
        assert_eq!(animation_zoom(100), 2);
        assert_eq!(animation_zoom(192), 1);
        assert_eq!(animation_zoom(600), 1);
        assert_eq!(animation_zoom(8), MAX_ZOOM);
        assert_eq!(animation_zoom(0), MAX_ZOOM);
    }

    #[test]
    fn the_frame_size_depends_on_the_images_only() {
        let image = vec![1.0; 12 * 8];
        let panels = [panel(&image, 0.5), panel(&image, 1.5e-7)];
        let frame = AnimationFrame {
            width: 12,
            height: 8,
            zoom: 4,
            panels: &panels,
            exposure: 1.0,
            title: "a title far longer than the frame is wide, which is simply cut off",
            subtitle: "",
            progress: (0, 3),
        };
        let pm = animation_frame(&frame, Theme::Light).expect("valid frame");
        // Two cells of MIN_CELL_WIDTH (48 px images are narrower).
        assert_eq!((pm.width(), pm.height()), animation_frame_size(12, 8, 4, 2));
        assert_eq!(pm.width(), 2 * MARGIN + 2 * MIN_CELL_WIDTH + MARGIN);
        let last = animation_frame(
            &AnimationFrame {
                progress: (2, 3),
                ..frame
            },
            Theme::Dark,
        )
        .expect("valid frame");
        assert_eq!((last.width(), last.height()), (pm.width(), pm.height()));
    }

    #[test]
    fn images_are_enlarged_pixel_for_pixel() {
        // A 2×1 image, black | white, at zoom 3 in one panel: 3×3 blocks of each.
        let image = [0.0, 1e9];
        let panels = [panel(&image, 0.0)];
        let frame = AnimationFrame {
            width: 2,
            height: 1,
            zoom: 3,
            panels: &panels,
            exposure: 1.0,
            title: "",
            subtitle: "",
            progress: (0, 1),
        };
        let pm = animation_frame(&frame, Theme::Light).expect("valid frame");
        let x0 = MARGIN + (MIN_CELL_WIDTH - 6) / 2;
        let at = |x: u32, y: u32| {
            let p = pm.pixel(x, y).expect("inside");
            [p.red(), p.green(), p.blue()]
        };
        for dy in 0..3 {
            for dx in 0..3 {
                assert_eq!(at(x0 + dx, TOP + dy), [0, 0, 0]);
                assert_eq!(at(x0 + 3 + dx, TOP + dy), [255, 255, 255]);
            }
        }
    }

    #[test]
    fn bad_inputs_are_refused() {
        let image = vec![1.0; 6];
        let panels = [panel(&image[..5], 1.0)];
        let frame = AnimationFrame {
            width: 3,
            height: 2,
            zoom: 1,
            panels: &panels,
            exposure: 1.0,
            title: "",
            subtitle: "",
            progress: (0, 1),
        };
        assert!(matches!(
            animation_frame(&frame, Theme::Light),
            Err(DrawError::Length {
                expected: 6,
                got: 5,
                ..
            })
        ));
        assert!(matches!(
            animation_frame(
                &AnimationFrame {
                    panels: &[],
                    ..frame
                },
                Theme::Light
            ),
            Err(DrawError::Empty(_))
        ));
        let ok = [panel(&image, 1.0)];
        assert!(matches!(
            animation_frame(
                &AnimationFrame {
                    panels: &ok,
                    zoom: 0,
                    ..frame
                },
                Theme::Light
            ),
            Err(DrawError::Size { .. })
        ));
        assert!(matches!(
            animation_frame(
                &AnimationFrame {
                    panels: &ok,
                    width: 0,
                    ..frame
                },
                Theme::Light
            ),
            Err(DrawError::Empty(_))
        ));
    }

    #[test]
    fn captions_fit_the_narrowest_cell() {
        for (line, weight) in [
            ("RMSE 8.88·10⁻¹⁸⁸", text::Weight::Regular),
            ("65536 spp", text::Weight::Regular),
            ("∝ contribution (tree)", text::Weight::Regular),
            ("alias (∝ power)", text::Weight::Bold),
        ] {
            let m = text::measure(line, CAPTION_SIZE, weight).expect("font");
            assert!(
                m.width + 17.0 < MIN_CELL_WIDTH as f32,
                "{line}: {} px",
                m.width
            );
            assert!(text::has_glyphs(line), "{line}");
        }
        assert_ne!(scheme_color(Scheme::Alias), UNIFORM);
    }

    #[test]
    fn rmse_captions() {
        assert_eq!(rmse_caption(0.5), "RMSE 0.500");
        assert_eq!(rmse_caption(12.345), "RMSE 12.3");
        assert_eq!(rmse_caption(1.5e-7), "RMSE 1.50·10⁻⁷");
        assert_eq!(rmse_caption(0.0), "RMSE 0");
        assert_eq!(rmse_caption(f64::INFINITY), "RMSE inf");
    }
}
