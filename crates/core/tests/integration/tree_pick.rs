//! The stepped record of a spatial pick (`lesson::tree_pick`) replays the sampler exactly:
//! the same light, the same pdf bit for bit (also `SpatialSampler::pdf`), the same estimate
//! and the same draws, on point lights, spots and ranges, and few lights (the exact pick).
//! Each step's probabilities sum to 1, culled lanes have none and a reason that holds.

use glam::{DVec2, DVec3, dvec2, dvec3};
use lightpick_core::Rng;
use lightpick_core::lesson::tree_pick::{Culled, LaneStep, TreePick};
use lightpick_core::scene::{Emission, ReceiverPlane, Scene};
use lightpick_core::spatial::importance::grid_masses;
use lightpick_core::spatial::{Child, SpatialSampler};

use crate::common::SplitMix;
use crate::common::scenes::{scattered_random, tilted_spot};

/// `n` lights over `[-3, 3]²` at heights 0.1–2: spots (cones 0.05–1.4 rad, tilted up to
/// 1.2 rad) when `spots`, and ranges (1.05–3 times the height) on every other light when
/// `ranges`.
fn emitting(n: usize, seed: u64, spots: bool, ranges: bool) -> Scene {
    let mut d = SplitMix(seed);
    let mut positions = Vec::new();
    let mut powers = Vec::new();
    let mut emission = Vec::new();
    for i in 0..n {
        let position = dvec3(d.range(-3.0, 3.0), d.range(-3.0, 3.0), d.range(0.1, 2.0));
        let spot = spots.then(|| {
            let outer = d.range(0.05, 1.4);
            let tilt = d.range(0.0, 1.2);
            tilted_spot(&mut d, outer, tilt, 0.0..0.9)
        });
        let range = (ranges && i % 2 == 0).then(|| position.z * d.range(1.05, 3.0));
        positions.push(position);
        powers.push(10f64.powf(d.range(-2.0, 2.0)));
        emission.push(Emission::new(spot, range).expect("valid"));
    }
    Scene::from_parts(
        "emitting",
        ReceiverPlane {
            min: dvec2(-3.0, -3.0),
            max: dvec2(3.0, 3.0),
            width: 32,
            height: 32,
        },
        positions,
        powers,
    )
    .expect("valid")
    .with_emission(emission)
}

/// Points over the scene's rectangle widened by half on each side (some where nothing
/// shines).
fn points(scene: &Scene, count: usize, d: &mut SplitMix) -> Vec<DVec2> {
    let (lo, hi) = (scene.plane.min, scene.plane.max);
    let pad = 0.5 * (hi - lo);
    (0..count)
        .map(|_| {
            dvec2(
                d.range(lo.x - pad.x, hi.x + pad.x),
                d.range(lo.y - pad.y, hi.y + pad.y),
            )
        })
        .collect()
}

/// Records and samples at `count` points with streams of `seed`, checks every record
/// against the sampler and its own sums; returns the culled lanes' reasons seen.
fn check_scene(scene: &Scene, count: usize, seed: u64) -> Vec<Culled> {
    let sampler = SpatialSampler::for_scene(scene);
    let pmf = scene.powers.pmf();
    let mut d = SplitMix(seed);
    let mut reasons = Vec::new();
    let (mut recorded, mut cut_records) = (0, 0);
    for (k, x) in points(scene, count, &mut d).into_iter().enumerate() {
        let mut by_record = Rng::new(seed, k as u64);
        let mut by_sampler = by_record.clone();
        let record = TreePick::record(&sampler, x, &mut by_record);
        let pick = sampler.sample(x, &mut by_sampler);
        assert_eq!(by_record, by_sampler, "point {k}: the same draws");
        assert_eq!(record.is_some(), pick.is_some(), "point {k} at {x}");
        let (Some(record), Some(pick)) = (record, pick) else {
            continue;
        };
        recorded += 1;
        cut_records += usize::from(record.cut.is_some());
        assert_eq!(record.light, pick.light, "point {k}");
        assert_eq!(record.pdf.to_bits(), pick.pdf.to_bits(), "point {k}");
        assert_eq!(record.estimate.to_bits(), pick.estimate.to_bits());
        let light = record.light as usize;
        assert_eq!(
            record.pdf.to_bits(),
            sampler.pdf(x, light).to_bits(),
            "point {k}: pdf(x, {light})"
        );
        assert_eq!(record.power_pmf, pmf[light]);
        let exact: f64 = (0..scene.powers.len())
            .map(|i| pmf[i] * scene.light_term(i, x))
            .sum();
        assert!(
            (record.irradiance - exact).abs() <= 1e-12 * exact,
            "{} vs {exact}",
            record.irradiance
        );
        assert_eq!(record.picked().light, record.light);
        assert_eq!(record.picked().contribution, record.contribution);
        assert!(record.contribution > 0.0);
        reasons.extend(check_steps(&record, &sampler, scene, x));
    }
    assert!(recorded > count / 4, "{recorded} of {count} points picked");
    if matches!(sampler, SpatialSampler::Tree(_)) {
        assert!(
            cut_records > 0,
            "picks on the plane start from its tiles' cuts"
        );
    }
    reasons
}

