//! The importance of a tree node at a shading point and the branch probability built on it.
//!
//! For a node with bounding box `[min, max]` (over its lights' positions), centre `c`, half
//! diagonal `h = |max − min|/2` and normalized power `Φ_node = Σ_{i∈node} p_i`, the importance
//! at `x = (x, y, 0)` is
//!
//! `I(node, x) = Φ_node · cos_bound / (4π · max(|x − c|², h²))`,
//!
//! * `cos_bound = z_max / √(ρ² + z_max²)` with `ρ` the horizontal distance from `x` to the
//!   box's `xy` rectangle (0 inside it): the largest `cos θ = z/r` of any point of the box,
//!   since `z/√(ρ_l² + z²)` grows with `z` and falls with `ρ_l ≥ ρ`; it is 0 only when
//!   `z_max ≤ 0`, i.e. when no light of the box can light the plane;
//! * the squared distance to the centre, clamped below by `h²` (pbrt-v4's choice): a node
//!   the point is close to or inside is not over-weighted without bound, and the
//!   denominator is never 0.
//!
//! A leaf (one light) has the exact importance `p_i·G_i(x)` (same units: `G = cos θ/(4π r²)`).
//! `I > 0` whenever the node holds a light with `p_i·G_i(x) > 0`, so every branch towards
//! such a light has positive probability: the descent is unbiased.

/// `I(node, x)` for a box `[min, max]` of normalized power `power` (see the module docs),
/// capped at `f64::MAX / 4` so that the sum of two importances stays finite.
#[inline]
pub fn node_importance(min: [f64; 3], max: [f64; 3], power: f64, x: [f64; 2]) -> f64 {
    let z_max = max[2];
    if z_max <= 0.0 || power <= 0.0 || z_max.is_nan() || power.is_nan() {
        return 0.0;
    }
    let gap_x = (min[0] - x[0]).max(x[0] - max[0]).max(0.0);
    let gap_y = (min[1] - x[1]).max(x[1] - max[1]).max(0.0);
    let rho2 = gap_x * gap_x + gap_y * gap_y;
    // cos_bound = z_max / √(ρ² + z_max²), folded into the one division below.
    let c = [
        0.5 * (min[0] + max[0]),
        0.5 * (min[1] + max[1]),
        0.5 * (min[2] + max[2]),
    ];
    let (dx, dy, dz) = (c[0] - x[0], c[1] - x[1], c[2]);
    let d2 = dx * dx + dy * dy + dz * dz;
    let (hx, hy, hz) = (
        0.5 * (max[0] - min[0]),
        0.5 * (max[1] - min[1]),
        0.5 * (max[2] - min[2]),
    );
    let h2 = hx * hx + hy * hy + hz * hz;
    let d2 = d2.max(h2).max(f64::MIN_POSITIVE);
    let denominator = 4.0 * std::f64::consts::PI * d2 * (rho2 + z_max * z_max).sqrt();
    (power * z_max / denominator).min(f64::MAX / 4.0)
}

/// The probability of taking the left child: `I_L / (I_L + I_R)`; when both importances are
/// 0 (only through underflow: a reached node always holds a contributing light), in
/// proportion to the children's powers `Φ_L / (Φ_L + Φ_R)`; when those are 0 too, `1/2`.
/// Returns `(P_left, P_right)`, each computed directly as `I·(1/s)` (not as `1 − P`).
#[inline]
pub fn branch_probabilities(
    i_left: f64,
    i_right: f64,
    phi_left: f64,
    phi_right: f64,
) -> (f64, f64) {
    let s = i_left + i_right;
    if s > 0.0 {
        let inv = 1.0 / s;
        (i_left * inv, i_right * inv)
    } else {
        let t = phi_left + phi_right;
        if t > 0.0 {
            (phi_left / t, phi_right / t)
        } else {
            (0.5, 0.5)
        }
    }
}

/// `2^24`: the branch decisions compare 24-bit integers (the top bits of a draw).
pub const BRANCH_GRID: u32 = 1 << 24;

