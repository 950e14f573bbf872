//! Sample passes: queuing samples for the whole image or for a band of rows, and the
//! time the device spent on them.

use std::ops::Range;

use super::GpuRenderer;
use super::tile_pass::TilePass;
use crate::Scheme;
use crate::gpu::GpuError;
use crate::gpu::pass_timer::PassClock;
use crate::gpu::render_kernel::{RenderParams, SAMPLES_PER_DISPATCH};
use crate::gpu::scheme::scheme_code;

impl GpuRenderer {
    /// Adds `samples_per_pixel` samples to every pixel: sample indices
    /// `k = spp, …, spp + samples_per_pixel − 1` continue the previous calls. A pass in
    /// progress ([`GpuRenderer::accumulate_rows`]) is completed first and counts as the
    /// first of them. The work is queued, not waited for ([`GpuRenderer::readback`] waits).
    /// The total per pixel may not pass `u32::MAX` (the stream's high word), else
    /// [`GpuError::TooManySamples`].
    pub fn accumulate(&mut self, samples_per_pixel: u32) -> Result<(), GpuError> {
        let total = self
            .samples_per_pixel
            .checked_add(samples_per_pixel)
            .ok_or(GpuError::TooManySamples {
                accumulated: self.samples_per_pixel,
                requested: samples_per_pixel,
                max: u32::MAX,
            })?;
        if samples_per_pixel == 0 {
            return Ok(());
        }
        let pixels = u64::from(self.width) * u64::from(self.height);
        let per_dispatch = (SAMPLES_PER_DISPATCH / pixels).clamp(1, u64::from(u32::MAX)) as u32;
        let mut k = self.samples_per_pixel;
        if self.band_row > 0 {
            self.dispatch(k, 1, self.band_row..self.height)?;
            self.band_row = 0;
            k += 1;
        }
        while k < total {
            let k_count = per_dispatch.min(total - k);
            self.dispatch(k, k_count, 0..self.height)?;
            k += k_count;
        }
        self.samples_per_pixel = total;
        Ok(())
    }

    /// Adds sample `k = spp` to at most `max_rows` (at least 1) more rows of the image,
    /// continuing the pass in progress from where it stopped (from the top row). When the
    /// pass reaches the bottom row every pixel holds `spp + 1` samples: the pass is complete,
    /// [`GpuRenderer::samples_per_pixel`] grows by one and `Ok(true)` is returned.
    ///
    /// This splits one sample pass of a costly scheme (the light tree on a million lights)
    /// over several UI frames. While a pass is in progress, [`GpuRenderer::tonemap`] divides
    /// each row by its own sample count and [`GpuRenderer::readback`] is refused
    /// ([`GpuError::PassInProgress`]); [`GpuRenderer::finish_pass`] completes it. The same
    /// samples as [`GpuRenderer::accumulate`] are drawn, so the sums are identical.
    pub fn accumulate_rows(&mut self, max_rows: u32) -> Result<bool, GpuError> {
        if self.samples_per_pixel == u32::MAX {
            return Err(GpuError::TooManySamples {
                accumulated: self.samples_per_pixel,
                requested: 1,
                max: u32::MAX,
            });
        }
        let end = self
            .band_row
            .saturating_add(max_rows.max(1))
            .min(self.height);
        self.dispatch(self.samples_per_pixel, 1, self.band_row..end)?;
        if end == self.height {
            self.band_row = 0;
            self.samples_per_pixel += 1;
            Ok(true)
        } else {
            self.band_row = end;
            Ok(false)
        }
    }

    /// Completes the pass in progress, if any ([`GpuRenderer::accumulate_rows`]).
    pub fn finish_pass(&mut self) -> Result<(), GpuError> {
        if self.band_row > 0 {
            self.accumulate_rows(self.height)?;
        }
        Ok(())
    }

    /// The seconds the device spent in this renderer's sample passes since the last call
    /// (waits for the passes queued so far): pass time only, never tonemapping, readback or
    /// other work on the device. See [`PassClock`] for where the time comes from.
    pub fn take_pass_seconds(&mut self) -> Result<f64, GpuError> {
        self.timer.take_seconds(&self.ctx)
    }

    /// Where [`GpuRenderer::take_pass_seconds`] reads its time: the device's timestamps
    /// when it has `TIMESTAMP_QUERY`, else the CPU clock over each pass alone.
    pub fn pass_clock(&self) -> PassClock {
        self.timer.clock()
    }

    /// Rows of the pass in progress done so far (0 when no pass is in progress).
    pub fn pass_rows_done(&self) -> u32 {
        self.band_row
    }

    /// Queues `k_count` samples `k_base, …` for the pixels of `rows`.
    fn dispatch(&mut self, k_base: u32, k_count: u32, rows: Range<u32>) -> Result<(), GpuError> {
        if self.scheme == Scheme::Spatial {
            self.ensure_spatial()?;
        }
        let (pipeline, bind_group, spatial_root, scheme) = match &self.spatial {
            Some(s) if self.scheme == Scheme::Spatial => {
                (&s.pipeline, &s.bind_group, s.root, s.code)
            }
            _ => (
                &self.targets.accumulate_pipeline,
                &self.targets.accumulate_bind_group,
                0,
                scheme_code(self.scheme)?,
            ),
        };
        let params = RenderParams {
            seed_lo: self.seed as u32,
            seed_hi: (self.seed >> 32) as u32,
            k_base,
            k_count,
            width: self.width,
            height: self.height,
            n_lights: self.samplers.scene().light_count() as u32,
            scheme,
            plane_min_x: self.plane[0],
            plane_max_y: self.plane[1],
            plane_extent_x: self.plane[2],
            plane_extent_y: self.plane[3],
            n_f32: self.samplers.scene().light_count() as f32,
            spatial_root,
            row_begin: rows.start,
            row_end: rows.end,
        };
        let timestamp_writes = self.timer.begin_pass(&self.ctx)?;
        let pass = TilePass {
            label: "render accumulate",
            pipeline,
            bind_group,
            params_buffer: &self.targets.params,
        };
        pass.submit(
            &self.ctx,
            "dispatching render samples",
            bytemuck::bytes_of(&params),
            (self.width, rows),
            timestamp_writes,
        )?;
        self.timer.end_pass(&self.ctx)
    }
}
