//! The lanes' data, bottom up: each lane's normalized power `Σ p_i`, power-weighted
//! centroid (the representative light of [`super::super::importance`]) and, for lights with
//! emission profiles, its [`LaneBounds`]. A lane over a subtree combines its child node's
//! four lanes; a lane over a leaf cluster sums its lights. The same pass serves the build
//! and [`super::LightTree::refit`] (new powers, same layout), so a refit equals a fresh
//! build bit for bit; subtrees are filled in parallel, each in a fixed order, so the result
//! does not depend on the thread count.

use glam::DVec3;

use super::node::{Child, ChildRef, TREE_WIDTH, TreeNode};
use crate::scene::EmissionShape;
use crate::spatial::grid::MappedLanes;
use crate::spatial::{LaneBounds, SpatialLight};

/// Subtrees of more nodes than this (about `2^13` lights) are filled in parallel.
const PARALLEL_FILL: usize = 1 << 9;

/// What a lane (or a whole node) holds, summed: power, the pieces of its power-weighted
/// centroid and the box of its lights. 80 bytes: the pass moves many of these, so the
/// lights with profiles carry their bounds beside it ([`Bounded`]) rather than in it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Aggregate {
    /// `Σ p_i`.
    pub(super) power: f64,
    /// The power-weighted centroid, clamped into the box (the box's centre without power).
    pub(super) centroid: DVec3,
    min: DVec3,
    max: DVec3,
}

/// An [`Aggregate`] with the lane's [`LaneBounds`] (`None` for an empty lane), for lights
/// with emission profiles.
#[derive(Clone, Copy, Debug)]
pub(super) struct Bounded {
    aggregate: Aggregate,
    bounds: Option<LaneBounds>,
}

/// What the pass sums per lane: [`Aggregate`] for point lights, [`Bounded`] with profiles.
pub(super) trait Summary: Copy + Send {
    /// An empty lane.
    const EMPTY: Self;
    /// The lights of a leaf cluster (with their profiles for [`Bounded`]).
    fn of_leaf(lights: &[SpatialLight], emission: Option<&[EmissionShape]>) -> Self;
    /// A node's lanes, together.
    fn of_lanes(lanes: &[Self; TREE_WIDTH]) -> Self;
    /// The power and centroid part.
    fn aggregate(&self) -> &Aggregate;
    /// What the pass writes for each node beside its [`TreeNode`]: nothing over point
    /// lights, the lanes' bounds in a build over profiles, their intensities in a refit.
    type Lanes: Send;
    /// Writes a node's lanes' part into `out`.
    fn write_lanes(lanes: &[Self; TREE_WIDTH], out: &mut Self::Lanes);
}

impl Summary for Aggregate {
    const EMPTY: Aggregate = Aggregate {
        power: 0.0,
        centroid: DVec3::new(0.0, 0.0, 1.0),
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
    };

    fn of_leaf(lights: &[SpatialLight], _emission: Option<&[EmissionShape]>) -> Self {
        let (power, centroid, min, max) = Self::combine(lights.iter().map(|l| {
            (
                l.power,
                l.position_in_world,
                l.position_in_world,
                l.position_in_world,
            )
        }));
        Aggregate {
            power,
            centroid,
            min,
            max,
        }
    }

    fn of_lanes(lanes: &[Aggregate; TREE_WIDTH]) -> Self {
        let (power, centroid, min, max) =
            Self::combine(lanes.iter().map(|a| (a.power, a.centroid, a.min, a.max)));
        Aggregate {
            power,
            centroid,
            min,
            max,
        }
    }

    fn aggregate(&self) -> &Aggregate {
        self
    }

    type Lanes = ();

    fn write_lanes(_: &[Self; TREE_WIDTH], (): &mut ()) {}
}

impl Summary for Bounded {
    const EMPTY: Bounded = Bounded {
        aggregate: Aggregate::EMPTY,
        bounds: None,
    };

    fn of_leaf(lights: &[SpatialLight], emission: Option<&[EmissionShape]>) -> Self {
        let bounds = emission.map(|e| {
            lights.iter().zip(e).fold(LaneBounds::EMPTY, |b, (l, e)| {
                LaneBounds::union(&b, &LaneBounds::of_light(l, e))
            })
        });
        Bounded {
            aggregate: Aggregate::of_leaf(lights, emission),
            bounds,
        }
    }

