#![allow(clippy::unwrap_used)]
//! The sampling path at the extremes, on the CPU and on the GPU: `N = 1`, `N = 2^24 + 1`
//! and `2^25` (past the reach of `f32(u)·N`), all lights equal, one light `10^30` times the
//! rest, half the lights at zero, subnormal and near-`f64::MAX` powers, and images whose
//! exact irradiance spans `10^-30 … 10^30`.
//!
//! # Exhaustive over the column/threshold space
//! A two-random pick depends on `r1` only through its column `c = ⌊r1·N/2^32⌋` and on `r2`
//! only through `r2 < T_c`, so every possible outcome is one of: column `c` kept (`r2 = T_c −
//! 1`, when `T_c > 0`) or its alias taken (`r2 = T_c`). The probe kernel below evaluates both,
//! for one `r1` inside every column, with the project's own WGSL (`mulhi32`,
//! `alias_resolve`, the `pick.wgsl` prelude), and the CPU does the same with
//! `AliasTable::sample_u32`: no zero-power light may come out, and the two must agree.
//! The default path (`AliasTable::sample`) differs from this raw map only by redrawing the
//! `2^32 mod N` draws Lemire's test rejects; an accepted `r1` has the same column
//! `mulhi32(r1, N)`, so covering every column covers the default path too (its loop is
//! checked against the GPU in `gpu_rng.rs`, `gpu_histogram.rs` and `gpu_render.rs`).
//!
//! # Tables beyond one storage binding
//! `gpu::histogram` splits the packed table (8 bytes per light) and the counts (4) over as
//! many storage bindings as the device's `max_storage_buffer_binding_size` needs (128 MiB
//! on lavapipe: two for the table of `2^24 + 1` or `2^25` lights); its counts must equal
//! the CPU's bin for bin there. The probe binds thresholds and aliases as two arrays of
//! 4 bytes per light, so `2^25` lights fit one binding each.

use crate::common;
use crate::common::scenes::preset_at;
use glam::{DVec3, dvec2};

use std::sync::atomic::{AtomicU32, Ordering};

use lightpick_core::gpu::{self, GpuContext, GpuRenderer};
use lightpick_core::precision::{column_r_range, compare_one_random, compare_thresholds};
use lightpick_core::render::CpuRenderer;
use lightpick_core::scene::{ReceiverPlane, Scene};
use lightpick_core::{AliasTable, LightPowers, Rng, Sampler, Scheme};
use rayon::prelude::*;
use wgpu::util::DeviceExt as _;

/// For input `i`: `r1 = r1s[i]`, `column = mulhi32(r1, n)`, then the keep outcome
/// (`r2 = T − 1`, or `0xffffffff` when `T = 0`) and the alias outcome (`r2 = T`).
const PROBE_KERNEL: &str = r"
struct ProbeParams { n: u32, count: u32, pad0: u32, pad1: u32 }
@group(0) @binding(0) var<uniform> params: ProbeParams;
@group(0) @binding(1) var<storage, read> thresholds: array<u32>;
@group(0) @binding(2) var<storage, read> aliases: array<u32>;
@group(0) @binding(3) var<storage, read> r1s: array<u32>;
@group(0) @binding(4) var<storage, read_write> outputs: array<u32>;

fn alias_entry(column: u32) -> vec2<u32> {
    return vec2<u32>(thresholds[column], aliases[column]);
}

@compute @workgroup_size(256)
fn probe_columns(@builtin(global_invocation_id) gid: vec3<u32>,
                 @builtin(num_workgroups) groups: vec3<u32>) {
    let i = gid.y * groups.x * 256u + gid.x;
    if i >= params.count { return; }
    let column = mulhi32(r1s[i], params.n);
    let entry = alias_entry(column);
    var kept = 0xffffffffu;
    if entry.x > 0u {
        kept = alias_resolve(column, entry, entry.x - 1u);
    }
    outputs[3u * i] = column;
    outputs[3u * i + 1u] = kept;
    outputs[3u * i + 2u] = alias_resolve(column, entry, entry.x);
}
";

/// Columns probed per dispatch.
const CHUNK: usize = 1 << 21;

fn build(powers: Vec<f64>) -> (LightPowers, AliasTable) {
    let powers = LightPowers::new(powers).unwrap();
    let table = AliasTable::build(&powers);
    (powers, table)
}

/// An `r1` inside column `c`: the first of its range for even `c`, the last for odd `c`
/// and for the last column (whose last `r1` is `u32::MAX`).
fn r1_of(c: usize, n: usize) -> u32 {
    let (first, end) = column_r_range(c as u64, n as u64);
    if c.is_multiple_of(2) && c + 1 != n {
        first as u32
    } else {
        (end - 1) as u32
    }
}

