//! One spatial pick recorded step by step: what the light tree's descent
//! ([`crate::spatial::LightTree::sample`]) weighs at each node for a shading point `x`,
//! which random number it draws, which lane that takes, and what the pick's pdf becomes.
//!
//! # What a step holds
//! On a tile of the tree's per-tile cuts ([`crate::spatial::TileCuts`]) the pick starts with
//! the tile's cut: its entries (subtrees or single lights) with grid masses `m_e` fixed for
//! the tile, and one draw that takes entry `e` with probability `m_e / 2^24`; the descent
//! goes on from there.
//! At internal node `k` the four lanes get importances `I_l(x)` (a representative light's
//! `Φ_l·c_z/|c − x|³` for point lights, a lane map's value for spots and ranges), the
//! defensive mixture with their power shares
//!
//! `P_l = (1 − ε)·I_l/Σ I + ε·Φ_l/Σ Φ`,
//!
//! and grid masses `m_l` on `2^24` cells ([`crate::spatial::importance`]); the 24-bit draw
//! `u = r >> 8` takes the lane whose interval of the cumulative masses holds it, with
//! probability exactly `m_l / 2^24`. A lane of mass 0 is **culled**: empty, or (for lights
//! with emission profiles) bounds that cannot reach `x` ([`Culled`]). In the leaf cluster the
//! contributions `c_j = p_j·G_j(x)·S_j(x)` are evaluated and one more draw picks light `j` by
//! the masses of `c_j / Σ c`. The pick's probability is the product of the realized factors
//!
//! `P(i | x) = m_e / 2^24 · Π_steps m_lane / 2^24 · m_j / 2^24` (without the first factor off the cuts),
//!
//! bit for bit the pdf of [`SpatialSampler::sample`] and [`SpatialSampler::pdf`], since the
//! record multiplies the same factors in the same order. For few lights
//! ([`SpatialSampler::Exact`]) the record is one leaf-like step over every contributing
//! light with `P(i | x) = c_i / Σ c` (not on the grid), whose estimate `Σ c` is the same for
//! every pick.
//!
//! The record ends with what a class compares: the estimate `ê = c_i / P(i | x)`, the exact
//! normalized irradiance `Σ_j c_j` it averages to, and the power pmf `p_i` of the same light.

use std::ops::Range;

use glam::DVec2;

use crate::rng::Rng;
use crate::spatial::importance::{
    GRID_CELL, IMPORTANCE_CAP, branch_probabilities, lane_importances, pick_on_grid,
};
use crate::spatial::{
    Child, ChildRef, ExactSampler, LightTree, MappedLanes, SpatialLight, SpatialSampler,
    TREE_WIDTH, unit24,
};

/// Why a lane of a node has no probability at the shading point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Culled {
    /// The lane holds no light.
    Empty,
    /// The point lies outside the lane's footprint box on the plane
    /// ([`LaneBounds::footprint`](crate::spatial::LaneBounds::footprint)), outside which
    /// none of its lights gives anything.
    OutsideFootprint,
    /// The point is farther from the box of the lane's lights than their longest range
    /// (tested, as in [`LaneBounds::reach`](crate::spatial::LaneBounds::reach), only where
    /// the footprint is unbounded; a range bounds a light's footprint, so such a lane holds
    /// a light without one, its longest range is infinite, and with today's footprints this
    /// reason does not occur).
    BeyondRange,
    /// No spot direction of the lane's cone comes within its widest outer cone of the
    /// point's direction (pbrt-v4's cone test,
    /// [`LaneBounds::reach`](crate::spatial::LaneBounds::reach)).
    OutsideCone,
    /// The lane holds lights but no weight: all of them have power 0 (they stay in the tree,
    /// so that new powers refit it). Lights on or below the plane never enter the tree, so
    /// no lane is culled for that.
    NoPower,
}

/// One lane of a node as the descent weighs it at `x`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LaneStep {
    /// What the lane holds (a node, a leaf cluster, or nothing).
    #[serde(skip)]
    pub child: Child,
    /// The leaf-order range of the lane's lights ([`LightTree::span`]; empty for an empty
    /// lane).
    pub lights: Range<usize>,
    /// The box of its lights' positions on the plane (`x, y`), `None` for an empty lane.
    pub box_on_plane: Option<[DVec2; 2]>,
    /// Its importance `I_l(x)` (capped at [`IMPORTANCE_CAP`]); up to the common factor
    /// `1/(4π)` for point lights.
    pub importance: f64,
    /// Its defensive share `Φ_l` (normalized power; `Σ p_i·g_i` for spots and ranges, 0
    /// where its bounds cull it).
    pub share: f64,
    /// `P_l`, the mixture's probability before the grid.
    pub branch_probability: f64,
    /// Its grid mass `m_l` (of `2^24`).
    pub mass: u32,
    /// `m_l / 2^24`, the probability the draw realizes.
    pub probability: f64,
    /// Why it has mass 0, `None` when it has some.
    pub culled: Option<Culled>,
}