    fn of_lanes(lanes: &[Bounded; TREE_WIDTH]) -> Self {
        let bounds = lanes[0].bounds.map(|first| {
            lanes[1..]
                .iter()
                .filter_map(|a| a.bounds)
                .fold(first, |b, l| LaneBounds::union(&b, &l))
        });
        Bounded {
            aggregate: Aggregate::of_lanes(&lanes.map(|l| l.aggregate)),
            bounds,
        }
    }

    fn aggregate(&self) -> &Aggregate {
        &self.aggregate
    }

    type Lanes = [LaneBounds; TREE_WIDTH];

    fn write_lanes(lanes: &[Self; TREE_WIDTH], out: &mut [LaneBounds; TREE_WIDTH]) {
        *out = lanes.map(|a| a.bounds.unwrap_or(LaneBounds::EMPTY));
    }
}

/// An [`Aggregate`] with the lane's `Σ p_i·g_i` alone (`None` for an empty lane), for a
/// refit over lights with profiles, written into the node's [`MappedLanes`]: the rest of a
/// lane's [`LaneBounds`] (boxes, cones, ranges, footprints) depends on positions and
/// profiles only, so it stays as built, and
/// the sum is taken in the order [`LaneBounds::union`] takes it (a lane's lights in leaf
/// order, a node's lanes in lane order): the same bits as a build, without the lights'
/// footprints and cones computed again.
#[derive(Clone, Copy, Debug)]
pub(super) struct Reweighed {
    aggregate: Aggregate,
    intensity: Option<f64>,
}

impl Summary for Reweighed {
    const EMPTY: Reweighed = Reweighed {
        aggregate: Aggregate::EMPTY,
        intensity: None,
    };

    fn of_leaf(lights: &[SpatialLight], emission: Option<&[EmissionShape]>) -> Self {
        let intensity = emission.map(|e| {
            // `LaneBounds::EMPTY ∪ first` is the first light's bounds, then each adds.
            let mut each = lights.iter().zip(e).map(|(l, e)| l.power * e.gain());
            let first = each.next().unwrap_or(0.0);
            each.fold(first, |sum, i| sum + i)
        });
        Reweighed {
            aggregate: Aggregate::of_leaf(lights, emission),
            intensity,
        }
    }

    fn of_lanes(lanes: &[Reweighed; TREE_WIDTH]) -> Self {
        let intensity = lanes[0].intensity.map(|first| {
            lanes[1..]
                .iter()
                .filter_map(|a| a.intensity)
                .fold(first, |sum, i| sum + i)
        });
        Reweighed {
            aggregate: Aggregate::of_lanes(&lanes.map(|l| l.aggregate)),
            intensity,
        }
    }

    fn aggregate(&self) -> &Aggregate {
        &self.aggregate
    }

    type Lanes = MappedLanes;

    /// Only each lane's intensity: the rest is as built (an empty lane's stays 0).
    fn write_lanes(lanes: &[Self; TREE_WIDTH], out: &mut MappedLanes) {
        for (k, lane) in lanes.iter().enumerate() {
            if let Some(i) = lane.intensity {
                out.set_intensity(k, i);
            }
        }
    }
}

impl Aggregate {
    /// The reach of what was summed ([`TreeNode`]'s `reach`): the distance from its centroid
    /// to the farthest corner of its lights' box (every light lies within it), rounded up
    /// to `f32`, and the box's lowest height rounded down; `0` and `∞` without lights.
    fn reach(&self) -> [f32; 2] {
        if self.min.z > self.max.z {
            return [0.0, f32::INFINITY];
        }
        let farthest = (self.centroid - self.min).max(self.max - self.centroid);
        // One step of `f32` beyond the nearest `f32` covers the `f64` roundings of the
        // length (relative `~10^-16`).
        let radius = (farthest.length() as f32).next_up();
        let floor = (self.min.z as f32).next_down().max(0.0);
        [radius, floor]
    }

