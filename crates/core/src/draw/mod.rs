//! Headless drawings: every picture the app shows, rendered with tiny-skia into a
//! [`Pixmap`] and encoded as PNG with `image`, with no display and no system fonts.
//!
//! Each drawing is a pure function from plain data and a [`Style`] (size and [`Theme`]) to a
//! pixmap, so the same input gives the same pixels on every machine:
//!
//! * [`table_diagram()`]: the alias table as unit-height columns split at their thresholds;
//! * [`histogram()`]: expected pmf beside empirical frequencies per scheme, with χ² fits;
//! * [`convergence()`]: log-log RMSE against samples per pixel or seconds;
//! * [`image_sheet()`]: uniform | importance | spatial | reference and their error maps;
//! * [`animation_frame`]: one frame of a convergence animation (schemes side by side,
//!   captioned with spp and RMSE);
//! * [`tree_view()`]: the light tree from above (lights by power, the groups at a depth, a
//!   recorded pick, lights coloured by a pick probability);
//! * [`variance_sheet`]: per-pixel variance maps of several schemes on one log scale.
//!
//! Colours come from [`palette`], text from [`text`] (a bundled `DejaVu Sans` subset).
//! [`encode_png`] and [`write_png`] turn any of them into a PNG.

mod animation;
mod axes;
mod canvas;
mod convergence;
mod histogram;
mod image_sheet;
pub mod palette;
mod table_diagram;
pub mod text;
mod tree_view;
mod variance_maps;

use std::path::{Path, PathBuf};

/// The canvas every drawing returns (re-exported so callers need no tiny-skia dependency).
pub use tiny_skia::Pixmap;

pub use animation::{
    AnimationFrame, AnimationPanel, MAX_ZOOM, MIN_CELL_WIDTH, TARGET_PANEL_WIDTH, animation_frame,
    animation_frame_size, animation_zoom, rmse_caption,
};
pub use convergence::{
    ConvergenceAxis, ConvergencePoint, ConvergenceSeries, convergence, zero_variance_series,
};
pub use histogram::{HISTOGRAM_TOP_K, HistogramData, SchemeCounts, histogram};
pub use image_sheet::{
    ERROR_LOG10_RANGE, SheetImages, auto_exposure, error_color, image_sheet, viridis,
};
pub use palette::{Rgba8, Theme};
pub use table_diagram::{TABLE_DETAIL_LIMIT, fraction_denominator, table_diagram};
pub use tree_view::{
    DOT_AREA_SHARE, FOOTPRINT_LIMIT, LANE_COLORS, MAP_OCTAVES, MAX_DOT_RADIUS, PROBABILITY_DECADES,
    PlaneToPixels, PlaneView, TreeGroup, TreeView, pick_stages, tree_groups, tree_view,
    tree_view_caption, tree_view_plane,
};
pub use variance_maps::{
    VARIANCE_DECADES, VarianceScale, VarianceSheet, variance_caption, variance_mean,
    variance_method_line, variance_rgba, variance_scheme_name, variance_sheet,
};

/// Errors of the drawing functions.
#[derive(Debug, thiserror::Error)]
pub enum DrawError {
    /// The canvas size is zero or too large for tiny-skia.
    #[error("cannot create a {width}×{height} canvas")]
    Size {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
    },
    /// The bundled font failed to parse (a corrupted build).
    #[error("the bundled font could not be read")]
    Font,
    /// Two inputs that must have equal lengths do not.
    #[error("{what} has {got} entries, expected {expected}")]
    Length {
        /// Which input is wrong.
        what: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        got: usize,
    },
    /// There is nothing to draw (no lights, no series, no plottable points).
    #[error("nothing to draw: {0}")]
    Empty(&'static str),
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Png(#[from] image::ImageError),
    /// Writing the file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file that could not be written.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// Canvas size and theme shared by every drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Style {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Light or dark surroundings.
    pub theme: Theme,
}

impl Default for Style {
    /// 800×500 on the light theme (the size of the snapshot goldens and handouts).
    fn default() -> Self {
        Self {
            width: 800,
            height: 500,
            theme: Theme::Light,
        }
    }
}

/// The straight-alpha `RGBA8` bytes of a pixmap (tiny-skia stores premultiplied alpha).
pub fn to_rgba8(pixmap: &Pixmap) -> Vec<u8> {
    pixmap
        .pixels()
        .iter()
        .flat_map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue(), c.alpha()]
        })
        .collect()
}

