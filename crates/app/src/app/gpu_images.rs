//! Progressive images on the GPU: three `lightpick_core::gpu::GpuRenderer`s (uniform,
//! importance and spatial) on eframe's own wgpu device, whose `Rgba8Unorm` outputs egui
//! shows as native textures (no copy through the CPU). Every few frames the sums are read
//! back for the RMSE, the error maps and the convergence curves, computed exactly as the CPU
//! engine does.
//!
//! All of it runs on the UI thread, which waits for each lane's compute work (an honest time
//! per frame). Each frame gets the GPU work that fits in what the frame leaves
//! ([`super::frame_budget`]): whole sample passes, or a band of rows of one when a pass is
//! costlier than that, so a slow device slows the images, never the window. The sums are
//! read back at pass boundaries only.

use std::sync::Arc;
use std::time::Instant;

use eframe::egui_wgpu::{self, wgpu};
use lightpick_core::gpu::{GpuContext, GpuRenderer};
use lightpick_core::render::{Reference, mean_variance_scaled, normalized_variance_per_sample};
use lightpick_core::scene::Scene;
use lightpick_core::{SceneSamplers, Scheme};

use super::background::{Polled, Worker};
use super::engine::{self, ConvergencePoint, EngineConfig, Published, RendererBytes, SchemeImage};
use super::frame_budget::{self, FrameBudget, LaneWork};
use super::state::SYNC_BUILD_LIMIT;

/// Read the sums back (RMSE, error maps, curves) every this many frames.
const READBACK_EVERY: u64 = 4;

/// One scheme on the GPU.
struct Lane {
    renderer: GpuRenderer,
    texture: egui::TextureId,
    image: SchemeImage,
    /// Measured seconds per row of one sample pass (a moving average), once known.
    row_seconds: Option<f64>,
    /// The sums should be read back as soon as no pass is in progress.
    readback_due: bool,
}

/// The GPU images of one scene.
struct Lanes {
    generation: u64,
    seed: u64,
    scene: Arc<Scene>,
    /// Computed on a background thread (up to a second for huge scenes).
    reference: Option<Reference>,
    reference_note: Option<String>,
    uniform: Lane,
    importance: Lane,
    spatial: Lane,
    frame: u64,
}

/// Weight of the newest measurement in a lane's moving average of its cost per row.
const ROW_COST_SMOOTHING: f64 = 0.3;

impl Lanes {
    /// The uniform, importance and spatial lanes, in display order.
    fn each_mut(&mut self) -> [&mut Lane; 3] {
        [&mut self.uniform, &mut self.importance, &mut self.spatial]
    }
}

/// The three renderers of a scene: uniform, importance, spatial.
type Trio = (GpuRenderer, GpuRenderer, GpuRenderer);

/// Every renderer of a scene: one `O(N)` upload of the scene's shared table and light data
/// that the three read ([`GpuRenderer::from_samplers_sharing`]), and one of its shared light
/// tree (nothing is built again here).
fn build_trio(ctx: &GpuContext, samplers: &SceneSamplers, seed: u64) -> Result<Trio, String> {
    let uniform = GpuRenderer::from_samplers(ctx, samplers, Scheme::Uniform, seed)
        .map_err(|e| e.to_string())?;
    let sharing = |scheme| {
        GpuRenderer::from_samplers_sharing(ctx, samplers, scheme, seed, &uniform)
            .map_err(|e| e.to_string())
    };
    let (importance, spatial) = (sharing(Scheme::Alias)?, sharing(Scheme::Spatial)?);
    Ok((uniform, importance, spatial))
}

/// A scene's renderers being uploaded on a worker thread.
struct RendererUpload {
    generation: u64,
    seed: u64,
    samplers: SceneSamplers,
    worker: Worker<Result<Trio, String>>,
}

