//! The receiver of an imported light set, which names none: a plane over the footprint of
//! its lights.

use glam::{DVec2, DVec3};

use crate::scene::{MAX_PLANE_SIDE, ReceiverPlane};

/// Pixels on the longer side of an imported scene's plane.
pub const IMPORT_PLANE_PIXELS: u32 = 256;

/// A plane over the footprint of the lights above `z = 0` (all lights when none is): their
/// `(x, y)` box widened on every side by a margin of a quarter of its larger side, at least
/// the lights' median height (a light lights the plane out to a few times its height), and
/// `side` pixels along the longer side.
pub fn footprint_plane(positions: &[DVec3], side: u32) -> ReceiverPlane {
    let above: Vec<DVec3> = positions.iter().copied().filter(|p| p.z > 0.0).collect();
    let lights = if above.is_empty() {
        positions.to_vec()
    } else {
        above
    };
    let (mut min, mut max) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for p in &lights {
        min = min.min(p.truncate());
        max = max.max(p.truncate());
    }
    if !(min.x.is_finite() && max.x.is_finite() && min.y.is_finite() && max.y.is_finite()) {
        min = DVec2::splat(-1.0);
        max = DVec2::splat(1.0);
    }
    let mut heights: Vec<f64> = lights.iter().map(|p| p.z.abs()).collect();
    heights.sort_by(f64::total_cmp);
    let median = heights.get(heights.len() / 2).copied().unwrap_or(1.0);
    let extent = max - min;
    let margin = (0.25 * extent.max_element())
        .max(median)
        .max(f64::MIN_POSITIVE * 1e10);
    let (min, max) = (min - margin, max + margin);
    let size = max - min;
    let side = side.clamp(1, MAX_PLANE_SIDE);
    let (width, height) = if size.x >= size.y {
        (
            side,
            ((f64::from(side) * size.y / size.x).round() as u32).clamp(1, side),
        )
    } else {
        (
            ((f64::from(side) * size.x / size.y).round() as u32).clamp(1, side),
            side,
        )
    };
    ReceiverPlane {
        min,
        max,
        width,
        height,
    }
}
