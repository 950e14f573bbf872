//! The light tree: a 4-wide tree over the contributing lights, with leaf clusters of up to
//! [`LEAF_SIZE`] lights, descended stochastically.
//!
//! # Layout
//! The `M` contributing lights are permuted into leaf order (`order[j]` = scene index of the
//! `j`-th light). A range of more than [`LEAF_SIZE`] lights is one internal node whose up to
//! four children split it: at the median along the longest axis of the range's box, then
//! each half (if still larger than a leaf) at its own median along its own longest axis
//! (`select_nth_unstable`, ties broken by scene index, so the build is deterministic). A
//! range of at most [`LEAF_SIZE`] lights is a leaf cluster. A node holds, per child lane,
//! the child's power-weighted centroid and power (the representative light of
//! [`super::importance`]) and a [`ChildRef`]: an internal node, a leaf cluster (first light
//! and count), or empty. Nodes are stored depth first, each node's subtrees after it in lane
//! order, so the layout depends only on `M` and the subtrees build in parallel. On the GPU a
//! node is 80 bytes (four `(c.xyz, Φ)` as `f32` and four child words); a 10^6-light tree has
//! 87 381 nodes (`(4^9 − 1)/3`: its leaf clusters hold 3–4 lights), 7 bytes per light.
//!
//! Depth: about `log4(M / 8)` nodes (8–9 for 10^6 lights, against 20 levels of the binary
//! tree this replaced), then one pick inside the leaf. Among a million lights each level's
//! node is a cache miss: the renderer descends eight pixels' picks in lockstep
//! ([`LightTree::sample_many`]), and in a tree of at least `2^15` point lights each pick
//! asks for its next node (or leaf cluster) as soon as it is known, a round of the other
//! picks' steps before reading it (`prefetch`): 42–44 % off a spatial sample at 10^6
//! lights. Over more than 256 point lights the first sample a pass gives a pixel also takes
//! its tile's cut draw ahead and asks for the cut's lines it will read
//! ([`LightTree::sample_many_cold`]).
//!
//! # The pick and its pdf
//! From the root, each node's four children get the branch probabilities of
//! [`super::importance::branch_probabilities`] and their grid masses, and one draw `r`
//! (its top 24 bits) picks a lane ([`super::importance::pick_on_grid`]); at a leaf cluster
//! every light's contribution `c_j = p_j·G_j(x)` is evaluated and one more draw picks light
//! `j` with the grid masses of `c_j / Σ c`. The pick's probability is the product of the
//! realized factors,
//!
//! `P(i | x) = Π_nodes m_lane / 2^24 · m_j / 2^24`,
//!
//! and since each node's (and the leaf's) masses sum to exactly `2^24`, `Σ_i P(i | x) = 1`.
//! Every child holding power keeps a positive mass (the power share of the mixture), every
//! light of a leaf with `c_j > 0` too, so `P(i | x) > 0` wherever `p_i·G_i(x) > 0`: the
//! estimate `p_i·G_i(x) / P(i | x)` is unbiased, with no rounding term from the decisions.
//!
//! # Spots and ranges: footprints, maps and bounds
//! A tree over lights with emission profiles is laid out by where the lights shine, not by
//! where they hang: a surface-area heuristic over their footprints on the plane
//! ([`footprint_split`]), so a lane holds spots that light one part of the plane. Each lane
//! is bounded by a [`LaneBounds`](super::LaneBounds) (pbrt-v4's `LightBounds`: the box of
//! its lights, the cone of their spot axes, their widest outer cone and longest range, the
//! box of their footprints) and keeps a map of what its lights give the plane
//! ([`super::grid`]: the mean irradiance per cell of a 16 × 16 raster over its footprints).
//! Of the bounds a node keeps its lanes' footprint boxes and intensities beside their maps
//! ([`super::grid::MappedLanes`]), and the rest ([`super::LaneReach`]) only where a lane's
//! footprint is unbounded (a cone reaching the horizon without a range): a bounded
//! footprint already holds every point the lane's cones and ranges reach, so elsewhere the
//! rest is never read. At a point, a lane whose bounds exclude it is culled
//! (probability 0: the bounds are conservative, so no light that gives the point anything is
//! lost, and where no light reaches the point the descent returns `None` at the first node
//! that says so); the others get the branch probabilities of
//! [`super::importance::branch_probabilities`] with their map's value as importance and
//! their peak intensity `Σ p_i·g_i` as the defensive share. Picking stays unbiased whatever
//! the maps say, and every light with `c_i(x) > 0` keeps `P(i | x) > 0`. The layout depends
//! on positions and cones only, so new powers refit the tree (maps included) bit for bit. A
//! scene of point lights keeps the median layout and the representative-light importance,
//! bit for bit as before.

