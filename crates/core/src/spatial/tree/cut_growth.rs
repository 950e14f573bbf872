//! How one tile's cut grows from the root ([`super::TileCuts`], whose module docs give the
//! rule and what it guarantees): the splits, what each entry is estimated to give the
//! tile's weighing points, and when a cut is done.
//!
//! **Which clusters split.** An entry that is a single light costs a pick one evaluation; a
//! leaf cluster costs its every light's, at the pixel. Exact variances over the tree's and
//! times per pixel sample over an alias pick's (`cargo run --release -p lightpick-core
//! --example tile_cuts`, one thread, 128 × 128 pixels), by the rule that lets a cluster's
//! lights enter one by one:
//!
//! | rule | grid | stage | gallery | arena | random |
//! | --- | ---: | ---: | ---: | ---: | ---: |
//! | each light within ½ of its largest at the points, no cone edge across the tile | 0.64×, 4.6 | 0.58×, 4.2 | 1.71×, 3.8 | 0.44×, 5.7 | 0.93×, 6.8 |
//! | within ¼, no cone edge | 0.27×, 2.7 | 0.58×, 4.1 | 1.71×, 3.7 | 0.44×, 5.6 | 0.93×, 5.9 |
//! | within a tenth, positive (edges may cross) | 0.19×, 2.5 | 0.56×, 3.6 | 1.72×, 3.4 | 0.43×, 5.3 | 0.93×, 5.3 |
//! | the same, a spot whose cone or range misses the tile left out of the rule | **0.19×, 2.5** | **0.37×, 3.2** | **1.71×, 3.3** | **0.42×, 4.6** | **0.59×, 4.9** |
//! | within a tenth, a light dark at every point too | 0.19×, 2.5 | 0.35×, 2.9 | 2.56×, 3.1 | 0.41×, 4.4 | 0.55×, 5.2 |
//! | positive, any spread | 0.19×, 2.5 | 0.56×, 4.4 | 1.73×, 3.2 | 9.74×, 4.4 | 0.93×, 5.6 |
//! | every cluster, dark lights too | 0.19×, 2.5 | 0.35×, 1.6 | 2.66×, 3.0 | 9.82×, 2.9 | – |
//! | an edge across the tile weighed by its bound `Φ·G·g` | – | 5.6×, 2.0 | 7.1×, 2.9 | 2.7×, 2.7 | 2.3×, 3.4 |
//!
//! `equal`'s cuts are all single lights under each rule; on the point-light sets of 10^4
//! (`heavy-tail`, `clusters-low`, `chandeliers`, `strips`) the tile's mass lies mostly on
//! groups and each rule keeps their variance (0.16×, 0.04×, 0.11×, 0.07–0.08×) within the
//! times' noise. A light dark at every weighing point is the one to keep whole: where it
//! is lit between them the cut gave it only its share of power. Most of those lights are
//! dark on the whole tile, though (a cone's footprint box meets the tile where its ellipse
//! does not): such a light gives the tile nothing and is left out of the cut like a light
//! whose box misses it, by an exact test of its cone against the tile (the first, a bound
//! of angles, found a few less: `stage` 406× below power, 416× now) and of the tile's
//! nearest point against a range, and no longer keeps its cluster whole. Letting lights in
//! where they fade more than tenfold across the tile costs `arena` its gain (a spot's
//! falloff between two points); weighing a crossing edge by its unshadowed bound spends
//! the cut on dark pixels.
//!
//! **A cluster's flat ends.** A cluster that is not flat on the tile need not stay whole:
//! its **core**, from its first light that is not flat to its last, stays whole (weighed
//! by its lights' summed estimates, picked by contribution at the pixel), and the flat
//! lights before and after it enter alone ([`peel_flat_ends`]). Exact variances below
//! power sampling's (`tree_variance` example) and light evaluations a pick spends on the
//! cut's clusters and single lights (the entries' mass times their lights), by what the
//! core must be:
//!
//! | the core | `stage` | `gallery` | `random` | `arena` | `clusters-low` | `strips` |
//! | --- | ---: | ---: | ---: | ---: | ---: | ---: |
//! | none: the cluster whole (before) | 477×, 3.07 | 2510×, 1.67 | 281×, 2.21 | 537×, 3.12 | 372× | 408× |
//! | flat itself (its summed estimates) | 493×, 2.88 | 2498×, 1.63 | 283×, 2.17 | 541×, 2.85 | – | – |
//! | positive at every point | 513×, 2.47 | 2481×, 1.54 | 312×, 1.97 | 539×, 2.46 | – | – |
//! | lit at 5 points or more | 512×, 2.03 | 2429×, 1.48 | 367×, 1.75 | 524×, 2.06 | – | – |
//! | of two lights or more, lit at a point | 492×, 2.65 | 2434×, 1.56 | 309×, 2.07 | 537×, 2.55 | 363× | 463× |
//! | **lit at a point** | **535×, 1.62** | **2398×, 1.40** | **389×, 1.55** | **519×, 1.77** | **344×** | **469×** |
//! | anything | 571×, 1.20 | 2398×, 1.29 | 489×, 1.34 | 414×, 1.49 | – | – |
//!
//! (`clusters-low` spends 1.29 → 1.11 evaluations, `strips` 1.69 → 1.50; `heavy-tail`,
//! `chandeliers`, `grid` and `equal` keep their cuts.) A core lit at no weighing point is
//! the case the cluster is kept whole for (a cone's edge crossing the tile between the
//! points): alone it would be weighed by power. Allowed that too, `arena` loses a fifth of
//! its gain.