/// Encodes a pixmap as PNG bytes (straight alpha, 8 bits per channel).
pub fn encode_png(pixmap: &Pixmap) -> Result<Vec<u8>, DrawError> {
    use image::ImageEncoder as _;
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes).write_image(
        &to_rgba8(pixmap),
        pixmap.width(),
        pixmap.height(),
        image::ExtendedColorType::Rgba8,
    )?;
    Ok(bytes)
}

/// Writes a pixmap to `path` as a PNG file, atomically
/// ([`crate::atomic_file::write_bytes_atomically`]: a failed write leaves the old file).
pub fn write_png(pixmap: &Pixmap, path: impl AsRef<Path>) -> Result<(), DrawError> {
    let path = path.as_ref();
    let bytes = encode_png(pixmap)?;
    crate::atomic_file::write_bytes_atomically(path, &bytes).map_err(|source| DrawError::Io {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trips() {
        let mut pm = Pixmap::new(3, 2).expect("valid test input");
        pm.fill(tiny_skia::Color::from_rgba8(10, 20, 30, 255));
        let bytes = encode_png(&pm).expect("valid test input");
        let decoded = image::load_from_memory(&bytes)
            .expect("valid test input")
            .to_rgba8();
        assert_eq!(decoded.dimensions(), (3, 2));
        assert_eq!(decoded.as_raw(), &to_rgba8(&pm));
        assert_eq!(&decoded.as_raw()[..4], &[10, 20, 30, 255]);
    }

    #[test]
    fn tiny_canvases_draw_without_panicking() {
        use crate::{AliasTable, Scheme, WorkedExample};
        let powers = WorkedExample::powers();
        let table = AliasTable::build_exact(&powers);
        let pmf = powers.pmf();
        let counts = SchemeCounts::new(Scheme::Alias, vec![2, 5, 20], pmf.clone())
            .expect("valid test input");
        let points = vec![ConvergencePoint {
            spp: 1,
            rmse: 0.5,
            seconds: 0.1,
        }];
        let img = [1.0; 4];
        for (width, height) in [(120, 80), (1, 1)] {
            let style = Style {
                width,
                height,
                theme: Theme::Dark,
            };
            let pm = table_diagram(&table, Some(27), &style).expect("valid test input");
            assert_eq!((pm.width(), pm.height()), (width, height));
            let data = HistogramData {
                pmf: pmf.clone(),
                schemes: vec![counts.clone()],
            };
            histogram(&data, &style).expect("valid test input");
            let series = [ConvergenceSeries::for_scheme(Scheme::Cdf, points.clone())];
            convergence(&series, ConvergenceAxis::Seconds, &style).expect("valid test input");
            let sheet = SheetImages {
                width: 2,
                height: 2,
                uniform: &img,
                importance: &img,
                spatial: &img,
                reference: &img,
                spp: 1,
                exposure: Some(1.0),
            };
            image_sheet(&sheet, &style).expect("valid test input");
        }
        let zero = Style {
            width: 0,
            ..Style::default()
        };
        assert!(matches!(
            table_diagram(&table, None, &zero),
            Err(DrawError::Size { width: 0, .. })
        ));
    }

    #[test]
    fn write_png_reports_the_path() {
        let pm = Pixmap::new(1, 1).expect("valid test input");
        let err = write_png(&pm, "/nonexistent-dir/x.png").expect_err("must be refused");
        assert!(matches!(err, DrawError::Io { .. }));
        assert!(err.to_string().contains("/nonexistent-dir/x.png"), "{err}");
    }
}
