//! Progressive images on the GPU: three `lightpick_core::gpu::GpuRenderer`s (uniform,
//! power and spatial) on eframe's own wgpu device, whose `Rgba8Unorm` outputs egui
//! shows as native textures (no copy through the CPU). Every few frames the sums are read
//! back for the RMSE, the error maps and the convergence curves, computed exactly as the CPU
//! engine does.
//!
//! All of it runs on the UI thread, which waits for each run's compute work (an honest time
//! per frame). Each frame gets the GPU work that fits in what the frame leaves
//! ([`super::frame_budget`]): whole sample passes, or a band of rows of one when a pass is
//! costlier than that, so a slow device slows the images, never the window. The sums are
//! read back at pass boundaries only.
//!
//! `runs` holds the three runs and what each does in a frame; this file decides, per
//! frame, what they do: restart, upload (on a worker for large scenes), the reference (on a
//! worker), accumulate, tonemap, read back, publish.

mod runs;

use std::sync::Arc;
use std::time::Instant;

use eframe::egui_wgpu;
use lightpick_core::SceneSamplers;
use lightpick_core::gpu::GpuContext;
use lightpick_core::render::Reference;
use lightpick_core::scene::Scene;

use crate::app::background::{Job, JobPolled};
use crate::app::images::frame_budget::{self, FrameBudget, RunWork};
use crate::app::images::published::{EngineConfig, Published, RendererBytes};
use crate::app::images::reference::reference;
use crate::app::state::rebuild::SYNC_BUILD_LIMIT;
use runs::{GpuRuns, Trio, build_trio, register_textures};

/// Read the sums back (RMSE, error maps, curves) every this many frames.
const READBACK_EVERY: u64 = 4;

/// A scene's renderers being uploaded on a worker thread, keyed by scene generation and
/// seed; the job hands back the scene with the trio.
type RendererUpload = Job<(u64, u64), (Arc<Scene>, Result<Trio, String>)>;

/// A reference computed on a worker thread, keyed by its scene generation.
type ReferenceJob = Job<u64, (Reference, Option<String>)>;

