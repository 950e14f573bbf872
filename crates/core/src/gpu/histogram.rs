//! The histogram of light picks, computed on the GPU.

use super::scheme::scheme_code;
use super::split::{Access, ArrayLayout, SplitArray, SplitShape, check_bindings, declarations};
use super::{GpuContext, GpuError, PICK_WGSL, WORKGROUP_SIZE};
use crate::{PackedAliasEntry, PointFreeSampler as _, Sampler};

pub(crate) const HISTOGRAM_WGSL: &str = include_str!("histogram.wgsl");

/// The split-array layouts of the histogram kernel: the packed table and the counts.
pub(crate) const TABLE_LAYOUT: ArrayLayout = ArrayLayout {
    name: "alias_table",
    element: "vec2<u32>",
    bytes: 8,
};
pub(crate) const COUNTS_LAYOUT: ArrayLayout = ArrayLayout {
    name: "counts",
    element: "atomic<u32>",
    bytes: 4,
};

/// The source of the histogram kernel for a table and counts split as given.
pub(crate) fn histogram_source(table: SplitShape, counts: SplitShape) -> String {
    super::shader_source(&[
        PICK_WGSL,
        &declarations(TABLE_LAYOUT, table, 1, Access::Read),
        &declarations(
            COUNTS_LAYOUT,
            counts,
            1 + table.chunks as u32,
            Access::AtomicAdd,
        ),
        HISTOGRAM_WGSL,
    ])
}

/// Samples per dispatch: bins are `u32` and one dispatch adds at most this many counts, so
/// no bin can wrap; the CPU sums the dispatches in `u64`. Also keeps `k + stride` in `u32`.
const MAX_SAMPLES_PER_DISPATCH: u64 = 1 << 31;
/// Each thread takes at least this many samples (amortizes the per-workgroup bin flush).
const MIN_SAMPLES_PER_THREAD: u64 = 64;
/// At most this many workgroups per dispatch; threads loop over the rest.
const MAX_WORKGROUPS: u64 = 4096;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct HistogramParams {
    seed_lo: u32,
    seed_hi: u32,
    base_lo: u32,
    base_hi: u32,
    count: u32,
    n_lights: u32,
    scheme: u32,
    stride: u32,
}

/// How often each light is picked by samples `0..count`: sample `k` draws from
/// [`crate::Rng::new`]`(seed, k)` and picks with exactly the draws of
/// [`Sampler::pick_light`], so the counts equal the CPU loop's counts, bin for bin.
///
/// Counts are `u32` atomics on the GPU (in workgroup memory first when there are at most 2048
/// lights); the table (8 bytes per light) and the counts (4) are split over as many storage
/// bindings as the device's binding limit requires (`crate::gpu` § Limits); the work is split into
/// dispatches of at most `2^31` samples so no bin can wrap, and the dispatches are summed in `u64`.
/// The 64-bit sample index is `base + local` with the carry propagated in WGSL. [`Sampler::Cdf`] is
/// refused with [`GpuError::UnsupportedScheme`].
pub fn histogram(
    ctx: &GpuContext,
    sampler: &Sampler,
    count: u64,
    seed: u64,
) -> Result<Vec<u64>, GpuError> {
    histogram_range(ctx, sampler, 0, count, seed)
}

/// Like [`histogram`], for the samples `first, first + 1, …, first + count − 1` (indices
/// wrap modulo `2^64`, as `u64::wrapping_add` does).
pub fn histogram_range(
    ctx: &GpuContext,
    sampler: &Sampler,
    first: u64,
    count: u64,
    seed: u64,
) -> Result<Vec<u64>, GpuError> {
    histogram_range_split(ctx, sampler, first, count, seed, MAX_SAMPLES_PER_DISPATCH)
}