mod build;
mod cut_candidate;
mod cut_columns;
mod cut_growth;
mod cut_order;
mod cut_words;
mod dark_over;
mod descent;
mod fill;
mod footprint_split;
mod layout;
mod leaf_terms;
mod map_fill;
mod node;
mod prefetch;
mod tile_cut;

pub use node::{Child, ChildRef, LEAF_SIZE, TREE_WIDTH, TreeNode};
pub use tile_cut::{
    CUT_LARGE_TREE, CUT_MAX_ENTRIES, CUT_MAX_ENTRIES_LARGE, CUT_MAX_SPREAD,
    CUT_MAX_SPREAD_PROFILES, CUT_TILES_PER_SIDE, CUT_TREE_SHARE, TileCuts, tile_side_for,
};

use glam::DVec2;

use super::SpatialLight;
use super::grid::MappedLanes;
use crate::scene::{EmissionShape, ReceiverPlane};

/// What a tree over spots integrates its lanes' maps in, per light in leaf order.
#[derive(Clone, Debug, PartialEq)]
struct MapWeights {
    /// Each light's weight `w_i = Φ_i·2^-e` ([`crate::PmfScale::weight`]).
    weight: Vec<f64>,
    /// One bit per light, set by [`LightTree::refit`] where the light's weight changed (only
    /// the lanes over such lights are mapped again) and cleared once read.
    reweighed: Vec<u64>,
}

/// A light tree over the contributing lights of a scene; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTree {
    /// Internal nodes, depth first (empty when the root is a leaf cluster or empty).
    nodes: Vec<TreeNode>,
    /// Leaf-order index of each node's first light (what [`LightTree::pdf`] descends by).
    node_first: Vec<u32>,
    /// The contributing lights in leaf order.
    lights: Vec<SpatialLight>,
    /// Scene index of each light, in leaf order.
    order: Vec<u32>,
    /// Node 0, a single leaf cluster (at most [`LEAF_SIZE`] lights) or empty.
    root: ChildRef,
    /// Draws of the longest pick: nodes on the deepest path, plus the leaf's.
    depth: u32,
    /// Number of lights of the scene.
    n: usize,
    /// What the lights' emission factors are evaluated with, in leaf order (empty for point
    /// lights).
    emission: Vec<EmissionShape>,
    /// The region of the plane the lanes of spots are mapped over (`[min, max]`; `None` over
    /// point lights, and where lights whose footprint is unbounded are weighed by their
    /// representative light).
    region: Option<[DVec2; 2]>,
    /// Each node's lanes as the descent over spots reads them ([`super::grid`]; empty for
    /// point lights).
    mapped: Vec<MappedLanes>,
    /// The lights' weights the lanes' maps are integrated in (`None` for point lights).
    weights: Option<Box<MapWeights>>,
    /// The per-tile cuts a pick starts from on the receiver's rectangle ([`TileCuts`];
    /// `None`: every pick descends from the root).
    cuts: Option<Box<TileCuts>>,
}

impl LightTree {
    /// Node `k`'s lanes as the descent over spots reads them ([`super::grid`]), when the
    /// lights have emission profiles.
    pub fn mapped(&self, k: usize) -> Option<&MappedLanes> {
        self.mapped.get(k)
    }

    /// What the lights' emission factors are evaluated with ([`EmissionShape`]), in leaf
    /// order (empty for point lights).
    pub fn emission(&self) -> &[EmissionShape] {
        &self.emission
    }

