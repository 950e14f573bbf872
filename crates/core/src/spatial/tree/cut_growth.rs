//! How one tile's cut grows from the root ([`super::TileCuts`], whose module docs give the
//! rule and what it guarantees): the splits, what each entry is estimated to give the
//! tile's weighing points, and when a cut is done.

use glam::{DVec2, DVec3};

use super::LightTree;
use super::cut_candidate::{Candidate, WEIGHING_POINTS, Weighing};
use super::node::{Child, ChildRef, TREE_WIDTH};
use crate::scene::Emission;
use crate::spatial::importance::{GRID_CELL, IMPORTANCE_CAP, branch_probabilities, grid_masses};

/// How a tile's cut grows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rules {
    /// The most entries of a tile's cut.
    pub(super) max_entries: usize,
    /// The most spread `Σ_e max_k s_e(x_k)` of a tile's cut.
    pub(super) max_spread: f64,
    /// Whether leaf clusters may split into their lights.
    pub(super) split_leaves: bool,
    /// What the cut grows by (its splits' order and its spread).
    pub(super) weighing: Weighing,
    /// The share of the weights given by the tree's probabilities.
    pub(super) tree_share: f64,
}

/// How far a cut's total estimate at a weighing point may move before its entries' largest
/// shares are taken again ([`grow`]).
const TOTALS_DRIFT: f64 = 1.0 / 16.0;

/// Each estimate is capped here, so that the cut's sum of at most
/// [`super::CUT_MAX_ENTRIES`] of them stays finite (a light `10^-150` above the plane gives
/// `~10^298`).
const ESTIMATE_CAP: f64 = IMPORTANCE_CAP / 256.0;

/// A cut splits a leaf cluster into its lights only where each light's contribution at
/// every weighing point is positive and at least this fraction of its largest there
/// (whatever the cut grows by; [`flat_on_tile`]). Measured by exact variances over the
/// tree's (the module docs of `tile_cut`): at `1/2`, which also kept a cluster whole
/// wherever a spot's cone or range edge might cross the tile, `grid` had 0.64× and its
/// picks cost 4.6 alias picks; at `1/10` 0.19× and 2.5, `stage` 0.56× and 3.6 (0.58× and
/// 4.2), `arena` 0.43× and 5.3 (0.44× and 5.7), every other scene as before; at 0 a
/// spot lit at every point but fading fast across the tile enters alone, weighed a tenth
/// of what its brightest pixel needs (`arena` 9.7×).
const LEAF_FLATNESS: f64 = 0.1;

/// A subtree of point lights is split ahead of its largest share when its bound
/// ([`super::TreeNode::lane_bound`]), as a share of the cut's largest total, is
/// more than this many times that share ([`urgency`]).
const BOUND_OVER_SHARE: f64 = 64.0;

