//! One compute pass over an image's 16 × 16 tiles, as the accumulate and tonemap kernels
//! run: its parameters written, one dispatch over a band of rows, one submit.

use std::ops::Range;

use crate::gpu::render_kernel::TILE;
use crate::gpu::{self, GpuContext, GpuError};

/// A kernel over the image's tiles: its pipeline, bind group and uniform parameters.
pub(super) struct TilePass<'a> {
    /// The pass's label (and its encoder's).
    pub(super) label: &'static str,
    pub(super) pipeline: &'a wgpu::ComputePipeline,
    pub(super) bind_group: &'a wgpu::BindGroup,
    pub(super) params_buffer: &'a wgpu::Buffer,
}

impl TilePass<'_> {
    /// Writes `params`, then queues one pass over the tiles of `rows` of an image `width`
    /// pixels wide (timed by `timestamp_writes`, if any) and submits it, inside error
    /// scopes named `during`.
    pub(super) fn submit(
        &self,
        ctx: &GpuContext,
        during: &'static str,
        params: &[u8],
        (width, rows): (u32, Range<u32>),
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        gpu::scoped(ctx, during, || {
            ctx.queue().write_buffer(self.params_buffer, 0, params);
            let mut encoder =
                ctx.device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some(self.label),
                    });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(self.label),
                    timestamp_writes,
                });
                pass.set_pipeline(self.pipeline);
                pass.set_bind_group(0, self.bind_group, &[]);
                pass.dispatch_workgroups(
                    width.div_ceil(TILE),
                    (rows.end - rows.start).div_ceil(TILE),
                    1,
                );
            }
            ctx.queue().submit([encoder.finish()]);
            Ok(())
        })
    }
}