/// The CPU half: both outcomes of every column through `sample_u32`; no zero light.
fn check_cpu_columns(powers: &LightPowers, table: &AliasTable) {
    let n = table.len();
    let p = powers.as_slice();
    for c in 0..n {
        let r1 = r1_of(c, n);
        assert_eq!(table.column(r1), c, "r1 {r1}");
        let t = table.packed()[c].threshold;
        if t > 0 {
            let kept = table.sample_u32(r1, t - 1);
            assert_eq!(kept as usize, c);
            assert!(p[c] > 0.0, "column {c} keeps a zero light");
        }
        let aliased = table.sample_u32(r1, t) as usize;
        assert!(p[aliased] > 0.0, "column {c} aliases zero light {aliased}");
    }
}

/// The GPU half: the probe kernel over every column, compared with the CPU.
fn check_gpu_columns(ctx: &GpuContext, powers: &LightPowers, table: &AliasTable) {
    let n = table.len();
    let device = ctx.device();
    let thresholds: Vec<u32> = table.packed().iter().map(|e| e.threshold).collect();
    let aliases: Vec<u32> = table.packed().iter().map(|e| e.alias).collect();
    let table_buffers = [
        storage_buffer(device, "probe thresholds", &thresholds),
        storage_buffer(device, "probe aliases", &aliases),
    ];
    drop((thresholds, aliases));
    let pipeline = probe_pipeline(device);
    let p = powers.as_slice();
    for start in (0..n).step_by(CHUNK) {
        let count = CHUNK.min(n - start);
        let r1s: Vec<u32> = (start..start + count).map(|c| r1_of(c, n)).collect();
        let words = probe_chunk(ctx, &pipeline, &table_buffers, &r1s, n);
        for (j, w) in words.chunks_exact(3).enumerate() {
            let c = start + j;
            let r1 = r1s[j];
            let t = table.packed()[c].threshold;
            assert_eq!(w[0] as usize, c, "GPU column of r1 = {r1}");
            if t > 0 {
                assert_eq!(w[1], table.sample_u32(r1, t - 1), "kept, column {c}");
            } else {
                assert_eq!(w[1], u32::MAX);
            }
            assert_eq!(w[2], table.sample_u32(r1, t), "aliased, column {c}");
            assert!(
                p[w[2] as usize] > 0.0,
                "GPU: column {c} gives zero light {}",
                w[2]
            );
        }
    }
}

/// A read-only storage buffer holding `contents`.
fn storage_buffer(device: &wgpu::Device, label: &str, contents: &[u32]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(contents),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

/// The probe kernel's pipeline: [`PROBE_KERNEL`] behind the RNG prelude and `pick.wgsl`.
fn probe_pipeline(device: &wgpu::Device) -> wgpu::ComputePipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("probe columns"),
        source: wgpu::ShaderSource::Wgsl(
            gpu::shader_source(&[gpu::PICK_WGSL, PROBE_KERNEL]).into(),
        ),
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("probe columns"),
        layout: None,
        module: &module,
        entry_point: Some("probe_columns"),
        compilation_options: wgpu::PipelineCompilationOptions::default(),
        cache: None,
    })
}

/// One dispatch of the probe kernel over `r1s` against the table's `[thresholds,
/// aliases]` buffers of `n` columns; waits and returns three words per input (column,
/// kept outcome, aliased outcome).
fn probe_chunk(
    ctx: &GpuContext,
    pipeline: &wgpu::ComputePipeline,
    [threshold_buffer, alias_buffer]: &[wgpu::Buffer; 2],
    r1s: &[u32],
    n: usize,
) -> Vec<u32> {
    let device = ctx.device();
    let count = r1s.len();
    let r1_buffer = storage_buffer(device, "probe r1", r1s);
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("probe params"),
        contents: bytemuck::cast_slice(&[n as u32, count as u32, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let out_bytes = (count * 12) as u64;
    let outputs = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe outputs"),
        size: out_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe staging"),
        size: out_bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("probe columns"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            (0, params.as_entire_binding()),
            (1, threshold_buffer.as_entire_binding()),
            (2, alias_buffer.as_entire_binding()),
            (3, r1_buffer.as_entire_binding()),
            (4, outputs.as_entire_binding()),
        ]
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource }),
    });
    let groups = (count as u32).div_ceil(256);
    let (gx, gy) = if groups > 65_535 {
        (65_535, groups.div_ceil(65_535))
    } else {
        (groups, 1)
    };
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("probe columns"),
    });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("probe columns"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
    }
    encoder.copy_buffer_to_buffer(&outputs, 0, &staging, 0, out_bytes);
    ctx.queue().submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, .., move |r| {
        sender.send(r).ok();
    });
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    receiver.recv().unwrap().unwrap();
    let words: Vec<u32> = bytemuck::cast_slice(&staging.get_mapped_range(..).unwrap()).to_vec();
    staging.unmap();
    words
}

