//! The tree's layout over lights with spot cones or ranges: binary splits by a surface-area
//! heuristic over the lights' **footprints** on the plane (the region each can light,
//! [`EmissionShape::footprint`]), two of them per 4-wide node. Spots that shine on one part
//! of the plane share lanes, whatever truss they hang from, so a lane's map of what it gives
//! the plane ([`super::super::grid`]) is sharp and its footprint culls the rest of the plane.
//!
//! # The cost of a split
//! A range of lights is split in two where
//!
//! `cost(side) = n · area(footprints)`
//!
//! summed over both sides is least, among 12 buckets of the footprints' centres along `x`
//! and along `y` (the buckets of pbrt-v4's and Cycles' builds):
//!
//! * `n`: the side's number of lights. Counting lights rather than weighing their powers
//!   keeps the layout a function of positions and cones alone, so that new powers refit the
//!   tree ([`super::LightTree::refit`]) and the refit equals a fresh build bit for bit;
//! * `area(footprints)`: the area of the box holding the side's footprints, each extent
//!   padded by `10^-3` of the range's longest one (so that equal footprints still cost).
//!
//! A light whose footprint is unbounded (a point light, a spot that reaches the horizon)
//! stands for its own position on the plane. The surface-area-orientation heuristic of
//! pbrt-v4 and Cycles (position boxes, cones of axes) was measured beside this split and
//! lost on every spot scene: the table is in the [`super::super::grid`] docs.
//!
//! A node splits its range in two, then each half above a leaf cluster in two again, so a
//! half of at most [`LEAF_SIZE`] lights leaves one lane empty. Splitting the largest range
//! until the four lanes are full was measured (10^5 spots of `lightpick bench`: 10 % fewer
//! nodes, 23 bytes a light less; `tile_cuts` example: the same time per pick with
//! the tiles' cuts, their variance 11 % higher on `gallery` and 4 % on `arena`) and not kept.
//!
//! # Determinism
//! Buckets, costs and the in-place partition depend only on the lights and their order,
//! never on threads: large ranges lay out their parts in parallel, each on its own slice,
//! so the layout is the same on any number of threads.

use glam::{DVec2, DVec3};

use super::node::{ChildRef, LEAF_SIZE, TREE_WIDTH, TreeNode};
use crate::scene::EmissionShape;

/// Buckets along each key (pbrt and Cycles use 12).
const BUCKETS: usize = 12;

/// Ranges of more lights than this lay out their parts in parallel.
const PARALLEL_LAYOUT: usize = 1 << 13;

/// What the split reads of one light: its scene index and its footprint's box.
#[derive(Clone, Copy, Debug)]
pub(super) struct Footprinted {
    /// The light's scene index.
    pub(super) index: u32,
    /// The box on the plane outside which it gives nothing ([`EmissionShape::footprint`]), or
    /// its position on the plane when that region is unbounded.
    area: [DVec2; 2],
}

impl Footprinted {
    /// The light `index` at `position` with the profile `emission`.
    pub(super) fn new(index: u32, position: DVec3, emission: &EmissionShape) -> Self {
        let at = position.truncate();
        Footprinted {
            index,
            area: emission.footprint(position).unwrap_or([at, at]),
        }
    }

    /// The footprint's centre along `k` (0: `x`, 1: `y`).
    #[inline]
    fn key(&self, k: usize) -> f64 {
        0.5 * (self.area[0][k] + self.area[1][k])
    }
}

/// A side of a candidate split: its light count and the box of its footprints.
#[derive(Clone, Copy, Debug)]
struct Side {
    count: usize,
    min: DVec2,
    max: DVec2,
}

impl Side {
    const EMPTY: Side = Side {
        count: 0,
        min: DVec2::INFINITY,
        max: DVec2::NEG_INFINITY,
    };

    fn add(&mut self, l: &Footprinted) {
        self.count += 1;
        self.min = self.min.min(l.area[0]);
        self.max = self.max.max(l.area[1]);
    }

