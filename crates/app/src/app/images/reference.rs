//! What the CPU engine and the GPU runs compute alike from their sums: the exact
//! reference and its note, the error maps, and the thinning of the convergence series.

use lightpick_core::render::Reference;
use lightpick_core::scene::Scene;

use super::published::ConvergencePoint;
use crate::app::colors;

/// Keeps a convergence series short: past 1024 points, every other point of the older half
/// is dropped (on a log axis the recent, dense end loses nothing visible).
pub fn thin(series: &mut Vec<ConvergencePoint>) {
    if series.len() <= 1024 {
        return;
    }
    let half = series.len() / 2;
    let mut k = 0;
    series.retain(|_| {
        k += 1;
        k > half || k % 2 == 1
    });
}

/// The error-map scale: errors are shown relative to the reference's mean.
pub fn error_scale(reference: &[f64]) -> f64 {
    let mean = reference.iter().sum::<f64>() / reference.len().max(1) as f64;
    if mean > 0.0 { 1.0 / mean } else { 1.0 }
}

/// The error map: `|estimate − reference| · scale` through the palette's error ramp.
pub fn error_map(image: &[f64], reference: &[f64], scale: f64) -> Vec<u8> {
    image
        .iter()
        .zip(reference)
        .flat_map(|(e, r)| {
            let [red, green, blue] = colors::error_ramp((e - r).abs() * scale);
            [red, green, blue, 255]
        })
        .collect()
}

/// The exact reference within the core's budget (every pixel, or a fixed subset for huge
/// `N·P`), and a note when it is a subset or when an irradiance exceeds `f64` (naming the
/// pixel and the light).
pub fn reference(scene: &Scene) -> (Reference, Option<String>) {
    let reference = Reference::compute(scene);
    if let Some(overflow) = reference.overflow() {
        return (
            reference,
            Some(format!("{overflow}: RMSE and images are not meaningful")),
        );
    }
    let note = (!reference.is_complete()).then(|| {
        format!(
            "reference at {} of {} pixels ({} lights): RMSE over those pixels, no reference image",
            reference.pixels().len(),
            scene.plane.pixel_count(),
            scene.light_count()
        )
    });
    (reference, note)
}
