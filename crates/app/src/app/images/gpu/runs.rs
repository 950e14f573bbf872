//! The GPU runs of one scene: a `GpuRenderer` per scheme (uniform, power, spatial)
//! whose output egui shows as a native texture, with the figures read back from its sums;
//! how a run advances by the work a frame allows, how its sums are read back at pass
//! boundaries, and the frame the three publish.

use std::sync::Arc;
use std::time::Instant;

use eframe::egui_wgpu::{self, wgpu};
use lightpick_core::gpu::{GpuContext, GpuRenderer};
use lightpick_core::render::{Reference, mean_variance_scaled, normalized_variance_per_sample};
use lightpick_core::scene::Scene;
use lightpick_core::{SceneSamplers, Scheme};

use crate::app::images::frame_budget::RunWork;
use crate::app::images::published::{ConvergencePoint, Published, RendererBytes, SchemeImage};
use crate::app::images::reference::{error_map, error_scale, thin};

/// Weight of the newest measurement in a run's moving average of its cost per row.
const ROW_COST_SMOOTHING: f64 = 0.3;

/// The three renderers of a scene: uniform, power, spatial.
pub(super) type Trio = (GpuRenderer, GpuRenderer, GpuRenderer);

/// Every renderer of a scene: one `O(N)` upload of the scene's shared table and light data
/// that the three read ([`GpuRenderer::from_samplers_sharing`]), and one of its shared light
/// tree (nothing is built again here).
pub(super) fn build_trio(
    ctx: &GpuContext,
    samplers: &SceneSamplers,
    seed: u64,
) -> Result<Trio, String> {
    let uniform = GpuRenderer::from_samplers(ctx, samplers, Scheme::Uniform, seed)
        .map_err(|e| e.to_string())?;
    let sharing = |scheme| {
        GpuRenderer::from_samplers_sharing(ctx, samplers, scheme, seed, &uniform)
            .map_err(|e| e.to_string())
    };
    let (power, spatial) = (sharing(Scheme::Alias)?, sharing(Scheme::Spatial)?);
    Ok((uniform, power, spatial))
}

/// Points egui's textures at the outputs of `trio`: the `ids` kept across scenes when there
/// are some, else three newly registered.
pub(super) fn register_textures(
    render_state: &egui_wgpu::RenderState,
    ids: Option<[egui::TextureId; 3]>,
    (uniform, power, spatial): &Trio,
) -> [egui::TextureId; 3] {
    let device = &render_state.device;
    let filter = wgpu::FilterMode::Nearest;
    let mut renderer = render_state.renderer.write();
    match ids {
        Some(ids) => {
            for (id, r) in ids.iter().zip([uniform, power, spatial]) {
                renderer.update_egui_texture_from_wgpu_texture(
                    device,
                    r.output_view(),
                    filter,
                    *id,
                );
            }
            ids
        }
        None => [
            renderer.register_native_texture(device, uniform.output_view(), filter),
            renderer.register_native_texture(device, power.output_view(), filter),
            renderer.register_native_texture(device, spatial.output_view(), filter),
        ],
    }
}

/// One scheme on the GPU.
pub(super) struct SchemeRun {
    pub(super) renderer: GpuRenderer,
    pub(super) texture: egui::TextureId,
    pub(super) image: SchemeImage,
    /// Measured seconds per row of one sample pass (a moving average), once known.
    pub(super) row_seconds: Option<f64>,
    /// The sums should be read back as soon as no pass is in progress.
    readback_due: bool,
}

impl SchemeRun {
    fn new(renderer: GpuRenderer, texture: egui::TextureId) -> Self {
        Self {
            renderer,
            texture,
            image: SchemeImage::default(),
            row_seconds: None,
            readback_due: true,
        }
    }

    /// Starts the images over (same renderer, sums cleared).
    pub(super) fn reset(&mut self) {
        self.renderer.reset();
        self.image = SchemeImage::default();
    }

