//! The tree's nodes: a child lane's word ([`ChildRef`], what the GPU reads too) and an
//! internal node's four lanes ([`TreeNode`]) with the grid masses a descent picks by.

use glam::{DVec2, DVec3};

use crate::spatial::grid::MappedLanes;
use crate::spatial::importance::{
    IMPORTANCE_CAP, branch_probabilities, grid_masses, lane_importances,
};

/// Children per internal node.
pub const TREE_WIDTH: usize = 4;

/// The most lights in a leaf cluster, picked by their exact contributions.
///
/// Measured at 16 (the child word's count one bit wider; `tile_cuts` example, the cuts as
/// built, against 8 in the same hour; `lightpick bench --no-gpu --presets none --sizes
/// 100000`): a tree over 10^5 spots held 238 bytes a light instead of 349 (half the nodes;
/// measured before the nodes dropped their lanes' full bounds and empty lanes' maps, 253 now)
/// and refitted in 207 ms instead of 249, the variances moved within ±15 % (`stage` 415× →
/// 356× below power sampling, `gallery` 2620× → 2965×, `random` 289× → 285×, `arena`
/// 526× → 525×, `heavy-tail` 1233× → 1242×), but a pick over spots evaluates twice the
/// lights where it lands in a cluster: `stage` 2.8× → 4.6× an alias pick's time, `gallery`
/// 2.9× → 3.2×, `random` 3.8× → 4.1×, `arena` 3.8× → 4.0× (`heavy-tail` unchanged). Not
/// kept: the time per pick is the goal furthest from met.
///
/// Measured at 4 over spots and ranges alone (the footprint split stopping at four lights,
/// a cluster of at most four evaluated as one vector of four lanes under AVX2; `lightpick
/// bench --no-gpu --presets stage,gallery --scene random.json --scene arena.json --sizes
/// 1000`, two runs alternating with 8): a spatial sample over an alias one `stage` 3.94×,
/// 3.41× → 2.95×, 2.74×, `gallery` 4.63×, 3.64× → 3.23×, 3.53×, `random` 5.84×, 6.51× →
/// 5.72×, 5.60×, `arena` 5.77×, 5.91× → 4.48×, 5.24×; efficiency over the alias table's
/// 5–25 % higher on each; the exact variances (`tree_variance` example) 5–8 % higher
/// (`stage` 477× → 453× below power sampling, `gallery` 2510× → 2377×, `random` 281× →
/// 260×, `arena` 537× → 509×). But twice the nodes: the tree's heap 253 → 368 bytes a light
/// over 10^5 spots (245 → 360 at 10^3), a full refit 103–107 → 124 ms, and the GPU twin
/// (without the tiles' cuts) 231–247 → 365–373 bytes a light on these four scenes. Not
/// kept: the twin must stay no larger than it is, and the bytes a light are the goal
/// furthest from met after the time per pick. Evaluating only the first four lanes of a
/// cluster of at most four in these trees of eight (a branch on the count) gained nothing
/// measurable on the same scenes (`pass_order` example).
pub const LEAF_SIZE: usize = 8;

