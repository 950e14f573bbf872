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
//! about 4.4·10^4 nodes, 3.5 bytes per light.
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
//! # Spots and ranges: lane bounds
//! Over lights with emission profiles each lane also keeps a [`LaneBounds`] (pbrt-v4's
//! `LightBounds`): the box of its lights, the cone of their spot axes, their widest outer
//! cone and longest range, and their power weighted by each spot's on-axis gain. A lane's
//! importance is then that intensity at the representative centroid, `Σ p_i·g_i · G(c, x)`,
//! times [`LaneBounds::reach`]: 0 where no light of the lane can light `x` (beyond every
//! range, or outside every cone wherever in the box the light is), else 1. The mixture's
//! power share still reaches every lane with power, so a bound that rounds the wrong way
//! costs variance, never bias. A scene of point lights keeps no bounds and evaluates the
//! importance as before, bit for bit.

use glam::{DQuat, DVec2, DVec3};

use super::importance::{
    GRID_CELL, branch_probabilities, grid_masses, lane_importances, pick_on_grid,
};
use super::{SpatialLight, SpatialPick, contributing};
use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::scene::Emission;

/// Children per internal node.
pub const TREE_WIDTH: usize = 4;

/// The most lights in a leaf cluster, picked by their exact contributions.
pub const LEAF_SIZE: usize = 8;

/// Ranges of more lights than this build their subtrees in parallel.
const PARALLEL_BUILD: usize = 1 << 13;

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

    /// The grid masses with lane bounds (lights with emission profiles): each lane's
    /// importance is its intensity at the centroid times its reach at `point_on_plane`.
    #[inline]
    pub fn masses_bounded(
        &self,
        bounds: &[LaneBounds; TREE_WIDTH],
        point_on_plane: DVec2,
    ) -> [u32; TREE_WIDTH] {
        let [x, y, z] = &self.centroid;
        let intensity = bounds.map(|b| b.intensity);
        let mut importance = lane_importances([x, y, z], &intensity, point_on_plane);
        for (i, b) in importance.iter_mut().zip(bounds) {
            *i *= b.reach(point_on_plane);
        }
        grid_masses(branch_probabilities(importance, self.power))
    }
}

/// What the lights of a tree lane can do at most, for lights with emission profiles
/// (pbrt-v4's `LightBounds`; the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneBounds {
    /// The box of the lane's light positions, in the world.
    pub min: DVec3,
    /// See [`LaneBounds::min`].
    pub max: DVec3,
    /// `Σ p_i·g_i`: the lane's normalized power weighted by each light's on-axis gain
    /// ([`Emission::gain`]; 1 for a light without a spot).
    pub intensity: f64,
    /// The axis of the cone that holds every light's spot axis.
    pub axis: DVec3,
    /// `cos θo` of that cone's half-angle; −1 (any direction) when some light is not a spot.
    pub cos_spread: f64,
    /// `cos θe` of the widest outer cone; −1 when some light is not a spot.
    pub cos_emission: f64,
    /// The longest range; `∞` when some light has none.
    pub range: f64,
}

impl LaneBounds {
    /// An empty lane's bounds (no light: no intensity, reaches nothing).
    pub const EMPTY: LaneBounds = LaneBounds {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
        intensity: 0.0,
        axis: DVec3::Z,
        cos_spread: 1.0,
        cos_emission: 1.0,
        range: 0.0,
    };

    /// The bounds of one light.
    pub fn of_light(light: &SpatialLight, emission: &Emission) -> Self {
        let (axis, cos_spread, cos_emission) = match emission.spot() {
            Some(_) => (emission.axis(), 1.0, emission.cos_outer()),
            None => (DVec3::Z, -1.0, -1.0),
        };
        LaneBounds {
            min: light.position_in_world,
            max: light.position_in_world,
            intensity: light.power * emission.gain(),
            axis,
            cos_spread,
            cos_emission,
            range: emission.range().unwrap_or(f64::INFINITY),
        }
    }

    /// The bounds of the lights of `a` and of `b` together.
    pub fn union(a: &LaneBounds, b: &LaneBounds) -> Self {
        if a.intensity == 0.0 && a.min.x > a.max.x {
            return *b;
        }
        if b.intensity == 0.0 && b.min.x > b.max.x {
            return *a;
        }
        let (axis, cos_spread) = cone_union((a.axis, a.cos_spread), (b.axis, b.cos_spread));
        LaneBounds {
            min: a.min.min(b.min),
            max: a.max.max(b.max),
            intensity: a.intensity + b.intensity,
            axis,
            cos_spread,
            cos_emission: a.cos_emission.min(b.cos_emission),
            range: a.range.max(b.range),
        }
    }