impl LaneStep {
    /// How many lights the lane holds.
    pub fn light_count(&self) -> usize {
        self.lights.len()
    }
}

/// One entry of a tile's cut ([`crate::spatial::TileCuts`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CutEntry {
    /// Its subtree (a node, a leaf cluster, or one light of a cluster).
    #[serde(skip)]
    pub child: Child,
    /// Its depth in the tree (the root is 0).
    pub depth: usize,
    /// The leaf-order range of its lights ([`LightTree::span`]).
    pub lights: Range<usize>,
    /// The light's scene index when the entry is a single light (a leaf cluster the cut
    /// split), `None` for a group.
    pub light: Option<u32>,
    /// The box of its lights' positions on the plane (`x, y`).
    pub box_on_plane: Option<[DVec2; 2]>,
    /// Its grid mass `m_e` (of `2^24`).
    pub mass: u32,
    /// `m_e / 2^24`, the probability the draw realizes.
    pub probability: f64,
}

/// The first draw of a pick on a tile of the per-tile cuts: which entry of the tile's cut
/// the descent starts from.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CutStep {
    /// The tile's index ([`crate::spatial::TileCuts::tile_at`]).
    pub tile: usize,
    /// Its pixels: first column and row, and one past the last.
    pub pixels: [[u32; 2]; 2],
    /// Its cut's entries, in leaf order.
    pub entries: Vec<CutEntry>,
    /// The draw's top 24 bits `u = r >> 8`.
    pub random24: u32,
    /// The index in [`CutStep::entries`] of the entry the tile's alias columns give `u`
    /// ([`crate::spatial::TileCuts::pick`]).
    pub entry: usize,
    /// The pick's probability so far, `m_e / 2^24`.
    pub pdf_after: f64,
}

/// One internal node of the descent.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TreePickStep {
    /// The node's index ([`LightTree::nodes`]).
    pub node: usize,
    /// Its depth (the root is 0).
    pub depth: usize,
    /// Its four lanes.
    pub lanes: [LaneStep; TREE_WIDTH],
    /// The draw's top 24 bits `u = r >> 8`.
    pub random24: u32,
    /// The lane whose interval of the cumulative masses holds `u`.
    pub lane: usize,
    /// The pick's probability so far, `Π m_lane / 2^24` down to this node.
    pub pdf_after: f64,
}

/// One light of the final cluster.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LeafLight {
    /// Its index in the scene.
    pub light: u32,
    /// `c_j = p_j·G_j(x)·S_j(x)`, its normalized contribution at `x`.
    pub contribution: f64,
    /// Its grid mass (of `2^24`) in a tree's leaf cluster; `None` in the exact pick, which
    /// is not on the grid.
    pub mass: Option<u32>,
    /// The probability of picking it within the cluster: `m_j / 2^24`, or `c_j / Σ c` in
    /// the exact pick.
    pub probability: f64,
}

/// The pick inside a leaf cluster (or, for few lights, among all of them).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LeafStep {
    /// The cluster's lights in leaf order.
    pub lights: Vec<LeafLight>,
    /// The draw's top 24 bits `u = r >> 8`.
    pub random24: u32,
    /// The index in [`LeafStep::lights`] of the picked light.
    pub picked: usize,
    /// The pick's probability, the path's times the cluster's.
    pub pdf_after: f64,
}

/// One spatial pick at a shading point, recorded step by step (see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TreePick {
    /// The shading point on the plane.
    pub x: DVec2,
    /// The tile's cut the pick started from, when the tree has per-tile cuts and `x` lies
    /// on the receiver (`None`: the descent starts at the root).
    pub cut: Option<CutStep>,
    /// The internal nodes from the cut's entry (or the root) down (none for the exact pick,
    /// or when the descent starts at a leaf cluster).
    pub steps: Vec<TreePickStep>,
    /// The pick in the cluster reached.
    pub leaf: LeafStep,
    /// The picked light's index in the scene.
    pub light: u32,
    /// `P(i | x)`, the product of the steps' factors: bit for bit
    /// [`SpatialSampler::pdf`]`(x, light)`.
    pub pdf: f64,
    /// The picked light's `c_i = p_i·G_i(x)·S_i(x)`.
    pub contribution: f64,
    /// The estimate `ê` the sampler returns: `c_i / P(i | x)` (for the exact pick `Σ c`,
    /// which that equals up to rounding).
    pub estimate: f64,
    /// The exact normalized irradiance `Σ_j c_j(x)` over every light, what `ê` averages to.
    pub irradiance: f64,
    /// The picked light's power pmf `p_i = Φ_i / ΣΦ`.
    pub power_pmf: f64,
}

