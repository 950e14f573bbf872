//! One tile's cut as it is grown ([`super::TileCuts`]): the points of a tile where its
//! entries are weighed, and each candidate entry with what the cut weighs it by.

use super::node::ChildRef;

/// Weighing points along a tile's side.
pub(super) const WEIGHING_SIDE: usize = 3;

/// The points of a tile (as fractions of its width and height) where the cut's weights are
/// taken: the centres of its 3 × 3 ninths.
pub(super) const WEIGHING_POINTS: [[f64; 2]; WEIGHING_SIDE * WEIGHING_SIDE] = {
    let mut points = [[0.0; 2]; WEIGHING_SIDE * WEIGHING_SIDE];
    let mut k = 0;
    while k < points.len() {
        let (i, j) = ((k % WEIGHING_SIDE) as f64, (k / WEIGHING_SIDE) as f64);
        points[k] = [
            (i + 0.5) / WEIGHING_SIDE as f64,
            (j + 0.5) / WEIGHING_SIDE as f64,
        ];
        k += 1;
    }
    points
};

/// One tile's cut as it is grown: each entry's subtree, its probability under the tree at
/// each weighing point, and its power.
#[derive(Clone, Copy, Debug)]
pub(super) struct Candidate {
    /// The entry's subtree (a node, a leaf cluster, or a single light).
    pub(super) at: ChildRef,
    /// `P_tree(e | x_k)` at each weighing point `x_k`.
    pub(super) reach: [f64; WEIGHING_POINTS.len()],
    /// The largest of `reach`: `q̄_e = max_k P_tree(e | x_k)`.
    pub(super) peak: f64,
    /// What the cut weighs the entry by: `q̃_e = √(q̄_e · q_e)`, `q_e` the root mean square
    /// of `reach` (the module docs of `tile_cut`).
    pub(super) weight: f64,
    /// `Φ_e`, the normalized power of the entry's lights.
    pub(super) power: f64,
    /// Whether the cut keeps this entry whole (a leaf cluster whose lights' shares change
    /// too much across the tile).
    pub(super) whole: bool,
}

impl Candidate {
    /// The entry `at`, reached with `reach` at the weighing points, of power `power`.
    pub(super) fn new(at: ChildRef, reach: [f64; WEIGHING_POINTS.len()], power: f64) -> Self {
        let peak = reach.iter().fold(0.0f64, |m, &r| m.max(r));
        let mean_square = reach.iter().map(|r| r * r).sum::<f64>() / reach.len() as f64;
        Self {
            at,
            reach,
            peak,
            weight: (peak * mean_square.sqrt()).sqrt(),
            power,
            whole: false,
        }
    }
}