    /// 0 when no light of the lane can light `point_on_plane`, else 1: beyond the longest
    /// range from the box, or outside every cone: with `θw` the angle between the cone's
    /// axis and the direction from the box's centre to the point, `θb` the half-angle the
    /// box's bounding sphere subtends there (π inside it), no light direction within `θo` of
    /// the axis comes within `θe` of the point's direction when `max(0, θw − θo − θb) ≥ θe`
    /// (pbrt-v4's `LightBounds::Importance`, its cosines composed without inverse
    /// trigonometry).
    #[inline]
    pub fn reach(&self, point_on_plane: DVec2) -> f64 {
        let p = point_on_plane.extend(0.0);
        let outside = (self.min - p).max(p - self.max).max(DVec3::ZERO);
        if outside.length_squared() >= self.range * self.range {
            return 0.0;
        }
        if self.cos_spread <= -1.0 || self.cos_emission <= -1.0 {
            return 1.0;
        }
        let centre = 0.5 * (self.min + self.max);
        let radius2 = 0.25 * (self.max - self.min).length_squared();
        let to_point = p - centre;
        let d2 = to_point.length_squared();
        if d2 <= radius2 {
            return 1.0;
        }
        let d = d2.sqrt();
        let cos_w = (self.axis.dot(to_point) / d).clamp(-1.0, 1.0);
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let sin_spread = (1.0 - self.cos_spread * self.cos_spread).max(0.0).sqrt();
        let sin2_b = radius2 / d2;
        let cos_b = (1.0 - sin2_b).max(0.0).sqrt();
        let sin_b = sin2_b.sqrt();
        // θx = max(0, θw − θo), then θp = max(0, θx − θb).
        let (cos_x, sin_x) = cos_sin_sub_clamped((cos_w, sin_w), (self.cos_spread, sin_spread));
        let (cos_p, _) = cos_sin_sub_clamped((cos_x, sin_x), (cos_b, sin_b));
        if cos_p <= self.cos_emission { 0.0 } else { 1.0 }
    }
}

/// `(cos, sin)` of `max(0, a − b)` from those of `a` and `b` (angles in `[0, π]`).
#[inline]
fn cos_sin_sub_clamped((cos_a, sin_a): (f64, f64), (cos_b, sin_b): (f64, f64)) -> (f64, f64) {
    if cos_a > cos_b {
        (1.0, 0.0)
    } else {
        (
            cos_a * cos_b + sin_a * sin_b,
            (sin_a * cos_b - cos_a * sin_b).max(0.0),
        )
    }
}

/// The smallest cone (axis, `cos` half-angle) found by pbrt-v4's `DirectionCone::Union`
/// that holds two cones; `cos = −1` is every direction.
fn cone_union((wa, cos_a): (DVec3, f64), (wb, cos_b): (DVec3, f64)) -> (DVec3, f64) {
    if cos_a <= -1.0 || cos_b <= -1.0 {
        return (DVec3::Z, -1.0);
    }
    let theta_a = cos_a.clamp(-1.0, 1.0).acos();
    let theta_b = cos_b.clamp(-1.0, 1.0).acos();
    let theta_d = wa.angle_between(wb);
    if (theta_d + theta_b).min(std::f64::consts::PI) <= theta_a {
        return (wa, cos_a);
    }
    if (theta_d + theta_a).min(std::f64::consts::PI) <= theta_b {
        return (wb, cos_b);
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b);
    if theta_o >= std::f64::consts::PI {
        return (DVec3::Z, -1.0);
    }
    let theta_r = theta_o - theta_a;
    let wr = wa.cross(wb);
    if wr.length_squared() == 0.0 {
        return (DVec3::Z, -1.0);
    }
    let w = DQuat::from_axis_angle(wr.normalize(), theta_r) * wa;
    // Rounding in the rotation: keep the cone a touch wider than computed.
    (
        w.normalize(),
        (theta_o + 1e-9).min(std::f64::consts::PI).cos(),
    )
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
}