/// Grows a tile's cut from the root (module docs): splits the most urgent entry (largest
/// share `max_k s_e(x_k)`, or a subtree's bound where that share may be far off:
/// [`urgency`]) while the cut keeps at most `rules.max_entries` entries and a
/// spread `Σ_e max_k s_e(x_k)` of at most `rules.max_spread`, then weighs each entry by
/// its shares and by its probabilities under the tree (`Candidate::weigh`).
///
/// The shares `s_e(x_k) = Ê_e(x_k) / Σ_f Ê_f(x_k)` are taken against the totals of the
/// cut as it stands; every split changes those totals a little, so the entries' largest
/// shares are kept against the totals they were last taken against and taken again,
/// all of them, only when a total has moved by more than [`TOTALS_DRIFT`] since: the
/// cut then costs `O(n)` a split instead of `O(9n)`, and the order of its splits and
/// its spread are those of the current totals within that drift.
pub(super) fn grow(
    tree: &LightTree,
    tile: ([DVec2; WEIGHING_POINTS.len()], [DVec2; 2]),
    cut: &mut Vec<Candidate>,
    children: &mut Vec<Candidate>,
    rules: Rules,
) {
    const W: usize = WEIGHING_POINTS.len();
    let by = rules.weighing;
    let reciprocal = |t: [f64; W]| t.map(|t| if t > 0.0 { 1.0 / t } else { 0.0 });
    let mut total = [1.0; W];
    // 1/total at each point as the entries' peaks were last taken.
    let mut taken_at = reciprocal(total);
    cut[0].peak = 1.0;
    let mut spread = 1.0;
    // `1 / max_k Ê(x_k)`: the entries' bounds as shares of the cut's largest total (none
    // when the cut grows by the tree's probabilities).
    let mut bound_scale = 0.0;
    while let Some(k) = cut
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.whole && splits(c.at, rules.split_leaves))
        .max_by(|a, b| urgency(a.1, bound_scale).total_cmp(&urgency(b.1, bound_scale)))
        .map(|(k, _)| k)
    {
        children.clear();
        if !split_into(tree, cut[k].at, cut[k].tree_probability, tile, children) {
            cut[k].whole = true;
            continue;
        }
        let mut grown = total;
        for (p, g) in grown.iter_mut().enumerate() {
            *g += children.iter().map(|c| c.grown_by(by)[p]).sum::<f64>() - cut[k].grown_by(by)[p];
        }
        let drifted = grown.iter().zip(&taken_at).any(|(&g, &r)| {
            let moved = (g * r - 1.0).abs();
            moved.is_nan() || moved > TOTALS_DRIFT
        });
        if drifted {
            taken_at = reciprocal(grown);
            if by == Weighing::Estimates {
                bound_scale = taken_at.iter().fold(f64::INFINITY, |m, &r| m.min(r));
            }
            for c in cut.iter_mut() {
                c.peak = c.largest_share(by, &taken_at);
            }
            spread = cut.iter().map(|c| c.peak).sum();
        }
        for c in children.iter_mut() {
            c.peak = c.largest_share(by, &taken_at);
        }
        let grown_spread = spread - cut[k].peak + children.iter().map(|c| c.peak).sum::<f64>();
        if cut.len() - 1 + children.len() > rules.max_entries || grown_spread > rules.max_spread {
            // The most urgent entry that can still be split cannot: the cut is done (trying
            // the others costs more than it gains, measured).
            break;
        }
        total = grown;
        spread = grown_spread;
        cut.swap_remove(k);
        cut.append(children);
    }
    // Both weights of every entry, against the final cut's totals of each.
    let totals = |of: fn(&Candidate) -> &[f64; W]| {
        cut.iter().fold([0.0; W], |mut t, c| {
            t.iter_mut().zip(of(c)).for_each(|(t, r)| *t += r);
            t
        })
    };
    let (estimated, by_tree) = (
        reciprocal(totals(|c| &c.estimate)),
        reciprocal(totals(|c| &c.tree_probability)),
    );
    for c in cut.iter_mut() {
        c.weigh(&estimated, &by_tree);
    }
}

/// How urgently a cut splits `c`: its largest share `max_k s_e(x_k)`, or its bound as a
/// share of the cut's largest total (`bound_scale = 1 / max_k Ê(x_k)`) where that is more
/// than [`BOUND_OVER_SHARE`] times larger: a subtree whose representative light may
/// misjudge it that much (a group of lights hanging just above the tile) is split ahead of
/// what its estimates say ([`grow`]).
fn urgency(c: &Candidate, bound_scale: f64) -> f64 {
    let bound_share = c.bound * bound_scale;
    if bound_share > BOUND_OVER_SHARE * c.peak {
        bound_share
    } else {
        c.peak
    }
}

/// Whether a cut of `tree` can split `at`: an internal node into its lanes; when
/// `split_leaves`, a leaf cluster of more than one light into its lights (whether it does
/// on a tile is [`split_into`]'s call).
fn splits(at: ChildRef, split_leaves: bool) -> bool {
    match at.get() {
        Child::Node(_) => true,
        Child::Leaf { count, .. } => split_leaves && count > 1,
        Child::Empty => false,
    }
}

/// Whether a leaf cluster's lights, as [`split_into`] gave them, may enter the cut one by
/// one: each light's estimate at every weighing point positive and at least
/// [`LEAF_FLATNESS`] of its largest. A spot whose cone or range edge crosses the tile
/// between the points (dark at all of them, lit between) keeps its cluster whole, whose
/// pick weighs it at the pixel itself.
fn flat_on_tile(lights: &[Candidate]) -> bool {
    let flat = |c: &Candidate| {
        let largest = c.estimate.iter().fold(0.0f64, |m, &r| m.max(r));
        largest > 0.0 && c.estimate.iter().all(|&r| r >= LEAF_FLATNESS * largest)
    };
    lights.iter().all(flat)
}

