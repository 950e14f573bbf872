//! The GPU twin of the spatial scheme (`spatial.wgsl`) against the CPU renderer, same seed.
//!
//! # The agreement criterion
//! The descent's branch decisions compare the same 24-bit uniform `u` with a branch
//! probability computed in `f32` on the GPU and in `f64` on the CPU, so a decision can differ
//! when `u` falls within the probability's rounding error of the boundary. Each importance
//! is a formula of the same kind as `G` (offsets, squares, a square root, a division), so it
//! carries the `f32` relative error `E = (57 B/z_min + 26)·u` derived in `gpu_render.rs`
//! (`u = 2^-24`, `B` the largest coordinate); a branch probability `I_L/(I_L + I_R)` then
//! carries `≤ 2E + 3u`. Hence:
//!
//! * where every decision agrees, the estimate `p_i·G_i/Π P` differs by at most
//!   `((2d + 1)·E + (4d + 3 + spp)·u)` relative (d = depth; `spp` for the f32 running sum);
//! * the decision `(r >> 8) < t`, `t = ⌈P·2^24⌉`, uses a threshold that differs between the
//!   two sides by at most `1 + P·2^24·(2E + 3u)`: the realized factor `t/2^24` then differs
//!   by `(2E + 3u)` relative plus `1/t`, and the decision itself flips with probability
//!   `≤ 2E + 4u` per level; the `1/t` term matters only for small `t`, that is for a branch
//!   taken with probability `t·2^-24`, rare enough to fall among the flips;
//! * so at most `spp·d·(2E + 4u)` of the pixels are expected to differ beyond the first
//!   bound; we allow twice that plus 3 pixels, and print what we see (typically 0);
//! * the image means (over all pixels) agree within 5 standard errors of the CPU mean.

use crate::common;

use crate::common::scenes::{preset_at, scattered_random};
use lightpick_core::Scheme;
use lightpick_core::gpu::GpuRenderer;
use lightpick_core::render::CpuRenderer;
use lightpick_core::scene::Scene;
use lightpick_core::spatial::SpatialSampler;

const U: f64 = 1.0 / (1u64 << 24) as f64;

/// `(per-pixel relative tolerance, allowed fraction of pixels beyond it)`; see the docs.
fn criterion(scene: &Scene, spp: u32) -> (f64, f64) {
    let p = &scene.plane;
    let mut b = p.min[0]
        .abs()
        .max(p.max[0].abs())
        .max(p.min[1].abs())
        .max(p.max[1].abs());
    let mut z_min = f64::INFINITY;
    for l in scene.positions.iter() {
        b = b.max(l[0].abs()).max(l[1].abs()).max(l[2].abs());
        if l[2] > 0.0 {
            z_min = z_min.min(l[2]);
        }
    }
    let depth = match SpatialSampler::build(&scene.positions, &scene.powers) {
        SpatialSampler::Exact(_) => 1.0, // the sum of ≤ 16 terms: covered by one "level"
        SpatialSampler::Tree(t) => f64::from(t.draws()),
    };
    let e = (57.0 * b / z_min + 26.0) * U;
    let spp = f64::from(spp);
    let rel = (2.0 * depth + 1.0) * e + (4.0 * depth + 3.0 + spp) * U;
    let flip = spp * depth * (2.0 * e + 4.0 * U);
    (rel, flip)
}

fn compare(scene: &Scene, seed: u64, what: &str) {
    let Some(ctx) = common::context() else {
        return;
    };
    let mut gpu = GpuRenderer::new(ctx, scene, Scheme::Spatial, seed).expect("renderer");
    gpu.accumulate(7).expect("accumulate");
    gpu.accumulate(9).expect("accumulate");
    let g = gpu.readback().expect("readback");
    let mut cpu = CpuRenderer::new(scene, Scheme::Spatial, seed);
    cpu.accumulate(16);
    let c = cpu.accumulator();
    let (rel, flip) = criterion(scene, 16);
    let pixels = c.sum.len();
    let mut differing = 0usize;
    let mut worst = 0.0f64;
    let (mut mean_g, mut mean_c, mut var) = (0.0, 0.0, 0.0);
    for p in 0..pixels {
        let (a, b) = (g.mean(p), c.mean(p));
        assert!(a.is_finite() && a >= 0.0, "{what}: GPU pixel {p} = {a}");
        if (a - b).abs() > rel * b {
            differing += 1;
        } else if b > 0.0 {
            worst = worst.max((a - b).abs() / b);
        }
        mean_g += a / pixels as f64;
        mean_c += b / pixels as f64;
        var += c.variance_per_sample(p) / 16.0 / (pixels as f64 * pixels as f64);
    }
    let allowed = 2.0 * flip * pixels as f64 + 3.0;
    eprintln!(
        "{what}: {differing} of {pixels} pixels beyond {rel:.2e} (allowed {allowed:.1}); \
         worst agreeing {worst:.2e}; means GPU {mean_g:.6e} CPU {mean_c:.6e}; {} B/light",
        gpu.gpu_bytes_per_light()
    );
    assert!(
        (differing as f64) <= allowed,
        "{what}: {differing} pixels differ"
    );
    assert!(
        (mean_g - mean_c).abs() <= 5.0 * var.sqrt() + rel * mean_c,
        "{what}: means {mean_g} vs {mean_c}"
    );
}

