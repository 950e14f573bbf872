//! Every scheme over spots and ranges: the light tree's pdf (Σ = 1, positive exactly where a
//! light contributes), its picks (χ²), unbiased estimates for every scheme, lane bounds that
//! never cull a lane that lights the point, and point scenes left exactly as they were.

use glam::{DVec2, dvec2, dvec3};
use lightpick_core::render::{CpuRenderer, Reference};
use lightpick_core::scene::{Emission, ReceiverPlane, Scene, Spot};
use lightpick_core::spatial::{Child, LightTree, SpatialSampler, TREE_WIDTH};
use lightpick_core::{Rng, Sampler, Scheme};

use crate::common::SplitMix;
use crate::common::fit::assert_picks_fit;
use crate::common::scenes::tilted_spot;

/// `n` lights over `[-2, 2]²` at heights 0.2–1.5: 60 % spots (cones 0.1–1.3 rad, most aimed
/// down, every 8th grazing or upwards), every third with a range of 0.5–3, every 9th at
/// power 0.
fn shaped(n: usize, seed: u64) -> Scene {
    shaped_with(n, seed, 3, 3)
}

/// [`shaped`] with `spots` of every 5 lights spots and every `range_every`-th light
/// ranged (1: all).
fn shaped_with(n: usize, seed: u64, spots: usize, range_every: usize) -> Scene {
    let mut d = SplitMix(seed);
    let mut positions = Vec::new();
    let mut powers = Vec::new();
    let mut emission = Vec::new();
    for i in 0..n {
        positions.push(dvec3(
            d.range(-2.0, 2.0),
            d.range(-2.0, 2.0),
            d.range(0.2, 1.5),
        ));
        powers.push(if i % 9 == 8 {
            0.0
        } else {
            10f64.powf(d.range(-2.0, 2.0))
        });
        let spot = (i % 5 < spots).then(|| {
            let outer = d.range(0.1, 1.3);
            let tilt = if i % 8 == 0 {
                d.range(1.0, 2.8)
            } else {
                d.range(0.0, 0.9)
            };
            tilted_spot(&mut d, outer, tilt, 0.0..0.9)
        });
        let range = (i % range_every == range_every / 2).then(|| d.range(0.5, 3.0));
        emission.push(Emission::new(spot, range).expect("valid"));
    }
    powers[0] = 1.0;
    Scene::from_parts(
        "shaped",
        ReceiverPlane {
            min: dvec2(-2.0, -2.0),
            max: dvec2(2.0, 2.0),
            width: 24,
            height: 24,
        },
        positions,
        powers,
    )
    .expect("valid")
    .with_emission(emission)
}

const POINTS: [DVec2; 5] = [
    dvec2(0.0, 0.0),
    dvec2(1.7, -1.6),
    dvec2(-0.37, 1.21),
    dvec2(3.0, 2.5),
    dvec2(0.5, 0.45),
];

fn tree(scene: &Scene) -> LightTree {
    LightTree::build_with_emission(&scene.positions, &scene.powers, scene.emission.as_deref())
}

/// The trees a scene with spots gets: without a region (unbounded lights weighed as
/// representative lights), mapped over the receiver's rectangle, and that one cut per tile
/// of the receiver's pixels (as [`SpatialSampler::for_scene`] builds it).
fn trees(scene: &Scene) -> [LightTree; 3] {
    let region = [scene.plane.min, scene.plane.max];
    let mapped = LightTree::build_over(
        &scene.positions,
        &scene.powers,
        scene.emission.as_deref(),
        Some(region),
    );
    [
        tree(scene),
        mapped.clone(),
        mapped.with_tile_cuts(&scene.plane),
    ]
}

/// `Σ_i P(i | x) ≤ 1`: with spots a descent may end in a leaf cluster none of whose lights
/// lights `x` (then `ê = 0`, no bias: those lights contribute nothing), so the pdf over the
/// lights sums to 1 less that leaf's probability; without such leaves it is 1.
#[test]
fn the_pdf_sums_to_one_and_is_positive_exactly_where_a_light_contributes() {
    for (n, seed) in [(40, 1), (400, 2)] {
        let scene = shaped(n, seed);
        for tree in trees(&scene) {
            pdf_sums_and_positivity(&scene, &tree);
        }
    }
}