impl TreePick {
    /// Replays [`SpatialSampler::sample`]`(x, rng)` with the same draws and records it;
    /// `None` exactly when the sampler returns `None` (no light contributes at `x`). `rng`
    /// advances as the sampler's would.
    pub fn record(sampler: &SpatialSampler, x: DVec2, rng: &mut Rng) -> Option<TreePick> {
        match sampler {
            SpatialSampler::Exact(exact) => record_exact(exact, x, rng),
            SpatialSampler::Tree(tree) => record_tree(tree, x, rng),
        }
    }

    /// The lights of the cluster reached, with the picked one.
    pub fn picked(&self) -> &LeafLight {
        &self.leaf.lights[self.leaf.picked]
    }
}

/// The exact pick recorded: one draw, the running sum of `c_j` past `u·Σ c`.
fn record_exact(exact: &ExactSampler, x: DVec2, rng: &mut Rng) -> Option<TreePick> {
    let contributions: Vec<f64> = exact
        .lights()
        .iter()
        .enumerate()
        .map(|(k, (_, l))| l.contribution_with(exact.emission(k), x))
        .collect();
    // The sampler's own order of summation.
    let mut total = 0.0;
    for &c in &contributions {
        total += c;
    }
    let r = rng.next_u32();
    if total <= 0.0 {
        return None;
    }
    let target = unit24(r) * total;
    let (mut running, mut picked) = (0.0, None);
    for (k, &c) in contributions.iter().enumerate() {
        if c > 0.0 {
            picked = Some(k);
            running += c;
            if running > target {
                break;
            }
        }
    }
    let picked = picked?;
    let lights: Vec<LeafLight> = exact
        .lights()
        .iter()
        .zip(&contributions)
        .map(|(&(light, _), &c)| LeafLight {
            light,
            contribution: c,
            mass: None,
            probability: c / total,
        })
        .collect();
    let pdf = lights[picked].probability;
    Some(TreePick {
        x,
        cut: None,
        steps: Vec::new(),
        light: lights[picked].light,
        pdf,
        contribution: lights[picked].contribution,
        estimate: total,
        irradiance: total,
        power_pmf: exact.lights()[picked].1.power,
        leaf: LeafStep {
            lights,
            random24: r >> 8,
            picked,
            pdf_after: pdf,
        },
    })
}

/// Where a recorded descent starts.
enum Start {
    /// At the root: `x` is off the per-tile cuts, or the tree has none.
    Root,
    /// At the entry the tile's cut took.
    Cut(CutStep, ChildRef),
    /// Nowhere: no entry of the tile's cut has power (the pick ends with `ê = 0`).
    Nothing,
}

/// The tile's cut at `x` recorded (its draw taken from `rng`), with the entry it takes.
fn record_cut(tree: &LightTree, x: DVec2, rng: &mut Rng) -> Start {
    let Some((cuts, tile)) = tree.cut_tile_at(x) else {
        return Start::Root;
    };
    let u = rng.next_u32() >> 8;
    let Some((entry, mass)) = cuts.pick(tree, tile, u) else {
        return Start::Nothing;
    };
    let entries: Vec<CutEntry> = cuts
        .entries(tree, tile)
        .map(|(e, m)| {
            let lights = tree.span(e).unwrap_or(0..0);
            CutEntry {
                child: e.get(),
                depth: tree.depth_of(e).unwrap_or(0),
                box_on_plane: plane_box(tree.lights(), lights.clone()),
                light: (lights.len() == 1 && !matches!(e.get(), Child::Node(_)))
                    .then(|| tree.order()[lights.start]),
                lights,
                mass: m,
                probability: f64::from(m) * GRID_CELL,
            }
        })
        .collect();
    let Some(index) = entries.iter().position(|e| e.child == entry.get()) else {
        return Start::Nothing;
    };
    let step = CutStep {
        tile,
        pixels: cuts.tile_pixels(tile),
        entries,
        random24: u,
        entry: index,
        pdf_after: f64::from(mass) * GRID_CELL,
    };
    Start::Cut(step, entry)
}

