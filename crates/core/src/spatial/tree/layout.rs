//! The tree's layout: which lights go under which lane, by median splits of the lights'
//! positions. It depends on the positions alone, never on the powers, so new powers keep
//! it and only the lanes' data are recomputed ([`super::fill`]). (Splitting spots by where
//! they shine as well was tried on `stage` and raised the mean relative variance from 6.5
//! to 11.8: the representative light's centroid then mixes far-apart positions.)

use glam::DVec3;

use super::node::{ChildRef, LEAF_SIZE, TREE_WIDTH, TreeNode};

/// Ranges of more lights than this lay out their subtrees in parallel.
const PARALLEL_LAYOUT: usize = 1 << 13;

/// Internal nodes of a range of `m` lights: 0 for a leaf cluster, else one plus those of
/// its parts ([`parts`]). Depends only on `m`, which fixes the depth-first layout.
///
/// `O(log m)`: one descent computes the counts of two neighbouring sizes at each level
/// ([`part_internal_nodes`]) instead of visiting every subtree.
pub(super) fn internal_nodes(m: usize) -> usize {
    internal_nodes_pair(m).0
}

/// `(internal_nodes(k), internal_nodes(k + 1))`.
fn internal_nodes_pair(k: usize) -> (usize, usize) {
    if k < LEAF_SIZE {
        // k + 1 ≤ LEAF_SIZE: both are leaf clusters.
        return (0, 0);
    }
    let count = |m: usize| {
        if m <= LEAF_SIZE {
            0
        } else {
            1 + part_internal_nodes(m).iter().sum::<usize>()
        }
    };
    (count(k), count(k + 1))
}

/// [`internal_nodes`] of each of the parts of `m > LEAF_SIZE` ([`parts`], lane order).
///
/// Halves of `m` lie in `{⌊m/2⌋, ⌊m/2⌋ + 1}`, so the parts that are split further (not
/// leaf clusters) lie in `{q, q + 1}` with `q = ⌊⌊m/2⌋/2⌋`: one descent for the pair.
pub(super) fn part_internal_nodes(m: usize) -> [usize; TREE_WIDTH] {
    let q = m / 2 / 2;
    let (at_q, at_q1) = internal_nodes_pair(q);
    parts(m).map(|s| match s {
        s if s <= LEAF_SIZE => 0,
        s if s == q => at_q,
        s => {
            debug_assert_eq!(s, q + 1, "a part of {m} outside {{q, q + 1}}");
            at_q1
        }
    })
}

/// The sizes of the children of a range of `m > LEAF_SIZE` lights, in lane order (0 for an
/// unused lane): the halves `⌊m/2⌋`, `⌈m/2⌉`, each halved again when larger than a leaf.
pub(super) fn parts(m: usize) -> [usize; TREE_WIDTH] {
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

/// A light to lay out: its scene index and its position.
pub(super) type Item = (u32, DVec3);

/// The longest axis of the positions' box (the first of equals).
fn longest_axis(items: &[Item]) -> usize {
    let (min, max) = items.iter().fold(
        (DVec3::INFINITY, DVec3::NEG_INFINITY),
        |(lo, hi), (_, k)| (lo.min(*k), hi.max(*k)),
    );
    let e = max - min;
    if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    }
}

/// Splits `items` at the median along the longest axis of their positions (ties by scene
/// index).
fn split_at_median(items: &mut [Item]) -> usize {
    let axis = longest_axis(items);
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| {
        a.1[axis].total_cmp(&b.1[axis]).then(a.0.cmp(&b.0))
    });
    mid
}

/// One subtree to lay out: its items (more than [`LEAF_SIZE`]), its node's index and
/// leaf-order offset, and the node slots of the subtree (its own first).
pub(super) struct Job<'a> {
    pub(super) items: &'a mut [Item],
    pub(super) index: usize,
    pub(super) first: usize,
    pub(super) nodes: &'a mut [TreeNode],
    pub(super) node_first: &'a mut [u32],
}

/// Sets the job's node's child words and, depth first, lays out its subtrees (in parallel
/// when large); permutes the items into leaf order.
pub(super) fn lay_out(job: Job<'_>) {
    let Job {
        items,
        index,
        first,
        nodes,
        node_first,
    } = job;
    // The parts in lane order: halves at the median, each halved again if larger than a leaf
    // (the sizes of `parts`).
    let len = items.len();
    let mid = split_at_median(items);
    let (left, right) = items.split_at_mut(mid);
    let mut ranges: Vec<&mut [Item]> = Vec::with_capacity(TREE_WIDTH);
    for half in [left, right] {
        if half.len() > LEAF_SIZE {
            let quarter = split_at_median(half);
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
            .eq(parts(len).into_iter().filter(|&s| s > 0))
    );
    let (this, mut below) = nodes.split_at_mut(1);
    let (this_first, mut below_first) = node_first.split_at_mut(1);
    this_first[0] = first as u32;
    let mut jobs = Vec::with_capacity(TREE_WIDTH);
    let (mut next_index, mut next_first) = (index + 1, first);
    for (lane, range) in ranges.into_iter().enumerate() {
        let count = internal_nodes(range.len());
        let len = range.len();
        if count == 0 {
            this[0].child[lane] = ChildRef::leaf(next_first, len);
        } else {
            this[0].child[lane] = ChildRef::node(next_index);
            let (slots, rest) = below.split_at_mut(count);
            let (slots_first, rest_first) = below_first.split_at_mut(count);
            below = rest;
            below_first = rest_first;
            jobs.push(Job {
                items: range,
                index: next_index,
                first: next_first,
                nodes: slots,
                node_first: slots_first,
            });
        }
        next_index += count;
        next_first += len;
    }
    if jobs.iter().map(|j| j.items.len()).sum::<usize>() > PARALLEL_LAYOUT {
        rayon::scope(|s| {
            for job in jobs {
                s.spawn(move |_| lay_out(job));
            }
        });
    } else {
        jobs.into_iter().for_each(lay_out);
    }
}

#[cfg(test)]
mod tests {
    use super::{LEAF_SIZE, internal_nodes, part_internal_nodes, parts};

    /// The definition, visiting every subtree.
    fn by_definition(m: usize) -> usize {
        if m <= LEAF_SIZE {
            return 0;
        }
        1 + parts(m).iter().map(|&s| by_definition(s)).sum::<usize>()
    }

    #[test]
    fn internal_nodes_follows_its_definition() {
        let large = [65_536, 99_999, 1_000_000, 1_048_575, 1_048_577, 3_000_001];
        for m in (0..5000).chain(large) {
            assert_eq!(internal_nodes(m), by_definition(m), "m = {m}");
            if m > LEAF_SIZE {
                let each = parts(m).map(by_definition);
                assert_eq!(part_internal_nodes(m), each, "m = {m}");
            }
        }
    }
}
