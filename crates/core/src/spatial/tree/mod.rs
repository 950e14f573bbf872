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
//! tree this replaced), then one pick inside the leaf.
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
//! keeps a [`LaneBounds`] (pbrt-v4's `LightBounds`: the box of its lights, the cone of their
//! spot axes, their widest outer cone and longest range, the box of their footprints) and a
//! map of what its lights give the plane ([`super::grid`]: the mean irradiance per cell of a
//! 16 × 16 raster over its footprints). At a point, a lane whose bounds exclude it is culled
//! (probability 0: the bounds are conservative, so no light that gives the point anything is
//! lost, and where no light reaches the point the descent returns `None` at the first node
//! that says so); the others get the branch probabilities of
//! [`super::importance::branch_probabilities`] with their map's value as importance and
//! their peak intensity `Σ p_i·g_i` as the defensive share. Picking stays unbiased whatever
//! the maps say, and every light with `c_i(x) > 0` keeps `P(i | x) > 0`. The layout depends
//! on positions and cones only, so new powers refit the tree (maps included) bit for bit. A
//! scene of point lights keeps the median layout and the representative-light importance,
//! bit for bit as before.

use glam::{DVec2, DVec3};

use super::importance::{
    GRID_CELL, IMPORTANCE_CAP, branch_probabilities, grid_masses, lane_importances, pick_on_grid,
};
mod fill;
mod footprint_split;
mod layout;

use super::bounds::LaneBounds;
use super::grid::{LaneGrid, MappedLanes};
use super::{SpatialLight, SpatialPick, contributing};
use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::scene::Emission;

/// Children per internal node.
pub const TREE_WIDTH: usize = 4;

/// The most lights in a leaf cluster, picked by their exact contributions.
pub const LEAF_SIZE: usize = 8;

/// What a child lane of a node holds, in one `u32` (the word the GPU reads too): an internal
/// node's index (bit 31 clear), or a leaf cluster `1 << 31 | count << 27 | first` (its
/// `count ≤ 8` lights from leaf-order index `first < 2^27`); an empty lane is the leaf
/// cluster of no lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChildRef(u32);

/// A [`ChildRef`] decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Child {
    /// An internal node, by index.
    Node(usize),
    /// A leaf cluster: lights `first .. first + count` in leaf order.
    Leaf {
        /// Leaf-order index of its first light.
        first: usize,
        /// Its number of lights, `1 ..=` [`LEAF_SIZE`].
        count: usize,
    },
    /// No child.
    Empty,
}

impl ChildRef {
    const LEAF_BIT: u32 = 1 << 31;
    const COUNT_SHIFT: u32 = 27;
    const FIRST_MASK: u32 = (1 << Self::COUNT_SHIFT) - 1;

    /// An empty lane.
    pub const EMPTY: ChildRef = ChildRef(Self::LEAF_BIT);

    /// The internal node `index` (`< 2^31`).
    fn node(index: usize) -> Self {
        debug_assert!(index < Self::LEAF_BIT as usize);
        ChildRef(index as u32)
    }

    /// The leaf cluster of `count` lights from `first` (`count ≤ 8`, `first < 2^27`).
    fn leaf(first: usize, count: usize) -> Self {
        debug_assert!(count <= LEAF_SIZE && first <= Self::FIRST_MASK as usize);
        ChildRef(Self::LEAF_BIT | (count as u32) << Self::COUNT_SHIFT | first as u32)
    }

    /// What the lane holds.
    #[inline]
    pub fn get(self) -> Child {
        if self.0 & Self::LEAF_BIT == 0 {
            return Child::Node(self.0 as usize);
        }
        let count = ((self.0 & !Self::LEAF_BIT) >> Self::COUNT_SHIFT) as usize;
        if count == 0 {
            Child::Empty
        } else {
            Child::Leaf {
                first: (self.0 & Self::FIRST_MASK) as usize,
                count,
            }
        }
    }

    /// The encoded word (uploaded as is to the GPU).
    pub fn bits(self) -> u32 {
        self.0
    }
}

