//! Runs the WGSL RNG prelude (and its exact uniform pick) on chosen inputs, so tests can
//! compare it with the CPU.

use super::{GpuContext, GpuError, WORKGROUP_SIZE};

pub(crate) const PROBE_WGSL: &str = include_str!("probe.wgsl");

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ProbeParams {
    count: u32,
    draws: u32,
    threads_per_row: u32,
    n: u32,
}

/// The first `draws` outputs of the GPU's `Rng::new(seed, stream)` for each pair, row by
/// row: element `i·draws + d` is draw `d` of pair `i`, which must equal the CPU's
/// [`crate::Rng::new`]`(seed, stream)` followed by `d + 1` calls of `next_u32`.
pub fn probe_rng(ctx: &GpuContext, pairs: &[(u64, u64)], draws: u32) -> Result<Vec<u32>, GpuError> {
    let inputs = key_words(pairs);
    run(ctx, "probe_rng", &inputs, draws, 0)
}

/// `(pick, next)` for each `(seed, stream)` pair as the GPU computes them: `pick_uniform(n)`
/// (Lemire's exact pick, redrawing from the stream while a draw is rejected) on
/// `Rng::new(seed, stream)`, and the draw that follows it. They must equal the CPU's
/// [`crate::Uniform::sample`] and the `next_u32` after it (same pick, same draws consumed).
///
/// # Panics
/// If `n` is 0.
pub fn probe_pick_uniform(
    ctx: &GpuContext,
    pairs: &[(u64, u64)],
    n: u32,
) -> Result<Vec<(u32, u32)>, GpuError> {
    assert!(n > 0, "no values to pick from");
    let words = run(ctx, "probe_pick_uniform", &key_words(pairs), 2, n)?;
    Ok(words.chunks_exact(2).map(|w| (w[0], w[1])).collect())
}

/// `(seed_lo, seed_hi, stream_lo, stream_hi)` of each pair.
fn key_words(pairs: &[(u64, u64)]) -> Vec<[u32; 4]> {
    pairs
        .iter()
        .map(|&(seed, stream)| {
            [
                seed as u32,
                (seed >> 32) as u32,
                stream as u32,
                (stream >> 32) as u32,
            ]
        })
        .collect()
}

/// `(high, low)` words of `a·b` for each pair as the GPU computes them: `mulhi32(a, b)`
/// from 16-bit halves, and the wrapping product. They must equal
/// `((a as u64 · b as u64) >> 32, a·b mod 2^32)`.
pub fn probe_mulhi32(ctx: &GpuContext, pairs: &[(u32, u32)]) -> Result<Vec<(u32, u32)>, GpuError> {
    let inputs: Vec<[u32; 4]> = pairs.iter().map(|&(a, b)| [a, b, 0, 0]).collect();
    let words = run(ctx, "probe_mulhi32", &inputs, 2, 0)?;
    Ok(words.chunks_exact(2).map(|w| (w[0], w[1])).collect())
}

/// Dispatches `entry` over `inputs` (one thread each, `n` in the params) and reads
/// `outputs_per_input` words per input back.
fn run(
    ctx: &GpuContext,
    entry: &'static str,
    inputs: &[[u32; 4]],
    outputs_per_input: u32,
    n: u32,
) -> Result<Vec<u32>, GpuError> {
    let count = inputs.len() as u64;
    if count == 0 || outputs_per_input == 0 {
        return Ok(Vec::new());
    }
    let out_bytes = count * u64::from(outputs_per_input) * 4;
    let input_buffer = super::storage_buffer(
        ctx,
        "probe inputs",
        bytemuck::cast_slice(inputs),
        wgpu::BufferUsages::empty(),
    )?;
    check_count(ctx, out_bytes)?;
    let output_buffer = super::zeroed_storage_buffer(
        ctx,
        "probe outputs",
        out_bytes,
        wgpu::BufferUsages::COPY_SRC,
    )?;
    let (groups_x, groups_y) = super::workgroups_2d(ctx, count)?;
    let params = ProbeParams {
        count: count as u32,
        draws: outputs_per_input,
        threads_per_row: groups_x * WORKGROUP_SIZE,
        n,
    };
    let params_buffer = super::uniform_buffer(ctx, "probe params", 16);
    ctx.queue()
        .write_buffer(&params_buffer, 0, bytemuck::bytes_of(&params));
    let pipeline = super::compute_pipeline(ctx, entry, &[PROBE_WGSL], entry)?;
    super::scoped(ctx, entry, || {
        let bind_group = super::bind_buffers(
            ctx,
            entry,
            &pipeline,
            &[&params_buffer, &input_buffer, &output_buffer],
        );
        let mut encoder = ctx
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(entry) });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(entry),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups_x, groups_y, 1);
        }
        ctx.queue().submit([encoder.finish()]);
        Ok(())
    })?;
    let bytes = super::read_buffer(ctx, "probe outputs", &output_buffer, out_bytes)?;
    Ok(super::words(&bytes))
}

/// The probe indexes outputs with `u32`: refuse more than `u32::MAX` output words.
fn check_count(ctx: &GpuContext, out_bytes: u64) -> Result<(), GpuError> {
    let limit = u64::from(u32::MAX) * 4;
    if out_bytes > limit {
        return Err(GpuError::BufferTooLarge {
            what: "probe outputs",
            bytes: out_bytes,
            limit,
        });
    }
    super::check_storage_size(ctx, "probe outputs", out_bytes)
}