/// What a child lane of a node holds, in one `u32` (the word the GPU reads too): an internal
/// node's index (bit 31 clear), or a leaf cluster `1 << 31 | count << 27 | first` (its
/// `count ≤ 8` lights from leaf-order index `first < 2^27`); an empty lane is the leaf
/// cluster of no lights.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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
    pub(super) fn node(index: usize) -> Self {
        debug_assert!(index < Self::LEAF_BIT as usize);
        ChildRef(index as u32)
    }

    /// The leaf cluster of `count` lights from `first` (`count ≤ 8`, `first < 2^27`).
    pub(super) fn leaf(first: usize, count: usize) -> Self {
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

    /// The lane whose word is `bits` ([`ChildRef::bits`] undone).
    pub(super) fn from_bits(bits: u32) -> Self {
        ChildRef(bits)
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
    pub(super) centroid: [[f64; TREE_WIDTH]; 3],
    /// `Φ_c = Σ p_i` of each lane's lights (0 for an empty lane).
    pub(super) power: [f64; TREE_WIDTH],
    /// Each lane's child.
    pub(super) child: [ChildRef; TREE_WIDTH],
    /// Where this node's lights can be ([`TreeNode::lane_bound`]): the radius `r` of a
    /// sphere about their power-weighted centroid (the one its parent's lane holds) that
    /// holds them all (`f32`, rounded up), and the height `z_min` of the lowest (`f32`,
    /// rounded down).
    pub(super) reach: [f32; 2],
}

impl TreeNode {
    pub(super) const EMPTY: TreeNode = TreeNode {
        centroid: [[0.0; TREE_WIDTH], [0.0; TREE_WIDTH], [1.0; TREE_WIDTH]],
        power: [0.0; TREE_WIDTH],
        child: [ChildRef::EMPTY; TREE_WIDTH],
        reach: [0.0, f32::INFINITY],
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

    /// An upper bound of what lane `lane`'s point lights, the lights of node `child` (the
    /// lane's child), give any point `x` of the rectangle `rect` (`[min, max]`) on the plane:
    ///
    /// `Σ p_i·G_i(x) ≤ Φ_c · min(1, (c_z + r)/d) / (4π·d²)`,  `d = max(|c − rect| − r, z_min)`,
    ///
    /// `c` the lane's centroid, `|c − rect|` its distance to the rectangle, `r` the radius of
    /// a sphere about `c` that holds every light of the lane and `z_min` the lowest light's
    /// height (the child's reach, rounded outward to `f32`). Each light `y_i` is at least
    /// `d` from every point of the rectangle (`|y_i − x| ≥ |c − x| − |y_i − c|`, and
    /// `≥ z_i`), no higher than `c_z + r`, and `G_i(x) = z_i / (4π|y_i − x|³)`. Unlike the
    /// representative light it cannot miss a light hanging just above the rectangle. 0 for
    /// a lane without power; `∞` where `d` is 0.
    pub fn lane_bound(&self, lane: usize, child: &TreeNode, [lo, hi]: [DVec2; 2]) -> f64 {
        let power = self.power[lane];
        if power <= 0.0 {
            return 0.0;
        }
        let c = self.centroid(lane);
        let dx = (lo.x - c.x).max(c.x - hi.x).max(0.0);
        let dy = (lo.y - c.y).max(c.y - hi.y).max(0.0);
        let [radius, floor] = child.reach.map(f64::from);
        let d = ((dx * dx + dy * dy + c.z * c.z).sqrt() - radius).max(floor);
        let cosine = ((c.z + radius) / d).min(1.0);
        power * cosine / (4.0 * std::f64::consts::PI * d * d)
    }

    /// The four lanes' importances at `point_on_plane` for point lights (`4π·I_c`,
    /// [`lane_importances`]) and their powers: what [`TreeNode::masses`] mixes.
    #[inline]
    pub fn weights(&self, point_on_plane: DVec2) -> ([f64; TREE_WIDTH], [f64; TREE_WIDTH]) {
        let [x, y, z] = &self.centroid;
        let importance = lane_importances([x, y, z], &self.power, point_on_plane);
        (importance, self.power)
    }

    /// The grid masses of the four lanes at `point_on_plane` for point lights (summing to
    /// `2^24`, or all 0 when no lane has power).
    #[inline]
    pub fn masses(&self, point_on_plane: DVec2) -> [u32; TREE_WIDTH] {
        let (importance, power) = self.weights(point_on_plane);
        grid_masses(branch_probabilities(importance, power))
    }

    /// The four lanes' importances at `point_on_plane` for lights with emission profiles
    /// (their maps' values, capped at [`IMPORTANCE_CAP`]) and their shares of peak intensity
    /// `Σ p_i·g_i` ([`MappedLanes::weights`]; both 0 for a lane whose bounds exclude the
    /// point): what [`TreeNode::masses_mapped`] mixes.
    #[inline]
    pub fn weights_mapped(
        mapped: &MappedLanes,
        point_on_plane: DVec2,
    ) -> ([f64; TREE_WIDTH], [f64; TREE_WIDTH]) {
        let (importance, share) = mapped.weights(point_on_plane);
        (importance.map(|i| i.min(IMPORTANCE_CAP)), share)
    }

    /// The grid masses of four lanes of lights with emission profiles at `point_on_plane`:
    /// a lane whose bounds exclude the point gets none; the others are weighed by their
    /// maps, mixed with their shares of peak intensity `Σ p_i·g_i`
    /// ([`TreeNode::weights_mapped`], [`branch_probabilities`]). All zero when every lane
    /// is culled.
    #[inline]
    pub fn masses_mapped(mapped: &MappedLanes, point_on_plane: DVec2) -> [u32; TREE_WIDTH] {
        let (importance, share) = Self::weights_mapped(mapped, point_on_plane);
        grid_masses(branch_probabilities(importance, share))
    }
}
