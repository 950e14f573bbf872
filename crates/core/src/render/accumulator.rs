//! Per-pixel running sums of the normalized estimate.

use crate::Scaled;

/// Sums `Σ ê'` and `Σ ê'²` of the per-sample estimate in the accumulation unit of every
/// pixel, and that unit.
///
/// A renderer's normalized estimate `ê` (irradiance per unit of total power, see
/// [`crate::render`]) is stored as `ê' = ê·2^-s` with the shift `s` of
/// [`crate::scene::Scene::irradiance_shift`] (0 for the GPU's `f32` sums): an exact scaling
/// that keeps `ê'` near 1 and `ê'²` in range whatever the scene's geometry. The irradiance
/// is `E(p) = U · Σê'/spp` with the unit `U = Φ_total · 2^s` ([`Accumulator::unit`]), a
/// [`Scaled`] so that a total power beyond `f64` still has a unit. Scaling every power by
/// `2^k` leaves the sums' bits unchanged and multiplies `U` by `2^k`.
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulator {
    /// Pixel columns.
    pub width: u32,
    /// Pixel rows.
    pub height: u32,
    /// Samples per pixel accumulated so far.
    pub samples_per_pixel: u32,
    /// `Φ_total`, the total power, whatever its magnitude.
    pub total_power: Scaled,
    /// `s`: the sums hold `ê·2^-s`.
    pub shift: i32,
    /// `Σ ê'` per pixel, row-major.
    pub sum: Vec<f64>,
    /// `Σ ê'²` per pixel, row-major.
    pub sum_sq: Vec<f64>,
}

impl Accumulator {
    /// An empty accumulator for a `width × height` image of a scene of total power
    /// `total_power`, summing `ê·2^-shift`.
    pub fn new(width: u32, height: u32, total_power: Scaled, shift: i32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            samples_per_pixel: 0,
            total_power,
            shift,
            sum: vec![0.0; n],
            sum_sq: vec![0.0; n],
        }
    }

    /// The same image size, power and shift with no samples.
    #[must_use]
    pub fn emptied(&self) -> Self {
        Self::new(self.width, self.height, self.total_power, self.shift)
    }

    /// The unit `U = Φ_total·2^s` of the sums: `E(p) = U · Σê'/spp`.
    pub fn unit(&self) -> Scaled {
        self.total_power * Scaled::pow2(self.shift)
    }

    /// The irradiance estimate of pixel `p`: `U · Σ ê' / spp` (0 before any sample; `inf`
    /// where it exceeds `f64`).
    pub fn mean(&self, p: usize) -> f64 {
        self.unit().mul_f64(self.mean_in_unit(p)).to_f64()
    }

    /// The estimate of pixel `p` in the unit, `Σ ê' / spp` (0 before any sample).
    pub fn mean_in_unit(&self, p: usize) -> f64 {
        if self.samples_per_pixel == 0 {
            0.0
        } else {
            self.sum[p] / f64::from(self.samples_per_pixel)
        }
    }

    /// The whole image of estimates, row-major.
    pub fn image(&self) -> Vec<f64> {
        let unit = self.unit();
        (0..self.sum.len())
            .map(|p| unit.mul_f64(self.mean_in_unit(p)).to_f64())
            .collect()
    }

    /// The sample variance of one sample at pixel `p`, in irradiance units:
    /// `U² · (Σê'² − (Σê')²/n) / (n − 1)` (`inf` where it exceeds `f64`).
    pub fn variance_per_sample(&self, p: usize) -> f64 {
        self.unit()
            .square()
            .mul_f64(self.variance_in_unit(p))
            .to_f64()
    }

    /// The sample variance of one sample at pixel `p` in the squared unit:
    /// `(Σê'² − (Σê')²/n) / (n − 1)` (0 before two samples).
    pub fn variance_in_unit(&self, p: usize) -> f64 {
        let n = f64::from(self.samples_per_pixel);
        if n < 2.0 {
            return 0.0;
        }
        let centered = (self.sum_sq[p] - self.sum[p] * self.sum[p] / n).max(0.0);
        centered / (n - 1.0)
    }
}