    /// `Σ w_k·y_k / Σ w_k` with `w_k = p_k / max p` (no underflow however small the powers),
    /// clamped into the box; the box's centre when nothing has power.
    fn combine(
        parts: impl Iterator<Item = (f64, DVec3, DVec3, DVec3)> + Clone,
    ) -> (f64, DVec3, DVec3, DVec3) {
        let largest = parts.clone().map(|(p, ..)| p).fold(0.0f64, f64::max);
        let (mut power, mut weight, mut weighted) = (0.0, 0.0, DVec3::ZERO);
        let (mut min, mut max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (p, c, lo, hi) in parts {
            power += p;
            min = min.min(lo);
            max = max.max(hi);
            if largest > 0.0 {
                let w = p / largest;
                weight += w;
                weighted += w * c;
            }
        }
        let centroid = if weight > 0.0 {
            (weighted / weight).clamp(min, max)
        } else {
            0.5 * (min + max)
        };
        (power, centroid, min, max)
    }
}

/// Where the subtree of a node's internal lane `lane` ends in the depth-first layout: at
/// the next internal lane's node, or at `end`, the end of the node's own subtree.
pub(super) fn subtree_end(children: &[Child; TREE_WIDTH], lane: usize, end: usize) -> usize {
    children[lane + 1..]
        .iter()
        .find_map(|c| match c {
            Child::Node(j) => Some(*j),
            _ => None,
        })
        .unwrap_or(end)
}

/// One subtree to fill: its node slots (its own first, then its subtrees depth first) and
/// what the pass writes beside each ([`Summary::Lanes`]; `None`: nothing), and the global
/// index of its node.
pub(super) struct Fill<'a, L> {
    pub(super) nodes: &'a mut [TreeNode],
    pub(super) lanes: Option<&'a mut [L]>,
    pub(super) index: usize,
}

/// Fills the subtree's nodes' lanes from `lights` (leaf order, with `emission` beside them
/// when the lights have profiles, then summed as [`Bounded`]) and returns the node's
/// summary.
///
/// The node's child words say what each lane holds: a leaf cluster's lights, or an
/// internal node whose subtree occupies the slots from its index up to the next internal
/// lane's index (or the end of this subtree's slots): the depth-first layout, whatever
/// split made it.
pub(super) fn fill<S: Summary>(
    job: Fill<'_, S::Lanes>,
    lights: &[SpatialLight],
    emission: Option<&[EmissionShape]>,
) -> S {
    let Fill {
        nodes,
        lanes: out,
        index,
    } = job;
    let end = index + nodes.len();
    let children = nodes[0].child.map(ChildRef::get);
    let (this, mut below) = nodes.split_at_mut(1);
    let (this_out, mut below_out) = match out {
        Some(b) => {
            let (t, r) = b.split_at_mut(1);
            (Some(t), Some(r))
        }
        None => (None, None),
    };
    // Each lane: a leaf cluster now, or a subtree to fill (in parallel when large).
    let mut lanes = [S::EMPTY; TREE_WIDTH];
    // At most one subtree per lane, in arrays: the pass allocates nothing.
    let mut jobs: [Option<Fill<'_, S::Lanes>>; TREE_WIDTH] = std::array::from_fn(|_| None);
    for (lane, child) in children.iter().enumerate() {
        match *child {
            Child::Leaf { first, count } => {
                lanes[lane] = S::of_leaf(
                    &lights[first..first + count],
                    emission.map(|e| &e[first..first + count]),
                );
            }
            Child::Node(k) => {
                let count = subtree_end(&children, lane, end) - k;
                let (slots, rest) = below.split_at_mut(count);
                below = rest;
                let slot_out = below_out.take().map(|b| {
                    let (slots, rest) = b.split_at_mut(count);
                    below_out = Some(rest);
                    slots
                });
                jobs[lane] = Some(Fill {
                    nodes: slots,
                    lanes: slot_out,
                    index: k,
                });
            }
            Child::Empty => {}
        }
    }
    // Each subtree's aggregate lands in its lane directly (no copies of the large
    // aggregates through a results array).
    let fill_one = |(lane, job): (&mut S, &mut Option<Fill<'_, S::Lanes>>)| {
        if let Some(job) = job.take() {
            *lane = fill(job, lights, emission);
        }
    };
    if end - index > PARALLEL_FILL {
        use rayon::prelude::*;
        lanes
            .par_iter_mut()
            .zip(jobs.par_iter_mut())
            .for_each(fill_one);
    } else {
        lanes.iter_mut().zip(jobs.iter_mut()).for_each(fill_one);
    }
    let node = &mut this[0];
    for (lane, a) in lanes.iter().enumerate() {
        let a = a.aggregate();
        node.power[lane] = a.power;
        for (axis, c) in node.centroid.iter_mut().zip(a.centroid.to_array()) {
            axis[lane] = c;
        }
    }
    if let Some(out) = this_out {
        S::write_lanes(&lanes, &mut out[0]);
    }
    let summary = S::of_lanes(&lanes);
    node.reach = summary.aggregate().reach();
    summary
}
