//! The light tree's cases (`tree-build`, `tree-refit`) and the app's whole answer to a power
//! edit (`app-repower`, `app-repower-one`), each beside the time of one pick of the tree at a
//! shading point.

// The app's state, driven as a power drag drives it (kept here, one place to re-point).
use crate::app::scene_io;
use crate::app::state::{AppState, Settings};

use glam::DVec3;
use lightpick_core::scene::Scene;
use lightpick_core::spatial::LightTree;
use lightpick_core::{LightPowers, Rng};

use super::case::Case;
use super::timing::median_ns;

/// The light tree at `N` lights spread over a unit square at heights `0.1 … 1`: `tree-build`
/// (layout by positions and lanes, `O(N log N)`), `tree-refit` (new powers, same
/// positions: [`lightpick_core::spatial::LightTree::refit`], `O(N)` bottom up, in `build_ns`),
/// `tree-refit-cuts` (the same with the tiles' cuts cut again, [`time_refit_with_cuts`]),
/// over spots `tree-refit-spots` (every power changed) and `tree-refit-spots-one` (one light's
/// power changed, as a drag does: only the maps over it are integrated again), and
/// the app's whole answer to a power edit ([`time_app_repower`]): `app-repower` with every
/// power changed (Randomize, a typed list) and `app-repower-one` with one light's (a drag),
/// each with the time of one pick at a shading point.
pub(super) fn time_tree(
    n: usize,
    powers: &LightPowers,
    other: &LightPowers,
    seed: u64,
    reps: usize,
) -> Vec<Case> {
    let unit = |i: usize, salt: u64| {
        f64::from(lightpick_core::pcg_hash(
            (i as u32) ^ (seed as u32) ^ salt as u32,
        )) / f64::from(u32::MAX)
    };
    let positions: Vec<DVec3> = (0..n)
        .map(|i| glam::dvec3(unit(i, 1), unit(i, 2), 0.1 + 0.9 * unit(i, 3)))
        .collect();
    let threads = rayon::current_num_threads();
    let build_ns = median_ns(reps.min(3), 1, |_| LightTree::build(&positions, powers));
    let mut tree = LightTree::build(&positions, powers);
    let tree_bytes = tree.heap_bytes() as f64 / n as f64;
    let refit_ns = median_ns(reps, 1, |rep| {
        tree.refit(if rep % 2 == 0 { other } else { powers });
    });
    let picks = 1 << 16;
    let sample_ns = median_ns(reps, picks, |k| {
        let mut rng = Rng::new(seed, k as u64);
        let x = glam::dvec2(unit(k, 4), unit(k, 5));
        tree.sample(x, &mut rng).map_or(0, |p| p.light)
    });
    let refit_cut_ns = time_refit_with_cuts(&positions, powers, other, reps);
    let repower_ns = time_app_repower(&positions, powers, other, reps);
    let repower_one_ns = time_app_repower(&positions, powers, &one_changed(powers), reps);
    let mut cases = vec![
        ("tree-build", build_ns, Some(tree_bytes)),
        ("tree-refit", refit_ns, None),
        ("tree-refit-cuts", refit_cut_ns, None),
        ("app-repower", repower_ns, None),
        ("app-repower-one", repower_one_ns, None),
    ];
    if n <= SPOT_REFIT_MAX_LIGHTS {
        let (all_ns, spot_bytes) = time_spot_refit(&positions, powers, other, seed, reps);
        cases.push(("tree-refit-spots", all_ns, Some(spot_bytes)));
        let (one_ns, _) = time_spot_refit(&positions, powers, &one_changed(powers), seed, reps);
        cases.push(("tree-refit-spots-one", one_ns, None));
    }
    cases
        .into_iter()
        .map(|(method, build_ns, bytes_per_light)| Case {
            n,
            method,
            rng: "pcg",
            build_ns,
            rebuild_ns: None,
            sample_ns,
            threads,
            build_faults: None,
            rebuild_faults: None,
            bytes_per_light,
        })
        .collect()
}