/// The descent recorded: the tile's cut (when the tree has cuts), one step per node, then
/// the leaf cluster.
fn record_tree(tree: &LightTree, x: DVec2, rng: &mut Rng) -> Option<TreePick> {
    let (cut, mut at, mut pdf) = match record_cut(tree, x, rng) {
        Start::Cut(step, entry) => {
            let pdf = step.pdf_after;
            (Some(step), entry, pdf)
        }
        Start::Nothing => return None,
        Start::Root => (None, tree.root(), 1.0),
    };
    let first_depth = tree.depth_of(at).unwrap_or(0);
    let mut steps = Vec::new();
    while let Child::Node(k) = at.get() {
        let masses = tree.node_masses_at(k, x);
        let u = rng.next_u32() >> 8;
        let lane = pick_on_grid(&masses, u);
        pdf *= f64::from(masses[lane]) * GRID_CELL;
        steps.push(TreePickStep {
            node: k,
            depth: first_depth + steps.len(),
            lanes: lanes_at(tree, k, x, masses),
            random24: u,
            lane,
            pdf_after: pdf,
        });
        at = tree.nodes()[k].child(lane);
    }
    let Child::Leaf { first, count } = at.get() else {
        return None;
    };
    let (masses, c) = tree.leaf_masses_at(first, count, x);
    let u = rng.next_u32() >> 8;
    let j = pick_on_grid(&masses[..count], u);
    let pdf = pdf * (f64::from(masses[j]) * GRID_CELL);
    if !(c[j] > 0.0 && pdf > 0.0) {
        return None;
    }
    let lights = (0..count)
        .map(|m| LeafLight {
            light: tree.order()[first + m],
            contribution: c[m],
            mass: Some(masses[m]),
            probability: f64::from(masses[m]) * GRID_CELL,
        })
        .collect();
    Some(TreePick {
        x,
        cut,
        steps,
        light: tree.order()[first + j],
        pdf,
        contribution: c[j],
        estimate: c[j] / pdf,
        irradiance: irradiance(tree, x),
        power_pmf: tree.lights()[first + j].power,
        leaf: LeafStep {
            lights,
            random24: u,
            picked: j,
            pdf_after: pdf,
        },
    })
}

/// `Σ_j c_j(x)` over the tree's lights (every light that can contribute anywhere).
fn irradiance(tree: &LightTree, x: DVec2) -> f64 {
    tree.lights()
        .iter()
        .enumerate()
        .map(|(j, l)| l.contribution_with(tree.emission().get(j), x))
        .sum()
}

/// Node `k`'s four lanes at `x` with the masses `masses` the descent drew by.
fn lanes_at(tree: &LightTree, k: usize, x: DVec2, masses: [u32; TREE_WIDTH]) -> [LaneStep; 4] {
    let node = &tree.nodes()[k];
    let (importance, share) = if let Some(m) = tree.mapped(k) {
        let (importance, share) = m.weights(x);
        (importance.map(|i| i.min(IMPORTANCE_CAP)), share)
    } else {
        let c: [_; TREE_WIDTH] = std::array::from_fn(|l| node.centroid(l));
        let power = std::array::from_fn(|l| node.power(l));
        let coords = [c.map(|c| c.x), c.map(|c| c.y), c.map(|c| c.z)];
        let importance = lane_importances([&coords[0], &coords[1], &coords[2]], &power, x);
        (importance, power)
    };
    let probability = branch_probabilities(importance, share);
    std::array::from_fn(|l| {
        let child = node.child(l).get();
        let lights = tree.span(node.child(l)).unwrap_or(0..0);
        LaneStep {
            child,
            box_on_plane: plane_box(tree.lights(), lights.clone()),
            lights,
            importance: importance[l],
            share: share[l],
            branch_probability: probability[l],
            mass: masses[l],
            probability: f64::from(masses[l]) * GRID_CELL,
            culled: (masses[l] == 0).then(|| cull_reason(child, tree.mapped(k).map(|m| (m, l)), x)),
        }
    })
}

/// The box `[min, max]` of the positions (`x, y`) of `lights[range]`, `None` when empty.
pub fn plane_box(lights: &[SpatialLight], range: Range<usize>) -> Option<[DVec2; 2]> {
    lights[range].iter().fold(None, |acc, l| {
        let p = l.position_in_world.truncate();
        Some(match acc {
            None => [p, p],
            Some([lo, hi]) => [lo.min(p), hi.max(p)],
        })
    })
}

/// Why a lane of mass 0 has none: empty, else the first test of
/// [`MappedLanes::reaches`] that excludes `x` (footprint, range, cone) for lane `lane` of
/// `lanes`, else no power at all.
fn cull_reason(child: Child, lanes: Option<(&MappedLanes, usize)>, x: DVec2) -> Culled {
    if child == Child::Empty {
        return Culled::Empty;
    }
    let Some((m, lane)) = lanes else {
        return Culled::NoPower;
    };
    let [lo, hi] = m.footprint_of(lane);
    if !(x.cmpge(lo).all() && x.cmple(hi).all()) {
        return Culled::OutsideFootprint;
    }
    // A bounded footprint holds every point the lane's cones and ranges reach.
    let Some(g) = m.reach_of(lane) else {
        return Culled::NoPower;
    };
    if g.beyond_range(x) {
        return Culled::BeyondRange;
    }
    if g.reach(x) == 0.0 {
        Culled::OutsideCone
    } else {
        Culled::NoPower
    }
}
