//! The light tree's cases (`tree-build`, `tree-refit`) and the app's whole answer to a power
//! drag (`app-repower`), each beside the time of one pick of the tree at a shading point.

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
/// positions: [`lightpick_core::spatial::LightTree::refit`], `O(N)` bottom up, in `build_ns`)
/// and `app-repower` (the app's whole answer to a power drag, [`time_app_repower`]), each
/// with the time of one pick at a shading point.
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
    let refit_ns = median_ns(reps, 1, |rep| {
        tree.refit(if rep % 2 == 0 { other } else { powers });
    });
    let picks = 1 << 16;
    let sample_ns = median_ns(reps, picks, |k| {
        let mut rng = Rng::new(seed, k as u64);
        let x = glam::dvec2(unit(k, 4), unit(k, 5));
        tree.sample(x, &mut rng).map_or(0, |p| p.light)
    });
    let repower_ns = time_app_repower(&positions, powers, other, reps);
    ["tree-build", "tree-refit", "app-repower"]
        .into_iter()
        .zip([build_ns, refit_ns, repower_ns])
        .map(|(method, build_ns)| Case {
            n,
            method,
            rng: "pcg",
            build_ns,
            rebuild_ns: None,
            sample_ns,
            threads,
            build_faults: None,
            rebuild_faults: None,
        })
        .collect()
}

/// The app's answer to a power drag, in `build_ns`: from `AppState::powers_changed` (new
/// powers, same positions) until the rebuilt samplers are installed (validation, the
/// scene's assembly, the table's rebuild and the tree's refit, on the worker thread for
/// large scenes, polled every 0.1 ms as a frame would). The images restart on the next
/// frame.
fn time_app_repower(
    positions: &[DVec3],
    powers: &LightPowers,
    other: &LightPowers,
    reps: usize,
) -> f64 {
    let plane = scene_io::seed_scene().plane;
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
