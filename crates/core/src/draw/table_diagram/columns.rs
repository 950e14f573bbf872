//! The geometry of the table panel's columns: a unit column split at its threshold (and
//! how it is painted), the summary's bins and their whole-pixel edges.

use tiny_skia::Pixmap;

use crate::draw::canvas;
use crate::draw::palette::Rgba8;

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

impl ColumnRects {
    /// Paints the own-light part in `own` and the alias part above it in `alias`.
    pub(crate) fn fill(&self, pixmap: &mut Pixmap, own: Rgba8, alias: Rgba8) {
        canvas::fill_rect(
            pixmap,
            self.x,
            self.own_top,
            self.width,
            self.own_height,
            own,
        );
        let (top, height) = (self.alias_top, self.alias_height);
        canvas::fill_rect(pixmap, self.x, top, self.width, height, alias);
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AliasTable, WorkedExample};

    #[test]
    fn column_split_heights_equal_thresholds() {
        let table = AliasTable::build_exact(&WorkedExample::powers());
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
        let table = AliasTable::build_exact(&WorkedExample::powers());
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
}