fn pdf_sums_and_positivity(scene: &Scene, tree: &LightTree) {
    {
        let n = scene.light_count();
        let pmf = scene.powers.pmf();
        let depth = f64::from(tree.draws());
        for x in POINTS {
            let pdfs = tree.pdfs(x);
            let total: f64 = pdfs.iter().sum();
            assert!(
                total <= 1.0 + 16.0 * depth * f64::EPSILON,
                "Σ pdf = {total}"
            );
            // The rest is the probability of a descent that picks nothing: measured, it is
            // within 5 binomial standard deviations of 1 − Σ pdf.
            let draws = 20_000u64;
            let none = (0..draws)
                .filter(|&s| {
                    tree.sample(x, &mut lightpick_core::Rng::new(77, s))
                        .is_none()
                })
                .count() as f64;
            let q = (1.0 - total).max(0.0);
            let sd = (draws as f64 * q * (1.0 - q)).sqrt();
            assert!(
                (none - q * draws as f64).abs() <= 5.0 * sd + 1.0,
                "{none} empty picks of {draws}, expected {}",
                q * draws as f64
            );
            for i in 0..n {
                let c = pmf[i] * scene.light_term(i, x);
                assert_eq!(pdfs[i], tree.pdf(x, i));
                assert_eq!(
                    pdfs[i] > 0.0,
                    c > 0.0,
                    "light {i} at {x}: c {c}, pdf {}",
                    pdfs[i]
                );
            }
        }
    }
}

#[test]
fn picks_follow_their_pdf() {
    let scene = shaped(60, 3);
    let sampler = SpatialSampler::for_scene(&scene);
    let x = dvec2(0.3, -0.4);
    let pdfs = sampler.pdfs(x);
    let draws = 200_000u64;
    // One bucket per light, and a last one for a descent that reaches only dark lights
    // (a lane's map is a cell's mean, so a leaf may be taken where none of its lights
    // shines): its probability is what the lights' pdfs leave.
    let n = scene.light_count();
    let mut counts = vec![0u64; n + 1];
    for s in 0..draws {
        match sampler.sample(x, &mut Rng::new(5, s)) {
            Some(pick) => {
                assert!((pick.pdf - pdfs[pick.light as usize]).abs() <= 1e-12 * pick.pdf);
                counts[pick.light as usize] += 1;
            }
            None => counts[n] += 1,
        }
    }
    let none = (1.0 - pdfs.iter().sum::<f64>()).max(0.0);
    assert!(
        counts[..n].iter().sum::<u64>() > draws / 2,
        "lights contribute"
    );
    assert_picks_fit(&counts, draws, |i| if i < n { pdfs[i] } else { none });
}

/// Every scheme's mean of 60 000 estimates at each point is within 5 standard errors of
/// the exact `Σ p_i·G_i·S_i`.
#[test]
fn every_scheme_is_unbiased_with_spots_and_ranges() {
    let scene = shaped(300, 4);
    let pmf = scene.powers.pmf();
    let n = scene.light_count() as f64;
    let spatial = SpatialSampler::for_scene(&scene);
    for (k, x) in POINTS.iter().enumerate() {
        let exact: f64 = (0..scene.light_count())
            .map(|i| pmf[i] * scene.light_term(i, *x))
            .sum();
        for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::Cdf, Scheme::Spatial] {
            let sampler =
                (scheme != Scheme::Spatial).then(|| Sampler::build(scheme, &scene.powers));
            let m = 60_000u64;
            let (mut s, mut q) = (0.0, 0.0);
            for j in 0..m {
                let mut rng = Rng::new(k as u64 + 100, j);
                let e = match &sampler {
                    Some(sampler) => {
                        let i = sampler.pick_light(&mut rng) as usize;
                        let w = if scheme == Scheme::Uniform {
                            n * pmf[i]
                        } else {
                            1.0
                        };
                        w * scene.light_term(i, *x)
                    }
                    None => spatial.estimate(*x, &mut rng),
                };
                s += e;
                q += e * e;
            }
            let mean = s / m as f64;
            let se = ((q / m as f64 - mean * mean).max(0.0) / m as f64).sqrt();
            assert!(
                (mean - exact).abs() <= 5.0 * se + 1e-12 * exact,
                "{scheme} at {x}: mean {mean} vs exact {exact} (se {se})"
            );
        }
    }
}