/// An internal node: per child lane, the representative light (power-weighted centroid and
/// total normalized power of the child's lights) and what the lane holds. The centroids are
/// stored by coordinate (one array of the four lanes' `x`, one of `y`, one of `z`), so that
/// the four importances evaluate together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeNode {
    /// `c = Σ p_i·y_i / Σ p_i` of each lane's lights, in the world (clamped into the
    /// child's box, so `c_z > 0`), as `[x; 4], [y; 4], [z; 4]`; `(0, 0, 1)` in empty lanes.
    centroid: [[f64; TREE_WIDTH]; 3],
    /// `Φ_c = Σ p_i` of each lane's lights (0 for an empty lane).
    power: [f64; TREE_WIDTH],
    /// Each lane's child.
    child: [ChildRef; TREE_WIDTH],
}

impl TreeNode {
    const EMPTY: TreeNode = TreeNode {
        centroid: [[0.0; TREE_WIDTH], [0.0; TREE_WIDTH], [1.0; TREE_WIDTH]],
        power: [0.0; TREE_WIDTH],
        child: [ChildRef::EMPTY; TREE_WIDTH],
    };

    /// The power-weighted centroid of lane `lane`'s lights, in the world.
    pub fn centroid(&self, lane: usize) -> DVec3 {
        let [x, y, z] = &self.centroid;
        DVec3::new(x[lane], y[lane], z[lane])
    }

    /// `Φ_c = Σ p_i` of lane `lane`'s lights (0 for an empty lane).
    pub fn power(&self, lane: usize) -> f64 {
        self.power[lane]
    }

    /// What lane `lane` holds.
    pub fn child(&self, lane: usize) -> ChildRef {
        self.child[lane]
    }

    /// The grid masses of the four lanes at `point_on_plane` for point lights (summing to
    /// `2^24`, or all 0 when no lane has power).
    #[inline]
    pub fn masses(&self, point_on_plane: DVec2) -> [u32; TREE_WIDTH] {
        let [x, y, z] = &self.centroid;
        let importance = lane_importances([x, y, z], &self.power, point_on_plane);
        grid_masses(branch_probabilities(importance, self.power))
    }

    /// The grid masses of four lanes of lights with emission profiles at `point_on_plane`:
    /// a lane whose bounds exclude the point gets none; the others are weighed by their
    /// maps, mixed with their shares of peak intensity `Σ p_i·g_i`
    /// ([`MappedLanes::weights`], [`branch_probabilities`]). All zero when every lane is
    /// culled.
    #[inline]
    pub fn masses_mapped(
        bounds: &[LaneBounds; TREE_WIDTH],
        mapped: &MappedLanes,
        point_on_plane: DVec2,
    ) -> [u32; TREE_WIDTH] {
        let (importance, share) = mapped.weights(bounds, point_on_plane);
        grid_masses(branch_probabilities(
            importance.map(|i| i.min(IMPORTANCE_CAP)),
            share,
        ))
    }
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
    /// The lights' emission profiles in leaf order (empty for point lights).
    emission: Vec<Emission>,
    /// Each node's lane bounds (empty for point lights).
    bounds: Vec<[LaneBounds; TREE_WIDTH]>,
    /// Where each light is mapped on the plane, in leaf order: its footprint
    /// ([`Emission::footprint`]) within the region of interest, or the region for a light
    /// whose footprint is unbounded (`None` without a region); empty for point lights.
    footprints: Vec<Option<[DVec2; 2]>>,
    /// Each node's lanes as the descent over spots reads them ([`super::grid`]; empty for
    /// point lights).
    mapped: Vec<MappedLanes>,
}

impl LightTree {
    /// Builds the tree over the lights with `z_i > 0` (`O(N log N)`, large subtrees in
    /// parallel; the result does not depend on the thread count). Lights of power 0 are in
    /// the tree (so that new powers keep its layout) but never picked: their lanes and
    /// leaf masses are 0.
    ///
    /// # Panics
    /// If `positions` and `powers` have different lengths, or the scene holds more than
    /// `2^27` lights.
    pub fn build(positions: &[DVec3], powers: &LightPowers) -> Self {
        Self::build_with_emission(positions, powers, None)
    }

