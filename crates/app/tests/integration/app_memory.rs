//! Memory per light: the app's own accounting of the heap bytes each part holds
//! ([`LightpickApp::memory_by_part`], from capacities and uploaded sizes), on a generated
//! scene of 10^6 lights against the worked example. The bound is what the code holds by
//! construction (a sum of capacities), not a measurement of the process: docs/numbers.md
//! gives both.

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use lightpick::app::LightpickApp;

use crate::common::{HANG_GUARD, gpu_expected, wgpu_eframe, window};

/// The lights of the generated scene.
const LIGHTS: usize = 1_000_000;

/// Bytes per light above the worked example the accounting may reach with the CPU renderer,
/// by construction: the scene's positions and powers (24 + 8; the edit shares them), the
/// packed table (8; the pmf the panels show is computed for the lights they show, a few
/// hundred), the light tree (leaf-order lights 32, scene indices 4,
/// 87 381 nodes of 152 + 4 bytes, each node's 8-byte reach among them: 49.6), its per-tile cuts
/// (64 × 64 tiles on its square receiver, each a 24-byte cell and, once cut, a 4-byte column count, 64
/// alias columns of 4 bytes and 64 entries of 8: 3.26) and the histograms' chi-square cells
/// (62 500 cells of 16 lights, 4 + 4 + 8 bytes each: 1.0); the CPU runs read the scene's
/// arrays. In all 93.89.
const CPU_BOUND: f64 = 93.9;

/// The same with the GPU runs (device bytes, in the process on lavapipe): lights 24, tree
/// lights 16, 80-byte nodes (7) and the cuts' words (3.2: 8 bytes a tile and the tiles'
/// words as on the CPU). In all 144.06.
const GPU_BOUND: f64 = 144.1;

/// Parts that must hold something once 10^6 lights are generated and a frame rendered.
const GROWING: [&str; 5] = [
    "scene: positions",
    "scene: powers",
    "alias table",
    "spatial sampler (light tree)",
    "histograms",
];

/// The accounting: heap bytes by part ([`LightpickApp::memory_by_part`]).
type Parts = Vec<(&'static str, usize)>;

fn total(parts: &[(&'static str, usize)]) -> usize {
    parts.iter().map(|(_, bytes)| bytes).sum()
}

/// Renders one frame (stepped) until the images of the current scene have been published.
fn step_until_published(harness: &mut Harness<'static, LightpickApp>) {
    let deadline = Instant::now() + HANG_GUARD;
    loop {
        harness.state_mut().step();
        harness.step();
        let generation = harness.state().state.built.generation;
        if harness
            .state_mut()
            .published()
            .is_some_and(|p| p.generation == generation)
        {
            return;
        }
        assert!(Instant::now() < deadline, "no frame of the scene arrived");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Generates [`LIGHTS`] lights as the Lights panel's Generate does (over the worked example's
/// plane, so the per-pixel parts are the worked example's), waits for the background build, renders a
/// frame, and returns the accounting before and after.
fn seed_and_generated(mut harness: Harness<'static, LightpickApp>) -> (Parts, Parts) {
    step_until_published(&mut harness);
    let seed = harness.state().memory_by_part();
    harness.state_mut().state.generate(LIGHTS);
    let deadline = Instant::now() + HANG_GUARD;
    while harness.state().state.built.len() != LIGHTS {
        assert!(Instant::now() < deadline, "the table never arrived");
        std::thread::sleep(Duration::from_millis(20));
        harness.step();
    }
    step_until_published(&mut harness);
    // A second frame: whatever the panels derive lazily (table rows, histograms) exists.
    harness.state_mut().step();
    harness.step();
    (seed, harness.state().memory_by_part())
}

/// Prints the table (for docs/numbers.md) and checks every part is reported, the growing ones
/// non-empty, and the total per light above the worked example within `bound`.
fn check(seed: &[(&'static str, usize)], large: &[(&'static str, usize)], bound: f64) {
    let names: Vec<_> = seed.iter().map(|(name, _)| *name).collect();
    assert_eq!(
        names,
        large.iter().map(|(name, _)| *name).collect::<Vec<_>>()
    );
    eprintln!("| part | bytes per light at 10^6 |");
    for (&(name, s), &(_, l)) in seed.iter().zip(large) {
        eprintln!("| {name} | {:.1} |", (l as f64 - s as f64) / LIGHTS as f64);
    }
    // Per-pixel parts (sums, outputs, the reference) depend on the plane, which generation
    // keeps, and on how far the reference of each scene had got: they are no cost per light.
    let per_light_parts = |parts: &[(&'static str, usize)]| {
        let kept: Vec<_> = parts
            .iter()
            .copied()
            .filter(|(name, _)| !name.contains("pixel"))
            .collect();
        total(&kept) as f64
    };
    let per_light = (per_light_parts(large) - per_light_parts(seed)) / LIGHTS as f64;
    eprintln!("| total above the worked example (per-pixel parts aside) | {per_light:.1} |");
    for part in GROWING {
        let bytes = large.iter().find(|(name, _)| *name == part).map(|p| p.1);
        assert!(bytes.is_some_and(|b| b > 0), "{part}: {bytes:?}");
    }
    assert!(
        per_light <= bound,
        "{per_light:.1} bytes per light above the worked example, over {bound}"
    );
}

/// The CPU renderer (kittest without a GPU: the images render inline on the CPU).
#[test]
fn a_million_generated_lights_cost_what_the_accounting_bounds_on_the_cpu() {
    let harness = window(LightpickApp::for_tests(), [1560.0, 960.0]);
    let (seed, large) = seed_and_generated(harness);
    let part = |name: &str| large.iter().find(|(n, _)| *n == name).map(|p| p.1);
    // The CPU runs render (their sums exist) and read the scene's own positions and powers:
    // for point lights they hold nothing per light.
    let sums = part("CPU runs: pixel sums, reference");
    assert!(sums.is_some_and(|b| b > 0), "{sums:?}");
    let lights = part("CPU runs: light profiles (positions and powers are the scene's)");
    assert_eq!(lights, Some(0));
    check(&seed, &large, CPU_BOUND);
}

/// The GPU runs on kittest's wgpu device (lavapipe here), whose buffers count as uploaded.
#[test]
fn a_million_generated_lights_cost_what_the_accounting_bounds_on_the_gpu() {
    if !gpu_expected() {
        return;
    }
    let harness = wgpu_eframe([1560.0, 960.0]);
    let (seed, large) = seed_and_generated(harness);
    let gpu = large
        .iter()
        .find(|(name, _)| *name == "GPU runs: lights, tree")
        .map(|p| p.1);
    assert!(gpu.is_some_and(|b| b > 0), "{gpu:?}");
    check(&seed, &large, GPU_BOUND);
}
