//! The descent: a pick with one draw per node and one in the leaf cluster (one point, or
//! several in lockstep), and the pdf `P(i | x)` it realizes, for one light or all.
//!
//! **Below a group, by power alone? Measured, not kept.** Below an entry of a tile's cut
//! ([`super::TileCuts`]) that is a node of point lights, a pick could take each lane and
//! then the light by power alone (no representative lights, no square roots). Exact
//! variances and picks alone (the `tile_cuts` example, `heavy-tail`): below every such
//! entry (55 % of a tile's mass), 6.1× the variance (1233× below power's became 203×) for
//! 14 % less time a pick (136 → 117 ns; 130 → 111 ns in lockstep); `clusters-low` kept its
//! variance (291× → 279×) for 11 % less. Below only the entries whose lights' geometry terms
//! provably differ by at most 4× (8×) across the tile (a bound from the node's reach), 3 %
//! (11 %) of the mass took it, for 1.05× (1.26×) the variance and no time gained. The
//! levels' importances are not what a pick below a group spends its time on.

use glam::DVec2;

use super::LightTree;
use super::cut_words::{pick_in, prefetch_pick};
use super::leaf_terms::{point_contributions, shaped_contributions};
use super::node::{Child, ChildRef, LEAF_SIZE, TREE_WIDTH, TreeNode};
use super::prefetch::{CUT_PREFETCH_MIN_LIGHTS, PREFETCH_MIN_LIGHTS, prefetch, prefetch_all};
use crate::rng::Rng;
use crate::spatial::SpatialPick;
use crate::spatial::importance::{GRID, GRID_CELL, grid_masses, pick_on_grid};

impl LightTree {
    /// The grid masses of node `k`'s lanes at `x` (by its mapped lanes when the lights have
    /// emission profiles).
    #[inline]
    fn node_masses(&self, k: usize, x: DVec2) -> [u32; TREE_WIDTH] {
        match self.mapped.get(k) {
            Some(mapped) => TreeNode::masses_mapped(mapped, x),
            None => self.nodes[k].masses(x),
        }
    }

    /// Node `k`'s lanes' importances and defensive shares at `x`, from which
    /// [`LightTree::node_masses_at`] mixes its masses: point lights' `4π·I_c` and powers
    /// ([`TreeNode::weights`]), or lanes' maps and peak intensities
    /// ([`TreeNode::weights_mapped`]).
    #[inline]
    pub(super) fn node_weights(
        &self,
        k: usize,
        x: DVec2,
    ) -> ([f64; TREE_WIDTH], [f64; TREE_WIDTH]) {
        match self.mapped.get(k) {
            Some(mapped) => TreeNode::weights_mapped(mapped, x),
            None => self.nodes[k].weights(x),
        }
    }