    /// Where light `j` (leaf order) is mapped on the plane: its footprint
    /// ([`EmissionShape::footprint`]) within the region the lanes are mapped over, or the
    /// region for a light whose footprint is unbounded; `None` for a tree of point lights,
    /// and for such a light without a region (both reach every point). Computed when asked
    /// (a few dozen operations) rather than kept: 40 bytes a light.
    fn footprint(&self, j: usize) -> Option<[DVec2; 2]> {
        let shape = self.emission.get(j)?;
        let f = shape.footprint(self.lights[j].position_in_world);
        match (f, self.region) {
            (Some([a, b]), Some([lo, hi])) => Some([a.max(lo), b.min(hi)]),
            (None, Some(r)) => Some(r),
            (f, None) => f,
        }
    }

    /// The leaf-order index of the first light below `at` (`None` for an empty lane).
    fn first_of(&self, at: ChildRef) -> Option<usize> {
        match at.get() {
            Child::Node(k) => Some(self.node_first[k] as usize),
            Child::Leaf { first, .. } => Some(first),
            Child::Empty => None,
        }
    }

    /// Draws on the deepest path below `at` (one per node, one for the leaf).
    fn deepest(&self, at: ChildRef) -> u32 {
        match at.get() {
            Child::Node(k) => {
                1 + self.nodes[k]
                    .child
                    .iter()
                    .map(|&c| self.deepest(c))
                    .max()
                    .unwrap_or(0)
            }
            Child::Leaf { .. } => 1,
            Child::Empty => 0,
        }
    }

    /// The leaf-order index of internal node `k`'s first light.
    ///
    /// # Panics
    /// If `k` is not a node of the tree.
    pub fn node_first(&self, k: usize) -> usize {
        self.node_first[k] as usize
    }

    /// The lane of node `k` whose subtree holds the light of leaf-order index `j` (of the
    /// node's range): the last lane whose range starts at or before `j`.
    fn lane_holding(&self, k: usize, j: usize) -> usize {
        let node = &self.nodes[k];
        (0..TREE_WIDTH)
            .rev()
            .find(|&lane| self.first_of(node.child[lane]).is_some_and(|f| f <= j))
            .unwrap_or(0)
    }

    /// The depth of subtree `at` in the tree (the root's is 0): the lanes followed from the
    /// root down to it, by its first light. A tile's cut may hold part of a leaf cluster: a
    /// single light of it lies one below the cluster, a narrower range of its lights at the
    /// cluster's depth. `None` for an empty lane or a range no cluster holds.
    pub fn depth_of(&self, at: ChildRef) -> Option<usize> {
        let first = self.first_of(at)?;
        let (mut here, mut depth) = (self.root, 0);
        while here != at {
            match (here.get(), at.get()) {
                (Child::Node(k), _) => here = self.nodes[k].child[self.lane_holding(k, first)],
                (Child::Leaf { first: f, count }, Child::Leaf { count: c, .. }) => {
                    let within = f <= first && first + c <= f + count;
                    return within.then_some(depth + usize::from(c == 1));
                }
                _ => return None,
            }
            depth += 1;
        }
        Some(depth)
    }

    /// The leaf-order range of the lights below `at` (`None` for an empty lane): a leaf
    /// cluster's own lights, or for a node every light from its first to the end of its
    /// last non-empty lane. Subtrees are contiguous in leaf order, so this is all of them.
    pub fn span(&self, at: ChildRef) -> Option<std::ops::Range<usize>> {
        let first = self.first_of(at)?;
        let mut last = at;
        loop {
            match last.get() {
                Child::Node(k) => {
                    // A node holds lights, so some lane is not empty.
                    last = *self.nodes[k]
                        .child
                        .iter()
                        .rev()
                        .find(|c| c.get() != Child::Empty)?;
                }
                Child::Leaf { first: f, count } => return Some(first..f + count),
                Child::Empty => return None,
            }
        }
    }

    /// Number of lights of the scene.
    pub fn light_count(&self) -> usize {
        self.n
    }