/// `tree-refit-cuts`: the refit of the tree cut per tile of a 512 × 512 pixel receiver
/// over the unit square (as a scene's spatial sampler is), in `build_ns`: the lanes bottom
/// up, then every tile's cut again ([`lightpick_core::spatial::TileCuts::cut_all`], which
/// a first render pass does tile by tile as it needs them).
fn time_refit_with_cuts(
    positions: &[DVec3],
    powers: &LightPowers,
    other: &LightPowers,
    reps: usize,
) -> f64 {
    let plane = lightpick_core::scene::ReceiverPlane {
        min: glam::dvec2(0.0, 0.0),
        max: glam::dvec2(1.0, 1.0),
        width: 512,
        height: 512,
    };
    let mut tree = LightTree::build(positions, powers).with_tile_cuts(&plane);
    median_ns(reps.min(5), 1, |rep| {
        tree.refit(if rep % 2 == 0 { other } else { powers });
        // The tiles are cut when first needed: here all of them, as a first pass does.
        if let Some(cuts) = tree.tile_cuts() {
            cuts.cut_all(&tree);
        }
    })
}

/// The most lights the spot tree's refit is timed at (its maps make it the dearest case).
const SPOT_REFIT_MAX_LIGHTS: usize = 100_000;

/// `powers` with one light's changed, as a drag changes it: the dimmest light's, to halfway
/// towards the brightest (the largest power, and so every other light's weight, unchanged).
fn one_changed(powers: &LightPowers) -> LightPowers {
    let mut changed = powers.as_slice().to_vec();
    let (dimmest, _) = changed
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &0.0));
    changed[dimmest] = 0.5 * (changed[dimmest] + powers.max());
    LightPowers::new(changed).unwrap_or_else(|_| powers.clone())
}

/// `tree-refit-spots` (and `tree-refit-spots-one`, with `other` the powers of
/// [`one_changed`]): the refit of a tree over the same positions as spots (each aimed down
/// within 0.6 rad, cones of 0.1–0.8 rad) mapped over the unit square, in `build_ns`: the
/// lanes' bounds bottom up and the maps of the lanes over a light whose power changed
/// integrated again from their lights (see [`lightpick_core::spatial::LightTree::refit`]);
/// and the tree's heap bytes per light.
fn time_spot_refit(
    positions: &[DVec3],
    powers: &LightPowers,
    other: &LightPowers,
    seed: u64,
    reps: usize,
) -> (f64, f64) {
    use lightpick_core::scene::{Emission, Spot};
    let unit = |i: usize, salt: u64| {
        f64::from(lightpick_core::pcg_hash(
            (i as u32) ^ (seed as u32) ^ salt as u32,
        )) / f64::from(u32::MAX)
    };
    let emission: Vec<Emission> = (0..positions.len())
        .map(|i| {
            let (tilt, turn) = (0.6 * unit(i, 7), std::f64::consts::TAU * unit(i, 8));
            let outer = 0.1 + 0.7 * unit(i, 9);
            let spot = Spot {
                direction: glam::dvec3(
                    tilt.sin() * turn.cos(),
                    tilt.sin() * turn.sin(),
                    -tilt.cos(),
                ),
                inner_cone: 0.5 * outer,
                outer_cone: outer,
            };
            Emission::new(Some(spot), None).unwrap_or(Emission::POINT)
        })
        .collect();
    let region = Some([glam::dvec2(0.0, 0.0), glam::dvec2(1.0, 1.0)]);
    let mut tree = LightTree::build_over(positions, powers, Some(&emission), region);
    let refit_ns = median_ns(reps.min(5), 1, |rep| {
        tree.refit(if rep % 2 == 0 { other } else { powers });
    });
    (
        refit_ns,
        tree.heap_bytes() as f64 / positions.len().max(1) as f64,
    )
}

/// The app's answer to a power edit from `powers` to `other` and back, in `build_ns`: from
/// writing the new powers into the edit and `AppState::powers_changed` (same positions)
/// until the rebuilt samplers are installed (validation, the scene's assembly, the table's
/// rebuild and the tree's refit, on the worker thread for large scenes, polled every 0.1 ms
/// as a frame would, then the undo step and the histograms' restart). The images restart on
/// the next frame.
fn time_app_repower(
    positions: &[DVec3],
    powers: &LightPowers,
    other: &LightPowers,
    reps: usize,
) -> f64 {
    let plane = scene_io::worked_example_scene().plane;
    let scene = Scene::new("bench", plane, positions.to_vec(), powers.clone());
    let mut state = AppState::new(scene, Settings::default());
    let inputs = [other.as_slice(), powers.as_slice()];
    median_ns(reps.min(5), 1, |rep| {
        state.edit.powers_mut().copy_from_slice(inputs[rep % 2]);
        state.powers_changed();
        while state.is_building() {
            std::thread::sleep(std::time::Duration::from_micros(100));
            state.poll_build();
        }
        state.built.generation
    })
}
