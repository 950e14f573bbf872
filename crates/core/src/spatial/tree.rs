//! The light tree: a binary tree over the contributing lights, descended stochastically.
//!
//! # Layout
//! The `M` contributing lights are permuted into leaf order (`order[j]` = scene index of
//! leaf `j`). A node covers a leaf range `[lo, hi)` and splits it at `mid = lo + (hi − lo)/2`
//! (the median along the longest axis of the node's box, placed by `select_nth_unstable`):
//! `O(N log N)` to build. Only the `M − 1` internal nodes are stored, in depth-first order:
//! the left child of node `k` is `k + 1`, the right child `k + (mid − lo)` (the left subtree
//! holds `mid − lo − 1` internal nodes); a child range of one leaf is that light itself. So a
//! node is just its box and its power — no child pointers: 32 bytes on the GPU
//! (`min.xyz, Φ, max.xyz, pad` as `f32`) plus 4 bytes of `order` per light.
//!
//! # The pick and its pdf
//! From the root, at each node both children get an importance
//! ([`super::importance::node_importance`] for a subtree, the exact `p_i·G_i(x)` for a
//! leaf), giving `P_left = I_L/(I_L+I_R)` ([`super::importance::branch_probabilities`]);
//! the descent goes left iff `(r >> 8) < P_left·2^24` (clamped) for the level's draw `r`
//! (one draw per level, depth `⌈log2 M⌉`; [`super::importance::branch_threshold`]), that is
//! iff `(r >> 8) < t` with `t = ⌈P_left·2^24⌉`, so
//! left is taken with probability exactly `t/2^24` and right with `(2^24 − t)/2^24`. The
//! pick's probability is the product of these realized branch probabilities,
//!
//! `P(i | x) = Π_{levels} P_branch`,   each `P_branch` within `2^-24` of `I_child/(I_L+I_R)`,
//!
//! and since the two branches of a level sum to exactly 1, summing over the leaves of any
//! subtree gives 1 level by level: `Σ_i P(i | x) = 1`. A child holding a light with
//! `p_i·G_i(x) > 0` has `I > 0` and a threshold that keeps it reachable, so `P(i | x) > 0`
//! wherever the contribution is: the estimate `p_i·G_i(x)/P(i | x)` is unbiased, with no
//! rounding term from the decisions (the pdf is what the integer comparisons realize).

use super::importance::{
    branch_probabilities, branch_threshold, grid_probabilities, node_importance,
};
use super::{SpatialLight, SpatialPick, contributing};
use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::scene::geometry_term;

/// An internal node: the bounding box of its lights' positions and their total normalized
/// power `Φ_node = Σ p_i`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeNode {
    /// Lower corner of the box.
    pub min: [f64; 3],
    /// Upper corner of the box.
    pub max: [f64; 3],
    /// `Σ p_i` over the node's lights.
    pub power: f64,
}

/// A light tree over the contributing lights of a scene; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTree {
    /// Internal nodes, depth-first (`M − 1` of them for `M ≥ 1` leaves).
    nodes: Vec<TreeNode>,
    /// Scene index of each leaf, in leaf order.
    order: Vec<u32>,
    /// `(x, y, z, p)` of each leaf, in leaf order.
    leaves: Vec<SpatialLight>,
    /// Number of lights of the scene.
    n: usize,
}

/// One child during the descent: its leaf range and, when internal, its node index.
#[derive(Clone, Copy)]
struct Child {
    lo: usize,
    hi: usize,
    node: usize,
}

impl LightTree {
    /// Builds the tree over the lights with `p_i > 0` and `z_i > 0` (`O(N log N)`).
    ///
    /// # Panics
    /// If `positions` and `powers` have different lengths.
    pub fn build(positions: &[[f64; 3]], powers: &LightPowers) -> Self {
        let mut lights = contributing(positions, powers);
        let m = lights.len();
        let mut nodes = Vec::with_capacity(m.saturating_sub(1));
        if m >= 2 {
            build_node(&mut lights, &mut nodes);
        }
        Self {
            nodes,
            order: lights.iter().map(|(i, _)| *i).collect(),
            leaves: lights.iter().map(|(_, l)| *l).collect(),
            n: positions.len(),
        }
    }

    /// Number of lights of the scene.
    pub fn light_count(&self) -> usize {
        self.n
    }

    /// The internal nodes, depth-first.
    pub fn nodes(&self) -> &[TreeNode] {
        &self.nodes
    }

    /// The scene index of each leaf, in leaf order.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The depth of the deepest leaf, `⌈log2 M⌉` (draws per pick).
    pub fn depth(&self) -> u32 {
        self.order.len().next_power_of_two().trailing_zeros()
    }

    #[inline]
    fn importance(&self, c: Child, x: [f64; 2]) -> (f64, f64) {
        if c.hi - c.lo == 1 {
            let l = &self.leaves[c.lo];
            (l[3] * geometry_term([l[0], l[1], l[2]], x), l[3])
        } else {
            let n = &self.nodes[c.node];
            (node_importance(n.min, n.max, n.power, x), n.power)
        }
    }