    /// [`LightTree::build`] for lights with emission profiles (`None`: point lights), with
    /// each node's lane bounds.
    ///
    /// # Panics
    /// As [`LightTree::build`], or if the profiles' count differs.
    pub fn build_with_emission(
        positions: &[DVec3],
        powers: &LightPowers,
        emission: Option<&[Emission]>,
    ) -> Self {
        Self::build_over(positions, powers, emission, None)
    }

    /// [`LightTree::build_with_emission`] with lanes of spots mapped over `region` of the
    /// plane (`[min, max]`, the receiver's rectangle: [`super::grid`]): each light's
    /// footprint within it, and there too the lights whose footprint is unbounded (without a
    /// region, those are weighed as one representative light per lane). Picks stay unbiased
    /// everywhere; outside the region they are as good as the lanes' bounds make them.
    ///
    /// # Panics
    /// As [`LightTree::build_with_emission`].
    pub fn build_over(
        positions: &[DVec3],
        powers: &LightPowers,
        emission: Option<&[Emission]>,
        region: Option<[DVec2; 2]>,
    ) -> Self {
        // Every light that can reach the plane, whatever its power: the layout depends on
        // the positions (and cones) only, so that new powers refit it ([`LightTree::refit`]).
        let contributing = contributing(positions, powers, emission, true);
        let m = contributing.len();
        assert!(m < 1 << 27, "at most 2^27 lights");
        let (nodes, node_first, order, root) = match emission {
            // Spots and ranges: split by where the lights shine.
            Some(e) if m > LEAF_SIZE => {
                let mut items: Vec<footprint_split::Footprinted> = contributing
                    .iter()
                    .map(|(i, l, _)| {
                        footprint_split::Footprinted::new(*i, l.position_in_world, &e[*i as usize])
                    })
                    .collect();
                let (nodes, node_first) = footprint_split::lay_out(&mut items);
                let order = items.iter().map(|l| l.index).collect();
                (nodes, node_first, order, ChildRef::node(0))
            }
            _ => {
                let mut items: Vec<layout::Item> = contributing
                    .iter()
                    .map(|(i, l, _)| (*i, l.position_in_world))
                    .collect();
                let node_count = layout::internal_nodes(m);
                let mut nodes = vec![TreeNode::EMPTY; node_count];
                let mut node_first = vec![0u32; node_count];
                let root = if m == 0 {
                    ChildRef::EMPTY
                } else if m <= LEAF_SIZE {
                    ChildRef::leaf(0, m)
                } else {
                    layout::lay_out(layout::Job {
                        items: &mut items,
                        index: 0,
                        first: 0,
                        nodes: &mut nodes,
                        node_first: &mut node_first,
                    });
                    ChildRef::node(0)
                };
                let order: Vec<u32> = items.iter().map(|(i, _)| *i).collect();
                (nodes, node_first, order, root)
            }
        };
        let node_count = nodes.len();
        let pmf = powers.pmf();
        let lights = order
            .iter()
            .map(|&i| SpatialLight {
                position_in_world: positions[i as usize],
                power: pmf[i as usize],
            })
            .collect();
        let mut tree = Self {
            nodes,
            node_first,
            lights,
            root,
            depth: 0,
            n: positions.len(),
            emission: emission
                .map_or_else(Vec::new, |e| order.iter().map(|&i| e[i as usize]).collect()),
            bounds: if emission.is_some() {
                vec![[LaneBounds::EMPTY; TREE_WIDTH]; node_count]
            } else {
                Vec::new()
            },
            footprints: emission.map_or_else(Vec::new, |e| {
                order
                    .iter()
                    .map(|&i| {
                        let f = e[i as usize].footprint(positions[i as usize]);
                        match (f, region) {
                            (Some([a, b]), Some([lo, hi])) => Some([a.max(lo), b.min(hi)]),
                            (None, Some(r)) => Some(r),
                            (f, None) => f,
                        }
                    })
                    .collect()
            }),
            mapped: Vec::new(),
            order,
        };
        tree.depth = tree.deepest(tree.root);
        tree.fill_lanes();
        tree
    }

