//! One tile's cut as it is grown ([`super::TileCuts`]): the points of a tile where its
//! entries are weighed, and each candidate entry with what the cut weighs it by.

use super::node::ChildRef;

/// What a cut grows by: the order of its splits and its spread.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Weighing {
    /// Their estimated contributions `Ê_e(x_k)` (module docs).
    Estimates,
    /// The tree's probabilities `P_tree(e | x_k)` (for measuring the alternative).
    TreeProbabilities,
}

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

/// One tile's cut as it is grown: each entry's subtree, its estimate and its probability
/// under the tree at each weighing point, and its power.
#[derive(Clone, Copy, Debug)]
pub(super) struct Candidate {
    /// The entry's subtree (a node, a leaf cluster, or a single light).
    pub(super) at: ChildRef,
    /// `Ê_e(x_k)`, what the entry is estimated to give each weighing point `x_k`.
    pub(super) estimate: [f64; WEIGHING_POINTS.len()],
    /// `P_tree(e | x_k)`, the tree's probability of descending into the entry at each
    /// weighing point.
    pub(super) tree_probability: [f64; WEIGHING_POINTS.len()],
    /// Its largest share `max_k Ê_e(x_k)/Ê(x_k)` against the cut's totals `Ê(x_k)` as
    /// they were last taken (the growth's order and spread; of `P_tree` when the cut grows
    /// by the tree's probabilities).
    pub(super) peak: f64,
    /// What the cut weighs the entry by: `q̃_e = √(q̄_e · q_e)`, `q̄_e` the largest and `q_e`
    /// the root mean square of its shares against the final cut's totals
    /// ([`Candidate::weigh`]; the module docs of `tile_cut`).
    pub(super) weight: f64,
    /// The same of its probabilities under the tree.
    pub(super) tree_weight: f64,
    /// `Φ_e`, the normalized power of the entry's lights.
    pub(super) power: f64,
    /// Whether the cut keeps this entry whole (a leaf cluster whose lights' shares change
    /// too much across the tile).
    pub(super) whole: bool,
    /// An upper bound of what the entry's lights give any point of the tile
    /// ([`super::TreeNode::lane_bound`]), for a subtree of point lights; 0 where
    /// none is taken (leaf clusters, single lights, lanes of spots).
    pub(super) bound: f64,
}

impl Candidate {
    /// The entry `at` with the estimates `estimate` and the tree's probabilities
    /// `tree_probability` at the weighing points, of power `power`;
    /// its peak and weight are taken later ([`Candidate::largest_share`],
    /// [`Candidate::weigh`]).
    pub(super) fn new(
        at: ChildRef,
        estimate: [f64; WEIGHING_POINTS.len()],
        tree_probability: [f64; WEIGHING_POINTS.len()],
        power: f64,
    ) -> Self {
        Self {
            at,
            estimate,
            tree_probability,
            peak: 0.0,
            weight: 0.0,
            tree_weight: 0.0,
            power,
            whole: false,
            bound: 0.0,
        }
    }

    /// The same entry with the bound `bound` of what it gives the tile.
    pub(super) fn bounded_by(self, bound: f64) -> Self {
        Self { bound, ..self }
    }

    /// What the cut grows by: the estimates, or the tree's probabilities.
    #[inline]
    pub(super) fn grown_by(&self, by: Weighing) -> &[f64; WEIGHING_POINTS.len()] {
        match by {
            Weighing::Estimates => &self.estimate,
            Weighing::TreeProbabilities => &self.tree_probability,
        }
    }

    /// The entry's largest share by `by` against the totals whose reciprocals are
    /// `inverse_total`.
    #[inline]
    pub(super) fn largest_share(
        &self,
        by: Weighing,
        inverse_total: &[f64; WEIGHING_POINTS.len()],
    ) -> f64 {
        self.grown_by(by)
            .iter()
            .zip(inverse_total)
            .fold(0.0f64, |m, (r, t)| m.max(r * t))
    }

    /// Sets [`Candidate::weight`] and [`Candidate::tree_weight`] from the shares against the
    /// totals whose reciprocals are given: `√(q̄_e · q_e)` of each.
    pub(super) fn weigh(
        &mut self,
        estimated: &[f64; WEIGHING_POINTS.len()],
        by_tree: &[f64; WEIGHING_POINTS.len()],
    ) {
        self.weight = mixed_weight(&self.estimate, estimated);
        self.tree_weight = mixed_weight(&self.tree_probability, by_tree);
    }
}

/// `√(q̄ · q)` of the shares `estimate[k]·inverse_total[k]`: `q̄` their largest, `q` their root
/// mean square.
fn mixed_weight(
    estimate: &[f64; WEIGHING_POINTS.len()],
    inverse_total: &[f64; WEIGHING_POINTS.len()],
) -> f64 {
    let shares: [f64; WEIGHING_POINTS.len()] =
        std::array::from_fn(|k| estimate[k] * inverse_total[k]);
    let peak = shares.iter().fold(0.0f64, |m, &s| m.max(s));
    let mean_square = shares.iter().map(|s| s * s).sum::<f64>() / shares.len() as f64;
    (peak * mean_square.sqrt()).sqrt()
}