#[test]
fn exact_scheme_matches_the_cpu() {
    compare(&scattered_random(3, 1, 1.0, 1.0), 42, "3 lights (exact)");
    compare(&scattered_random(16, 2, 1.0, 3.0), 43, "16 lights (exact)");
}

#[test]
fn light_tree_matches_the_cpu() {
    compare(&scattered_random(700, 3, 1.0, 3.0), 9, "700 lights (tree)");
    compare(&scattered_random(17, 4, 1.0, 1.0), 10, "17 lights (tree)");
}

#[test]
fn extreme_powers_and_scales_match_the_cpu() {
    compare(
        &scattered_random(300, 5, 1.0, 30.0),
        3,
        "powers 1e-30..1e30",
    );
    compare(&scattered_random(200, 6, 1e15, 2.0), 4, "scale 1e15");
    compare(&scattered_random(200, 7, 1e-15, 2.0), 5, "scale 1e-15");
}

#[test]
fn presets_match_the_cpu() {
    // `heavy-tail`'s tiles are cut into more than 128 entries: the GPU's draw through 256
    // alias columns (eight alias bits above a 16-bit threshold) is compared too.
    let heavy = preset_at("heavy-tail", 32, 32);
    let SpatialSampler::Tree(tree) = SpatialSampler::for_scene(&heavy) else {
        panic!("a tree");
    };
    let cuts = tree.tile_cuts().expect("cuts");
    let [tx, ty] = cuts.tiles();
    let most = (0..(tx * ty) as usize)
        .map(|tile| cuts.entries(&tree, tile).count())
        .max();
    assert!(
        most > Some(128),
        "heavy-tail's largest cut: {most:?} entries"
    );
    for name in ["extreme-range", "heavy-tail", "million", "zeros"] {
        compare(&preset_at(name, 32, 32), 1, name);
    }
}

#[test]
fn one_light_and_lights_below_the_plane() {
    let mut one = scattered_random(1, 8, 1.0, 0.0);
    std::sync::Arc::make_mut(&mut one.positions)[0][2] = 0.7;
    compare(&one, 2, "one light");
    let Some(ctx) = common::context() else {
        return;
    };
    let mut below = scattered_random(40, 9, 1.0, 1.0);
    for p in std::sync::Arc::make_mut(&mut below.positions) {
        p[2] = -p[2].abs();
    }
    let mut r = GpuRenderer::new(ctx, &below, Scheme::Spatial, 1).expect("renderer");
    r.accumulate(4).expect("accumulate");
    assert!(
        r.readback()
            .expect("readback")
            .sum
            .iter()
            .all(|&s| s == 0.0)
    );
}

/// Switching to spatial and back, and new powers, give the images of fresh renderers; the
/// tree costs its lights in leaf order (16 bytes each) and its 80-byte nodes (one per ~22
/// lights): under 24 more GPU bytes per light; its per-tile cuts 8 bytes an entry, 4 a
/// column (fewer than two an entry) and 8 a tile, and 12 more.
#[test]
fn scheme_switches_and_new_powers_rebuild_the_tree() {
    let Some(ctx) = common::context() else {
        return;
    };
    let a = scattered_random(500, 10, 1.0, 2.0);
    let mut r = GpuRenderer::new(ctx, &a, Scheme::Alias, 6).expect("renderer");
    assert_eq!(r.gpu_bytes_per_light(), 24);
    r.set_scheme(Scheme::Spatial).expect("spatial");
    let SpatialSampler::Tree(tree) = SpatialSampler::for_scene(&a) else {
        panic!("500 lights take the tree");
    };
    let tree_bytes = (tree.nodes().len() * 80 + tree.lights().len() * 16) as u64;
    assert!(tree_bytes.div_ceil(500) <= 24);
    let cuts = tree.tile_cuts().expect("cut per tile");
    let [tx, ty] = cuts.tiles();
    let (offsets, words) = cuts.gpu_words(&tree);
    assert_eq!(offsets.len() as u32, tx * ty + 1);
    // Per tile its column count, columns (K ≤ 2n) and entries (mass, child).
    let entries: usize = (0..(tx * ty) as usize)
        .map(|t| cuts.entries(&tree, t).count())
        .sum();
    assert!(words.len() <= (tx * ty) as usize + 4 * entries);
    let cut_bytes = 12 + 4 * offsets.len() as u64 + 4 * words.len() as u64;
    assert_eq!(
        r.gpu_bytes_per_light(),
        24 + (tree_bytes + cut_bytes).div_ceil(500)
    );
    r.accumulate(4).expect("accumulate");
    let mut fresh = GpuRenderer::new(ctx, &a, Scheme::Spatial, 6).expect("renderer");
    fresh.accumulate(4).expect("accumulate");
    assert_eq!(
        r.readback().expect("readback"),
        fresh.readback().expect("readback")
    );

    let b = scattered_random(500, 11, 1.0, 2.0);
    r.set_powers(&b.powers).expect("powers");
    r.accumulate(4).expect("accumulate");
    let mut b_scene = a.clone();
    b_scene.powers = b.powers.clone();
    let mut fresh = GpuRenderer::new(ctx, &b_scene, Scheme::Spatial, 6).expect("renderer");
    fresh.accumulate(4).expect("accumulate");
    assert_eq!(
        r.readback().expect("readback"),
        fresh.readback().expect("readback")
    );
}