    /// Recomputes every lane's power, centroid and bounds from the lights, bottom up.
    fn fill_lanes(&mut self) {
        if self.nodes.is_empty() {
            return;
        }
        let emission = (!self.emission.is_empty()).then_some(self.emission.as_slice());
        let bounds = (!self.bounds.is_empty()).then_some(self.bounds.as_mut_slice());
        let job = fill::Fill {
            nodes: &mut self.nodes,
            bounds,
            index: 0,
        };
        if emission.is_some() {
            fill::fill::<fill::Bounded>(job, &self.lights, emission);
            self.fill_grids();
        } else {
            fill::fill::<fill::Aggregate>(job, &self.lights, None);
        }
    }

    /// Recomputes every lane's map ([`super::grid`]) from its lights, nodes in parallel
    /// (each map depends on its own lights only: the same bits on any thread count).
    fn fill_grids(&mut self) {
        use rayon::prelude::*;
        let ranges = self.lane_ranges();
        let (lights, emission, footprints) = (&self.lights, &self.emission, &self.footprints);
        let mut mapped = std::mem::take(&mut self.mapped);
        mapped.resize(self.nodes.len(), MappedLanes::EMPTY);
        mapped
            .par_iter_mut()
            .zip(ranges.par_iter())
            .zip(self.bounds.par_iter())
            .with_max_len(1)
            .for_each(|((node, lanes), bounds)| {
                let grids: [LaneGrid; TREE_WIDTH] = std::array::from_fn(|k| {
                    let (first, count) = lanes[k];
                    let r = first as usize..(first + count) as usize;
                    if count == 0 {
                        LaneGrid::EMPTY
                    } else {
                        LaneGrid::of_lights(
                            &lights[r.clone()],
                            &emission[r.clone()],
                            &footprints[r],
                        )
                    }
                });
                *node = MappedLanes::new(bounds, &grids);
            });
        self.mapped = mapped;
    }

    /// Each node's lanes' lights as `(first, count)` in leaf order, top down.
    fn lane_ranges(&self) -> Vec<[(u32, u32); TREE_WIDTH]> {
        let mut ranges = vec![[(0u32, 0u32); TREE_WIDTH]; self.nodes.len()];
        if self.nodes.is_empty() {
            return ranges;
        }
        // (node, end of its lights)
        let mut stack = vec![(0usize, self.lights.len())];
        while let Some((k, end)) = stack.pop() {
            let node = &self.nodes[k];
            for (lane, range) in ranges[k].iter_mut().enumerate() {
                let Some(first) = self.first_of(node.child[lane]) else {
                    continue;
                };
                let lane_end = (lane + 1..TREE_WIDTH)
                    .find_map(|next| self.first_of(node.child[next]))
                    .unwrap_or(end);
                *range = (first as u32, (lane_end - first) as u32);
                if let Child::Node(j) = node.child[lane].get() {
                    stack.push((j, lane_end));
                }
            }
        }
        ranges
    }

    /// New powers for the same lights (same positions, cones and ranges): each light's
    /// normalized power is replaced and every lane recomputed bottom up, `O(N)`, in
    /// parallel, without allocating; the tree then equals [`LightTree::build`] over the new
    /// powers bit for bit (the layout depends on positions only, and both fill the lanes
    /// with the same pass).
    ///
    /// # Panics
    /// If `powers` holds a different number of lights.
    pub fn refit(&mut self, powers: &LightPowers) {
        use rayon::prelude::*;
        assert_eq!(powers.len(), self.n, "one power per light of the tree");
        let raw = powers.as_slice();
        let pmf = powers.pmf_scale();
        // Each light's new share is a function of its own power: any split gives the same.
        self.lights
            .par_iter_mut()
            .zip(self.order.par_iter())
            .with_min_len(1 << 14)
            .for_each(|(l, &i)| l.power = pmf.of(raw[i as usize]));
        self.fill_lanes();
    }