/// A lane whose bounds say it cannot reach `x` holds no light that lights `x`: where every
/// spot has a range (every footprint bounded, culled by its box) and where none has (spots
/// tilted toward the horizon have unbounded footprints, culled by the cones the tree keeps
/// for their nodes alone).
#[test]
fn lane_bounds_never_cull_a_lane_that_lights_the_point() {
    // All spots, all ranged: every lane can be culled by its footprint.
    let (culled, by_cones) = cull_checked(&shaped_with(2000, 5, 5, 1));
    assert!(
        culled > 100,
        "the bounds cull something ({culled} lane-points)"
    );
    assert_eq!(by_cones, 0, "bounded footprints need no cones");
    let keeping_cones = |tree: &LightTree| {
        (0..tree.nodes().len())
            .filter(|&k| tree.mapped(k).is_some_and(|m| m.unbounded.is_some()))
            .count()
    };
    assert_eq!(
        keeping_cones(&tree(&shaped_with(2000, 5, 5, 1))),
        0,
        "nodes of bounded lanes keep no cones"
    );
    assert!(keeping_cones(&tree(&shaped_with(2000, 6, 5, usize::MAX))) > 0);
    // All spots, none ranged: a spot in eight tilts past the horizon.
    let (culled, by_cones) = cull_checked(&shaped_with(2000, 6, 5, usize::MAX));
    assert!(
        by_cones > 20,
        "the cones cull within unbounded footprints ({by_cones} of {culled} lane-points)"
    );
}

/// Checks that no lane of `scene`'s tree that culls a point of a 9 × 9 grid over the plane
/// (and around it) holds a light giving that point anything; returns the lane-points culled,
/// and of those the ones whose footprint held the point (culled by cone or range).
fn cull_checked(scene: &Scene) -> (usize, usize) {
    let tree = tree(scene);
    let pmf = scene.powers.pmf();
    let order = tree.order();
    // The leaf-order range of each child, from the node's first light.
    let (mut culled, mut by_cones) = (0usize, 0usize);
    let mut stack = vec![(0usize, 0usize)];
    let grid: Vec<DVec2> = (0..9)
        .flat_map(|a| {
            (0..9).map(move |b| dvec2(-2.2 + 0.55 * f64::from(a), -2.2 + 0.55 * f64::from(b)))
        })
        .collect();
    while let Some((k, first)) = stack.pop() {
        let node = &tree.nodes()[k];
        let lanes = tree.mapped(k).expect("shaped tree maps its lanes");
        let mut start = first;
        for lane in 0..TREE_WIDTH {
            let count = match node.child(lane).get() {
                Child::Node(j) => {
                    stack.push((j, start));
                    count_below(&tree, j)
                }
                Child::Leaf { count, .. } => count,
                Child::Empty => 0,
            };
            let [lo, hi] = lanes.footprint_of(lane);
            for &x in &grid {
                if lanes.reaches(lane, x) == 0.0 {
                    culled += 1;
                    if x.cmpge(lo).all() && x.cmple(hi).all() {
                        by_cones += 1;
                    }
                    for &i in &order[start..start + count] {
                        let c = pmf[i as usize] * scene.light_term(i as usize, x);
                        assert_eq!(
                            c, 0.0,
                            "node {k} lane {lane} culled at {x} but light {i} gives {c}"
                        );
                    }
                }
            }
            start += count;
        }
    }
    (culled, by_cones)
}

fn count_below(tree: &LightTree, k: usize) -> usize {
    (0..TREE_WIDTH)
        .map(|lane| match tree.nodes()[k].child(lane).get() {
            Child::Node(j) => count_below(tree, j),
            Child::Leaf { count, .. } => count,
            Child::Empty => 0,
        })
        .sum()
}

/// The CPU spatial render of a shaped scene converges to the reference: image mean within
/// 5 standard errors.
#[test]
fn spatial_renders_of_shaped_scenes_match_the_reference() {
    let scene = shaped(500, 6);
    let reference = Reference::compute(&scene);
    let mut r = CpuRenderer::new(&scene, Scheme::Spatial, 2);
    r.accumulate(32);
    let acc = r.accumulator();
    let p = acc.sum.len() as f64;
    let mean = acc.image().iter().sum::<f64>() / p;
    let exact = reference.values().iter().sum::<f64>() / p;
    let var: f64 = (0..acc.sum.len())
        .map(|q| acc.variance_per_sample(q))
        .sum::<f64>()
        / 32.0
        / (p * p);
    assert!(
        (mean - exact).abs() <= 5.0 * var.sqrt(),
        "{mean} vs {exact}"
    );
}

/// New powers on the same lights: the refitted tree equals a fresh build over them bit for
/// bit, for point lights and for spots and ranges, lights going to and from power 0
/// included.
#[test]
fn a_refit_equals_a_fresh_build() {
    for scene in [shaped(700, 9), {
        let mut s = shaped(700, 10);
        s.emission = None;
        s
    }] {
        let mut tree = tree(&scene);
        let mut d = SplitMix(3);
        let new: Vec<f64> = (0..scene.light_count())
            .map(|i| {
                if i % 7 == 0 {
                    0.0
                } else {
                    10f64.powf(d.range(-3.0, 3.0))
                }
            })
            .collect();
        let powers = lightpick_core::LightPowers::new(new).expect("valid");
        tree.refit(&powers);
        let fresh =
            LightTree::build_with_emission(&scene.positions, &powers, scene.emission.as_deref());
        assert!(tree == fresh, "refit differs from a fresh build");
        // The scene's own sampler, its lanes mapped over the receiver.
        let mut sampler = SpatialSampler::for_scene(&scene);
        let mut repowered = scene.clone();
        repowered.powers = powers;
        sampler.refit(&repowered);
        assert!(
            sampler == SpatialSampler::for_scene(&repowered),
            "the mapped tree's refit differs from a fresh build"
        );
    }
}