impl LightTree {
    /// Builds the tree over the lights with `p_i > 0` and `z_i > 0` (`O(N log N)`, large
    /// subtrees in parallel; the result does not depend on the thread count).
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
        let mut lights: Vec<(u32, SpatialLight)> = contributing(positions, powers, emission)
            .into_iter()
            .map(|(i, l, _)| (i, l))
            .collect();
        let m = lights.len();
        assert!(m < 1 << 27, "at most 2^27 lights");
        let node_count = internal_nodes(m);
        let mut nodes = vec![TreeNode::EMPTY; node_count];
        let mut node_first = vec![0u32; node_count];
        let root = if m == 0 {
            ChildRef::EMPTY
        } else if m <= LEAF_SIZE {
            ChildRef::leaf(0, m)
        } else {
            let bounds = Bounds::of(&lights);
            build_node(Job {
                lights: &mut lights,
                bounds,
                index: 0,
                first: 0,
                nodes: &mut nodes,
                node_first: &mut node_first,
            });
            ChildRef::node(0)
        };
        let mut tree = Self {
            nodes,
            node_first,
            order: lights.iter().map(|(i, _)| *i).collect(),
            lights: lights.into_iter().map(|(_, l)| l).collect(),
            root,
            depth: 0,
            n: positions.len(),
            emission: Vec::new(),
            bounds: Vec::new(),
        };
        tree.depth = tree.deepest(tree.root);
        if let Some(e) = emission {
            tree.emission = tree.order.iter().map(|&i| e[i as usize]).collect();
            tree.bounds = tree.lane_bounds();
        }
        tree
    }

    /// Every node's lane bounds, children before parents (nodes are stored depth first,
    /// so a node's children have larger indices).
    fn lane_bounds(&self) -> Vec<[LaneBounds; TREE_WIDTH]> {
        let mut bounds = vec![[LaneBounds::EMPTY; TREE_WIDTH]; self.nodes.len()];
        for k in (0..self.nodes.len()).rev() {
            for lane in 0..TREE_WIDTH {
                bounds[k][lane] = match self.nodes[k].child[lane].get() {
                    Child::Node(j) => bounds[j][1..]
                        .iter()
                        .fold(bounds[j][0], |a, b| LaneBounds::union(&a, b)),
                    Child::Leaf { first, count } => (first..first + count)
                        .map(|j| LaneBounds::of_light(&self.lights[j], &self.emission[j]))
                        .fold(LaneBounds::EMPTY, |a, b| LaneBounds::union(&a, &b)),
                    Child::Empty => LaneBounds::EMPTY,
                };
            }
        }
        bounds
    }

    /// The grid masses of node `k`'s lanes at `x` (with its lane bounds when the lights
    /// have emission profiles).
    #[inline]
    fn node_masses(&self, k: usize, x: DVec2) -> [u32; TREE_WIDTH] {
        match self.bounds.get(k) {
            Some(bounds) => self.nodes[k].masses_bounded(bounds, x),
            None => self.nodes[k].masses(x),
        }
    }

    /// Node `k`'s lane bounds, when the lights have emission profiles.
    pub fn bounds(&self, k: usize) -> Option<&[LaneBounds; TREE_WIDTH]> {
        self.bounds.get(k)
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

/// Internal nodes of a range of `m` lights: 0 for a leaf cluster, else one plus those of
/// its parts ([`parts`]). Depends only on `m`, which fixes the depth-first layout.
fn internal_nodes(m: usize) -> usize {
    if m <= LEAF_SIZE {
        return 0;
    }
    1 + parts(m).iter().map(|&s| internal_nodes(s)).sum::<usize>()
}

/// The sizes of the children of a range of `m > LEAF_SIZE` lights, in lane order (0 for an
/// unused lane): the halves `⌊m/2⌋`, `⌈m/2⌉`, each halved again when larger than a leaf.
fn parts(m: usize) -> [usize; TREE_WIDTH] {
    let halves = [m / 2, m - m / 2];
    let mut out = [0; TREE_WIDTH];
    let mut lane = 0;
    for h in halves {
        if h > LEAF_SIZE {
            out[lane] = h / 2;
            out[lane + 1] = h - h / 2;
            lane += 2;
        } else {
            out[lane] = h;
            lane += 1;
        }
    }
    out
}

/// The box of a range of lights, in the world.
#[derive(Clone, Copy)]
struct Bounds {
    min: DVec3,
    max: DVec3,
}

impl Bounds {
    fn of(lights: &[(u32, SpatialLight)]) -> Self {
        lights.iter().fold(
            Bounds {
                min: DVec3::INFINITY,
                max: DVec3::NEG_INFINITY,
            },
            |b, (_, l)| Bounds {
                min: b.min.min(l.position_in_world),
                max: b.max.max(l.position_in_world),
            },
        )
    }

    /// The axis of the largest extent (the first of equals).
    fn longest_axis(&self) -> usize {
        let e = self.max - self.min;
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }
}

/// Splits `lights` at the median along the longest axis of `bounds` (ties by scene index).
fn split_at_median(lights: &mut [(u32, SpatialLight)], bounds: Bounds) -> usize {
    let axis = bounds.longest_axis();
    let mid = lights.len() / 2;
    lights.select_nth_unstable_by(mid, |a, b| {
        a.1.position_in_world[axis]
            .total_cmp(&b.1.position_in_world[axis])
            .then(a.0.cmp(&b.0))
    });
    mid
}

/// `(Φ, centroid)` of a range: `Σ p_i`, and `Σ w_i·y_i / Σ w_i` with `w_i = p_i / max p`
/// (no underflow however small the powers), clamped into `bounds`.
fn representative(lights: &[(u32, SpatialLight)], bounds: Bounds) -> (f64, DVec3) {
    let largest = lights.iter().map(|(_, l)| l.power).fold(0.0f64, f64::max);
    let (mut power, mut weight, mut weighted) = (0.0, 0.0, DVec3::ZERO);
    for (_, l) in lights {
        power += l.power;
        let w = l.power / largest;
        weight += w;
        weighted += w * l.position_in_world;
    }
    let centroid = (weighted / weight).clamp(bounds.min, bounds.max);
    (power, centroid)
}

/// One subtree to build: its lights (more than [`LEAF_SIZE`]), their box, its node's index
/// and leaf-order offset, and the node slots of the subtree (its own first).
struct Job<'a> {
    lights: &'a mut [(u32, SpatialLight)],
    bounds: Bounds,
    index: usize,
    first: usize,
    nodes: &'a mut [TreeNode],
    node_first: &'a mut [u32],
}

