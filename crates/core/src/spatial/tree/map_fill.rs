//! The lanes' maps over spots ([`crate::spatial::grid`]), bottom up: a lane over a leaf
//! cluster integrates its lights ([`LaneGrid::of_weighted`]), a lane over a node resamples
//! that node's four maps ([`LaneGrid::of_lanes`]). Each light is integrated once, into its
//! leaf cluster's lane, whatever the tree's depth; a lane above costs `O(cells)`. Subtrees
//! are mapped in parallel, each in a fixed order, so the maps do not depend on the thread
//! count, and a refit maps what a build maps.

use super::fill::subtree_end;
use super::node::{Child, ChildRef, LEAF_SIZE, TREE_WIDTH};
use super::{LightTree, MapWeights};
use crate::spatial::grid::{LaneGrid, MappedLanes};

/// Subtrees of more nodes than this are mapped in parallel.
const PARALLEL_MAP: usize = 1 << 6;

/// Maps the lanes of the subtree of node `index`, whose nodes (its own first, then its
/// subtrees depth first) are `slots`, in the lights' weights `w`: every lane, or with
/// `only_reweighed` only the lanes over a light whose bit in `w.reweighed` is set (a lane
/// whose lights kept their weights keeps its map: it would map to the same bits). The maps'
/// normalization is left to the caller.
pub(super) fn map_subtree(
    tree: &LightTree,
    w: &MapWeights,
    slots: &mut [MappedLanes],
    index: usize,
    only_reweighed: bool,
) {
    let node = &tree.nodes[index];
    // Which lanes to map, each found once (a lane's lights by `span`, `O(depth)`).
    let remap: [bool; TREE_WIDTH] = std::array::from_fn(|lane| {
        !only_reweighed
            || tree
                .span(node.child[lane])
                .is_some_and(|r| any_bit_in(&w.reweighed, r))
    });
    if !remap.contains(&true) {
        return;
    }
    let end = index + slots.len();
    let children = node.child.map(ChildRef::get);
    let (this, mut below) = slots.split_at_mut(1);
    // Each internal lane's subtree: its slots and its node's index (no allocation).
    let mut jobs: [Option<(&mut [MappedLanes], usize)>; TREE_WIDTH] = std::array::from_fn(|_| None);
    for (lane, child) in children.iter().enumerate() {
        if let Child::Node(k) = *child {
            let (subtree, rest) = below.split_at_mut(subtree_end(&children, lane, end) - k);
            below = rest;
            jobs[lane] = Some((subtree, k));
        }
    }
    let map_one = |job: &mut Option<(&mut [MappedLanes], usize)>| {
        if let Some((subtree, k)) = job {
            map_subtree(tree, w, subtree, *k, only_reweighed);
        }
    };
    if end - index > PARALLEL_MAP {
        use rayon::prelude::*;
        jobs.par_iter_mut().for_each(map_one);
    } else {
        jobs.iter_mut().for_each(map_one);
    }
    let lanes = &mut this[0];
    for (lane, child) in children.iter().enumerate() {
        if !remap[lane] {
            continue;
        }
        let grid = match (child, &jobs[lane]) {
            (Child::Node(_), Some((subtree, _))) => LaneGrid::of_lanes(&subtree[0]),
            (Child::Leaf { first, count }, _) => {
                let r = *first..first + count;
                let weights = &w.weight[r.clone()];
                let mut footprints = [None; LEAF_SIZE];
                for (j, f) in r.clone().zip(&mut footprints) {
                    *f = tree.footprint(j);
                }
                LaneGrid::of_weighted(
                    &tree.lights[r.clone()],
                    |j| weights[j],
                    &tree.emission[r],
                    &footprints[..*count],
                )
            }
            _ => LaneGrid::EMPTY,
        };
        lanes.set_map(lane, &grid);
    }
}

/// Whether any bit of `bits` (bit `j % 64` of word `j / 64` for `j`) in `range` is set.
fn any_bit_in(bits: &[u64], range: std::ops::Range<usize>) -> bool {
    if range.is_empty() {
        return false;
    }
    let (first, last) = (range.start / 64, (range.end - 1) / 64);
    let head = u64::MAX << (range.start % 64);
    let tail = u64::MAX >> (63 - (range.end - 1) % 64);
    if first == last {
        return bits[first] & head & tail != 0;
    }
    bits[first] & head != 0
        || bits[first + 1..last].iter().any(|&w| w != 0)
        || bits[last] & tail != 0
}

#[cfg(test)]
mod tests {
    use super::any_bit_in;

    /// Every range of a 200-bit set, against a bit-by-bit scan.
    #[test]
    fn any_bit_in_a_range_is_found_as_a_scan_finds_it() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for density in [1u64, 8, 64] {
            let mut bits = [0u64; 4];
            for j in 0..200 {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                if (state >> 33).is_multiple_of(density) {
                    bits[j / 64] |= 1 << (j % 64);
                }
            }
            for start in 0..=200 {
                for end in start..=200 {
                    let scanned = (start..end).any(|j| bits[j / 64] >> (j % 64) & 1 == 1);
                    assert_eq!(any_bit_in(&bits, start..end), scanned, "{start}..{end}");
                }
            }
        }
    }
}