    /// The grid masses of node `k`'s lanes at `x` (with its lane bounds when the lights
    /// have emission profiles).
    #[inline]
    fn node_masses(&self, k: usize, x: DVec2) -> [u32; TREE_WIDTH] {
        match (self.bounds.get(k), self.mapped.get(k)) {
            (Some(bounds), Some(mapped)) => TreeNode::masses_mapped(bounds, mapped, x),
            _ => self.nodes[k].masses(x),
        }
    }

    /// Node `k`'s lane bounds, when the lights have emission profiles.
    pub fn bounds(&self, k: usize) -> Option<&[LaneBounds; TREE_WIDTH]> {
        self.bounds.get(k)
    }

    /// Node `k`'s lanes as the descent over spots reads them ([`super::grid`]), when the
    /// lights have emission profiles.
    pub fn mapped(&self, k: usize) -> Option<&MappedLanes> {
        self.mapped.get(k)
    }

    /// The emission profiles in leaf order (empty for point lights).
    pub fn emission(&self) -> &[Emission] {
        &self.emission
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

    /// Number of lights of the scene.
    pub fn light_count(&self) -> usize {
        self.n
    }

    /// Heap bytes the tree holds, by capacity: per contributing light its position and
    /// normalized power in leaf order (32 bytes) and its scene index (4), per internal node
    /// 144 bytes and its first light (4), and for lights with emission profiles those
    /// profiles and each node's lane bounds: for 10^6 point lights (87 381 nodes of mostly
    /// two to four leaf clusters) about 49 bytes per light.
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.nodes.capacity() * size_of::<TreeNode>()
            + self.node_first.capacity() * size_of::<u32>()
            + self.lights.capacity() * size_of::<SpatialLight>()
            + self.order.capacity() * size_of::<u32>()
            + self.emission.capacity() * size_of::<Emission>()
            + self.bounds.capacity() * size_of::<[LaneBounds; TREE_WIDTH]>()
            + self.footprints.capacity() * size_of::<Option<[DVec2; 2]>>()
            + self.mapped.capacity() * size_of::<MappedLanes>()
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

    /// The most draws a pick takes: internal nodes on the deepest path, plus one for the
    /// leaf cluster.
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The grid masses of the lights `first .. first + count` of a leaf cluster at `x`, by
    /// their contributions `c_j = p_j·G_j(x)`, and the contributions themselves.
    #[inline]
    fn leaf_masses(
        &self,
        first: usize,
        count: usize,
        x: DVec2,
    ) -> ([u32; LEAF_SIZE], [f64; LEAF_SIZE]) {
        let mut c = [0.0; LEAF_SIZE];
        let mut total = 0.0;
        for (j, cj) in c.iter_mut().enumerate().take(count) {
            *cj = self.lights[first + j].contribution_with(self.emission.get(first + j), x);
            total += *cj;
        }
        let mut p = [0.0; LEAF_SIZE];
        if total > 0.0 {
            let inv = 1.0 / total;
            for (pj, &cj) in p.iter_mut().zip(&c) {
                *pj = cj * inv;
            }
        }
        (grid_masses(p), c)
    }

    /// Descends from the root with one draw per node and one in the leaf cluster; `None`
    /// when there is no contributing light or every contribution of the leaf reached is 0
    /// (then `ê = 0`).
    #[inline]
    pub fn sample(&self, x: DVec2, rng: &mut Rng) -> Option<SpatialPick> {
        let (mut at, mut pdf) = (self.root, 1.0);
        while let Child::Node(k) = at.get() {
            at = self.step(k, x, rng, &mut pdf);
        }
        self.pick_in_leaf(at, x, rng, pdf)
    }

    /// [`LightTree::sample`] at `B` points at once, each from its own stream: the descents
    /// advance in lockstep, so that their node and light loads (cache misses among a million
    /// lights) are independent and overlap. Pick `b` is exactly `sample(points[b], rngs[b])`,
    /// with the same draws.
    #[inline]
    pub fn sample_many<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
    ) -> [Option<SpatialPick>; B] {
        let (mut at, mut pdf) = ([self.root; B], [1.0; B]);
        loop {
            let mut descending = false;
            for b in 0..B {
                if let Child::Node(k) = at[b].get() {
                    at[b] = self.step(k, points[b], &mut rngs[b], &mut pdf[b]);
                    descending = true;
                }
            }
            if !descending {
                break;
            }
        }
        std::array::from_fn(|b| self.pick_in_leaf(at[b], points[b], &mut rngs[b], pdf[b]))
    }