/// Fills the job's node and, depth first, its subtrees (in parallel when large).
fn build_node(job: Job<'_>) {
    let Job {
        lights,
        bounds,
        index,
        first,
        nodes,
        node_first,
    } = job;
    // The parts in lane order: halves at the median, each halved again if larger than a leaf
    // (the sizes of `parts`).
    let lights_len = lights.len();
    let mid = split_at_median(lights, bounds);
    let (left, right) = lights.split_at_mut(mid);
    let mut ranges: Vec<&mut [(u32, SpatialLight)]> = Vec::with_capacity(TREE_WIDTH);
    for half in [left, right] {
        if half.len() > LEAF_SIZE {
            let quarter = split_at_median(half, Bounds::of(half));
            let (a, b) = half.split_at_mut(quarter);
            ranges.push(a);
            ranges.push(b);
        } else {
            ranges.push(half);
        }
    }
    // The layout reserved node slots for exactly these sizes.
    debug_assert!(
        ranges
            .iter()
            .map(|r| r.len())
            .eq(parts(lights_len).into_iter().filter(|&s| s > 0))
    );

    let (this, mut below) = nodes.split_at_mut(1);
    let (this_first, mut below_first) = node_first.split_at_mut(1);
    this_first[0] = first as u32;
    let mut node = TreeNode::EMPTY;
    let mut jobs = Vec::with_capacity(TREE_WIDTH);
    let (mut next_index, mut next_first) = (index + 1, first);
    for (lane, range) in ranges.into_iter().enumerate() {
        let range_bounds = Bounds::of(range);
        let (power, centroid) = representative(range, range_bounds);
        node.power[lane] = power;
        for (axis, coordinate) in node.centroid.iter_mut().zip(centroid.to_array()) {
            axis[lane] = coordinate;
        }
        let count = internal_nodes(range.len());
        let len = range.len();
        if count == 0 {
            node.child[lane] = ChildRef::leaf(next_first, len);
        } else {
            node.child[lane] = ChildRef::node(next_index);
            let (slots, rest) = below.split_at_mut(count);
            let (slots_first, rest_first) = below_first.split_at_mut(count);
            below = rest;
            below_first = rest_first;
            jobs.push(Job {
                lights: range,
                bounds: range_bounds,
                index: next_index,
                first: next_first,
                nodes: slots,
                node_first: slots_first,
            });
        }
        next_index += count;
        next_first += len;
    }
    this[0] = node;
    if jobs.iter().map(|j| j.lights.len()).sum::<usize>() > PARALLEL_BUILD {
        rayon::scope(|s| {
            for job in jobs {
                s.spawn(move |_| build_node(job));
            }
        });
    } else {
        jobs.into_iter().for_each(build_node);
    }
}

#[cfg(test)]
mod tests {
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
