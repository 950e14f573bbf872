//! The one place the point-light irradiance formula and the pixel layout live.

/// `G(x) = max(0, z)/(4π r³)`: the irradiance at `x = (x, y, 0)` per unit power of a point
/// light at `p`, for the receiver normal `+z` (`cos θ = z/r`). Zero for a light on or below
/// the plane.
#[inline]
pub fn geometry_term(light: [f64; 3], x: [f64; 2]) -> f64 {
    let z = light[2];
    if z <= 0.0 {
        return 0.0;
    }
    let dx = light[0] - x[0];
    let dy = light[1] - x[1];
    let r2 = dx * dx + dy * dy + z * z;
    z / (4.0 * std::f64::consts::PI * r2 * r2.sqrt())
}

/// The centre of pixel `(px, py)` of `plane` on `z = 0` (row 0 at the top, `y = max[1]`).
#[inline]
pub fn pixel_center(plane: &super::ReceiverPlane, px: u32, py: u32) -> [f64; 2] {
    let fx = (f64::from(px) + 0.5) / f64::from(plane.width);
    let fy = (f64::from(py) + 0.5) / f64::from(plane.height);
    [
        plane.min[0] + fx * (plane.max[0] - plane.min[0]),
        plane.max[1] - fy * (plane.max[1] - plane.min[1]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_straight_above_follows_inverse_square() {
        let g1 = geometry_term([0.0, 0.0, 1.0], [0.0, 0.0]);
        let g2 = geometry_term([0.0, 0.0, 2.0], [0.0, 0.0]);
        assert!((g1 - 1.0 / (4.0 * std::f64::consts::PI)).abs() < 1e-15);
        assert!((g1 / g2 - 4.0).abs() < 1e-12);
    }

    #[test]
    fn light_below_the_plane_contributes_nothing() {
        assert_eq!(geometry_term([0.0, 0.0, -1.0], [0.0, 0.0]), 0.0);
        assert_eq!(geometry_term([1.0, 0.0, 0.0], [0.0, 0.0]), 0.0);
    }
}