    /// One level of the descent: node `k`'s lane picked by the next draw, its grid
    /// probability multiplied into `pdf`; returns the lane's child.
    #[inline]
    fn step(&self, k: usize, x: DVec2, rng: &mut Rng, pdf: &mut f64) -> ChildRef {
        let masses = self.node_masses(k, x);
        let lane = pick_on_grid(&masses, rng.next_u32() >> 8);
        *pdf *= f64::from(masses[lane]) * GRID_CELL;
        self.nodes[k].child[lane]
    }

    /// The end of a descent at `at` (a leaf cluster, or the empty root) with the path's
    /// probability `pdf`: a light of the cluster by the next draw, by its contribution.
    #[inline]
    fn pick_in_leaf(&self, at: ChildRef, x: DVec2, rng: &mut Rng, pdf: f64) -> Option<SpatialPick> {
        let Child::Leaf { first, count } = at.get() else {
            return None;
        };
        let (masses, c) = self.leaf_masses(first, count, x);
        let j = pick_on_grid(&masses[..count], rng.next_u32() >> 8);
        let pdf = pdf * (f64::from(masses[j]) * GRID_CELL);
        (c[j] > 0.0 && pdf > 0.0).then(|| SpatialPick {
            light: self.order[first + j],
            pdf,
            estimate: c[j] / pdf,
        })
    }

    /// `P(i | x)` of every light of the scene at once, indexed by scene index (0 for a light
    /// outside the tree): one traversal with the masses of [`LightTree::sample`], `O(N)`.
    pub fn pdfs(&self, x: DVec2) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        let mut stack = vec![(self.root, 1.0f64)];
        while let Some((at, pdf)) = stack.pop() {
            match at.get() {
                Child::Node(k) => {
                    let node = &self.nodes[k];
                    for (lane, &m) in self.node_masses(k, x).iter().enumerate() {
                        if m > 0 {
                            stack.push((node.child[lane], pdf * (f64::from(m) * GRID_CELL)));
                        }
                    }
                }
                Child::Leaf { first, count } => {
                    let (masses, _) = self.leaf_masses(first, count, x);
                    for (j, &m) in masses[..count].iter().enumerate() {
                        out[self.order[first + j] as usize] = pdf * (f64::from(m) * GRID_CELL);
                    }
                }
                Child::Empty => {}
            }
        }
        out
    }

    /// `P(i | x)`: the product of the realized factors on the path to light `i` (0 for a
    /// light outside the tree). `O(N)` to find the light: meant for tests and single lights.
    pub fn pdf(&self, x: DVec2, light: usize) -> f64 {
        let Some(j) = self.order.iter().position(|&i| i as usize == light) else {
            return 0.0;
        };
        let mut at = self.root;
        let mut pdf = 1.0;
        loop {
            match at.get() {
                Child::Node(k) => {
                    let node = &self.nodes[k];
                    let masses = self.node_masses(k, x);
                    // The last lane whose range starts at or before j holds it.
                    let lane = (0..TREE_WIDTH)
                        .rev()
                        .find(|&lane| self.first_of(node.child[lane]).is_some_and(|f| f <= j))
                        .unwrap_or(0);
                    pdf *= f64::from(masses[lane]) * GRID_CELL;
                    at = node.child[lane];
                }
                Child::Leaf { first, count } => {
                    let (masses, _) = self.leaf_masses(first, count, x);
                    return pdf * (f64::from(masses[j - first]) * GRID_CELL);
                }
                Child::Empty => return 0.0,
            }
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