/// A refit maps again only the lanes over lights whose weight changed: after each of a
/// series of edits (one light's power, a light to 0 and back, the brightest light (every
/// weight's scale changes), every power doubled (every weight changes, no share does)) the
/// mapped sampler equals a fresh build over the new powers bit for bit.
#[test]
fn a_refit_after_a_few_changed_powers_equals_a_fresh_build() {
    let scene = shaped(700, 9);
    let mut sampler = SpatialSampler::for_scene(&scene);
    let mut powers = scene.powers.as_slice().to_vec();
    let brightest = (0..powers.len())
        .max_by(|&a, &b| powers[a].total_cmp(&powers[b]))
        .expect("lights");
    let dim = (brightest + 1) % powers.len();
    let other = (brightest + 18) % powers.len();
    for k in 0..5 {
        match k {
            0 => powers[dim] *= 1.5,
            1 => powers[other] = 0.0,
            2 => powers[other] = 2.0,
            3 => powers[brightest] *= 4.0,
            _ => powers.iter_mut().for_each(|x| *x *= 2.0),
        }
        let mut edited = scene.clone();
        edited.powers = lightpick_core::LightPowers::new(powers.clone()).expect("valid");
        sampler.refit(&edited);
        assert!(
            sampler == SpatialSampler::for_scene(&edited),
            "edit {k}: the refit differs from a fresh build"
        );
    }
}

/// pbrt-v4's `OneSpot`, for a tree: narrow spots aimed at their own marks leave most of the
/// plane dark. Wherever no spot gives a point anything, the sampler says so: every pick is
/// `None` and every pdf 0 (it never returns a light that gives nothing); wherever one does,
/// each light that gives the point something has a positive pdf and the picks land only on
/// such lights.
#[test]
fn where_no_spot_reaches_the_sampler_says_so() {
    let mut d = SplitMix(41);
    let mut positions = Vec::new();
    let mut emission = Vec::new();
    for _ in 0..200 {
        let from = dvec3(d.range(-3.0, 3.0), d.range(-3.0, 3.0), d.range(2.0, 4.0));
        let mark = dvec3(d.range(-3.0, 3.0), d.range(-3.0, 3.0), 0.0);
        let outer = d.range(0.02, 0.08);
        let range = (d.range(0.0, 1.0) < 0.3).then(|| d.range(4.5, 8.0));
        positions.push(from);
        let spot = Spot {
            direction: mark - from,
            inner_cone: 0.5 * outer,
            outer_cone: outer,
        };
        emission.push(Emission::new(Some(spot), range).expect("valid"));
    }
    let powers = (0..200).map(|_| d.range(1.0, 100.0)).collect();
    let plane = ReceiverPlane {
        min: dvec2(-3.0, -3.0),
        max: dvec2(3.0, 3.0),
        width: 16,
        height: 16,
    };
    let scene = Scene::from_parts("spots", plane, positions, powers)
        .expect("valid")
        .with_emission(emission);
    let pmf = scene.powers.pmf();
    let (mut dark, mut lit) = (0, 0);
    for tree in trees(&scene) {
        for k in 0..400 {
            let x = dvec2(d.range(-3.5, 3.5), d.range(-3.5, 3.5));
            let c: Vec<f64> = (0..200).map(|i| pmf[i] * scene.light_term(i, x)).collect();
            let pdfs = tree.pdfs(x);
            for draw in 0..200 {
                let pick = tree.sample(x, &mut Rng::new(k, draw));
                if let Some(pick) = pick {
                    assert!(c[pick.light as usize] > 0.0, "picked a dark light at {x}");
                }
            }
            if c.iter().all(|&c| c == 0.0) {
                dark += 1;
                assert!(
                    pdfs.iter().all(|&q| q == 0.0),
                    "a pdf where nothing shines at {x}"
                );
            } else {
                lit += 1;
                for i in 0..200 {
                    assert_eq!(pdfs[i] > 0.0, c[i] > 0.0, "light {i} at {x}");
                }
            }
        }
    }
    assert!(
        dark > 100 && lit > 100,
        "both kinds of points ({dark} dark, {lit} lit)"
    );
}