    /// Heap bytes the tree holds, by capacity: per contributing light its position and
    /// normalized power in leaf order (32 bytes) and its scene index (4), per internal node
    /// 152 bytes (its lanes' representative lights and children, its reach) and its first
    /// light (4), and for lights with emission profiles what their factors are evaluated with
    /// (72 bytes, [`EmissionShape`]: not the profiles as given, and not their footprints,
    /// which the tree computes when it needs them), their weights (8 bytes,
    /// [`crate::PmfScale::weight`]) and each node's mapped lanes ([`MappedLanes`]: 392
    /// bytes, a 16 × 16 map of 256 bytes for each lane holding lights, and 544 bytes more
    /// for a node with an unbounded lane, [`super::UnboundedLanes`]): for 10^6 point lights
    /// (87 381 nodes of mostly two to four leaf clusters) about 50 bytes per light, for 10^5
    /// spots over the unit square about 255.
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.capacity() * size_of::<TreeNode>()
            + self.node_first.capacity() * size_of::<u32>()
            + self.lights.capacity() * size_of::<SpatialLight>()
            + self.order.capacity() * size_of::<u32>()
            + self.emission.capacity() * size_of::<EmissionShape>()
            + self.mapped.capacity() * size_of::<MappedLanes>()
            + self
                .mapped
                .iter()
                .map(MappedLanes::heap_bytes)
                .sum::<usize>()
            + self.weights.as_ref().map_or(0, |w| {
                size_of::<MapWeights>()
                    + w.weight.capacity() * size_of::<f64>()
                    + w.reweighed.capacity() * size_of::<u64>()
            })
            + self
                .cuts
                .as_ref()
                .map_or(0, |c| size_of::<TileCuts>() + c.heap_bytes())
    }

    /// The tree with per-tile cuts over `plane`'s pixel grid ([`TileCuts`]): picks on the
    /// plane's rectangle start at the entry their tile's cut draws instead of the root. A
    /// tree whose root is a leaf cluster keeps none.
    #[must_use]
    pub fn with_tile_cuts(mut self, plane: &ReceiverPlane) -> Self {
        self.cuts = TileCuts::build(&self, plane).map(Box::new);
        self
    }

    /// The tree with the given per-tile cuts (`None`: every pick descends from the root);
    /// `cuts` must have been built over this tree ([`TileCuts::build_sized`]).
    #[must_use]
    pub fn with_cuts(mut self, cuts: Option<TileCuts>) -> Self {
        self.cuts = cuts.map(Box::new);
        self
    }

    /// The per-tile cuts picks start from, if any.
    pub fn tile_cuts(&self) -> Option<&TileCuts> {
        self.cuts.as_deref()
    }

    /// The cuts and the tile a pick at `point_on_plane` starts from; `None` when the tree
    /// has no cuts or the point lies off them (the pick starts at the root).
    #[inline]
    pub fn cut_tile_at(&self, point_on_plane: DVec2) -> Option<(&TileCuts, usize)> {
        let cuts = self.cuts.as_deref()?;
        Some((cuts, cuts.tile_at(point_on_plane)?))
    }

    /// The internal nodes, depth first.
    pub fn nodes(&self) -> &[TreeNode] {
        &self.nodes
    }

    /// The contributing lights, in leaf order.
    pub fn lights(&self) -> &[SpatialLight] {
        &self.lights
    }

    /// The scene index of each light, in leaf order.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The root: node 0, a single leaf cluster, or empty (no contributing light).
    pub fn root(&self) -> ChildRef {
        self.root
    }

    /// The tree's levels: internal nodes on the deepest path, plus one for the leaf
    /// cluster (the most draws a pick from the root takes).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The most draws a pick takes, and so the most grid factors its pdf multiplies: the
    /// tree's [`LightTree::depth`], plus one for the tile's cut when the tree has cuts.
    pub fn draws(&self) -> u32 {
        self.depth + u32::from(self.cuts.is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::layout::{internal_nodes, parts};
    use super::*;

    #[test]
    fn child_words_round_trip() {
        assert_eq!(ChildRef::node(12).get(), Child::Node(12));
        assert_eq!(
            ChildRef::leaf(1 << 26, 8).get(),
            Child::Leaf {
                first: 1 << 26,
                count: 8
            }
        );
        assert_eq!(ChildRef::EMPTY.get(), Child::Empty);
    }

    #[test]
    fn a_single_lights_leaf_takes_the_grid_as_the_rule_for_many_does() {
        // The leaf of one light shortcuts the grid rule (module `descent`): the whole grid
        // for a finite positive contribution, none for 0, ∞ or NaN. The rule itself, on
        // the normalized share `c·(1/c)`, at the extremes of f64.
        use crate::spatial::importance::{GRID, grid_masses};
        let share = |c: f64| {
            let mut p = [0.0; LEAF_SIZE];
            if c > 0.0 {
                p[0] = c * (1.0 / c);
            }
            grid_masses(p)[0]
        };
        for c in [
            f64::from_bits(1),
            1e-310,
            f64::MIN_POSITIVE,
            1e-200,
            0.3,
            1.0,
            1e300,
            f64::MAX,
        ] {
            assert_eq!(share(c), GRID, "c = {c:e}");
        }
        for c in [0.0, f64::INFINITY, f64::NAN] {
            assert_eq!(share(c), 0, "c = {c}");
        }
        // The shortcut itself on a tree's lights, one of them so near the point that its
        // contribution overflows to ∞, one so far that it is tiny.
        let positions = [
            glam::dvec3(0.0, 0.0, 1e-160),
            glam::dvec3(1e100, 0.0, 1.0),
            glam::dvec3(0.5, 0.5, 1.0),
        ];
        let mut all = positions.to_vec();
        all.extend((0..20).map(|i| glam::dvec3(f64::from(i), 1.0, 2.0)));
        let powers = crate::powers::LightPowers::new(vec![1.0; all.len()]).expect("powers");
        let tree = LightTree::build(&all, &powers);
        for j in 0..all.len() {
            let (masses, c) = tree.leaf_masses_at(j, 1, DVec2::ZERO);
            assert_eq!(masses[0], share(c[0]), "light {j}: c = {:e}", c[0]);
        }
        let contributions: Vec<f64> = (0..all.len())
            .map(|j| tree.leaf_masses_at(j, 1, DVec2::ZERO).1[0])
            .collect();
        assert!(contributions.iter().any(|c| c.is_infinite()));
        assert!(contributions.iter().any(|&c| c > 0.0 && c < 1e-200));
    }

    #[test]
    fn a_leafs_contributions_are_each_lights_own_bit_for_bit() {
        // The leaf evaluates its point lights together over all eight lanes: each must be
        // exactly `SpatialLight::contribution`, at ordinary points and where `r³`
        // underflows (a light 10^-160 above the point), overflows, or the light is far.
        let mut all = vec![
            glam::dvec3(0.0, 0.0, 1e-160),
            glam::dvec3(1e100, 0.0, 1.0),
            glam::dvec3(0.5, 0.5, 1e-120),
            glam::dvec3(-3.0, 2.0, 1e200),
        ];
        all.extend((0..40).map(|i| glam::dvec3(f64::from(i % 7), f64::from(i / 7), 0.3)));
        let powers: Vec<f64> = (0..all.len()).map(|i| 1.0 + f64::from(i as u32)).collect();
        let powers = crate::powers::LightPowers::new(powers).expect("powers");
        let tree = LightTree::build(&all, &powers);
        let points = [DVec2::ZERO, DVec2::new(0.5, 0.5), DVec2::new(2.3, -1.7)];
        for x in points {
            for first in 0..all.len() {
                for count in 1..=LEAF_SIZE.min(all.len() - first) {
                    let (_, c) = tree.leaf_masses_at(first, count, x);
                    for (j, cj) in c.iter().enumerate() {
                        let own = if j < count {
                            tree.lights()[first + j].contribution(x)
                        } else {
                            0.0
                        };
                        assert_eq!(cj.to_bits(), own.to_bits(), "{first}+{j} of {count} at {x}");
                    }
                }
            }
        }
    }

    #[test]
    fn parts_cover_the_range_and_node_counts_match_the_layout() {
        for m in [9, 10, 16, 17, 33, 100, 1000, 12345] {
            let p = parts(m);
            assert_eq!(p.iter().sum::<usize>(), m);
            assert!(p.iter().filter(|&&s| s > 0).count() >= 2);
        }
        assert_eq!(internal_nodes(8), 0);
        assert_eq!(internal_nodes(9), 1);
        assert_eq!(internal_nodes(32), 1);
        assert_eq!(internal_nodes(33), 1 + 1);
    }
}