use glam::DVec2;

use super::LightTree;
use super::cut_candidate::{Candidate, WEIGHING_POINTS, Weighing};
use super::cut_columns::MOST_ENTRIES;
use super::cut_order::{NOT_SPLIT, Tournament, ordered_key};
use super::dark_over::dark_over;
use super::node::{Child, ChildRef, LEAF_SIZE, TREE_WIDTH};
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
/// [`super::cut_columns::MOST_ENTRIES`] of them stays finite (a light `10^-150` above the
/// plane gives `~10^298`).
const ESTIMATE_CAP: f64 = IMPORTANCE_CAP / MOST_ENTRIES as f64;

/// A cut splits a leaf cluster into its lights only where each light's contribution at
/// every weighing point is positive and at least this fraction of its largest there
/// (whatever the cut grows by; [`flat_on_tile`]). Measured by exact variances over the
/// tree's (the module docs of `tile_cut`): at `1/2`, which also kept a cluster whole
/// wherever a spot's cone or range edge might cross the tile, `grid` had 0.64× and its
/// picks cost 4.6 alias picks; at `1/10` 0.19× and 2.5, `stage` 0.56× and 3.6 (0.58× and
/// 4.2), `arena` 0.43× and 5.3 (0.44× and 5.7), every other scene as before; at 0 a
/// spot lit at every point but fading fast across the tile enters alone, weighed a tenth
/// of what its brightest pixel needs (`arena` 9.7×). Measured again once a cluster that does
/// not split came to keep only its core whole ([`peel_flat_ends`]; `tree_variance` example,
/// below power sampling, and the light evaluations a pick spends on the cut's clusters and
/// single lights): at `1/10` `strips` 469× at 1.50 evaluations, `clusters-low` 344× at
/// 1.11, `random` 389× at 1.55, `arena` 519× at 1.77; at `1/20` 459× at 1.11, 327× at 1.06,
/// 388× at 1.55, 516× at 1.74; at `1/5` 481× at 2.01, 363× at 1.25, 409× at 1.56, 527× at
/// 1.82; at `3/10` 489× at 2.36, 374× at 1.45, 404× at 1.58, 536× at 1.89 (`stage` and
/// `gallery` within 1 % at each).
const LEAF_FLATNESS: f64 = 0.1;

/// A subtree of point lights is split ahead of its largest share when its bound
/// ([`super::TreeNode::lane_bound`]), as a share of the cut's largest total, is
/// more than this many times that share ([`urgency`]).
const BOUND_OVER_SHARE: f64 = 64.0;