/// The record's own arithmetic: masses summing to `2^24`, probabilities to 1 exactly,
/// the pdf the product of the realized factors, culled lanes without probability and with
/// a reason that holds (an empty lane, dark lights only, or emission profiles that cull).
fn check_steps(
    record: &TreePick,
    sampler: &SpatialSampler,
    scene: &Scene,
    x: DVec2,
) -> Vec<Culled> {
    let mut reasons = Vec::new();
    let mut pdf = 1.0;
    let mut first_depth = 0;
    if let Some(cut) = &record.cut {
        // The cut's entries: masses summing to 2^24 over disjoint leaf-order ranges, the
        // draw taking the entry the tile's alias columns give it (each entry is taken for
        // exactly its mass of the 2^24 draws: tile_cuts.rs counts them all).
        let total: u64 = cut.entries.iter().map(|e| u64::from(e.mass)).sum();
        assert_eq!(total, 1 << 24, "tile {}", cut.tile);
        let SpatialSampler::Tree(tree) = sampler else {
            panic!("a cut belongs to a tree");
        };
        let cuts = tree.tile_cuts().expect("cuts");
        let (taken, mass) = cuts
            .pick(tree, cut.tile, cut.random24)
            .expect("the tile has power");
        let entry = &cut.entries[cut.entry];
        assert_eq!((taken.get(), mass), (entry.child, entry.mass));
        for pair in cut.entries.windows(2) {
            assert!(pair[0].lights.end <= pair[1].lights.start);
        }
        let [[x0, y0], [x1, y1]] = cut.pixels;
        let [px, py] = scene.plane.pixel_at(x);
        assert!((x0..x1).contains(&px) && (y0..y1).contains(&py), "x's tile");
        pdf = cut.entries[cut.entry].probability;
        assert_eq!(cut.pdf_after, pdf);
        first_depth = cut.entries[cut.entry].depth;
    }
    for (depth, step) in record.steps.iter().enumerate() {
        assert_eq!(step.depth, first_depth + depth);
        let total: u64 = step.lanes.iter().map(|l| u64::from(l.mass)).sum();
        assert_eq!(total, 1 << 24, "node {}", step.node);
        assert_eq!(step.lanes.iter().map(|l| l.probability).sum::<f64>(), 1.0);
        // The numbers shown are the descent's: its masses follow from the probabilities.
        let shown = std::array::from_fn(|l| step.lanes[l].branch_probability);
        let masses: [u32; 4] = std::array::from_fn(|l| step.lanes[l].mass);
        assert_eq!(grid_masses(shown), masses, "node {}", step.node);
        assert_eq!(
            step.lanes.iter().map(LaneStep::light_count).sum::<usize>(),
            {
                let all = &step.lanes;
                all.iter().map(|l| l.lights.end).max().unwrap_or(0)
                    - all
                        .iter()
                        .filter(|l| !l.lights.is_empty())
                        .map(|l| l.lights.start)
                        .min()
                        .unwrap_or(0)
            }
        );
        let chosen = &step.lanes[step.lane];
        assert!(chosen.mass > 0 && chosen.culled.is_none());
        assert!(step.random24 < 1 << 24);
        pdf *= chosen.probability;
        assert_eq!(step.pdf_after, pdf);
        for lane in &step.lanes {
            assert_eq!(lane.culled.is_some(), lane.mass == 0);
            let Some(reason) = lane.culled else {
                assert!(lane.branch_probability > 0.0 && !lane.lights.is_empty());
                continue;
            };
            assert_eq!(lane.probability, 0.0);
            assert_eq!(reason == Culled::Empty, lane.child == Child::Empty);
            assert_eq!(lane.box_on_plane.is_none(), lane.lights.is_empty());
            reasons.push(reason);
            if reason == Culled::NoPower {
                let SpatialSampler::Tree(tree) = sampler else {
                    panic!("steps come from a tree");
                };
                let power: f64 = lane.lights.clone().map(|j| tree.lights()[j].power).sum();
                assert_eq!(power, 0.0, "a lane without weight holds only dark lights");
            } else if reason != Culled::Empty {
                assert!(
                    scene.emission.is_some(),
                    "point lights are culled only when empty"
                );
            }
        }
    }
    let leaf = &record.leaf;
    let masses: Vec<u32> = leaf.lights.iter().filter_map(|l| l.mass).collect();
    if masses.is_empty() {
        assert!(record.steps.is_empty(), "the exact pick");
        let total: f64 = leaf.lights.iter().map(|l| l.probability).sum();
        assert!((total - 1.0).abs() < 1e-14, "{total}");
    } else {
        assert_eq!(masses.iter().map(|&m| u64::from(m)).sum::<u64>(), 1 << 24);
        pdf *= leaf.lights[leaf.picked].probability;
        assert_eq!(leaf.pdf_after.to_bits(), pdf.to_bits());
        assert_eq!(record.pdf.to_bits(), pdf.to_bits());
    }
    for l in &leaf.lights {
        let i = l.light as usize;
        let c = scene.powers.pmf()[i] * scene.light_term(i, x);
        assert!((l.contribution - c).abs() <= 1e-15 * c, "light {i}");
    }
    reasons
}