/// [`histogram_range`] with at most `max_per_dispatch` samples per dispatch (clamped to
/// `1..=2^31`), so tests can exercise the splitting and the 64-bit carry cheaply.
#[doc(hidden)]
pub fn histogram_range_split(
    ctx: &GpuContext,
    sampler: &Sampler,
    first: u64,
    count: u64,
    seed: u64,
    max_per_dispatch: u64,
) -> Result<Vec<u64>, GpuError> {
    let max_per_dispatch = max_per_dispatch.clamp(1, MAX_SAMPLES_PER_DISPATCH);
    let scheme = scheme_code(sampler.scheme())?;
    let n = sampler.light_count();
    let table: &[PackedAliasEntry] = match sampler {
        Sampler::Alias(t) | Sampler::AliasOneRandom(t) => t.packed(),
        // The uniform path never reads the table, but the binding needs a buffer.
        Sampler::Uniform(_) | Sampler::Cdf(_) => &[PackedAliasEntry {
            threshold: 0,
            alias: 0,
        }],
    };
    let mut totals = vec![0u64; n];
    if count == 0 {
        return Ok(totals);
    }
    let kernel = HistogramKernel::new(ctx, table, n)?;
    let mut done = 0u64;
    while done < count {
        let chunk = (count - done).min(max_per_dispatch);
        let base = first.wrapping_add(done);
        let workgroups = chunk
            .div_ceil(MIN_SAMPLES_PER_THREAD * u64::from(WORKGROUP_SIZE))
            .clamp(1, MAX_WORKGROUPS) as u32;
        let params = HistogramParams {
            seed_lo: seed as u32,
            seed_hi: (seed >> 32) as u32,
            base_lo: base as u32,
            base_hi: (base >> 32) as u32,
            count: chunk as u32,
            n_lights: n as u32,
            scheme,
            stride: workgroups * WORKGROUP_SIZE,
        };
        let counts = kernel.run(ctx, &params, workgroups)?;
        for (total, c) in totals.iter_mut().zip(counts) {
            *total += u64::from(c);
        }
        done += chunk;
    }
    Ok(totals)
}

/// The histogram kernel over one table: its buffers, pipeline and bind group.
struct HistogramKernel {
    params_buffer: wgpu::Buffer,
    /// Read through the bind group only; held as long as the kernel.
    _table_buffer: SplitArray,
    counts_buffer: SplitArray,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
}

impl HistogramKernel {
    /// Uploads `table` and makes room for the counts of `n` lights; refuses more bindings
    /// than a shader stage has.
    fn new(ctx: &GpuContext, table: &[PackedAliasEntry], n: usize) -> Result<Self, GpuError> {
        let table_words: Vec<[u32; 2]> = table.iter().map(|e| [e.threshold, e.alias]).collect();
        let table_buffer = SplitArray::with_contents(
            ctx,
            "alias table",
            TABLE_LAYOUT,
            bytemuck::cast_slice(&table_words),
            wgpu::BufferUsages::empty(),
        )?;
        drop(table_words);
        let counts_buffer = SplitArray::zeroed(
            ctx,
            "histogram counts",
            COUNTS_LAYOUT,
            n as u64,
            wgpu::BufferUsages::COPY_SRC,
        )?;
        let storage = (table_buffer.buffers().len() + counts_buffer.buffers().len()) as u32;
        check_bindings(ctx, "the histogram kernel", storage)?;
        let params_buffer = super::uniform_buffer(ctx, "histogram params", 32);
        let pipeline = super::compute_pipeline_from_source(
            ctx,
            "histogram",
            histogram_source(table_buffer.shape(), counts_buffer.shape()),
            "histogram",
        )?;
        let bind_group = super::scoped(ctx, "binding the histogram buffers", || {
            let buffers: Vec<&wgpu::Buffer> = std::iter::once(&params_buffer)
                .chain(table_buffer.buffers())
                .chain(counts_buffer.buffers())
                .collect();
            Ok(super::bind_buffers(ctx, "histogram", &pipeline, &buffers))
        })?;
        Ok(Self {
            params_buffer,
            _table_buffer: table_buffer,
            counts_buffer,
            pipeline,
            bind_group,
        })
    }

    /// One dispatch of `workgroups` over `params` from cleared counts; waits and returns
    /// its counts.
    fn run(
        &self,
        ctx: &GpuContext,
        params: &HistogramParams,
        workgroups: u32,
    ) -> Result<Vec<u32>, GpuError> {
        super::scoped(ctx, "dispatching the histogram", || {
            ctx.queue()
                .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(params));
            let mut encoder =
                ctx.device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("histogram"),
                    });
            self.counts_buffer.clear(&mut encoder);
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("histogram"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind_group, &[]);
                pass.dispatch_workgroups(workgroups, 1, 1);
            }
            ctx.queue().submit([encoder.finish()]);
            Ok(())
        })?;
        let bytes = self.counts_buffer.read(ctx, "histogram counts")?;
        Ok(super::words(&bytes))
    }
}