    #[inline]
    fn children(node: usize, lo: usize, hi: usize) -> (Child, Child) {
        let mid = lo + (hi - lo) / 2;
        (
            Child {
                lo,
                hi: mid,
                node: node + 1,
            },
            Child {
                lo: mid,
                hi,
                node: node + (mid - lo),
            },
        )
    }

    /// Descends from the root with one draw per level; `None` when there is no
    /// contributing light or the picked light's `p_i·G_i(x)` is 0 (then `ê = 0`).
    #[inline]
    pub fn sample(&self, x: [f64; 2], rng: &mut Rng) -> Option<SpatialPick> {
        let m = self.order.len();
        if m == 0 {
            return None;
        }
        let mut at = Child {
            lo: 0,
            hi: m,
            node: 0,
        };
        let mut pdf = 1.0;
        // The chosen child's importance: at a leaf, exactly its contribution p_i·G_i(x).
        let mut chosen = None;
        while at.hi - at.lo > 1 {
            let (left, right) = Self::children(at.node, at.lo, at.hi);
            let (il, pl) = self.importance(left, x);
            let (ir, pr) = self.importance(right, x);
            let (p_left, p_right) = branch_probabilities(il, ir, pl, pr);
            let y = branch_threshold(p_left, p_right);
            let (g_left, g_right) = grid_probabilities(y);
            if f64::from(rng.next_u32() >> 8) < y {
                pdf *= g_left;
                at = left;
                chosen = Some(il);
            } else {
                pdf *= g_right;
                at = right;
                chosen = Some(ir);
            }
        }
        let contribution = chosen.unwrap_or_else(|| self.importance(at, x).0);
        (contribution > 0.0 && pdf > 0.0).then(|| SpatialPick {
            light: self.order[at.lo],
            pdf,
            estimate: contribution / pdf,
        })
    }

    /// `P(i | x)` of every light of the scene at once, indexed by scene index (0 for a light
    /// outside the tree): one traversal with the branch probabilities of
    /// [`LightTree::sample`], `O(N)` (two importances per internal node).
    pub fn pdfs(&self, x: [f64; 2]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        let m = self.order.len();
        if m == 0 {
            return out;
        }
        let root = Child {
            lo: 0,
            hi: m,
            node: 0,
        };
        let mut stack = vec![(root, 1.0f64)];
        while let Some((at, pdf)) = stack.pop() {
            if at.hi - at.lo == 1 {
                out[self.order[at.lo] as usize] = pdf;
                continue;
            }
            let (left, right) = Self::children(at.node, at.lo, at.hi);
            let (il, pl) = self.importance(left, x);
            let (ir, pr) = self.importance(right, x);
            let (p_left, p_right) = branch_probabilities(il, ir, pl, pr);
            let (g_left, g_right) = grid_probabilities(branch_threshold(p_left, p_right));
            stack.push((left, pdf * g_left));
            stack.push((right, pdf * g_right));
        }
        out
    }

    /// `P(i | x)`: the product of the branch probabilities on the path to light `i`'s leaf
    /// (0 for a light outside the tree). `O(N)` to find the leaf: meant for tests.
    pub fn pdf(&self, x: [f64; 2], light: usize) -> f64 {
        let Some(leaf) = self.order.iter().position(|&i| i as usize == light) else {
            return 0.0;
        };
        let mut at = Child {
            lo: 0,
            hi: self.order.len(),
            node: 0,
        };
        let mut pdf = 1.0;
        while at.hi - at.lo > 1 {
            let (left, right) = Self::children(at.node, at.lo, at.hi);
            let (il, pl) = self.importance(left, x);
            let (ir, pr) = self.importance(right, x);
            let (p_left, p_right) = branch_probabilities(il, ir, pl, pr);
            let (g_left, g_right) = grid_probabilities(branch_threshold(p_left, p_right));
            if leaf < left.hi {
                pdf *= g_left;
                at = left;
            } else {
                pdf *= g_right;
                at = right;
            }
        }
        pdf
    }
}

/// Appends the node of `lights` (at least 2) and, depth-first, its internal descendants.
fn build_node(lights: &mut [(u32, SpatialLight)], nodes: &mut Vec<TreeNode>) {
    let (mut min, mut max, mut power) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0.0);
    for (_, l) in lights.iter() {
        for a in 0..3 {
            min[a] = min[a].min(l[a]);
            max[a] = max[a].max(l[a]);
        }
        power += l[3];
    }
    nodes.push(TreeNode { min, max, power });
    let axis = (0..3)
        .max_by(|&a, &b| (max[a] - min[a]).total_cmp(&(max[b] - min[b])))
        .unwrap_or(0);
    let mid = lights.len() / 2;
    lights.select_nth_unstable_by(mid, |a, b| {
        a.1[axis].total_cmp(&b.1[axis]).then(a.0.cmp(&b.0))
    });
    let (left, right) = lights.split_at_mut(mid);
    if left.len() >= 2 {
        build_node(left, nodes);
    }
    if right.len() >= 2 {
        build_node(right, nodes);
    }
}