#[test]
fn the_record_replays_point_light_trees() {
    let scene = scattered_random(1000, 41, 1.0, 2.0);
    let reasons = check_scene(&scene, 400, 7);
    // Zero-power lights stay in the tree (a refit may light them): a lane of only those
    // has no weight; nothing else is culled among point lights.
    assert!(
        reasons
            .iter()
            .all(|&r| r == Culled::Empty || r == Culled::NoPower),
        "{reasons:?}"
    );
    // A deeper tree: 5000 lights.
    check_scene(&scattered_random(5000, 42, 3.0, 3.0), 100, 8);
}

#[test]
fn the_record_replays_spot_and_range_trees_and_says_why_lanes_are_culled() {
    let mut seen = Vec::new();
    for (spots, ranges, seed) in [(true, false, 1), (false, true, 2), (true, true, 3)] {
        let scene = emitting(600, seed, spots, ranges);
        seen.extend(check_scene(&scene, 400, 10 + seed));
    }
    // Ranged lights have bounded footprints, so the range test of an unbounded lane (which
    // holds a light without a range) never culls here; the cone test does, at grazing spots.
    for reason in [Culled::Empty, Culled::OutsideFootprint, Culled::OutsideCone] {
        assert!(seen.contains(&reason), "{reason:?} never seen");
    }
}

#[test]
fn culled_lanes_hold_no_light_that_shines_at_the_point() {
    let scene = emitting(600, 5, true, true);
    let sampler = SpatialSampler::for_scene(&scene);
    let SpatialSampler::Tree(tree) = &sampler else {
        panic!("600 lights make a tree");
    };
    let mut d = SplitMix(99);
    let mut culled = 0;
    for (k, x) in points(&scene, 300, &mut d).into_iter().enumerate() {
        let Some(record) = TreePick::record(&sampler, x, &mut Rng::new(3, k as u64)) else {
            continue;
        };
        for step in &record.steps {
            for lane in step.lanes.iter().filter(|l| l.culled.is_some()) {
                for j in lane.lights.clone() {
                    let l = tree.lights()[j];
                    let c = l.contribution_with(tree.emission().get(j), x);
                    assert_eq!(c, 0.0, "light {j} of a culled lane shines at {x}");
                    culled += 1;
                }
            }
        }
    }
    assert!(culled > 100, "only {culled} culled lights checked");
}

#[test]
fn few_lights_record_the_exact_pick() {
    let scene = scattered_random(12, 3, 1.0, 1.0);
    assert!(matches!(
        SpatialSampler::for_scene(&scene),
        SpatialSampler::Exact(_)
    ));
    check_scene(&scene, 300, 4);
    let sampler = SpatialSampler::for_scene(&scene);
    let x = dvec2(0.1, -0.2);
    let record = TreePick::record(&sampler, x, &mut Rng::new(1, 2)).expect("lights shine");
    assert!(record.steps.is_empty());
    assert_eq!(record.estimate, record.irradiance, "zero variance");
    // Every contributing light listed once, none below the plane.
    let listed: Vec<usize> = record
        .leaf
        .lights
        .iter()
        .map(|l| l.light as usize)
        .collect();
    let above: Vec<usize> = (0..12)
        .filter(|&i| scene.positions[i].z > 0.0 && scene.powers.pmf()[i] > 0.0)
        .collect();
    assert_eq!(listed, above);
}

#[test]
fn nothing_to_pick_gives_no_record() {
    // Every light below the plane: no draw, no record.
    let scene = Scene::from_parts(
        "below",
        ReceiverPlane {
            min: dvec2(-1.0, -1.0),
            max: dvec2(1.0, 1.0),
            width: 4,
            height: 4,
        },
        (0..40)
            .map(|i| dvec3(f64::from(i) * 0.01, 0.0, -1.0))
            .collect::<Vec<DVec3>>(),
        vec![1.0; 40],
    )
    .expect("valid");
    let sampler = SpatialSampler::for_scene(&scene);
    let mut rng = Rng::new(0, 0);
    assert!(TreePick::record(&sampler, DVec2::ZERO, &mut rng).is_none());
    assert_eq!(rng, Rng::new(0, 0), "no draw");
}