/// The GPU side of the images panel.
pub struct GpuImages {
    ctx: GpuContext,
    render_state: egui_wgpu::RenderState,
    lanes: Option<Lanes>,
    exposure: Option<f64>,
    /// Texture ids kept across scenes (re-pointed at each new renderer's output).
    ids: Option<[egui::TextureId; 3]>,
    latest: Option<Arc<Published>>,
    pending: Option<RendererUpload>,
    /// The reference being computed, and for which scene generation.
    reference_job: Option<ReferenceJob>,
    /// How much GPU work each UI frame may take.
    budget: FrameBudget,
}

/// A reference computed on a worker thread, for one scene generation.
type ReferenceJob = (u64, Worker<(Reference, Option<String>)>);

impl GpuImages {
    /// Wraps eframe's device; `None` when eframe runs without wgpu.
    pub fn new(render_state: &egui_wgpu::RenderState) -> Self {
        let ctx = GpuContext::from_device(
            render_state.device.clone(),
            render_state.queue.clone(),
            render_state.adapter.get_info(),
        );
        Self {
            ctx,
            render_state: render_state.clone(),
            lanes: None,
            exposure: None,
            ids: None,
            latest: None,
            pending: None,
            reference_job: None,
            budget: FrameBudget::default(),
        }
    }