/// Whether the light at `light_in_world` with the profile `emission` gives no point of the
/// rectangle `[lo, hi]` of the plane anything (`S = 0` over all of it), by two conservative
/// tests that may say `false` of a dark rectangle but never `true` of a lit one:
/// - its range `r` ends before the rectangle's nearest point (`d_min ≥ r`, where the
///   window `1 − (d/r)⁴` is 0), with `10^-9` of `r` to spare;
/// - its cone misses the cone of directions from the light to the rectangle: with `w` the
///   direction to the rectangle's centre and `θ_R` the largest angle between `w` and the
///   direction to a corner (the rectangle, convex, lies in that cone when `θ_R < π/2`),
///   every point's angle to the axis is at least `∠(a, w) − θ_R` (the triangle inequality
///   on the sphere), so the spot is dark there where that exceeds `θo` (with `10^-6` rad
///   to spare against the rounding of `acos`).
fn dark_over(emission: &Emission, light_in_world: DVec3, [lo, hi]: [DVec2; 2]) -> bool {
    if let Some(range) = emission.range() {
        let nearest = light_in_world.truncate().clamp(lo, hi);
        let d_min = (nearest.extend(0.0) - light_in_world).length();
        if d_min >= range * (1.0 + 1e-9) {
            return true;
        }
    }
    let Some(spot) = emission.spot() else {
        return false;
    };
    let angle = |a: DVec3, b: DVec3| a.normalize().dot(b.normalize()).clamp(-1.0, 1.0).acos();
    let centre = ((lo + hi) * 0.5).extend(0.0) - light_in_world;
    let corners = [lo, DVec2::new(hi.x, lo.y), DVec2::new(lo.x, hi.y), hi];
    let spread = corners
        .iter()
        .map(|c| angle(centre, c.extend(0.0) - light_in_world))
        .fold(0.0f64, f64::max);
    spread < std::f64::consts::FRAC_PI_2 - 1e-6
        && angle(emission.axis(), centre) - spread > spot.outer_cone + 1e-6
}

/// Whether the footprint box `footprint` (`None`: unbounded) meets the box `rect`.
fn meets(footprint: Option<[DVec2; 2]>, [lo, hi]: [DVec2; 2]) -> bool {
    footprint.is_none_or(|[a, b]| a.cmple(hi).all() && b.cmpge(lo).all())
}