    /// Does `work` on an image `height` rows high and tonemaps what changed; returns the
    /// wall seconds the waits took.
    fn advance(&mut self, work: RunWork, height: u32, exposure: f64) -> Result<f64, String> {
        let before = self.renderer.pass_rows_done();
        let spp_before = self.renderer.samples_per_pixel();
        let started = Instant::now();
        let rows = match work {
            RunWork::Passes(n) => {
                self.renderer.accumulate(n).map_err(|e| e.to_string())?;
                n * height - before
            }
            RunWork::Rows(n) => {
                self.renderer
                    .accumulate_rows(n)
                    .map_err(|e| e.to_string())?;
                n.min(height - before)
            }
        };
        // The run's time is its passes' own (the device's timestamps, or the CPU
        // clock over each pass alone on an idle queue): never tonemapping, readback,
        // the other runs or egui's frame. The rows each run gets (equal samples or
        // equal time) are planned with the same pass time; the UI's own cost is the
        // frame's wall time less the wall time these waits took.
        let pass_seconds = self
            .renderer
            .take_pass_seconds()
            .map_err(|e| e.to_string())?;
        let spent = started.elapsed().as_secs_f64();
        let per_row = pass_seconds / f64::from(rows.max(1));
        self.row_seconds = Some(self.row_seconds.map_or(per_row, |t| {
            (1.0 - ROW_COST_SMOOTHING) * t + ROW_COST_SMOOTHING * per_row
        }));
        self.image.seconds += pass_seconds;
        self.image.last_frame_seconds = pass_seconds;
        self.image.spp = self.renderer.samples_per_pixel();
        self.image.pass_progress = self.renderer.pass_rows_done() as f32 / height.max(1) as f32;
        // A band changes only its rows; a completed pass changes every row's count.
        let after = self.renderer.pass_rows_done();
        let tonemap = if self.renderer.samples_per_pixel() == spp_before {
            self.renderer.tonemap_rows(exposure, before..after)
        } else {
            self.renderer.tonemap(exposure)
        };
        tonemap.map_err(|e| e.to_string())?;
        Ok(spent)
    }

    /// Reads the sums back when due and no pass is in progress (its rows would have one
    /// sample more): variance, and against the `reference` the RMSE, the error map and the
    /// next point of the convergence curve.
    fn read_back_if_due(&mut self, reference: Option<&Reference>) -> Result<(), String> {
        if !self.readback_due || self.renderer.pass_rows_done() > 0 {
            return Ok(());
        }
        self.readback_due = false;
        let acc = self.renderer.readback().map_err(|e| e.to_string())?;
        self.image.variance = mean_variance_scaled(&acc);
        self.image.normalized_variance = normalized_variance_per_sample(&acc);
        if let Some(r) = reference {
            let rmse = lightpick_core::render::rmse(&acc, r);
            self.image.rmse = Some(rmse);
            self.image.error_rgba = r
                .image()
                .map(|full| error_map(&acc.image(), full, error_scale(full)));
            if acc.samples_per_pixel > 0 {
                self.image.series.push(ConvergencePoint {
                    spp: acc.samples_per_pixel,
                    seconds: self.image.seconds,
                    rmse,
                });
                thin(&mut self.image.series);
            }
        }
        Ok(())
    }

    /// Fills `image` with this run's pixels, tonemapped on the CPU at `exposure` (the same
    /// tonemap as the GPU's), after completing a pass in progress so every pixel has the
    /// same number of samples.
    pub(super) fn export_into(
        &mut self,
        image: &mut SchemeImage,
        exposure: f64,
    ) -> Result<(), String> {
        if self.renderer.pass_rows_done() > 0 {
            // The rest of the pass counts in the run's render time like any other.
            self.renderer.finish_pass().map_err(|e| e.to_string())?;
            self.image.seconds += self
                .renderer
                .take_pass_seconds()
                .map_err(|e| e.to_string())?;
            self.renderer.tonemap(exposure).map_err(|e| e.to_string())?;
            self.image.spp = self.renderer.samples_per_pixel();
            self.image.pass_progress = 0.0;
        }
        let acc = self.renderer.readback().map_err(|e| e.to_string())?;
        image.spp = acc.samples_per_pixel;
        image.pass_progress = 0.0;
        image.rgba = lightpick_core::render::tonemap_rgba8(&acc.image(), exposure);
        Ok(())
    }
}