/// The left-branch threshold on the `2^24` grid: `y = P_left · 2^24`, clamped to
/// `[1, 2^24 − 1]` when both children have positive probability (to `0` or `2^24` when one
/// has none). Go left iff `(r >> 8) < y` for the level's draw `r`; for the integer `r >> 8`
/// that is `(r >> 8) < t` with `t = ⌈y⌉`, which happens with probability exactly `t / 2^24`
/// ([`grid_probabilities`]); right with `(2^24 − t) / 2^24`. The clamp keeps a child of
/// positive probability reachable, however small.
///
/// The pdf of a descent is the product of these grid probabilities: exactly what the
/// decisions realize (as the alias table's packed thresholds are exactly what its keep test
/// realizes), so the tree estimate is unbiased without any rounding term, while each factor
/// stays within `2^-24` of `P_left` or `P_right`. `P·2^24` is exact in `f32` and `f64`, so
/// the CPU and the GPU differ in `t` only where their `P` round across an integer. The
/// decision compares with `y` itself (no rounding up on the descent's critical path).
#[inline]
pub fn branch_threshold(p_left: f64, p_right: f64) -> f64 {
    let one = f64::from(BRANCH_GRID);
    let lo = if p_left > 0.0 { 1.0 } else { 0.0 };
    let hi = if p_right > 0.0 { one - 1.0 } else { one };
    (p_left * one).clamp(lo, hi)
}

/// The probabilities `(t / 2^24, (2^24 − t) / 2^24)`, `t = ⌈y⌉`, of the two branches of the
/// threshold `y` of [`branch_threshold`].
#[inline]
pub fn grid_probabilities(threshold: f64) -> (f64, f64) {
    let one = f64::from(BRANCH_GRID);
    let t = threshold.ceil();
    (t / one, (one - t) / one)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::geometry_term;

    #[test]
    fn a_point_box_far_away_bounds_the_true_contribution_from_above() {
        // A degenerate box (h = 0) at the light: I = p·cos_bound/(4π d²) with cos_bound ≥ cos θ.
        let light = [1.0, 2.0, 0.5];
        let x = [3.0, -1.0];
        let i = node_importance(light, light, 0.25, x);
        let g = 0.25 * geometry_term(light, x);
        assert!(i >= g * (1.0 - 1e-12), "{i} vs {g}");
        assert!(
            (i - g).abs() <= 1e-12 * g,
            "a point box is exact: {i} vs {g}"
        );
    }

    #[test]
    fn a_box_below_the_plane_or_without_power_has_no_importance() {
        assert_eq!(
            node_importance([0.0, 0.0, -2.0], [1.0, 1.0, 0.0], 1.0, [0.0, 0.0]),
            0.0
        );
        assert_eq!(
            node_importance([0.0, 0.0, 1.0], [1.0, 1.0, 2.0], 0.0, [0.0, 0.0]),
            0.0
        );
        assert!(node_importance([0.0, 0.0, -2.0], [1.0, 1.0, 1e-9], 1.0, [5.0, 0.0]) > 0.0);
    }

    #[test]
    fn thresholds_keep_every_positive_branch_reachable() {
        assert_eq!(branch_threshold(0.5, 0.5), 8_388_608.0);
        assert_eq!(branch_threshold(1e-30, 1.0), 1.0);
        assert_eq!(branch_threshold(1.0, 1e-30), 16_777_215.0);
        assert_eq!(branch_threshold(0.0, 1.0), 0.0);
        assert_eq!(branch_threshold(1.0, 0.0), 16_777_216.0);
        let (a, b) = grid_probabilities(2.5);
        assert_eq!(a + b, 1.0);
        assert_eq!(a, 3.0 / 16_777_216.0);
        // Left iff k < y, for every integer k: exactly ⌈y⌉ of the 2^24 values.
        let y = branch_threshold(0.3, 0.7);
        let t = y.ceil() as u32;
        assert!(f64::from(t - 1) < y && f64::from(t) >= y);
    }

    #[test]
    fn branch_probabilities_fall_back_to_powers_then_halves() {
        assert_eq!(branch_probabilities(1.0, 3.0, 9.0, 9.0), (0.25, 0.75));
        assert_eq!(branch_probabilities(0.0, 0.0, 1.0, 3.0), (0.25, 0.75));
        assert_eq!(branch_probabilities(0.0, 0.0, 0.0, 0.0), (0.5, 0.5));
        assert_eq!(branch_probabilities(0.0, 2.0, 1.0, 1.0), (0.0, 1.0));
    }
}