/// The GPU side of the images panel.
pub struct GpuImages {
    ctx: GpuContext,
    render_state: egui_wgpu::RenderState,
    runs: Option<GpuRuns>,
    exposure: Option<f64>,
    /// Texture ids kept across scenes (re-pointed at each new renderer's output).
    ids: Option<[egui::TextureId; 3]>,
    latest: Option<Arc<Published>>,
    pending: RendererUpload,
    /// The reference being computed, and for which scene generation.
    reference_job: ReferenceJob,
    /// How much GPU work each UI frame may take.
    budget: FrameBudget,
}

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
            runs: None,
            exposure: None,
            ids: None,
            latest: None,
            pending: RendererUpload::default(),
            reference_job: ReferenceJob::default(),
            budget: FrameBudget::default(),
        }
    }

    /// What the runs hold on the device (lavapipe's device memory is the process's) and the
    /// reference on the CPU; the scene, table and tree they were uploaded from are the
    /// app's `Built`.
    pub fn bytes(&self) -> RendererBytes {
        self.runs.as_ref().map(GpuRuns::bytes).unwrap_or_default()
    }

    /// Drops the runs (their light buffers, tree, sums and reference) and the last frame
    /// while the CPU renders the images; the next [`GpuImages::frame`] builds them again.
    pub fn release(&mut self) {
        self.runs = None;
        self.pending.cancel();
        self.reference_job.cancel();
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

    /// The native textures of the uniform, power and spatial images.
    pub fn texture_ids(&self) -> Option<[egui::TextureId; 3]> {
        self.runs
            .as_ref()
            .map(|l| [l.uniform.texture, l.power.texture, l.spatial.texture])
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
        let runs = self.runs.as_mut().ok_or("no image has been rendered yet")?;
        for (image, run) in [&mut frame.uniform, &mut frame.power, &mut frame.spatial]
            .into_iter()
            .zip(runs.each_mut())
        {
            run.export_into(image, exposure)?;
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
        let stale = self.restart(generation, samplers, config, reset)?;
        let Some(runs) = self
            .runs
            .as_mut()
            .filter(|l| l.generation == generation && l.seed == config.seed)
        else {
            // A large scene is still uploading: keep showing the last frame (marked stale).
            return Ok(());
        };
        let reference_arrived = poll_reference(&mut self.reference_job, runs);
        let advance = config.running || step;
        if advance {
            // A step (paused) renders whole passes, however long; while running, the frame
            // budget decides: whole passes when they fit, else a band of rows, so the window
            // keeps 30 frames per second (see `frame_budget`).
            let work = if step {
                [RunWork::Passes(config.spp_per_frame.max(1)); 3]
            } else {
                frame_budget::plan(
                    self.budget.gpu_budget(),
                    runs.each_mut().map(|l| l.row_seconds),
                    runs.scene.plane.height,
                    config.budget,
                    config.spp_per_frame,
                    runs.each_mut().map(|l| l.image.seconds),
                )
            };
            let spent = runs.accumulate(work, config.exposure)?;
            self.budget.gpu_spent(spent);
            runs.frame += 1;
        }
        if self.exposure != Some(config.exposure) {
            runs.tonemap(config.exposure)?;
            self.exposure = Some(config.exposure);
        }
        let readback = stale
            || reset
            || step
            || reference_arrived
            || (advance && runs.frame % READBACK_EVERY == 1);
        runs.read_back(readback)?;
        let frame = runs.publish(config.exposure, readback, &self.ctx.description());
        self.latest = Some(Arc::new(frame));
        Ok(())
    }

    /// The frame's start: new renderers for a new scene or seed (returns `true`: the runs
    /// were stale), or the same ones cleared on a reset; a finished upload installed; a new
    /// trio's outputs tonemapped (they are blank until then, black before any sample).
    fn restart(
        &mut self,
        generation: u64,
        samplers: &SceneSamplers,
        config: &EngineConfig,
        reset: bool,
    ) -> Result<bool, String> {
        let stale = self
            .runs
            .as_ref()
            .is_none_or(|l| l.generation != generation || l.seed != config.seed);
        if stale {
            self.request(generation, samplers, config.seed)?;
        } else if reset && let Some(runs) = self.runs.as_mut() {
            for run in runs.each_mut() {
                run.reset();
            }
            runs.frame = 0;
            self.exposure = None;
        }
        self.poll_pending(generation, samplers, config.seed)?;
        if self.exposure.is_none()
            && let Some(runs) = self.runs.as_mut()
        {
            runs.tonemap(config.exposure)?;
            self.exposure = Some(config.exposure);
        }
        Ok(stale)
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
        if self.pending.running_key() == Some(&(generation, seed)) {
            return Ok(());
        }
        if samplers.scene().light_count() <= SYNC_BUILD_LIMIT {
            let trio = build_trio(&self.ctx, samplers, seed)?;
            self.pending.cancel();
            self.install(generation, seed, samplers.scene(), trio);
            return Ok(());
        }
        if self.pending.is_running() {
            // Let the running build finish; `poll_pending` asks again for the newest scene.
            return Ok(());
        }
        let (ctx, for_build) = (self.ctx.clone(), samplers.clone());
        self.pending
            .start((generation, seed), "lightpick-gpu-upload", move || {
                let trio = build_trio(&ctx, &for_build, seed);
                (Arc::clone(for_build.scene()), trio)
            })
            .map_err(|e| e.to_string())
    }

    /// Installs a finished background build (and asks for a newer scene if there is one).
    fn poll_pending(
        &mut self,
        generation: u64,
        samplers: &SceneSamplers,
        seed: u64,
    ) -> Result<(), String> {
        let ((built_generation, built_seed), built_scene, trio) = match self.pending.poll() {
            JobPolled::Done(key, (scene, trio)) => (key, scene, trio?),
            JobPolled::Idle => return Ok(()),
            JobPolled::Lost(_) => return Err("the GPU upload thread stopped".to_owned()),
        };
        self.install(built_generation, built_seed, &built_scene, trio);
        if built_generation != generation || built_seed != seed {
            self.request(generation, samplers, seed)?;
        }
        Ok(())
    }

    /// Shows a new trio of renderers (the egui textures pointed at their outputs); their
    /// reference starts on the next frame.
    fn install(&mut self, generation: u64, seed: u64, scene: &Arc<Scene>, trio: Trio) {
        let ids = register_textures(&self.render_state, self.ids, &trio);
        self.ids = Some(ids);
        self.runs = Some(GpuRuns::new(generation, seed, scene, trio, ids));
        self.exposure = None;
    }
}

/// Takes the reference of `runs` when it is ready (returns whether it arrived now), and
/// starts computing it when none is running: one at a time (up to a second of both cores
/// for huge scenes), so a drag through many tables computes only the newest one's.
fn poll_reference(job: &mut ReferenceJob, runs: &mut GpuRuns) -> bool {
    let mut arrived = false;
    match job.poll() {
        JobPolled::Done(job_generation, (reference, note)) if job_generation == runs.generation => {
            runs.reference = Some(reference);
            runs.reference_note = note;
            arrived = true;
        }
        // A reference that failed is not tried again for these runs (it would fail again).
        JobPolled::Lost(job_generation) if job_generation == runs.generation => {
            runs.reference_note = Some("no reference: its computation stopped".to_owned());
            runs.reference_failed = true;
        }
        _ => {}
    }
    if runs.reference.is_none() && !runs.reference_failed && !job.is_running() {
        let for_reference = Arc::clone(&runs.scene);
        if let Err(e) = job.start(runs.generation, "lightpick-reference", move || {
            reference(&for_reference)
        }) {
            runs.reference_note = Some(format!("no reference: {e}"));
        }
    }
    arrived
}