    /// Light `first`'s contribution at `x` and whether, alone in its leaf (a single light of
    /// a tile's cut), it takes the whole grid there: where that contribution is finite and
    /// positive, as the rule of a cluster gives it (`c·(1/c)` rounds to the grid's `2^24`
    /// after its correction; `∞·0` is NaN), none elsewhere.
    #[inline]
    fn single_light(&self, first: usize, x: DVec2) -> (f64, bool) {
        let c = self.lights[first].contribution_with(self.emission.get(first), x);
        (c, c > 0.0 && c.is_finite())
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
        let mut masses = [0; LEAF_SIZE];
        if count == 1 {
            let (c0, whole) = self.single_light(first, x);
            masses[0] = if whole { GRID } else { 0 };
            let mut c = [0.0; LEAF_SIZE];
            c[0] = c0;
            return (masses, c);
        }
        let c = self.leaf_contributions(first, count, x);
        let mut total = 0.0;
        for &cj in &c[..count] {
            total += cj;
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

    /// The contributions `c_j = p_j·G_j(x)·S_j(x)` of the lights `first .. first + count` of
    /// a leaf cluster at `x` (0 beyond `count`).
    #[inline]
    pub(super) fn leaf_contributions(
        &self,
        first: usize,
        count: usize,
        x: DVec2,
    ) -> [f64; LEAF_SIZE] {
        let mut c = [0.0; LEAF_SIZE];
        let lights = &self.lights[first..first + count];
        if self.emission.is_empty() {
            point_contributions(lights, x, &mut c);
        } else {
            shaped_contributions(lights, &self.emission[first..first + count], x, &mut c);
        }
        c
    }

    /// Where a pick at `x` starts and with what probability: on a tile of the per-tile cuts
    /// the entry its cut takes by the next draw (`None` when no entry has power), elsewhere
    /// the root with probability 1.
    #[inline]
    fn start(&self, x: DVec2, rng: &mut Rng) -> Option<(ChildRef, f64)> {
        match self.cut_tile_at(x) {
            Some((cuts, tile)) => {
                let (entry, mass) = cuts.pick(self, tile, rng.next_u32() >> 8)?;
                Some((entry, f64::from(mass) * GRID_CELL))
            }
            None => Some((self.root, 1.0)),
        }
    }

    /// [`LightTree::start`] at `B` points, each from its own stream, with the same draws: on
    /// the cuts every pick's tile and draw are taken first, asking for the alias column and
    /// entry each will read (`cut_words::prefetch_pick`), so that the picks' loads (cache
    /// misses where the cuts outgrow the nearer caches) overlap rather than follow one
    /// another.
    ///
    /// Each start goes into `at[b]` and `pdf[b]` (the empty lane with probability 0 where
    /// no entry of the tile has power).
    #[inline]
    fn start_many<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
        at: &mut [ChildRef; B],
        pdf: &mut [f64; B],
    ) {
        let Some(cuts) = self.cuts.as_deref() else {
            *at = [self.root; B];
            *pdf = [1.0; B];
            return;
        };
        // A cut's words are never empty: an empty slice marks a point off the cuts.
        let mut words: [&[u32]; B] = [&[]; B];
        let mut u = [0; B];
        for b in 0..B {
            if let Some(tile) = cuts.tile_at(points[b]) {
                words[b] = cuts.cut(self, tile);
                u[b] = rngs[b].next_u32() >> 8;
                prefetch_pick(words[b], u[b]);
            }
        }
        for b in 0..B {
            (at[b], pdf[b]) = if words[b].is_empty() {
                (self.root, 1.0)
            } else {
                pick_in(words[b], u[b]).map_or((ChildRef::EMPTY, 0.0), |(e, m)| {
                    (e, f64::from(m) * GRID_CELL)
                })
            };
        }
    }

    /// The entries a pick at `x` may start from with their probabilities: the tile's cut,
    /// or the root alone off the cuts.
    fn starts(&self, x: DVec2) -> Vec<(ChildRef, f64)> {
        match self.cut_tile_at(x) {
            Some((cuts, tile)) => cuts
                .entries(self, tile)
                .filter(|&(_, m)| m > 0)
                .map(|(e, m)| (e, f64::from(m) * GRID_CELL))
                .collect(),
            None => vec![(self.root, 1.0)],
        }
    }

    /// A pick at `x`: on a tile of the per-tile cuts ([`super::TileCuts`]) one draw takes
    /// an entry of its cut, then (as from the root without cuts) one draw per node and one
    /// in the leaf cluster; `None` when there is no contributing light or every
    /// contribution of the leaf reached is 0 (then `ê = 0`).
    #[inline]
    pub fn sample(&self, x: DVec2, rng: &mut Rng) -> Option<SpatialPick> {
        let (mut at, mut pdf) = self.start(x, rng)?;
        while let Child::Node(k) = at.get() {
            at = self.step(k, x, rng, &mut pdf);
        }
        self.pick_in_leaf(at, x, rng, pdf)
    }

    /// [`LightTree::sample`] at `B` points at once, each from its own stream: the descents
    /// advance in lockstep, so that their node and light loads (cache misses among a million
    /// lights) are independent and overlap; in a tree of at least `2^15` point lights each
    /// pick also prefetches its next node or leaf cluster a round ahead. Pick `b` is exactly
    /// `sample(points[b], rngs[b])`, with the same draws.
    #[inline]
    pub fn sample_many<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
    ) -> [Option<SpatialPick>; B] {
        self.sample_many_with(points, rngs, false)
    }

