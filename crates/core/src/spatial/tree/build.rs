//! Building the tree (its layout, then its lanes bottom up) and refitting it to new
//! powers.

use glam::{DVec2, DVec3};

use super::node::{Child, ChildRef, LEAF_SIZE, TREE_WIDTH, TreeNode};
use super::{LightTree, MapWeights, fill, footprint_split, layout, map_fill};
use crate::powers::LightPowers;
use crate::scene::{Emission, EmissionShape};
use crate::spatial::bounds::LaneBounds;
use crate::spatial::grid::MappedLanes;
use crate::spatial::{SpatialLight, contributing};

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
    /// plane (`[min, max]`, the receiver's rectangle: [`crate::spatial::grid`]): each light's
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
        let (nodes, node_first, order, root) = lay_out(&contributing, emission.is_some());
        let (raw, pmf) = (powers.as_slice(), powers.pmf_scale());
        let lights = order
            .iter()
            .map(|&i| SpatialLight {
                position_in_world: positions[i as usize],
                power: pmf.of(raw[i as usize]),
            })
            .collect();
        let mut tree = Self {
            nodes,
            node_first,
            lights,
            root,
            depth: 0,
            n: positions.len(),
            emission: emission.map_or_else(Vec::new, |e| {
                order.iter().map(|&i| *e[i as usize].shape()).collect()
            }),
            region: emission.and(region),
            mapped: Vec::new(),
            weights: emission.map(|_| {
                Box::new(MapWeights {
                    weight: order.iter().map(|&i| pmf.weight(raw[i as usize])).collect(),
                    reweighed: vec![0; m.div_ceil(64)],
                })
            }),
            cuts: None,
            order,
        };
        tree.depth = tree.deepest(tree.root);
        tree.fill_lanes(pmf.sum(), false);
        tree
    }

    /// Recomputes every lane's power, centroid and bounds from the lights, bottom up, and
    /// over spots the lanes' maps: every lane's, or with `only_reweighed` (a refit: same
    /// positions and profiles) only the lanes' intensities and the maps over a light whose
    /// weight changed (the others keep theirs); `sum` is the weights' sum.
    fn fill_lanes(&mut self, sum: f64, only_reweighed: bool) {
        if self.nodes.is_empty() {
            return;
        }
        let Some(emission) = (!self.emission.is_empty()).then_some(self.emission.as_slice()) else {
            let job = fill::Fill {
                nodes: &mut self.nodes,
                lanes: None,
                index: 0,
            };
            fill::fill::<fill::Aggregate>(job, &self.lights, None);
            return;
        };
        if only_reweighed {
            // A refit keeps the lanes' footprints and geometry and sums their intensities
            // again, into the mapped lanes.
            let job = fill::Fill {
                nodes: &mut self.nodes,
                lanes: Some(self.mapped.as_mut_slice()),
                index: 0,
            };
            fill::fill::<fill::Reweighed>(job, &self.lights, Some(emission));
            self.fill_grids(sum, None);
        } else {
            // A build's bounds live only until the mapped lanes hold what the descent
            // reads of them.
            let mut bounds = vec![[LaneBounds::EMPTY; TREE_WIDTH]; self.nodes.len()];
            let job = fill::Fill {
                nodes: &mut self.nodes,
                lanes: Some(bounds.as_mut_slice()),
                index: 0,
            };
            fill::fill::<fill::Bounded>(job, &self.lights, Some(emission));
            self.fill_grids(sum, Some(&bounds));
        }
    }

    /// Recomputes the lanes' maps ([`crate::spatial::grid`]) in the lights' weights, bottom
    /// up ([`map_fill`]: a leaf cluster's lane from its lights, a node's lane from its child
    /// node's maps; subtrees in parallel, the same bits on any thread count): in a build
    /// (`bounds`, each node's lanes' bounds) every lane's, and each lane's footprint, peak
    /// intensity and geometry taken from its bounds; in a refit (`None`) only those over a
    /// light whose bit in `reweighed` is set. Then every map is normalized by `sum`. A refit
    /// allocates nothing.
    fn fill_grids(&mut self, sum: f64, bounds: Option<&[[LaneBounds; TREE_WIDTH]]>) {
        use rayon::prelude::*;
        let mut mapped = std::mem::take(&mut self.mapped);
        mapped.resize(self.nodes.len(), MappedLanes::EMPTY);
        if let Some(bounds) = bounds {
            // A build: maps for the lanes that hold lights (a refit keeps them), and the
            // lanes' footprints and peak intensities, before their maps.
            mapped
                .par_iter_mut()
                .zip(self.nodes.par_iter())
                .zip(bounds.par_iter())
                .with_min_len(1 << 6)
                .for_each(|((lanes, node), bounds)| {
                    lanes.keep_maps(node.child.map(|c| c.get() != Child::Empty));
                    lanes.set_bounds(bounds);
                });
        }
        // Every tree over spots has weights.
        if let Some(w) = self.weights.as_deref() {
            map_fill::map_subtree(self, w, &mut mapped, 0, bounds.is_none());
            mapped
                .par_iter_mut()
                .with_min_len(1 << 6)
                .for_each(|lanes| lanes.normalize(sum));
        }
        self.mapped = mapped;
    }

    /// New powers for the same lights (same positions, cones and ranges): each light's
    /// normalized power is replaced and every lane recomputed bottom up, in parallel; the
    /// tree then equals [`LightTree::build`] over the new powers bit for bit (the layout
    /// depends on positions only, and both fill the lanes with the same pass).
    ///
    /// Its cost: for point lights `O(N)` with no allocation. For a tree with spots or ranges
    /// mapped over a region, the lanes' maps ([`crate::spatial::grid`]) are integrated in the
    /// lights' weights `w_i = Φ_i·2^-e` ([`crate::PmfScale::weight`]) and divided by their
    /// sum: a light whose power changes changes its weight, the others keep theirs (unless
    /// the largest power's binary exponent `e` changes), so only the lanes over a light whose
    /// weight changed are mapped again (its leaf cluster's lane from its lights, the lanes
    /// above from their children's maps), and every other map is divided by the new sum.
    /// One light's new power costs one leaf lane's integration and `O(depth)` resampled maps
    /// (`tree-refit-spots-one` in `lightpick bench`); new powers everywhere cost `O(N)`
    /// footprint integrations and `O(cells)` a node, as a build (`tree-refit-spots`). Nothing
    /// is allocated either way. A tree with per-tile cuts ([`super::TileCuts`]) drops its
    /// tiles' cuts (nothing allocated): each tile is cut again when a pick next needs it
    /// (`O(K · depth)` a tile; `tree-refit-cuts` times the refit with every tile cut).
    ///
    /// # Panics
    /// If `powers` holds a different number of lights.
    pub fn refit(&mut self, powers: &LightPowers) {
        use rayon::prelude::*;
        assert_eq!(powers.len(), self.n, "one power per light of the tree");
        let raw = powers.as_slice();
        let pmf = powers.pmf_scale();
        // Each light's new share is a function of its own power: any split gives the same.
        if let Some(w) = self.weights.as_deref_mut() {
            // Over spots also each light's weight, and which weights changed: 64 lights a
            // word of `reweighed`.
            self.lights
                .par_chunks_mut(64)
                .zip(w.weight.par_chunks_mut(64))
                .zip(self.order.par_chunks(64))
                .zip(w.reweighed.par_iter_mut())
                .with_min_len(1 << 8)
                .for_each(|(((lights, weights), order), bits)| {
                    *bits = 0;
                    for (j, ((l, w), &i)) in lights.iter_mut().zip(weights).zip(order).enumerate() {
                        let new = pmf.weight(raw[i as usize]);
                        if new.to_bits() != w.to_bits() {
                            *bits |= 1 << j;
                            *w = new;
                        }
                        l.power = pmf.of(raw[i as usize]);
                    }
                });
        } else {
            self.lights
                .par_iter_mut()
                .zip(self.order.par_iter())
                .with_min_len(1 << 14)
                .for_each(|(l, &i)| l.power = pmf.of(raw[i as usize]));
        }
        self.fill_lanes(pmf.sum(), true);
        // Read; cleared for the next refit (and so that the tree equals a fresh build).
        if let Some(w) = self.weights.as_deref_mut() {
            w.reweighed.fill(0);
        }
        if let Some(cuts) = &mut self.cuts {
            cuts.clear();
        }
    }
}

/// The layout of the contributing lights (scene index, light, profile): the internal nodes,
/// each node's first light, the scene index of each light in leaf order, and the root.
/// Spots and ranges are split by where they shine ([`footprint_split`]), point lights at
/// medians of their positions ([`layout`]).
fn lay_out(
    contributing: &[(u32, SpatialLight, Option<EmissionShape>)],
    shaped: bool,
) -> (Vec<TreeNode>, Vec<u32>, Vec<u32>, ChildRef) {
    let m = contributing.len();
    // Spots and ranges: split by where the lights shine.
    if shaped && m > LEAF_SIZE {
        let mut items: Vec<footprint_split::Footprinted> = contributing
            .iter()
            .map(|(i, l, shape)| {
                let shape = shape.unwrap_or_default();
                footprint_split::Footprinted::new(*i, l.position_in_world, &shape)
            })
            .collect();
        let (nodes, node_first) = footprint_split::lay_out(&mut items);
        let order = items.iter().map(|l| l.index).collect();
        return (nodes, node_first, order, ChildRef::node(0));
    }
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