/// Grows a tile's cut from the root (module docs): splits the most urgent entry (largest
/// share `max_k s_e(x_k)`, or a subtree's bound where that share may be far off:
/// [`urgency`]) while the cut keeps at most `rules.max_entries` entries and a
/// spread `Σ_e max_k s_e(x_k)` of at most `rules.max_spread`, then weighs each entry by
/// its shares and by its probabilities under the tree (`Candidate::weigh`), and leaves
/// the cut in leaf order.
///
/// The shares `s_e(x_k) = Ê_e(x_k) / Σ_f Ê_f(x_k)` are taken against the totals of the
/// cut as it stands; every split changes those totals a little, so the entries' largest
/// shares are kept against the totals they were last taken against and taken again,
/// all of them, only when a total has moved by more than [`TOTALS_DRIFT`] since: the
/// order of its splits and its spread are those of the current totals within that drift.
/// The next split is the winner of a tournament over the entries' urgencies
/// ([`Tournament`], the same entry a scan of all of them takes), so that a split costs
/// its children's estimates and `O(log n)` beside them.
pub(super) fn grow(
    tree: &LightTree,
    tile: ([DVec2; WEIGHING_POINTS.len()], [DVec2; 2]),
    cut: &mut Vec<Candidate>,
    growth: &mut Growth,
    rules: Rules,
) {
    const W: usize = WEIGHING_POINTS.len();
    let Growth {
        children,
        keys,
        order,
    } = growth;
    // The tree's probabilities, only where the weights or the growth read them (else 0,
    // and a cut whose estimates say nothing is weighed by power).
    let with_tree = rules.tree_share > 0.0 || rules.weighing == Weighing::TreeProbabilities;
    let key = |c: &Candidate, bound_scale: f64| {
        if c.whole || !splits(c.at, rules.split_leaves) {
            NOT_SPLIT
        } else {
            ordered_key(urgency(c, bound_scale))
        }
    };
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
    order.reset(cut.iter().map(|c| key(c, bound_scale)));
    while let Some(k) = order.top() {
        children.clear();
        if let Split::Whole(narrowed) = split_into(
            tree,
            cut[k].at,
            cut[k].tree_probability,
            tile,
            with_tree,
            children,
        ) {
            (cut[k].at, cut[k].whole) = (narrowed, true);
            order.set(k, NOT_SPLIT);
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
            order.reset(cut.iter().map(|c| key(c, bound_scale)));
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
        let last = cut.len() - 1;
        cut.swap_remove(k);
        order.set(k, order.key(last));
        order.set(last, NOT_SPLIT);
        for (at, c) in (last..).zip(children.iter()) {
            order.set(at, key(c, bound_scale));
        }
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
    // In leaf order (the subtrees' ranges are disjoint): sorted as integers, first light
    // above entry, then moved once.
    keys.clear();
    keys.extend(cut.iter().enumerate().map(|(e, c)| {
        let first = tree.first_of(c.at).map_or(0, |f| f as i64 + 1);
        first << ENTRY_BITS | e as i64
    }));
    keys.sort_unstable();
    children.clear();
    children.extend(
        keys.iter()
            .map(|&key| cut[(key & ((1 << ENTRY_BITS) - 1)) as usize]),
    );
    std::mem::swap(cut, children);
}

/// Bits of an entry's index in a cut (at most [`MOST_ENTRIES`], `2^10`) below its first
/// light's in a sort key.
const ENTRY_BITS: u32 = 16;

/// What a tile's cut grows in besides the cut, kept from tile to tile on a thread.
#[derive(Default)]
pub(super) struct Growth {
    /// The entry being split's children.
    children: Vec<Candidate>,
    /// The entries' urgencies ([`urgency`]) as ordered integers, by position in the cut.
    order: Tournament,
    /// The entries' sort keys in leaf order, once grown.
    keys: Vec<i64>,
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
/// [`LEAF_FLATNESS`] of its largest ([`flat`]). A spot whose cone or range edge crosses the
/// tile between the points (dark at all of them, lit between) keeps the core of its
/// cluster whole ([`peel_flat_ends`]), whose pick weighs it at the pixel itself.
fn flat_on_tile(lights: &[Candidate]) -> bool {
    lights.iter().all(flat)
}

/// Whether `c`'s estimate at every weighing point is positive and at least
/// [`LEAF_FLATNESS`] of its largest.
fn flat(c: &Candidate) -> bool {
    let largest = c.estimate.iter().fold(0.0f64, |m, &r| m.max(r));
    largest > 0.0 && c.estimate.iter().all(|&r| r >= LEAF_FLATNESS * largest)
}

/// A leaf cluster of `tree` that is not [`flat_on_tile`], its lights that can light the tile in
/// `out[start..]` (leaf order, one [`Candidate`] each): its **core**, the lights from the
/// first that is not [`flat`] to the last, stays whole, and the flat lights before and
/// after it enter the cut alone. The core takes the sums of its lights' estimates, tree
/// probabilities and powers, and the range of leaf order from its first light to its last
/// (a light between them that cannot light the tile gives it nothing, as in a cluster
/// narrowed whole). Rewrites `out[start..]` to the lights before the core, the core, the
/// lights after it, and returns `true`; leaves `out` alone and returns `false` where no
/// light is peeled (the core is the whole cluster) or where the core's estimate is 0 at
/// every weighing point (lit only between them: kept with the whole cluster, whose pick
/// weighs it at the pixel).
fn peel_flat_ends(tree: &LightTree, out: &mut Vec<Candidate>, start: usize) -> bool {
    let lights = &out[start..];
    let (Some(a), Some(b)) = (
        lights.iter().position(|c| !flat(c)),
        lights.iter().rposition(|c| !flat(c)),
    ) else {
        return false;
    };
    if a == 0 && b + 1 == lights.len() {
        return false;
    }
    let mut core = lights[a];
    for c in &lights[a + 1..=b] {
        for k in 0..WEIGHING_POINTS.len() {
            core.estimate[k] = (core.estimate[k] + c.estimate[k]).min(ESTIMATE_CAP);
            core.tree_probability[k] += c.tree_probability[k];
        }
        core.power += c.power;
    }
    let (Some(from), Some(to)) = (tree.first_of(lights[a].at), tree.first_of(lights[b].at)) else {
        return false;
    };
    if core.estimate.iter().all(|&e| e <= 0.0) {
        return false;
    }
    (core.at, core.whole) = (ChildRef::leaf(from, to + 1 - from), true);
    out[start + a] = core;
    out.drain(start + a + 1..=start + b);
    true
}

/// Whether light `i` (leaf order) of `tree` can light any point of the rectangle `rect`:
/// its footprint (where it is mapped on the plane, within the receiver where picks are
/// made; none for point lights, which reach every tile) meets it, and its cone or range
/// does not provably miss all of it ([`dark_over`]; a footprint's box may meet a tile
/// that its ellipse misses).
fn lights_tile(tree: &LightTree, i: usize, rect: [DVec2; 2]) -> bool {
    meets(tree.footprint(i), rect)
        && tree
            .emission
            .get(i)
            .is_none_or(|e| !dark_over(e, tree.lights[i].position_in_world, rect))
}

/// What [`split_into`] makes of an entry.
enum Split {
    /// The entry's children (a node's lanes, a leaf cluster's lights, or a leaf cluster's
    /// flat lights and its core, [`peel_flat_ends`]) replace it.
    Children,
    /// A leaf cluster stays whole, narrowed to this range of its lights: from the first
    /// that can light the tile to the last. The lights beyond give every point of the tile
    /// exactly 0, so a pick by the lights' grid masses takes the same light with the same
    /// probability over the shorter range, for less work.
    Whole(ChildRef),
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
/// cluster's probability times its grid mass by contribution (those probabilities 0 unless
/// `with_tree`: no grid masses taken). A lane or a light whose
/// footprint misses the tile's box is left out, and so is a light whose cone or range
/// misses the whole box ([`dark_over`]): none of its lights gives the tile anything, and a
/// pick there never takes it (`P(i | x) = 0` where `c_i(x) = 0`).
/// Returns whether the cut may take them ([`Split`]): always a node's lanes; a leaf
/// cluster's lights where [`flat_on_tile`] holds for their estimates, else its flat lights
/// before and after its core and the core whole where [`peel_flat_ends`] can, else the
/// cluster stays whole, narrowed to the lights that can light the tile.
fn split_into(
    tree: &LightTree,
    at: ChildRef,
    tree_probability: [f64; WEIGHING_POINTS.len()],
    (points, rect): ([DVec2; WEIGHING_POINTS.len()], [DVec2; 2]),
    with_tree: bool,
    out: &mut Vec<Candidate>,
) -> Split {
    let n = match at.get() {
        Child::Node(n) => n,
        Child::Leaf { first, count } => {
            let lights = first..first + count;
            // The grid masses only where the tree's probabilities are wanted.
            let masses = points.map(|x| {
                if with_tree {
                    tree.leaf_masses_at(first, count, x)
                } else {
                    ([0; LEAF_SIZE], tree.leaf_contributions(first, count, x))
                }
            });
            let start = out.len();
            // The first and the last light that can light the tile.
            let mut lit: Option<(usize, usize)> = None;
            for (j, light) in tree.lights[lights].iter().enumerate() {
                // A light that gives the tile nothing is left out.
                if lights_tile(tree, first + j, rect) {
                    lit = Some((lit.map_or(j, |(from, _)| from), j));
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
            return match lit {
                Some(_) if flat_on_tile(&out[start..]) => Split::Children,
                Some(_) if peel_flat_ends(tree, out, start) => Split::Children,
                Some((from, to)) => {
                    out.truncate(start);
                    Split::Whole(ChildRef::leaf(first + from, to + 1 - from))
                }
                None => Split::Children,
            };
        }
        Child::Empty => return Split::Children,
    };
    let node = &tree.nodes()[n];
    let mapped_lanes = tree.mapped(n);
    // Each lane's importance and share at each weighing point, read once: the importance
    // is its estimate of what it gives the point (its map's value, with its unbounded
    // lights' representative light, for spots and ranges; for point lights its
    // representative light `Φ_c·G(c, x)`, of which the importance is `4π` times), and the
    // two mixed are the tree's branch masses there.
    let mapped = mapped_lanes.is_some();
    let importance_per_estimate = if mapped {
        1.0
    } else {
        4.0 * std::f64::consts::PI
    };
    let weights = points.map(|x| tree.node_weights(n, x));
    let estimates = weights
        .map(|(importance, _)| importance.map(|i| (i / importance_per_estimate).min(ESTIMATE_CAP)));
    let masses = weights.map(|(importance, share)| {
        if with_tree {
            grid_masses(branch_probabilities(importance, share))
        } else {
            [0; TREE_WIDTH]
        }
    });
    for lane in 0..TREE_WIDTH {
        let child = node.child[lane];
        let footprint = mapped_lanes.map(|m| m.footprint_of(lane));
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
    Split::Children
}