    /// What the lanes hold on the device (lavapipe's device memory is the process's) and the
    /// reference on the CPU; the scene, table and tree they were uploaded from are the
    /// app's `Built`.
    pub fn bytes(&self) -> RendererBytes {
        let Some(lanes) = &self.lanes else {
            return RendererBytes::default();
        };
        let renderers = [
            &lanes.uniform.renderer,
            &lanes.importance.renderer,
            &lanes.spatial.renderer,
        ];
        let all: u64 = renderers.iter().map(|r| r.gpu_bytes()).sum();
        // Lights shared with an earlier lane are held once.
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
                + lanes.reference.as_ref().map_or(0, Reference::heap_bytes),
        }
    }

    /// Drops the lanes (their light buffers, tree, sums and reference) and the last frame
    /// while the CPU renders the images; the next [`GpuImages::frame`] builds them again.
    pub fn release(&mut self) {
        self.lanes = None;
        self.pending = None;
        self.reference_job = None;
        self.latest = None;
        self.exposure = None;
    }

    /// Whether the adapter is a software rasterizer on the CPU (llvmpipe, lavapipe).
    pub fn is_software(&self) -> bool {
        self.ctx.is_software()
    }

    /// The adapter, in words ("llvmpipe (LLVM 19), Vulkan").
    pub fn description(&self) -> String {
        self.ctx.description()
    }

    /// The native textures of the uniform, importance and spatial images.
    pub fn texture_ids(&self) -> Option<[egui::TextureId; 3]> {
        self.lanes
            .as_ref()
            .map(|l| [l.uniform.texture, l.importance.texture, l.spatial.texture])
    }

    /// The latest frame with its images read back and tonemapped on the CPU (the same
    /// tonemap as the GPU's), for exporting them. A sample pass in progress (a costly scene
    /// renders in row bands) is completed first, so every pixel of an image has the same
    /// number of samples and the sums can be read.
    pub fn frame_with_images(&mut self, exposure: f64) -> Result<Published, String> {
        let mut frame = self
            .latest
            .as_deref()
            .cloned()
            .ok_or("no image has been rendered yet")?;
        let lanes = self
            .lanes
            .as_mut()
            .ok_or("no image has been rendered yet")?;
        for (image, lane) in [
            &mut frame.uniform,
            &mut frame.importance,
            &mut frame.spatial,
        ]
        .into_iter()
        .zip(lanes.each_mut())
        {
            if lane.renderer.pass_rows_done() > 0 {
                // The rest of the pass counts in the lane's render time like any other.
                lane.renderer.finish_pass().map_err(|e| e.to_string())?;
                lane.image.seconds += lane
                    .renderer
                    .take_pass_seconds()
                    .map_err(|e| e.to_string())?;
                lane.renderer.tonemap(exposure).map_err(|e| e.to_string())?;
                lane.image.spp = lane.renderer.samples_per_pixel();
                lane.image.pass_progress = 0.0;
            }
            let acc = lane.renderer.readback().map_err(|e| e.to_string())?;
            image.spp = acc.samples_per_pixel;
            image.pass_progress = 0.0;
            image.rgba = lightpick_core::render::tonemap_rgba8(&acc.image(), exposure);
        }
        Ok(frame)
    }

    /// The latest frame (its `rgba` fields are empty: the images are native textures).
    pub fn latest(&self) -> Option<Arc<Published>> {
        self.latest.clone()
    }

    /// Advances one UI frame: restarts on a new scene, seed or reset, accumulates when
    /// running or stepped, re-tonemaps, reads back every few frames. An error leaves the
    /// GPU images stopped and is returned for the status bar.
    pub fn frame(
        &mut self,
        generation: u64,
        samplers: &SceneSamplers,
        config: &EngineConfig,
        reset: bool,
        step: bool,
    ) -> Result<(), String> {
        self.budget.begin_frame(Instant::now());
        let stale = self
            .lanes
            .as_ref()
            .is_none_or(|l| l.generation != generation || l.seed != config.seed);
        if stale {
            self.request(generation, samplers, config.seed)?;
        } else if reset && let Some(lanes) = self.lanes.as_mut() {
            for lane in lanes.each_mut() {
                lane.renderer.reset();
                lane.image = SchemeImage::default();
            }
            lanes.frame = 0;
            self.exposure = None;
        }
        self.poll_pending(generation, samplers, config.seed)?;
        let current = self
            .lanes
            .as_ref()
            .is_some_and(|l| l.generation == generation && l.seed == config.seed);
        if self.exposure.is_none()
            && let Some(lanes) = self.lanes.as_mut()
        {
            // A new trio's outputs are blank until tonemapped (black before any sample).
            for lane in lanes.each_mut() {
                lane.renderer
                    .tonemap(config.exposure)
                    .map_err(|e| e.to_string())?;
            }
            self.exposure = Some(config.exposure);
        }
        if !current {
            // A large scene is still uploading: keep showing the last frame (marked stale).
            return Ok(());
        }
        let Some(lanes) = self.lanes.as_mut() else {
            return Ok(());
        };
        // One reference computation at a time (up to a second of both cores for huge
        // scenes): a drag through many tables computes only the newest one's.
        let mut reference_arrived = false;
        if let Some((job_generation, worker)) = &self.reference_job
            && let Polled::Done((reference, note)) = worker.poll()
        {
            if *job_generation == lanes.generation {
                lanes.reference = Some(reference);
                lanes.reference_note = note;
                reference_arrived = true;
            }
            self.reference_job = None;
        }
        if lanes.reference.is_none() && self.reference_job.is_none() {
            let for_reference = Arc::clone(&lanes.scene);
            let spawned = Worker::spawn("lightpick-reference", move || {
                engine::reference(&for_reference)
            });
            match spawned {
                Ok(worker) => self.reference_job = Some((lanes.generation, worker)),
                Err(e) => lanes.reference_note = Some(format!("no reference: {e}")),
            }
        }
        let advance = config.running || step;
        if advance {
            // A step (paused) renders whole passes, however long; while running, the frame
            // budget decides: whole passes when they fit, else a band of rows, so the window
            // keeps 30 frames per second (see `frame_budget`).
            let height = lanes.scene.plane.height;
            let work = if step {
                [LaneWork::Passes(config.spp_per_frame.max(1)); 3]
            } else {
                frame_budget::plan(
                    self.budget.gpu_budget(),
                    lanes.each_mut().map(|l| l.row_seconds),
                    height,
                    config.budget,
                    config.spp_per_frame,
                )
            };
            let mut total = 0.0;
            for (lane, work) in lanes.each_mut().into_iter().zip(work) {
                let before = lane.renderer.pass_rows_done();
                let spp_before = lane.renderer.samples_per_pixel();
                let started = Instant::now();
                let rows = match work {
                    LaneWork::Passes(n) => {
                        lane.renderer.accumulate(n).map_err(|e| e.to_string())?;
                        n * height - before
                    }
                    LaneWork::Rows(n) => {
                        lane.renderer
                            .accumulate_rows(n)
                            .map_err(|e| e.to_string())?;
                        n.min(height - before)
                    }
                };
                // The lane's time is its passes' own (the device's timestamps, or the CPU
                // clock over each pass alone on an idle queue): never tonemapping, readback,
                // the other lanes or egui's frame. The rows each lane gets (equal samples or
                // equal time) are planned with the same pass time; the UI's own cost is the
                // frame's wall time less the wall time these waits took.
                let pass_seconds = lane
                    .renderer
                    .take_pass_seconds()
                    .map_err(|e| e.to_string())?;
                let spent = started.elapsed().as_secs_f64();
                let per_row = pass_seconds / f64::from(rows.max(1));
                lane.row_seconds = Some(lane.row_seconds.map_or(per_row, |t| {
                    (1.0 - ROW_COST_SMOOTHING) * t + ROW_COST_SMOOTHING * per_row
                }));
                lane.image.seconds += pass_seconds;
                lane.image.last_frame_seconds = pass_seconds;
                lane.image.spp = lane.renderer.samples_per_pixel();
                lane.image.pass_progress =
                    lane.renderer.pass_rows_done() as f32 / height.max(1) as f32;
                // A band changes only its rows; a completed pass changes every row's count.
                let after = lane.renderer.pass_rows_done();
                let tonemap = if lane.renderer.samples_per_pixel() == spp_before {
                    lane.renderer.tonemap_rows(config.exposure, before..after)
                } else {
                    lane.renderer.tonemap(config.exposure)
                };
                tonemap.map_err(|e| e.to_string())?;
                total += spent;
            }
            self.budget.gpu_spent(total);
            lanes.frame += 1;
        }
        if self.exposure != Some(config.exposure) {
            for lane in lanes.each_mut() {
                lane.renderer
                    .tonemap(config.exposure)
                    .map_err(|e| e.to_string())?;
            }
            self.exposure = Some(config.exposure);
        }
        let readback = stale
            || reset
            || step
            || reference_arrived
            || (advance && lanes.frame % READBACK_EVERY == 1);
        if readback {
            for lane in lanes.each_mut() {
                lane.readback_due = true;
            }
        }
        {
            let Lanes {
                reference,
                uniform,
                importance,
                spatial,
                ..
            } = lanes;
            // The sums are read at pass boundaries only (a pass in progress has rows with
            // one sample more).
            for lane in [uniform, importance, spatial] {
                if !lane.readback_due || lane.renderer.pass_rows_done() > 0 {
                    continue;
                }
                lane.readback_due = false;
                let acc = lane.renderer.readback().map_err(|e| e.to_string())?;
                lane.image.variance = mean_variance_scaled(&acc);
                lane.image.normalized_variance = normalized_variance_per_sample(&acc);
                if let Some(r) = reference.as_ref() {
                    let rmse = lightpick_core::render::rmse(&acc, r);
                    lane.image.rmse = Some(rmse);
                    lane.image.error_rgba = r.image().map(|full| {
                        engine::error_map(&acc.image(), full, engine::error_scale(full))
                    });
                    if acc.samples_per_pixel > 0 {
                        lane.image.series.push(ConvergencePoint {
                            spp: acc.samples_per_pixel,
                            seconds: lane.image.seconds,
                            rmse,
                        });
                        engine::thin(&mut lane.image.series);
                    }
                }
            }
        }
        self.latest = Some(Arc::new(Published {
            generation: lanes.generation,
            frame: lanes.frame * 2 + u64::from(readback),
            width: lanes.scene.plane.width,
            height: lanes.scene.plane.height,
            light_count: lanes.scene.light_count(),
            uniform: lanes.uniform.image.clone(),
            importance: lanes.importance.image.clone(),
            spatial: lanes.spatial.image.clone(),
            reference_rgba: lanes
                .reference
                .as_ref()
                .and_then(Reference::image)
                .map(|r| lightpick_core::render::tonemap_rgba8(r, config.exposure)),
            reference_note: lanes.reference_note.clone(),
            device_note: format!("GPU: {}", self.ctx.description()),
            time_source: format!(
                "GPU pass time per pixel sample ({}), excluding tonemap and readback",
                lanes.importance.renderer.pass_clock().describe()
            ),
        }));
        Ok(())
    }

    /// Starts building the renderers of `scene` (on the UI thread for small scenes, so the
    /// images restart within the frame; on a worker for large ones, so the window never
    /// waits for an `O(N)` upload). One build at a time: the newest request wins.
    fn request(
        &mut self,
        generation: u64,
        samplers: &SceneSamplers,
        seed: u64,
    ) -> Result<(), String> {
        if self
            .pending
            .as_ref()
            .is_some_and(|p| p.generation == generation && p.seed == seed)
        {
            return Ok(());
        }
        if samplers.scene().light_count() <= SYNC_BUILD_LIMIT {
            let trio = build_trio(&self.ctx, samplers, seed)?;
            self.pending = None;
            self.lanes = Some(self.install(generation, seed, samplers.scene(), trio));
            self.exposure = None;
            return Ok(());
        }
        if self.pending.is_some() {
            // Let the running build finish; `poll_pending` asks again for the newest scene.
            return Ok(());
        }
        let (ctx, for_build) = (self.ctx.clone(), samplers.clone());
        let worker = Worker::spawn("lightpick-gpu-upload", move || {
            build_trio(&ctx, &for_build, seed)
        })
        .map_err(|e| e.to_string())?;
        self.pending = Some(RendererUpload {
            generation,
            seed,
            samplers: samplers.clone(),
            worker,
        });
        Ok(())
    }

    /// Installs a finished background build (and asks for a newer scene if there is one).
    fn poll_pending(
        &mut self,
        generation: u64,
        samplers: &SceneSamplers,
        seed: u64,
    ) -> Result<(), String> {
        let Some(pending) = &self.pending else {
            return Ok(());
        };
        let trio = match pending.worker.poll() {
            Polled::Done(result) => result?,
            Polled::Running => return Ok(()),
            Polled::Lost => {
                self.pending = None;
                return Err("the GPU upload thread stopped".to_owned());
            }
        };
        let (built_generation, built_seed, built_scene) = (
            pending.generation,
            pending.seed,
            Arc::clone(pending.samplers.scene()),
        );
        self.pending = None;
        self.lanes = Some(self.install(built_generation, built_seed, &built_scene, trio));
        self.exposure = None;
        if built_generation != generation || built_seed != seed {
            self.request(generation, samplers, seed)?;
        }
        Ok(())
    }

    /// Points the egui textures at a new trio of renderers and starts their reference.
    fn install(
        &mut self,
        generation: u64,
        seed: u64,
        scene: &Arc<Scene>,
        (uniform, importance, spatial): Trio,
    ) -> Lanes {
        let device = &self.render_state.device;
        let filter = wgpu::FilterMode::Nearest;
        let ids = {
            let mut renderer = self.render_state.renderer.write();
            match self.ids {
                Some(ids) => {
                    for (id, r) in ids.iter().zip([&uniform, &importance, &spatial]) {
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
                    renderer.register_native_texture(device, importance.output_view(), filter),
                    renderer.register_native_texture(device, spatial.output_view(), filter),
                ],
            }
        };
        self.ids = Some(ids);
        Lanes {
            generation,
            seed,
            scene: Arc::clone(scene),
            reference: None,
            reference_note: Some("computing the reference…".to_owned()),
            uniform: Lane {
                renderer: uniform,
                texture: ids[0],
                image: SchemeImage::default(),
                row_seconds: None,
                readback_due: true,
            },
            importance: Lane {
                renderer: importance,
                texture: ids[1],
                image: SchemeImage::default(),
                row_seconds: None,
                readback_due: true,
            },
            spatial: Lane {
                renderer: spatial,
                texture: ids[2],
                image: SchemeImage::default(),
                row_seconds: None,
                readback_due: true,
            },
            frame: 0,
        }
    }
}