/// The GPU images of one scene.
pub(super) struct GpuRuns {
    pub(super) generation: u64,
    pub(super) seed: u64,
    pub(super) scene: Arc<Scene>,
    /// Computed on a background thread (up to a second for huge scenes).
    pub(super) reference: Option<Reference>,
    pub(super) reference_note: Option<String>,
    /// The reference's computation stopped without one (not tried again for these runs).
    pub(super) reference_failed: bool,
    pub(super) uniform: SchemeRun,
    pub(super) power: SchemeRun,
    pub(super) spatial: SchemeRun,
    pub(super) frame: u64,
}

impl GpuRuns {
    /// The runs of `scene` over `trio`, showing through the textures `ids`.
    pub(super) fn new(
        generation: u64,
        seed: u64,
        scene: &Arc<Scene>,
        (uniform, power, spatial): Trio,
        ids: [egui::TextureId; 3],
    ) -> Self {
        Self {
            generation,
            seed,
            scene: Arc::clone(scene),
            reference: None,
            reference_note: Some("computing the reference…".to_owned()),
            reference_failed: false,
            uniform: SchemeRun::new(uniform, ids[0]),
            power: SchemeRun::new(power, ids[1]),
            spatial: SchemeRun::new(spatial, ids[2]),
            frame: 0,
        }
    }

    /// The uniform, power and spatial runs, in display order.
    pub(super) fn each_mut(&mut self) -> [&mut SchemeRun; 3] {
        [&mut self.uniform, &mut self.power, &mut self.spatial]
    }

    /// Tonemaps every run's output at `exposure`.
    pub(super) fn tonemap(&mut self, exposure: f64) -> Result<(), String> {
        for run in self.each_mut() {
            run.renderer.tonemap(exposure).map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// Does each run's `work`; returns the wall seconds the waits took.
    pub(super) fn accumulate(&mut self, work: [RunWork; 3], exposure: f64) -> Result<f64, String> {
        let height = self.scene.plane.height;
        let mut total = 0.0;
        for (run, work) in self.each_mut().into_iter().zip(work) {
            total += run.advance(work, height, exposure)?;
        }
        Ok(total)
    }

    /// Marks every run's sums for reading when `due`, and reads those that can be.
    pub(super) fn read_back(&mut self, due: bool) -> Result<(), String> {
        let GpuRuns {
            reference,
            uniform,
            power,
            spatial,
            ..
        } = self;
        for run in [uniform, power, spatial] {
            run.readback_due |= due;
            run.read_back_if_due(reference.as_ref())?;
        }
        Ok(())
    }

    /// The frame the panels show (its `rgba` fields are empty: the images are native
    /// textures), `readback` when its figures were just read.
    pub(super) fn publish(&self, exposure: f64, readback: bool, device: &str) -> Published {
        Published {
            generation: self.generation,
            frame: self.frame * 2 + u64::from(readback),
            width: self.scene.plane.width,
            height: self.scene.plane.height,
            light_count: self.scene.light_count(),
            uniform: self.uniform.image.clone(),
            power: self.power.image.clone(),
            spatial: self.spatial.image.clone(),
            reference_rgba: self
                .reference
                .as_ref()
                .and_then(Reference::image)
                .map(|r| lightpick_core::render::tonemap_rgba8(r, exposure)),
            reference_note: self.reference_note.clone(),
            device_note: format!("GPU: {device}"),
            time_source: format!(
                "GPU pass time per pixel sample ({}), excluding tonemap and readback",
                self.power.renderer.pass_clock().describe()
            ),
        }
    }

    /// What the runs hold on the device (lavapipe's device memory is the process's) and the
    /// reference on the CPU.
    pub(super) fn bytes(&self) -> RendererBytes {
        let renderers = [
            &self.uniform.renderer,
            &self.power.renderer,
            &self.spatial.renderer,
        ];
        let all: u64 = renderers.iter().map(|r| r.gpu_bytes()).sum();
        // Lights shared with an earlier run are held once.
        let shared: u64 = (1..renderers.len())
            .filter(|&k| {
                renderers[..k]
                    .iter()
                    .any(|r| renderers[k].shares_lights_with(r))
            })
            .map(|k| renderers[k].lights_upload_bytes())
            .sum();
        let lights = renderers.iter().map(|r| r.gpu_light_bytes()).sum::<u64>() - shared;
        let all = all - shared;
        RendererBytes {
            lights: lights as usize,
            pixels: (all - lights) as usize
                + self.reference.as_ref().map_or(0, Reference::heap_bytes),
        }
    }
}
