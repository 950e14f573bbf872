//! Convergence series: a progressive renderer run to `1, 2, 4, …` samples per pixel, with
//! its RMSE against the exact [`Reference`] and the rendering time at each count.

use std::time::Instant;

use super::Accumulator;
use super::metrics::rmse;
use super::reference::Reference;
use crate::sampler::Scheme;

/// One point of a convergence series: the error after `spp` samples per pixel and the
/// rendering time spent to get there. Serialized with the keys `spp`, `rmse`, `seconds`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SeriesPoint {
    /// Samples per pixel accumulated.
    pub spp: u32,
    /// RMSE against the reference at that point.
    pub rmse: f64,
    /// Cumulative rendering seconds (metric evaluation excluded).
    pub seconds: f64,
}

/// A renderer that adds samples to a running [`Accumulator`] (the CPU renderer; the GPU one
/// may implement it too), so one series runner serves both.
pub trait ProgressiveRenderer {
    /// Adds `samples_per_pixel` samples to every pixel, continuing the sample index.
    fn accumulate(&mut self, samples_per_pixel: u32);
    /// The running sums.
    fn accumulator(&self) -> &Accumulator;
}

/// The sample counts of a convergence series: `1, 2, 4, …` up to `max_spp`, and `max_spp`
/// itself last when it is not a power of two. Empty for `max_spp = 0`.
pub fn series_spp(max_spp: u32) -> Vec<u32> {
    let mut out: Vec<u32> = std::iter::successors(Some(1u32), |&s| s.checked_mul(2))
        .take_while(|&s| s <= max_spp)
        .collect();
    if max_spp > 0 && out.last() != Some(&max_spp) {
        out.push(max_spp);
    }
    out
}

/// Renders progressively to each count of [`series_spp`]`(max_spp)` (adding only the
/// missing samples each time, so the whole series costs `max_spp` samples per pixel) and
/// records the RMSE and the cumulative rendering time at each. Starts from the renderer's
/// current state: give it a fresh (or reset) renderer. On return the renderer holds
/// `max_spp` samples per pixel, the final image.
///
/// # Panics
/// If the renderer's and the reference's image sizes differ.
pub fn convergence_series<R: ProgressiveRenderer + ?Sized>(
    renderer: &mut R,
    reference: &Reference,
    max_spp: u32,
) -> Vec<SeriesPoint> {
    let mut seconds = 0.0;
    let mut points = Vec::new();
    for target in series_spp(max_spp) {
        let have = renderer.accumulator().samples_per_pixel;
        if target > have {
            let start = Instant::now();
            renderer.accumulate(target - have);
            seconds += start.elapsed().as_secs_f64();
        }
        let acc = renderer.accumulator();
        points.push(SeriesPoint {
            spp: acc.samples_per_pixel,
            rmse: rmse(acc, reference),
            seconds,
        });
    }
    points
}

/// The convergence series of one scheme (serialized as `{"scheme": …, "series": [{spp,
/// rmse, seconds}, …]}`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SchemeSeries {
    /// The scheme rendered.
    pub scheme: Scheme,
    /// Its points, in increasing `spp`.
    pub series: Vec<SeriesPoint>,
}
