//! Progressive images on the GPU: three `lightpick_core::gpu::GpuRenderer`s (uniform,
//! importance and spatial) on eframe's own wgpu device, whose `Rgba8Unorm` outputs egui
//! shows as native textures (no copy through the CPU). Every few frames the sums are read
//! back for the RMSE, the error maps and the convergence curves, computed exactly as the CPU
//! engine does.
//!
//! All of it runs on the UI thread, which waits for each lane's compute work (an honest time
//! per frame); when a frame of it takes more than the frame leaves, the next frames skip it
//! ([`super::frame_budget`]), so a slow device slows the images, never the window.

use std::sync::{Arc, mpsc};
use std::time::Instant;

use eframe::egui_wgpu::{self, wgpu};
use lightpick_core::Scheme;
use lightpick_core::gpu::{GpuContext, GpuRenderer};
use lightpick_core::render::{Reference, mean_variance_per_sample};
use lightpick_core::scene::Scene;

use super::engine::{self, ConvergencePoint, EngineConfig, Published, SchemeImage};
use super::frame_budget::FrameBudget;
use super::state::{BudgetMode, SYNC_BUILD_LIMIT};

/// Read the sums back (RMSE, error maps, curves) every this many frames.
const READBACK_EVERY: u64 = 4;

/// One scheme on the GPU.
struct Lane {
    renderer: GpuRenderer,
    texture: egui::TextureId,
    image: SchemeImage,
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
    /// Frames to skip before the next GPU work.
    cooldown: u32,
}

/// Most samples per pixel one lane dispatches in a frame of equal-time mode.
const MAX_EQUAL_TIME_SPP: u32 = 1 << 12;

/// Samples per pixel for one lane's frame in equal-time mode: as many as fit in
/// [`engine::EQUAL_TIME_SLICE_S`] at the lane's measured time per sample so far (one
/// dispatch, one wait), and 1 before there is a measurement. Every lane thus gets about the
/// same GPU time per frame, so the cheaper scheme accumulates more samples.
fn equal_time_spp(image: &SchemeImage) -> u32 {
    if image.spp == 0 || image.seconds <= 0.0 {
        return 1;
    }
    let per_spp = image.seconds / f64::from(image.spp);
    (engine::EQUAL_TIME_SLICE_S / per_spp)
        .floor()
        .clamp(1.0, f64::from(MAX_EQUAL_TIME_SPP)) as u32
}

impl Lanes {
    /// The uniform, importance and spatial lanes, in display order.
    fn each_mut(&mut self) -> [&mut Lane; 3] {
        [&mut self.uniform, &mut self.importance, &mut self.spatial]
    }
}

/// The three renderers of a scene: uniform, importance, spatial.
type Trio = (GpuRenderer, GpuRenderer, GpuRenderer);

/// Every renderer of a scene (`O(N)` alias tables and uploads, `O(N log N)` light tree).
fn build_trio(ctx: &GpuContext, scene: &Scene, seed: u64) -> Result<Trio, String> {
    let uniform = GpuRenderer::new(ctx, scene, Scheme::Uniform, seed).map_err(|e| e.to_string())?;
    let importance =
        GpuRenderer::new(ctx, scene, Scheme::Alias, seed).map_err(|e| e.to_string())?;
    let spatial = GpuRenderer::new(ctx, scene, Scheme::Spatial, seed).map_err(|e| e.to_string())?;
    Ok((uniform, importance, spatial))
}

/// Renderers being built on a worker thread.
struct PendingBuild {
    generation: u64,
    seed: u64,
    scene: Arc<Scene>,
    receiver: mpsc::Receiver<Result<Trio, String>>,
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
    pending: Option<PendingBuild>,
    /// The reference being computed, and for which scene generation.
    reference_job: Option<ReferenceJob>,
    /// How much GPU work each UI frame may take.
    budget: FrameBudget,
}

