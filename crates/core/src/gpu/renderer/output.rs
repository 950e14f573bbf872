//! What comes out of the renderer: the sums read back as an [`Accumulator`], and the
//! tonemapped image in the output texture (read back as RGBA8 or handed to a UI).

use std::ops::Range;

use super::GpuRenderer;
use super::tile_pass::TilePass;
use crate::gpu::render_kernel::TonemapParams;
use crate::gpu::{self, GpuError};
use crate::render::Accumulator;

impl GpuRenderer {
    /// Waits for the queued samples and returns the sums as an [`Accumulator`] (`f32`
    /// sums widened to `f64` and put in the CPU renderer's unit: `Σê·2^-s`, `Σê²·2^-2s`,
    /// exact scalings, with the same total power and shift `s`).
    ///
    /// Precision: each `Σ ê` is a running `f32` sum of non-negative terms, so it is within
    /// `(spp − 1)·2^-24` relative of the exact sum of the `f32` estimates (typically
    /// `√spp·2^-24`). `Σ ê²` overflows to `+inf` once a single estimate exceeds about
    /// `1.8·10^19` (`G` of a light closer than about `10^-10` scene units).
    pub fn readback(&self) -> Result<Accumulator, GpuError> {
        if self.band_row > 0 {
            return Err(GpuError::PassInProgress {
                rows_done: self.band_row,
                height: self.height,
            });
        }
        let pixels = u64::from(self.width) * u64::from(self.height);
        let bytes = gpu::read_buffer(&self.ctx, "pixel sums", &self.targets.sums, pixels * 8)?;
        let words = gpu::words(&bytes);
        let mut acc = Accumulator::new(self.width, self.height, self.total_scaled, self.shift);
        acc.samples_per_pixel = self.samples_per_pixel;
        let to_unit = crate::Scaled::pow2(-self.shift).to_f64();
        for ((sum, sum_sq), pair) in acc
            .sum
            .iter_mut()
            .zip(acc.sum_sq.iter_mut())
            .zip(words.chunks_exact(2))
        {
            *sum = f64::from(f32::from_bits(pair[0])) * to_unit;
            *sum_sq = f64::from(f32::from_bits(pair[1])) * to_unit * to_unit;
        }
        Ok(acc)
    }

    /// Writes the tonemapped image into [`GpuRenderer::output_view`]: the WGSL twin of
    /// [`crate::render::tonemap_value`] applied to `exposure · Φ_total · Σê / n`, where
    /// the factor `exposure · Φ_total / n` is computed in `f64` and clamped to the finite
    /// `f32` range (black before any sample), and `n` is the row's sample count: `spp`, or
    /// `spp + 1` for the rows a pass in progress has reached. The work is queued, not waited
    /// for.
    pub fn tonemap(&mut self, exposure: f64) -> Result<(), GpuError> {
        self.tonemap_rows(exposure, 0..self.height)
    }

    /// [`GpuRenderer::tonemap`] of the rows `rows` only (clamped to the image): after
    /// [`GpuRenderer::accumulate_rows`] only the band just rendered changed, so only it needs
    /// writing until the pass completes (then every row's sample count has changed).
    pub fn tonemap_rows(&mut self, exposure: f64, rows: Range<u32>) -> Result<(), GpuError> {
        let rows = rows.start.min(self.height)..rows.end.min(self.height);
        if rows.is_empty() {
            return Ok(());
        }
        let factor = |samples: u32| {
            let f = if samples == 0 {
                0.0
            } else {
                exposure * self.total_power / f64::from(samples)
            };
            if f.is_nan() {
                0.0
            } else {
                f.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32
            }
        };
        let params = TonemapParams {
            factor: factor(self.samples_per_pixel),
            width: self.width,
            height: self.height,
            band_row: self.band_row,
            factor_band: factor(self.samples_per_pixel.saturating_add(1)),
            row_begin: rows.start,
            pad: [0; 2],
        };
        let pass = TilePass {
            label: "render tonemap",
            pipeline: &self.targets.tonemap_pipeline,
            bind_group: &self.targets.tonemap_bind_group,
            params_buffer: &self.targets.tonemap_params,
        };
        pass.submit(
            &self.ctx,
            "dispatching the tonemap",
            bytemuck::bytes_of(&params),
            (self.width, rows),
            None,
        )
    }

    /// Copies the output texture to the CPU as row-major `RGBA8` (4 bytes per pixel),
    /// waiting for queued work first.
    pub fn read_output_rgba8(&self) -> Result<Vec<u8>, GpuError> {
        let row_bytes = self.width * 4;
        let padded = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let size = u64::from(padded) * u64::from(self.height);
        let staging = gpu::scoped(&self.ctx, "reading the output texture", || {
            let staging = self.ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("render output readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder =
                self.ctx
                    .device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("render output readback"),
                    });
            encoder.copy_texture_to_buffer(
                self.targets.output.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded),
                        rows_per_image: Some(self.height),
                    },
                },
                wgpu::Extent3d {
                    width: self.width,
                    height: self.height,
                    depth_or_array_layers: 1,
                },
            );
            self.ctx.queue().submit([encoder.finish()]);
            Ok(staging)
        })?;
        let bytes = gpu::map_and_copy(&self.ctx, "render output", &staging)?;
        Ok(bytes
            .chunks_exact(padded as usize)
            .flat_map(|row| &row[..row_bytes as usize])
            .copied()
            .collect())
    }

    /// The tonemapped `Rgba8Unorm` output (usage `TEXTURE_BINDING | STORAGE_BINDING |
    /// COPY_SRC`), for the app to register with egui.
    pub fn output_view(&self) -> &wgpu::TextureView {
        &self.targets.output_view
    }

    /// The output texture itself.
    pub fn output_texture(&self) -> &wgpu::Texture {
        &self.targets.output
    }
}