    /// [`LightTree::sample_many`] for points whose tiles' cuts have likely left the caches
    /// since they were last read (the first sample a pass takes at each pixel): in a tree
    /// of more than 256 point lights the picks take their cuts' draws first and ask for the
    /// lines each will read, then pick (`prefetch`). The same picks, with the same draws.
    #[inline]
    pub fn sample_many_cold<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
    ) -> [Option<SpatialPick>; B] {
        self.sample_many_with(points, rngs, true)
    }

    /// [`LightTree::sample_many`], or [`LightTree::sample_many_cold`] when `cold`.
    #[inline]
    pub(crate) fn sample_many_with<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
        cold: bool,
    ) -> [Option<SpatialPick>; B] {
        // Large trees of point lights ask for each pick's next node a round of the other
        // picks' steps before it is read, and cold picks over more point lights than a
        // cut's entries for their cuts' lines; the others run the loop without the hints,
        // compiled apart.
        let points_only = self.mapped.is_empty();
        let nodes = points_only && self.lights.len() >= PREFETCH_MIN_LIGHTS;
        let cuts = cold && points_only && self.lights.len() > CUT_PREFETCH_MIN_LIGHTS;
        match (nodes, cuts) {
            (true, true) => self.descend_many::<B, true, true>(points, rngs),
            (true, false) => self.descend_many::<B, true, false>(points, rngs),
            (false, true) => self.descend_many::<B, false, true>(points, rngs),
            (false, false) => self.descend_many::<B, false, false>(points, rngs),
        }
    }

    /// [`LightTree::sample_many`], prefetching each pick's next node or leaf cluster when
    /// `PREFETCH`, and its cut's lines when `PREFETCH_CUTS` ([`LightTree::start_many`]).
    #[inline]
    fn descend_many<const B: usize, const PREFETCH: bool, const PREFETCH_CUTS: bool>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
    ) -> [Option<SpatialPick>; B] {
        let mut at = [ChildRef::EMPTY; B];
        let mut pdf = [0.0; B];
        if PREFETCH_CUTS {
            self.start_many(points, rngs, &mut at, &mut pdf);
            if PREFETCH {
                for &a in &at {
                    self.prefetch_below(a);
                }
            }
        } else {
            for b in 0..B {
                (at[b], pdf[b]) = self
                    .start(points[b], &mut rngs[b])
                    .unwrap_or((ChildRef::EMPTY, 0.0));
                if PREFETCH {
                    self.prefetch_below(at[b]);
                }
            }
        }
        loop {
            let mut descending = false;
            for b in 0..B {
                if let Child::Node(k) = at[b].get() {
                    at[b] = self.step(k, points[b], &mut rngs[b], &mut pdf[b]);
                    if PREFETCH {
                        self.prefetch_below(at[b]);
                    }
                    descending = true;
                }
            }
            if !descending {
                break;
            }
        }
        std::array::from_fn(|b| self.pick_in_leaf(at[b], points[b], &mut rngs[b], pdf[b]))
    }

    /// Asks for what a descent reads next at `at` ([`super::prefetch`]): an internal node's
    /// lanes, or a leaf cluster's lights and scene indices.
    #[inline]
    fn prefetch_below(&self, at: ChildRef) {
        match at.get() {
            Child::Node(k) => prefetch(&self.nodes[k]),
            Child::Leaf { first, count } => {
                prefetch_all(&self.lights[first..first + count]);
                prefetch(&self.order[first]);
            }
            Child::Empty => {}
        }
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
        if count == 1 {
            // A single light of a tile's cut, without a leaf's arrays: `pdf` times exactly 1
            // where it takes the whole grid, as `leaf_masses` gives it; the draw is spent all
            // the same, as the GPU spends it.
            rng.next_u32();
            let (c, whole) = self.single_light(first, x);
            return (whole && pdf > 0.0).then(|| SpatialPick {
                light: self.order[first],
                pdf,
                estimate: c / pdf,
            });
        }
        let (masses, c) = self.leaf_masses(first, count, x);
        let j = pick_on_grid(&masses[..count], rng.next_u32() >> 8);
        let pdf = pdf * (f64::from(masses[j]) * GRID_CELL);
        (c[j] > 0.0 && pdf > 0.0).then(|| SpatialPick {
            light: self.order[first + j],
            pdf,
            estimate: c[j] / pdf,
        })
    }

    /// The grid masses `m_k` of node `k`'s four lanes at `x`, exactly those a descent picks
    /// by (summing to `2^24`, or all 0 where every lane is culled): branch `k` is taken with
    /// probability `m_k / 2^24`. For lessons and tests; the descent itself inlines them.
    pub fn node_masses_at(&self, k: usize, x: DVec2) -> [u32; TREE_WIDTH] {
        self.node_masses(k, x)
    }

    /// The grid masses of the lights `first .. first + count` (leaf order) of a leaf cluster
    /// at `x`, by `c_j / Σ c` with `c_j = p_j·G_j(x)·S_j(x)`, and the contributions `c_j`
    /// themselves (entries from `count` on are 0): exactly what a descent picks the light
    /// by. For lessons and tests.
    ///
    /// # Panics
    /// If `count > LEAF_SIZE` or the range leaves the tree's lights.
    pub fn leaf_masses_at(
        &self,
        first: usize,
        count: usize,
        x: DVec2,
    ) -> ([u32; LEAF_SIZE], [f64; LEAF_SIZE]) {
        assert!(
            count <= LEAF_SIZE,
            "a leaf cluster holds at most {LEAF_SIZE} lights"
        );
        self.leaf_masses(first, count, x)
    }

    /// `P(i | x)` of every light of the scene at once, indexed by scene index (0 for a light
    /// outside the tree): one traversal with the masses of [`LightTree::sample`], `O(N)`.
    pub fn pdfs(&self, x: DVec2) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        let mut stack = self.starts(x);
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
        let Some((mut at, mut pdf)) = self
            .starts(x)
            .into_iter()
            .find(|&(e, _)| self.span(e).is_some_and(|s| s.contains(&j)))
        else {
            return 0.0;
        };
        loop {
            match at.get() {
                Child::Node(k) => {
                    let masses = self.node_masses(k, x);
                    let lane = self.lane_holding(k, j);
                    pdf *= f64::from(masses[lane]) * GRID_CELL;
                    at = self.nodes[k].child[lane];
                }
                Child::Leaf { first, count } => {
                    let (masses, _) = self.leaf_masses(first, count, x);
                    return pdf * (f64::from(masses[j - first]) * GRID_CELL);
                }
                Child::Empty => return 0.0,
            }
        }
    }
}
