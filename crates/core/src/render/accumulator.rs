//! Per-pixel running sums of the normalized estimate.

/// Sums `Σ ê` and `Σ ê²` of the normalized per-sample estimate `ê` of every pixel, with
/// the scale `Φ_total` that turns them into irradiance: `E(p) = Φ_total · Σ ê / spp`.
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulator {
    /// Pixel columns.
    pub width: u32,
    /// Pixel rows.
    pub height: u32,
    /// Samples per pixel accumulated so far.
    pub samples_per_pixel: u32,
    /// `Φ_total`, the factor between normalized estimates and irradiance.
    pub scale: f64,
    /// `Σ ê` per pixel, row-major.
    pub sum: Vec<f64>,
    /// `Σ ê²` per pixel, row-major.
    pub sum_sq: Vec<f64>,
}

impl Accumulator {
    /// An empty accumulator for a `width × height` image with scale `Φ_total`.
    pub fn new(width: u32, height: u32, scale: f64) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            samples_per_pixel: 0,
            scale,
            sum: vec![0.0; n],
            sum_sq: vec![0.0; n],
        }
    }

    /// The irradiance estimate of pixel `p`: `Φ_total · Σ ê / spp` (0 before any sample).
    pub fn mean(&self, p: usize) -> f64 {
        if self.samples_per_pixel == 0 {
            0.0
        } else {
            self.scale * self.sum[p] / f64::from(self.samples_per_pixel)
        }
    }

    /// The whole image of estimates, row-major.
    pub fn image(&self) -> Vec<f64> {
        (0..self.sum.len()).map(|p| self.mean(p)).collect()
    }

    /// The sample variance of one sample at pixel `p`, in irradiance units:
    /// `Φ_total² · (Σê² − (Σê)²/n) / (n − 1)`.
    pub fn variance_per_sample(&self, p: usize) -> f64 {
        let n = f64::from(self.samples_per_pixel);
        if n < 2.0 {
            return 0.0;
        }
        let centered = (self.sum_sq[p] - self.sum[p] * self.sum[p] / n).max(0.0);
        self.scale * self.scale * centered / (n - 1.0)
    }
}