/// Both halves plus the exact pmf bounds of the packed and one-random forms.
fn check_everywhere(powers: &LightPowers, table: &AliasTable) {
    check_cpu_columns(powers, table);
    let t = compare_thresholds(table);
    assert!(t.u32_error_over_bound <= 1.0 + 1e-6, "{t:?}");
    assert_eq!(t.u32_lost_lights, 0);
    let o = compare_one_random(table);
    assert_eq!(o.one_zero_leak, 0.0);
    assert_eq!(o.two_zero_leak, 0.0);
    assert!(o.one_error_over_bound < 1.0, "{o:?}");
    if let Some(ctx) = common::context() {
        check_gpu_columns(ctx, powers, table);
    }
}

/// GPU histogram bin for bin equal to the CPU picks, zero lights never counted.
fn check_histogram(powers: &LightPowers, count: u64, seed: u64) {
    let Some(ctx) = common::context() else {
        return;
    };
    for scheme in [Scheme::Alias, Scheme::AliasOneRandom] {
        let sampler = Sampler::build(scheme, powers);
        let gpu_counts = gpu::histogram(ctx, &sampler, count, seed).unwrap();
        let mut cpu = vec![0u64; powers.len()];
        for k in 0..count {
            cpu[sampler.pick_light(&mut Rng::new(seed, k)) as usize] += 1;
        }
        assert_eq!(gpu_counts, cpu, "{scheme}");
        for (i, &p) in powers.as_slice().iter().enumerate() {
            if p == 0.0 {
                assert_eq!(gpu_counts[i], 0, "{scheme}: zero light {i}");
            }
        }
    }
}

#[test]
fn one_light() {
    let (powers, table) = build(vec![1e-300]);
    check_everywhere(&powers, &table);
    check_histogram(&powers, 10_000, 1);
}

#[test]
fn all_equal() {
    let (powers, table) = build(vec![7.0; 4099]);
    assert!(table.packed().iter().all(|e| e.threshold == u32::MAX));
    check_everywhere(&powers, &table);
    check_histogram(&powers, 1 << 18, 2);
}

#[test]
fn one_light_1e30_times_the_rest() {
    let mut p = vec![1.0; 1000];
    p[500] = 1e30;
    let (powers, table) = build(p);
    check_everywhere(&powers, &table);
    // The dim lights keep threshold ≥ 1: each stays reachable, at 2^-32/N at least.
    for (c, e) in table.packed().iter().enumerate() {
        if c != 500 {
            assert_eq!(e.threshold, 1, "column {c}");
            assert_eq!(e.alias, 500);
        }
    }
    check_histogram(&powers, 1 << 18, 3);
}

#[test]
fn half_the_lights_at_zero() {
    let p: Vec<f64> = (0..10_000)
        .map(|i| {
            if i % 2 == 1 {
                0.0
            } else {
                1.0 + f64::from(i % 13)
            }
        })
        .collect();
    let (powers, table) = build(p);
    check_everywhere(&powers, &table);
    check_histogram(&powers, 1 << 19, 4);
}

#[test]
fn subnormal_and_near_max_powers() {
    let tiny = f64::from_bits(1);
    for p in [
        vec![tiny, 3.0 * tiny, 0.0, 2.0 * tiny],
        vec![f64::MAX, 0.0, f64::MAX / 3.0, f64::MAX / 7.0],
        vec![tiny, f64::MAX, 1.0, 0.0],
    ] {
        let (powers, table) = build(p);
        check_everywhere(&powers, &table);
        check_histogram(&powers, 1 << 16, 5);
    }
}

