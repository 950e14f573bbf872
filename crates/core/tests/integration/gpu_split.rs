//! Arrays split over several storage bindings (`gpu/split.rs`): the kernels read element `i`
//! from chunk `i >> s`, so a split array must give exactly the results of one binding.
//!
//! The device's own limit (128 MiB on lavapipe) is reached only by tables of millions of
//! lights (`gpu_extremes.rs` runs `2^24 + 1` and `2^25`; the CLI tests render `8·10^6`);
//! here [`GpuContext::with_storage_binding_limit`] lowers it to a few KiB, so that small
//! scenes split into several chunks (the last one partial) and every kernel is compared,
//! bit for bit, with the same kernel over one binding: the histogram (table and atomic
//! counts split), the renderer's lights, and the spatial scheme's lights and tree nodes.

use crate::common::{self, SplitMix};

use glam::{dvec2, dvec3};
use lightpick_core::gpu::{self, GpuContext, GpuError, GpuRenderer};
use lightpick_core::scene::{ReceiverPlane, Scene};
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::{AliasTable, LightPowers, Rng, Sampler, Scheme};

/// `n` lights over `[-2, 2]² × [0.2, 1.2]`, powers over three decades, every 7th zero.
fn scene(n: usize, seed: u64) -> Scene {
    let mut d = SplitMix(seed);
    let positions: Vec<_> = (0..n)
        .map(|_| dvec3(d.range(-2.0, 2.0), d.range(-2.0, 2.0), d.range(0.2, 1.2)))
        .collect();
    let powers = (0..n)
        .map(|i| {
            if i % 7 == 3 {
                0.0
            } else {
                10f64.powf(d.range(-1.5, 1.5))
            }
        })
        .collect();
    Scene::new(
        format!("split-{n}"),
        ReceiverPlane {
            min: dvec2(-2.0, -1.5),
            max: dvec2(2.0, 1.5),
            width: 20,
            height: 15,
        },
        positions,
        LightPowers::new(powers).expect("valid"),
    )
}

/// The shared context with a binding limit of `bytes`.
fn limited(ctx: &GpuContext, bytes: u64) -> GpuContext {
    ctx.clone().with_storage_binding_limit(bytes)
}

/// The histogram with the table (8 bytes per light) in 6 chunks and the counts (4 bytes) in
/// 3, the last ones partial, equals the histogram over one binding and the CPU's counts.
#[test]
fn a_split_table_and_split_counts_count_what_one_binding_counts() {
    let Some(ctx) = common::context() else {
        return;
    };
    let n = 2500;
    let powers = scene(n, 1).powers;
    let sampler = Sampler::Alias(std::sync::Arc::new(AliasTable::build(&powers)));
    let small = limited(ctx, 4096);
    assert_eq!(small.storage_binding_limit(), 4096);
    eprintln!(
        "{} storage bindings per stage on {}",
        ctx.device().limits().max_storage_buffers_per_shader_stage,
        ctx.description()
    );
    let count = 400_000;
    let split = gpu::histogram(&small, &sampler, count, 3).expect("split histogram");
    let whole = gpu::histogram(ctx, &sampler, count, 3).expect("histogram");
    assert_eq!(split, whole);
    let mut cpu = vec![0u64; n];
    for k in 0..count {
        cpu[sampler.pick_light(&mut Rng::new(3, k)) as usize] += 1;
    }
    assert_eq!(split, cpu);
}

/// The renderer's lights (24 bytes each) in 5 chunks: uniform and alias images equal those
/// over one binding, bit for bit.
#[test]
fn split_lights_render_the_images_of_one_binding() {
    let Some(ctx) = common::context() else {
        return;
    };
    let s = scene(600, 2);
    let small = limited(ctx, 4096);
    for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::AliasOneRandom] {
        let mut split = GpuRenderer::new(&small, &s, scheme, 5).expect("split renderer");
        let mut whole = GpuRenderer::new(ctx, &s, scheme, 5).expect("renderer");
        split.accumulate(16).expect("accumulate");
        whole.accumulate(16).expect("accumulate");
        assert_eq!(
            split.readback().expect("readback"),
            whole.readback().expect("readback"),
            "{scheme}"
        );
    }
}

/// The spatial scheme's lights (16 bytes) and tree nodes (80 bytes) split too: the ~1700
/// contributing lights of 2000 are 7 chunks of 256 and the tree's nodes 3 of 32 at a 4 KiB
/// limit, and the image is the one over single bindings, bit for bit.
#[test]
fn a_split_light_tree_renders_the_image_of_one_binding() {
    let Some(ctx) = common::context() else {
        return;
    };
    // On 5 × 4 pixels: 20 tiles, whose cuts (up to 64 entries of 8 bytes each) split into
    // a few chunks too, beside the lights' and the nodes'.
    let mut s = scene(2000, 3);
    (s.plane.width, s.plane.height) = (5, 4);
    let SpatialSampler::Tree(tree) = SpatialSampler::build(&s.positions, &s.powers) else {
        panic!("2000 lights take the tree");
    };
    // 32 nodes of 80 bytes fit 4 KiB: more than 64 nodes are three chunks.
    assert!(tree.nodes().len() > 64, "{} nodes", tree.nodes().len());
    let small = limited(ctx, 4096);
    let mut split = GpuRenderer::new(&small, &s, Scheme::Spatial, 8).expect("split renderer");
    let mut whole = GpuRenderer::new(ctx, &s, Scheme::Spatial, 8).expect("renderer");
    split.accumulate(16).expect("accumulate");
    whole.accumulate(16).expect("accumulate");
    let (a, b) = (
        split.readback().expect("readback"),
        whole.readback().expect("readback"),
    );
    assert!(a.sum.iter().any(|&v| v > 0.0));
    assert_eq!(a, b);
    // Memory per light is unchanged by the split: only the bindings are.
    assert_eq!(split.gpu_bytes_per_light(), whole.gpu_bytes_per_light());
}

/// A split needing more bindings than the device offers per stage is refused by name,
/// before any pipeline is made: no panic.
#[test]
fn too_many_chunks_are_refused_with_a_message() {
    let Some(ctx) = common::context() else {
        return;
    };
    let limit = ctx.device().limits().max_storage_buffers_per_shader_stage;
    // 24-byte lights at 32 bytes per binding: one light per chunk, more chunks than bindings.
    let n = limit as usize + 8;
    let s = scene(n, 4);
    let small = limited(ctx, 32);
    let err = GpuRenderer::new(&small, &s, Scheme::Alias, 1).expect_err("too many bindings");
    assert!(
        matches!(err, GpuError::TooManyBindings { needed, limit: l, .. } if needed > l && l == limit),
        "{err}"
    );
    assert!(err.to_string().contains("storage bindings"), "{err}");
}