/// The lanes of node `at` that can light the tile (`tile`: its weighing points and box),
/// appended to `out` in leaf order, each with its estimate at each point (the lane's map or
/// representative light) and its probability under the tree there (`at`'s,
/// `tree_probability[k]` at weighing point `k`, times the node's grid probability of the
/// lane); or the lights of leaf cluster `at`, each with its exact contribution and the
/// cluster's probability times its grid mass by contribution. A lane or a light whose
/// footprint misses the tile's box is left out, and so is a light whose cone or range
/// misses the whole box ([`dark_over`]): none of its lights gives the tile anything, and a
/// pick there never takes it (`P(i | x) = 0` where `c_i(x) = 0`).
/// Returns whether the cut may take them: always a node's lanes; a leaf cluster's lights
/// where [`flat_on_tile`] holds for their estimates (else the cluster stays whole).
fn split_into(
    tree: &LightTree,
    at: ChildRef,
    tree_probability: [f64; WEIGHING_POINTS.len()],
    (points, rect): ([DVec2; WEIGHING_POINTS.len()], [DVec2; 2]),
    out: &mut Vec<Candidate>,
) -> bool {
    let n = match at.get() {
        Child::Node(n) => n,
        Child::Leaf { first, count } => {
            let lights = first..first + count;
            // Where each light is mapped on the plane (within the receiver, where picks are
            // made); none for point lights, which reach every tile.
            // A spot whose cone or range misses the whole tile (its footprint box may still
            // meet it) is left out as well.
            let footprints = tree.footprints.get(lights.clone());
            let emission = tree.emission.get(lights.clone());
            let lights_tile = |j: usize| {
                footprints.is_none_or(|f| meets(f[j], rect))
                    && emission.is_none_or(|e| {
                        !dark_over(&e[j], tree.lights[first + j].position_in_world, rect)
                    })
            };
            let masses = points.map(|x| tree.leaf_masses_at(first, count, x));
            let start = out.len();
            for (j, light) in tree.lights[lights].iter().enumerate() {
                // A light that gives the tile nothing is left out.
                if lights_tile(j) {
                    out.push(Candidate::new(
                        ChildRef::leaf(first + j, 1),
                        std::array::from_fn(|k| masses[k].1[j].min(ESTIMATE_CAP)),
                        std::array::from_fn(|k| {
                            tree_probability[k] * (f64::from(masses[k].0[j]) * GRID_CELL)
                        }),
                        light.power,
                    ));
                }
            }
            return flat_on_tile(&out[start..]);
        }
        Child::Empty => return true,
    };
    let node = &tree.nodes()[n];
    let bounds = tree.bounds(n);
    // Each lane's importance and share at each weighing point, read once: the importance
    // is its estimate of what it gives the point (its map's value, with its unbounded
    // lights' representative light, for spots and ranges; for point lights its
    // representative light `Φ_c·G(c, x)`, of which the importance is `4π` times), and the
    // two mixed are the tree's branch masses there.
    let mapped = tree.mapped(n).is_some();
    let importance_per_estimate = if mapped {
        1.0
    } else {
        4.0 * std::f64::consts::PI
    };
    let weights = points.map(|x| tree.node_weights(n, x));
    let estimates = weights
        .map(|(importance, _)| importance.map(|i| (i / importance_per_estimate).min(ESTIMATE_CAP)));
    let masses =
        weights.map(|(importance, share)| grid_masses(branch_probabilities(importance, share)));
    for lane in 0..TREE_WIDTH {
        let child = node.child[lane];
        let footprint = bounds.map(|b| b[lane].footprint);
        if child.get() == Child::Empty || !meets(footprint, rect) {
            continue;
        }
        let entry = Candidate::new(
            child,
            std::array::from_fn(|k| estimates[k][lane]),
            std::array::from_fn(|k| tree_probability[k] * (f64::from(masses[k][lane]) * GRID_CELL)),
            node.power(lane),
        );
        // A subtree of point lights, which its representative light may misjudge.
        out.push(match child.get() {
            Child::Node(k) if !mapped => entry.bounded_by(
                node.lane_bound(lane, &tree.nodes()[k], rect)
                    .min(ESTIMATE_CAP),
            ),
            _ => entry,
        });
    }
    true
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, dvec2, dvec3};

    use super::dark_over;
    use crate::scene::{Emission, Spot};

    /// Spots and ranges at random, over random rectangles of the plane: wherever
    /// [`dark_over`] calls a rectangle dark, every point of a 33 × 33 raster over it (its
    /// edges and corners included) gets `S = 0`; and the test is not vacuous: it calls many
    /// rectangles dark, and none that the spot's axis meets.
    #[test]
    fn a_rectangle_called_dark_gets_nothing_from_the_light_anywhere() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut dark, mut cases) = (0, 0);
        for _ in 0..4000 {
            let light = dvec3(
                4.0 * uniform() - 2.0,
                4.0 * uniform() - 2.0,
                0.05 + 2.0 * uniform(),
            );
            let outer = 0.05 + 1.4 * uniform();
            let spot = (uniform() < 0.8).then(|| Spot {
                direction: dvec3(uniform() - 0.5, uniform() - 0.5, -uniform()),
                inner_cone: outer * uniform(),
                outer_cone: outer,
            });
            let range = (uniform() < 0.4).then(|| light.z + 3.0 * uniform());
            let Ok(emission) = Emission::new(spot, range) else {
                continue;
            };
            let lo = dvec2(4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0);
            let hi = lo + dvec2(0.01 + uniform(), 0.01 + uniform());
            cases += 1;
            if !dark_over(&emission, light, [lo, hi]) {
                continue;
            }
            dark += 1;
            for a in 0..=32 {
                for b in 0..=32 {
                    let x = lo + (hi - lo) * dvec2(f64::from(a), f64::from(b)) / 32.0;
                    assert_eq!(
                        emission.factor(light, x),
                        0.0,
                        "{emission:?} at {light} lights {x} of [{lo}, {hi}]"
                    );
                }
            }
            // The axis's foot on the plane, where it reaches the plane inside the rectangle.
            let axis = emission.axis();
            if axis.z < 0.0 {
                let foot: DVec2 = (light + axis * (light.z / -axis.z)).truncate();
                assert!(
                    foot.cmplt(lo).any() || foot.cmpgt(hi).any(),
                    "the axis of {emission:?} at {light} meets [{lo}, {hi}], called dark"
                );
            }
        }
        assert!(dark * 5 > cases, "{dark} of {cases} rectangles called dark");
    }
}