/// A reference computed on a worker thread, for one scene generation.
type ReferenceJob = (u64, mpsc::Receiver<(Reference, Option<String>)>);

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
    /// tonemap as the GPU's), for exporting them.
    pub fn frame_with_images(&self, exposure: f64) -> Result<Published, String> {
        let lanes = self
            .lanes
            .as_ref()
            .ok_or("no image has been rendered yet")?;
        let mut frame = self
            .latest
            .as_deref()
            .cloned()
            .ok_or("no image has been rendered yet")?;
        for (image, lane) in [
            &mut frame.uniform,
            &mut frame.importance,
            &mut frame.spatial,
        ]
        .into_iter()
        .zip([&lanes.uniform, &lanes.importance, &lanes.spatial])
        {
            let acc = lane.renderer.readback().map_err(|e| e.to_string())?;
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
        scene: &Arc<Scene>,
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
            self.request(generation, scene, config.seed)?;
        } else if reset && let Some(lanes) = self.lanes.as_mut() {
            for lane in lanes.each_mut() {
                lane.renderer.reset();
                lane.image = SchemeImage::default();
            }
            lanes.frame = 0;
            self.exposure = None;
        }
        self.poll_pending(generation, scene, config.seed)?;
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
        if let Some((job_generation, receiver)) = &self.reference_job
            && let Ok((reference, note)) = receiver.try_recv()
        {
            if *job_generation == lanes.generation {
                lanes.reference = Some(reference);
                lanes.reference_note = note;
                reference_arrived = true;
            }
            self.reference_job = None;
        }
        if lanes.reference.is_none() && self.reference_job.is_none() {
            let (sender, receiver) = mpsc::channel();
            let for_reference = Arc::clone(&lanes.scene);
            let spawned = std::thread::Builder::new()
                .name("lightpick-reference".to_owned())
                .spawn(move || {
                    let _ = sender.send(engine::reference(&for_reference));
                });
            match spawned {
                Ok(_) => self.reference_job = Some((lanes.generation, receiver)),
                Err(e) => lanes.reference_note = Some(format!("no reference: {e}")),
            }
        }
        let mut advance = config.running || step;
        if config.running && !step && lanes.cooldown > 0 {
            lanes.cooldown -= 1;
            advance = false;
        }
        if advance {
            let mut total = 0.0;
            for lane in lanes.each_mut() {
                let spp = match config.budget {
                    BudgetMode::EqualSamples => config.spp_per_frame.max(1),
                    BudgetMode::EqualTime => equal_time_spp(&lane.image),
                };
                let started = Instant::now();
                lane.renderer.accumulate(spp).map_err(|e| e.to_string())?;
                // Wait for this lane's work, so the time per frame is the lane's own.
                let _ = self.ctx.device().poll(wgpu::PollType::wait_indefinitely());
                let spent = started.elapsed().as_secs_f64();
                lane.image.seconds += spent;
                lane.image.last_frame_seconds = spent;
                lane.image.spp = lane.renderer.samples_per_pixel();
                total += spent;
            }
            // Keep the window at 30 frames per second or more: GPU work beyond what the
            // frame leaves is followed by frames without any (see `frame_budget`).
            self.budget.gpu_spent(total);
            lanes.cooldown = self.budget.cooldown_after(total);
            lanes.frame += 1;
        }
        if advance || self.exposure != Some(config.exposure) {
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
            let Lanes {
                reference,
                uniform,
                importance,
                spatial,
                ..
            } = lanes;
            for lane in [uniform, importance, spatial] {
                let acc = lane.renderer.readback().map_err(|e| e.to_string())?;
                lane.image.variance = mean_variance_per_sample(&acc);
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
        }));
        Ok(())
    }

    /// Starts building the renderers of `scene` (on the UI thread for small scenes, so the
    /// images restart within the frame; on a worker for large ones, so the window never
    /// waits for an `O(N)` upload). One build at a time: the newest request wins.
    fn request(&mut self, generation: u64, scene: &Arc<Scene>, seed: u64) -> Result<(), String> {
        if self
            .pending
            .as_ref()
            .is_some_and(|p| p.generation == generation && p.seed == seed)
        {
            return Ok(());
        }
        if scene.light_count() <= SYNC_BUILD_LIMIT {
            let trio = build_trio(&self.ctx, scene, seed)?;
            self.pending = None;
            self.lanes = Some(self.install(generation, seed, scene, trio));
            self.exposure = None;
            return Ok(());
        }
        if self.pending.is_some() {
            // Let the running build finish; `poll_pending` asks again for the newest scene.
            return Ok(());
        }
        let (sender, receiver) = mpsc::channel();
        let (ctx, for_build) = (self.ctx.clone(), Arc::clone(scene));
        std::thread::Builder::new()
            .name("lightpick-gpu-upload".to_owned())
            .spawn(move || {
                let _ = sender.send(build_trio(&ctx, &for_build, seed));
            })
            .map_err(|e| e.to_string())?;
        self.pending = Some(PendingBuild {
            generation,
            seed,
            scene: Arc::clone(scene),
            receiver,
        });
        Ok(())
    }

    /// Installs a finished background build (and asks for a newer scene if there is one).
    fn poll_pending(
        &mut self,
        generation: u64,
        scene: &Arc<Scene>,
        seed: u64,
    ) -> Result<(), String> {
        let Some(pending) = &self.pending else {
            return Ok(());
        };
        let trio = match pending.receiver.try_recv() {
            Ok(result) => result?,
            Err(mpsc::TryRecvError::Empty) => return Ok(()),
            Err(mpsc::TryRecvError::Disconnected) => {
                self.pending = None;
                return Err("the GPU upload thread stopped".to_owned());
            }
        };
        let (built_generation, built_seed, built_scene) =
            (pending.generation, pending.seed, Arc::clone(&pending.scene));
        self.pending = None;
        self.lanes = Some(self.install(built_generation, built_seed, &built_scene, trio));
        self.exposure = None;
        if built_generation != generation || built_seed != seed {
            self.request(generation, scene, seed)?;
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
            },
            importance: Lane {
                renderer: importance,
                texture: ids[1],
                image: SchemeImage::default(),
            },
            spatial: Lane {
                renderer: spatial,
                texture: ids[2],
                image: SchemeImage::default(),
            },
            frame: 0,
            cooldown: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(spp: u32, seconds: f64) -> SchemeImage {
        SchemeImage {
            spp,
            seconds,
            ..SchemeImage::default()
        }
    }

    #[test]
    fn equal_time_gives_each_lane_the_samples_that_fit_its_slice() {
        // Unmeasured: one sample per pixel.
        assert_eq!(equal_time_spp(&image(0, 0.0)), 1);
        // 1 ms per spp so far: 12 of them fit in the 12 ms slice.
        let slice = engine::EQUAL_TIME_SLICE_S;
        assert_eq!(equal_time_spp(&image(10, 0.010)), (slice / 0.001) as u32);
        // A lane 4× cheaper gets 4× the samples (the point of equal-time mode).
        assert_eq!(
            equal_time_spp(&image(40, 0.010)),
            4 * equal_time_spp(&image(10, 0.010))
        );
        // Slower than the slice: still one; very fast: capped.
        assert_eq!(equal_time_spp(&image(1, 1.0)), 1);
        assert_eq!(equal_time_spp(&image(1_000_000, 1e-3)), MAX_EQUAL_TIME_SPP);
    }
}