    fn union(&self, o: &Side) -> Side {
        Side {
            count: self.count + o.count,
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// `n · area` with each extent padded by `pad`.
    fn cost(&self, pad: f64) -> f64 {
        let d = self.max - self.min + DVec2::splat(pad);
        self.count as f64 * d.x * d.y
    }
}

/// The bucket of key value `v` in `[low, high]` (`high > low`).
#[inline]
fn bucket(v: f64, low: f64, high: f64) -> usize {
    (((v - low) / (high - low) * BUCKETS as f64) as usize).min(BUCKETS - 1)
}

/// Splits `items` (at least two) in two by the least cost and returns the size of the
/// first part (`1 ..= len − 1`); in the middle when no key separates them.
fn split(items: &mut [Footprinted]) -> usize {
    let all = items.iter().fold(Side::EMPTY, |mut s, l| {
        s.add(l);
        s
    });
    let pad = 1e-3 * (all.max - all.min).max_element().max(f64::MIN_POSITIVE);
    // (cost, key, last bucket of the first part, key range)
    let mut best: Option<(f64, usize, usize, f64, f64)> = None;
    for k in 0..2 {
        let (low, high) = items
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), l| {
                (a.min(l.key(k)), b.max(l.key(k)))
            });
        if high.partial_cmp(&low) != Some(std::cmp::Ordering::Greater) {
            continue;
        }
        let mut buckets = [Side::EMPTY; BUCKETS];
        for l in items.iter() {
            buckets[bucket(l.key(k), low, high)].add(l);
        }
        let mut below = [Side::EMPTY; BUCKETS];
        let mut running = Side::EMPTY;
        for (b, side) in buckets.iter().zip(&mut below) {
            running = running.union(b);
            *side = running;
        }
        let mut above = Side::EMPTY;
        for last in (0..BUCKETS - 1).rev() {
            above = above.union(&buckets[last + 1]);
            if below[last].count == 0 || above.count == 0 {
                continue;
            }
            let cost = below[last].cost(pad) + above.cost(pad);
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, k, last, low, high));
            }
        }
    }
    let Some((_, k, last, low, high)) = best else {
        return items.len() / 2;
    };
    // In place: the first part's lights to the front.
    let first = |l: &Footprinted| bucket(l.key(k), low, high) <= last;
    let (mut i, mut j) = (0, items.len());
    while i < j {
        if first(&items[i]) {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    i
}

/// Lays out `items` (more than [`LEAF_SIZE`]) and returns each internal node's lane sizes
/// in depth-first order (the node, then its lanes' subtrees in lane order); permutes the
/// items into leaf order.
fn lane_sizes(items: &mut [Footprinted]) -> Vec<[u32; TREE_WIDTH]> {
    let len = items.len();
    let mid = split(items);
    let (left, right) = items.split_at_mut(mid);
    let mut ranges: Vec<&mut [Footprinted]> = Vec::with_capacity(TREE_WIDTH);
    for half in [left, right] {
        if half.len() > LEAF_SIZE {
            let quarter = split(half);
            let (a, b) = half.split_at_mut(quarter);
            ranges.push(a);
            ranges.push(b);
        } else {
            ranges.push(half);
        }
    }
    let mut sizes = [0u32; TREE_WIDTH];
    for (s, r) in sizes.iter_mut().zip(&ranges) {
        *s = r.len() as u32;
    }
    let below = |r: &mut [Footprinted]| {
        if r.len() > LEAF_SIZE {
            lane_sizes(r)
        } else {
            Vec::new()
        }
    };
    let subtrees: Vec<Vec<[u32; TREE_WIDTH]>> = if len > PARALLEL_LAYOUT {
        use rayon::prelude::*;
        ranges.into_par_iter().map(below).collect()
    } else {
        ranges.into_iter().map(below).collect()
    };
    let mut out = Vec::with_capacity(1 + subtrees.iter().map(Vec::len).sum::<usize>());
    out.push(sizes);
    for s in subtrees {
        out.extend(s);
    }
    out
}

/// The layout of `items` (more than [`LEAF_SIZE`]): the internal nodes with their child
/// words set (the lanes' data are left for [`super::fill`]) and each node's first light
/// in leaf order; the items are permuted into leaf order. The root is node 0.
pub(super) fn lay_out(items: &mut [Footprinted]) -> (Vec<TreeNode>, Vec<u32>) {
    let sizes = lane_sizes(items);
    let mut nodes = vec![TreeNode::EMPTY; sizes.len()];
    let mut node_first = vec![0u32; sizes.len()];
    let mut next = 0;
    assign(&sizes, &mut next, 0, &mut nodes, &mut node_first);
    debug_assert_eq!(next, sizes.len());
    (nodes, node_first)
}

/// Sets the child words of the node at `*next` (whose lights start at leaf-order index
/// `first`) and, depth first, of its subtrees; returns its reference.
fn assign(
    sizes: &[[u32; TREE_WIDTH]],
    next: &mut usize,
    first: usize,
    nodes: &mut [TreeNode],
    node_first: &mut [u32],
) -> ChildRef {
    let k = *next;
    *next += 1;
    node_first[k] = first as u32;
    let mut start = first;
    for lane in 0..TREE_WIDTH {
        let s = sizes[k][lane] as usize;
        nodes[k].child[lane] = match s {
            0 => ChildRef::EMPTY,
            s if s <= LEAF_SIZE => ChildRef::leaf(start, s),
            _ => assign(sizes, next, start, nodes, node_first),
        };
        start += s;
    }
    ChildRef::node(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(index: u32, lo: [f64; 2], hi: [f64; 2]) -> Footprinted {
        Footprinted {
            index,
            area: [DVec2::from(lo), DVec2::from(hi)],
        }
    }

    #[test]
    fn a_split_separates_two_groups_of_footprints() {
        // Two clusters of footprints, interleaved in the input order.
        let mut items: Vec<Footprinted> = (0..20)
            .map(|i| {
                let x = if i % 2 == 0 { 0.0 } else { 10.0 } + 0.01 * f64::from(i);
                at(i, [x, 0.0], [x + 1.0, 1.0])
            })
            .collect();
        let mid = split(&mut items);
        assert_eq!(mid, 10);
        assert!(items[..mid].iter().all(|l| l.index % 2 == 0));
        assert!(items[mid..].iter().all(|l| l.index % 2 == 1));
    }

    #[test]
    fn identical_footprints_split_in_the_middle() {
        let mut items: Vec<Footprinted> = (0..9).map(|i| at(i, [0.0, 0.0], [1.0, 1.0])).collect();
        assert_eq!(split(&mut items), 4);
    }

    #[test]
    fn the_layout_covers_every_light_once() {
        let mut items: Vec<Footprinted> = (0..1000)
            .map(|i| {
                let x = f64::from((i * 37) % 101);
                let y = f64::from((i * 11) % 53);
                at(i, [x, y], [x + 2.0, y + 3.0])
            })
            .collect();
        let (nodes, node_first) = lay_out(&mut items);
        let mut seen = vec![false; 1000];
        for l in &items {
            assert!(!std::mem::replace(&mut seen[l.index as usize], true));
        }
        assert!(seen.iter().all(|&s| s));
        // Leaves cover 0..1000 in leaf order, each at most LEAF_SIZE.
        let mut covered = 0;
        let mut stack = vec![0usize];
        while let Some(k) = stack.pop() {
            assert!(node_first[k] as usize <= 1000);
            for lane in 0..TREE_WIDTH {
                match nodes[k].child[lane].get() {
                    super::super::node::Child::Node(j) => stack.push(j),
                    super::super::node::Child::Leaf { count, .. } => {
                        assert!(count <= LEAF_SIZE);
                        covered += count;
                    }
                    super::super::node::Child::Empty => {}
                }
            }
        }
        assert_eq!(covered, 1000);
    }
}