/// `N` beyond `2^24`: every column reachable (the last one by `r1 = u32::MAX`) on CPU and
/// GPU, zero lights never returned, and `gpu::histogram` (its table past one 128 MiB
/// binding on lavapipe) counting exactly what the CPU counts.
fn check_large(n: usize) {
    // Odd lights at zero, except the last light, which is positive.
    let p: Vec<f64> = (0..n)
        .map(|i| {
            if i % 2 == 1 && i + 1 != n {
                0.0
            } else {
                1.0 + (i % 5) as f64
            }
        })
        .collect();
    let (powers, table) = build(p);
    assert!(powers.as_slice()[n - 1] > 0.0);
    assert_eq!(table.column(u32::MAX), n - 1);
    let t = table.packed()[n - 1].threshold;
    assert_eq!(table.sample_u32(u32::MAX, t - 1) as usize, n - 1);
    check_cpu_columns(&powers, &table);
    let Some(ctx) = common::context() else {
        return;
    };
    check_gpu_columns(ctx, &powers, &table);
    let limit = ctx.storage_binding_limit();
    let zero: Vec<bool> = powers.as_slice().iter().map(|&x| x == 0.0).collect();
    let sampler = Sampler::Alias(std::sync::Arc::new(table));
    eprintln!(
        "N = {n}: {} bytes of table in bindings of at most {limit} bytes on {}",
        8 * n,
        ctx.description()
    );
    // Two samples per light: the GPU histogram over a table split across bindings (and
    // counts too, past 2^25 lights) equals the CPU loop's counts bin for bin.
    let count = 2 * n as u64;
    let counts = gpu::histogram(ctx, &sampler, count, 7).unwrap();
    let cpu: Vec<AtomicU32> = (0..n).map(|_| AtomicU32::new(0)).collect();
    (0..count).into_par_iter().for_each(|k| {
        let light = sampler.pick_light(&mut Rng::new(7, k)) as usize;
        cpu[light].fetch_add(1, Ordering::Relaxed);
    });
    assert_eq!(counts.iter().sum::<u64>(), count);
    let differ = counts
        .iter()
        .zip(&cpu)
        .filter(|(g, c)| **g != u64::from(c.load(Ordering::Relaxed)))
        .count();
    assert_eq!(differ, 0, "bins where the GPU counts differ from the CPU's");
    assert!(
        counts.iter().zip(&zero).all(|(&c, &z)| !z || c == 0),
        "a zero light was picked"
    );
}

#[test]
fn two_to_the_24_plus_1_lights() {
    check_large((1 << 24) + 1);
}

#[test]
fn two_to_the_25_lights() {
    check_large(1 << 25);
}

/// 60 lights on a 24 × 16 plane, powers `scale · (1 + i mod 7)`.
fn scaled_scene(scale: f64) -> Scene {
    let positions: Vec<DVec3> = (0..60)
        .map(|i| {
            let f = f64::from(i);
            [
                (f * 0.37).sin() * 1.5,
                (f * 0.61).cos() * 1.2,
                0.2 + (f * 0.13) % 0.8,
            ]
        })
        .map(DVec3::from)
        .collect();
    let powers = (0..60).map(|i| scale * f64::from(1 + i % 7)).collect();
    Scene::new(
        format!("scaled {scale:e}"),
        ReceiverPlane {
            min: dvec2(-2.0, -1.5),
            max: dvec2(2.0, 1.5),
            width: 24,
            height: 16,
        },
        positions,
        LightPowers::new(powers).unwrap(),
    )
}

/// GPU images (read back) of scenes whose exact irradiance spans `10^-30 … 10^30`: finite,
/// non-negative, and equal to the CPU image of the same picks within `f32` accuracy.
#[test]
fn images_spanning_1e_minus_30_to_1e30_stay_finite_on_the_gpu() {
    let extreme = preset_at("extreme-range", 24, 24);
    let scenes = [scaled_scene(1e-30), scaled_scene(1e30), extreme];
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for scene in &scenes {
        for px in 0..scene.plane.width {
            for py in 0..scene.plane.height {
                let x = lightpick_core::scene::pixel_center(&scene.plane, px, py);
                let e = scene.exact_irradiance(x);
                lo = lo.min(e);
                hi = hi.max(e);
            }
        }
    }
    assert!(lo < 1e-29 && hi > 1e29, "exact range {lo:e} … {hi:e}");
    let Some(ctx) = common::context() else {
        return;
    };
    for scene in &scenes {
        for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::AliasOneRandom] {
            let mut gpu = GpuRenderer::new(ctx, scene, scheme, 9).unwrap();
            gpu.accumulate(16).unwrap();
            let image = gpu.readback().unwrap().image();
            let mut cpu = CpuRenderer::new(scene, scheme, 9);
            cpu.accumulate(16);
            let want = cpu.accumulator().image();
            let max = want.iter().copied().fold(0.0, f64::max);
            for (p, (&g, &c)) in image.iter().zip(&want).enumerate() {
                assert!(
                    g.is_finite() && g >= 0.0,
                    "{} {scheme}: pixel {p} = {g}",
                    scene.name
                );
                // f32 positions, G and running sums: well within 1e-3 relative. Uniform
                // picks of lights with p_i below the f32 range contribute 0 on the GPU
                // (1e-60 of the pixel at most): allowed as 1e-6 of the image's maximum.
                let tol = 1e-3 * c
                    + if scheme == Scheme::Uniform {
                        1e-6 * max
                    } else {
                        0.0
                    };
                assert!(
                    (g - c).abs() <= tol,
                    "{} {scheme}: pixel {p}: {g:e} vs {c:e}",
                    scene.name
                );
            }
        }
    }
}
