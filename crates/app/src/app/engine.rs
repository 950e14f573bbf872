//! The progressive-image engine: three renderers (uniform, importance and spatial) over the
//! last valid scene, their reference, errors, timings and convergence series. The lanes
//! share the scene's alias table and spatial sampler ([`SceneSamplers`], built once per
//! scene generation with the app's `Built`) rather than building their own.
//!
//! It runs on its own thread in the app (so rendering never blocks the window) or inline
//! (`threaded = false`, for tests: every step is deterministic and timings are virtual).
//! The UI sends [`Command`]s and reads the latest [`Published`] frame; every published frame
//! carries the scene generation it belongs to, so a frame of an old scene is never shown as
//! the new one's.

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use lightpick_core::render::{
    CpuRenderer, Reference, efficiency_of, mean_variance_scaled, normalized_variance_per_sample,
    pool_core_seconds, tonemap_rgba8,
};
use lightpick_core::scene::Scene;
use lightpick_core::{SceneSamplers, Scheme};

use super::background::Worker;
use super::colors;
use super::state::BudgetMode;

/// Compute time each scheme gets per frame in equal-time mode.
pub(crate) const EQUAL_TIME_SLICE_S: f64 = 0.012;

/// The worker renders passes of every scheme for about this long per frame the window shows.
const WORKER_BATCH_S: f64 = 0.012;
/// The longest rest after a long batch (a pass of the light tree on `million`).
const MAX_REST_S: f64 = 0.5;

/// Virtual seconds per pixel sample in inline mode (deterministic timings for tests).
const VIRTUAL_SECONDS_PER_SAMPLE: f64 = 1.0e-8;

/// What the engine renders with, as the UI set it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EngineConfig {
    /// Samples per pixel per frame (equal-samples mode).
    pub spp_per_frame: u32,
    /// Equal samples or equal time.
    pub budget: BudgetMode,
    /// Tonemap exposure.
    pub exposure: f64,
    /// The seed of the pixel streams.
    pub seed: u64,
    /// Whether frames accumulate continuously.
    pub running: bool,
}

/// A message from the UI to the engine.
#[derive(Clone, Debug)]
pub enum Command {
    /// Start over on this scene (new table, new seed, or reset).
    Reset {
        /// The scene generation (from `Built`).
        generation: u64,
        /// The scene with its shared table and spatial sampler.
        samplers: SceneSamplers,
    },
    /// New settings (exposure re-tonemaps at once, even while paused).
    Config(EngineConfig),
    /// Accumulate one frame while paused.
    Step,
    /// The UI has taken the last published frame (the worker may render the next).
    Shown,
    /// Drop the job (another renderer shows the images).
    Release,
}

/// One point of a convergence curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvergencePoint {
    /// Samples per pixel so far.
    pub spp: u32,
    /// Render seconds so far.
    pub seconds: f64,
    /// RMSE against the reference.
    pub rmse: f64,
}

/// One scheme's image and numbers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SchemeImage {
    /// Tonemapped RGBA8, row-major.
    pub rgba: Vec<u8>,
    /// Error map RGBA8 (|estimate − reference|), when a reference exists.
    pub error_rgba: Option<Vec<u8>>,
    /// Samples per pixel so far (complete passes).
    pub spp: u32,
    /// Rows of the next pass already rendered, as a fraction of the image, while a costly
    /// pass is split over frames (GPU images); 0 otherwise.
    pub pass_progress: f32,
    /// Render seconds so far.
    pub seconds: f64,
    /// Seconds of the last frame.
    pub last_frame_seconds: f64,
    /// RMSE against the reference.
    pub rmse: Option<f64>,
    /// Mean per-sample variance over the pixels `V`, in irradiance², whatever its
    /// magnitude ([`lightpick_core::render::mean_variance_scaled`]).
    pub variance: lightpick_core::Scaled,
    /// `V̂ = V/Φ_total²`, the same in units of the total power (for the efficiency
    /// `1/(V̂·T)`, [`lightpick_core::render::normalized_variance_per_sample`]), whatever its
    /// magnitude.
    pub normalized_variance: lightpick_core::Scaled,
    /// Convergence curve.
    pub series: Vec<ConvergencePoint>,
}

impl SchemeImage {
    /// Seconds per pixel sample `T`.
    pub fn seconds_per_sample(&self, pixels: usize) -> f64 {
        let samples = f64::from(self.spp) * pixels as f64;
        if samples > 0.0 {
            self.seconds / samples
        } else {
            0.0
        }
    }

    /// Efficiency `1/(V̂·T)` (normalized variance per sample times time per sample), the
    /// figure of [`lightpick_core::render::efficiency`] and `lightpick bench`, whatever its
    /// magnitude; `None` before a variance and a time are measured.
    pub fn efficiency(&self, pixels: usize) -> Option<lightpick_core::Scaled> {
        let t = self.seconds_per_sample(pixels);
        (self.normalized_variance > lightpick_core::Scaled::ZERO && t > 0.0)
            .then(|| efficiency_of(self.normalized_variance, t))
    }
}

/// The latest frame the engine published.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Published {
    /// The scene generation it renders.
    pub generation: u64,
    /// Counts published frames (the UI re-uploads textures when it changes).
    pub frame: u64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Uniform light selection.
    pub uniform: SchemeImage,
    /// Power-proportional selection (alias table).
    pub importance: SchemeImage,
    /// Contribution-aware selection (exact for few lights, light tree for many).
    pub spatial: SchemeImage,
    /// Lights in the scene rendered (whether the spatial lane is the exact pick).
    pub light_count: usize,
    /// The tonemapped exact reference.
    pub reference_rgba: Option<Vec<u8>>,
    /// Why there is no reference, when there is none.
    pub reference_note: Option<String>,
    /// Where it was rendered ("CPU (rayon, 2 threads)").
    pub device_note: String,
    /// What each lane's time `T` measures, in words (for the figures' hover text).
    pub time_source: String,
}

impl Published {
    /// The mean samples per pixel of the three images, with the fraction of a pass in
    /// progress (row bands).
    pub fn mean_spp(&self) -> f64 {
        [&self.uniform, &self.importance, &self.spatial]
            .iter()
            .map(|s| f64::from(s.spp) + f64::from(s.pass_progress))
            .sum::<f64>()
            / 3.0
    }

    /// Whether the spatial image is the exact contribution pick (few lights): zero variance
    /// by construction, so its measured variance and RMSE are rounding only.
    pub fn spatial_is_exact(&self) -> bool {
        self.light_count > 0 && lightpick_core::spatial::uses_exact_pick(self.light_count)
    }
}

/// What a scene's renderers hold beyond the scene, its table and its spatial sampler (which
/// the app's `Built` owns and counts), in heap bytes (on the GPU: device bytes, which a
/// software device such as lavapipe keeps in the process).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RendererBytes {
    /// Per light: what the lanes hold beyond the scene's arrays (CPU: emission profiles'
    /// copies; GPU: uploaded lights and trees), each counted once where lanes share them.
    pub lights: usize,
    /// Per pixel: the lanes' sums and outputs and the exact reference.
    pub pixels: usize,
}

/// One scheme's renderer and totals.
struct Lane {
    renderer: CpuRenderer,
    seconds: f64,
    last_frame_seconds: f64,
    series: Vec<ConvergencePoint>,
}

impl Lane {
    fn new(samplers: &SceneSamplers, scheme: Scheme, seed: u64) -> Self {
        Self {
            renderer: CpuRenderer::from_samplers(samplers, scheme, seed),
            seconds: 0.0,
            last_frame_seconds: 0.0,
            series: Vec::new(),
        }
    }

    /// Adds `spp` samples per pixel; returns the core seconds spent: the CPU time of the
    /// render threads in the pass ([`pool_core_seconds`]), which neither the window sharing
    /// the cores nor the pool's size changes (virtual in tests).
    fn run(&mut self, spp: u32, virtual_time: bool, pixels: usize) -> f64 {
        if virtual_time {
            self.renderer.accumulate(spp);
            f64::from(spp) * pixels as f64 * VIRTUAL_SECONDS_PER_SAMPLE
        } else {
            pool_core_seconds(|| self.renderer.accumulate(spp)).1
        }
    }
}

/// The state of one scene's rendering.
struct Job {
    generation: u64,
    samplers: SceneSamplers,
    uniform: Lane,
    importance: Lane,
    spatial: Lane,
    reference: Reference,
    reference_note: Option<String>,
    frame: u64,
}

impl Job {
    fn new(generation: u64, samplers: SceneSamplers, seed: u64) -> Self {
        let (reference, reference_note) = reference(samplers.scene());
        Self {
            generation,
            uniform: Lane::new(&samplers, Scheme::Uniform, seed),
            importance: Lane::new(&samplers, Scheme::Alias, seed),
            spatial: Lane::new(&samplers, Scheme::Spatial, seed),
            samplers,
            reference,
            reference_note,
            frame: 0,
        }
    }

    fn pixels(&self) -> usize {
        self.samplers.scene().plane.pixel_count()
    }

    /// What the three lanes and the reference hold.
    fn bytes(&self) -> RendererBytes {
        let lanes = [&self.uniform, &self.importance, &self.spatial];
        // Records shared with an earlier lane are held once.
        let lights = (0..lanes.len())
            .filter(|&k| {
                !lanes[..k]
                    .iter()
                    .any(|l| lanes[k].renderer.shares_lights_with(&l.renderer))
            })
            .map(|k| lanes[k].renderer.light_bytes())
            .sum();
        RendererBytes {
            lights,
            pixels: lanes
                .iter()
                .map(|l| l.renderer.pixel_bytes())
                .sum::<usize>()
                + self.reference.heap_bytes(),
        }
    }

    /// The worker's frame: [`Job::advance`] again while the batch took less than
    /// [`WORKER_BATCH_S`] (equal samples; an equal-time frame is one advance), so cheap
    /// scenes gain several samples per pixel for each frame the window shows. Returns the
    /// seconds the batch took.
    fn advance_batch(&mut self, config: &EngineConfig) -> f64 {
        let started = Instant::now();
        loop {
            self.advance(config, false);
            let elapsed = started.elapsed().as_secs_f64();
            if config.budget == BudgetMode::EqualTime || elapsed >= WORKER_BATCH_S {
                return elapsed;
            }
        }
    }

    /// Accumulates one frame of every scheme.
    fn advance(&mut self, config: &EngineConfig, virtual_time: bool) {
        let pixels = self.pixels();
        let reference = &self.reference;
        // Rotate which scheme goes first, so none is always timed right after the window's
        // own frame work (a bias in the time per frame on a loaded machine).
        let mut lanes = [&mut self.uniform, &mut self.importance, &mut self.spatial];
        lanes.rotate_left((self.frame % 3) as usize);
        for lane in lanes {
            let spent = match config.budget {
                BudgetMode::EqualSamples => {
                    lane.run(config.spp_per_frame.max(1), virtual_time, pixels)
                }
                BudgetMode::EqualTime => {
                    let mut spent = 0.0;
                    loop {
                        spent += lane.run(1, virtual_time, pixels);
                        if virtual_time || spent >= EQUAL_TIME_SLICE_S {
                            break;
                        }
                    }
                    spent
                }
            };
            lane.seconds += spent;
            lane.last_frame_seconds = spent;
            let acc = lane.renderer.accumulator();
            lane.series.push(ConvergencePoint {
                spp: acc.samples_per_pixel,
                seconds: lane.seconds,
                rmse: lightpick_core::render::rmse(acc, reference),
            });
            thin(&mut lane.series);
        }
    }

    fn publish(&mut self, config: &EngineConfig, device_note: &str) -> Published {
        self.frame += 1;
        let reference = &self.reference;
        let full = reference.image();
        let exposure = config.exposure;
        let error_scale = full.map(error_scale);
        let scheme_image = |lane: &Lane| {
            let acc = lane.renderer.accumulator();
            let image = acc.image();
            SchemeImage {
                rgba: tonemap_rgba8(&image, exposure),
                error_rgba: full
                    .zip(error_scale)
                    .map(|(r, scale)| error_map(&image, r, scale)),
                spp: acc.samples_per_pixel,
                pass_progress: 0.0,
                seconds: lane.seconds,
                last_frame_seconds: lane.last_frame_seconds,
                rmse: Some(lightpick_core::render::rmse(acc, reference)),
                variance: mean_variance_scaled(acc),
                normalized_variance: normalized_variance_per_sample(acc),
                series: lane.series.clone(),
            }
        };
        Published {
            generation: self.generation,
            frame: self.frame,
            width: self.samplers.scene().plane.width,
            height: self.samplers.scene().plane.height,
            light_count: self.samplers.scene().light_count(),
            uniform: scheme_image(&self.uniform),
            importance: scheme_image(&self.importance),
            spatial: scheme_image(&self.spatial),
            reference_rgba: full.map(|r| tonemap_rgba8(r, exposure)),
            reference_note: self.reference_note.clone(),
            device_note: device_note.to_owned(),
            time_source: if virtual_time_note(device_note) {
                "virtual time (inline test engine: 10 ns per pixel sample)".to_owned()
            } else {
                format!(
                    "CPU core time per pixel sample: the CPU time of the {} render thread(s) in \
                     each scheme's pass (not the window's), excluding tonemap and error maps; \
                     `lightpick bench`'s \"core ns\"",
                    rayon::current_num_threads()
                )
            },
        }
    }
}

/// Keeps a convergence series short: past 1024 points, every other point of the older half
/// is dropped (on a log axis the recent, dense end loses nothing visible).
pub(crate) fn thin(series: &mut Vec<ConvergencePoint>) {
    if series.len() <= 1024 {
        return;
    }
    let half = series.len() / 2;
    let mut k = 0;
    series.retain(|_| {
        k += 1;
        k > half || k % 2 == 1
    });
}

/// The error-map scale: errors are shown relative to the reference's mean.
pub(crate) fn error_scale(reference: &[f64]) -> f64 {
    let mean = reference.iter().sum::<f64>() / reference.len().max(1) as f64;
    if mean > 0.0 { 1.0 / mean } else { 1.0 }
}

/// The error map: `|estimate − reference| · scale` through the palette's error ramp.
pub(crate) fn error_map(image: &[f64], reference: &[f64], scale: f64) -> Vec<u8> {
    image
        .iter()
        .zip(reference)
        .flat_map(|(e, r)| {
            let [red, green, blue] = colors::error_ramp((e - r).abs() * scale);
            [red, green, blue, 255]
        })
        .collect()
}

/// The exact reference within the core's budget (every pixel, or a fixed subset for huge
/// `N·P`), and a note when it is a subset or when an irradiance exceeds `f64` (naming the
/// pixel and the light).
pub(crate) fn reference(scene: &Scene) -> (Reference, Option<String>) {
    let reference = Reference::compute(scene);
    if let Some(overflow) = reference.overflow() {
        return (
            reference,
            Some(format!("{overflow}: RMSE and images are not meaningful")),
        );
    }
    let note = (!reference.is_complete()).then(|| {
        format!(
            "reference at {} of {} pixels ({} lights): RMSE over those pixels, no reference image",
            reference.pixels().len(),
            scene.plane.pixel_count(),
            scene.light_count()
        )
    });
    (reference, note)
}

/// Where the engine runs.
#[allow(clippy::large_enum_variant)] // One engine per app; boxing would only add a hop.
enum Mode {
    /// A worker thread; frames come back through `shared`.
    Threaded {
        /// The render loop; it ends when `sender` is dropped.
        _thread: Worker<()>,
        sender: mpsc::Sender<Command>,
        shared: Arc<Mutex<Option<Arc<Published>>>>,
        last_seen: Option<u64>,
        /// What the worker's job holds, as it last reported.
        bytes: Arc<Mutex<RendererBytes>>,
    },
    /// On the caller's thread, with virtual timings (tests).
    Inline {
        job: Option<Job>,
        config: Option<EngineConfig>,
        latest: Option<Arc<Published>>,
    },
}

/// The engine handle the app holds.
pub struct Engine {
    mode: Mode,
    generation: Option<u64>,
    config: Option<EngineConfig>,
}

const CPU_NOTE: &str = "CPU renderer";
/// The device note of the inline (test) engine, whose timings are virtual.
const INLINE_NOTE: &str = "CPU renderer (inline, virtual time)";

/// Whether a frame published with `device_note` has virtual timings.
fn virtual_time_note(device_note: &str) -> bool {
    device_note == INLINE_NOTE
}

impl Engine {
    /// A threaded engine that asks `ctx` to repaint whenever a frame is ready.
    pub fn threaded(ctx: &egui::Context) -> Self {
        let (sender, receiver) = mpsc::channel();
        let shared = Arc::new(Mutex::new(None));
        let worker_shared = Arc::clone(&shared);
        let bytes = Arc::new(Mutex::new(RendererBytes::default()));
        let worker_bytes = Arc::clone(&bytes);
        let ctx = ctx.clone();
        let spawned = Worker::spawn("lightpick-render", move || {
            worker(&receiver, &worker_shared, &worker_bytes, &ctx);
        });
        let Ok(thread) = spawned else {
            // Without a thread the engine still works, on the UI thread.
            return Self::inline();
        };
        Self {
            mode: Mode::Threaded {
                _thread: thread,
                sender,
                shared,
                last_seen: None,
                bytes,
            },
            generation: None,
            config: None,
        }
    }

    /// An engine that renders on the caller's thread, only when asked, with virtual
    /// timings: deterministic frames for tests.
    pub fn inline() -> Self {
        Self {
            mode: Mode::Inline {
                job: None,
                config: None,
                latest: None,
            },
            generation: None,
            config: None,
        }
    }

    /// Whether frames render on a worker thread.
    pub fn is_threaded(&self) -> bool {
        matches!(self.mode, Mode::Threaded { .. })
    }

    /// What the current job holds (threaded: as the worker last reported it).
    pub fn bytes(&self) -> RendererBytes {
        match &self.mode {
            Mode::Threaded { bytes, .. } => bytes.lock().map(|b| *b).unwrap_or_default(),
            Mode::Inline { job, .. } => job.as_ref().map(Job::bytes).unwrap_or_default(),
        }
    }

    /// Restarts on the scene of `samplers` (its table and spatial sampler shared, not
    /// rebuilt) when its generation differs from the current one (or `force`).
    pub fn sync_scene(&mut self, generation: u64, samplers: &SceneSamplers, force: bool) {
        if !force && self.generation == Some(generation) {
            return;
        }
        self.generation = Some(generation);
        self.send(Command::Reset {
            generation,
            samplers: samplers.clone(),
        });
    }

    /// Drops the current job, its sums, reference and last frame, while
    /// another renderer shows the images; the next [`Engine::sync_scene`] starts afresh.
    pub fn release(&mut self) {
        if self.generation.take().is_some() {
            self.send(Command::Release);
        }
    }

    /// Sends the settings when they changed.
    pub fn sync_config(&mut self, config: EngineConfig) {
        if self.config == Some(config) {
            return;
        }
        self.config = Some(config);
        self.send(Command::Config(config));
    }

    /// Accumulates one frame (while paused).
    pub fn step(&mut self) {
        self.send(Command::Step);
    }

    /// In inline mode, renders a frame when running; a no-op when threaded.
    pub fn tick(&mut self) {
        if let Mode::Inline {
            job: Some(job),
            config: Some(config),
            latest,
        } = &mut self.mode
            && config.running
        {
            job.advance(config, true);
            *latest = Some(Arc::new(job.publish(config, INLINE_NOTE)));
        }
    }

    /// The latest frame. In threaded mode, taking a new frame lets the worker render the
    /// next one: rendering never runs ahead of what the window shows, so the UI keeps
    /// its share of the CPU.
    pub fn latest(&mut self) -> Option<Arc<Published>> {
        match &mut self.mode {
            Mode::Threaded {
                shared,
                sender,
                last_seen,
                ..
            } => {
                let latest = shared.lock().ok().and_then(|g| g.clone());
                if let Some(p) = &latest
                    && *last_seen != Some(p.frame)
                {
                    *last_seen = Some(p.frame);
                    let _ = sender.send(Command::Shown);
                }
                latest
            }
            Mode::Inline { latest, .. } => latest.clone(),
        }
    }

    fn send(&mut self, command: Command) {
        match &mut self.mode {
            Mode::Threaded { sender, .. } => {
                // A stopped worker only happens at shutdown; nothing to report then.
                let _ = sender.send(command);
            }
            Mode::Inline {
                job,
                config,
                latest,
            } => {
                handle(command, job, config, true);
                *latest = match (job.as_mut(), config.as_ref()) {
                    (Some(job), Some(config)) => Some(Arc::new(job.publish(config, INLINE_NOTE))),
                    (None, _) => None,
                    (Some(_), None) => latest.take(),
                };
            }
        }
    }
}

/// Applies one command; returns whether a frame must be accumulated now (a step).
fn handle(
    command: Command,
    job: &mut Option<Job>,
    config: &mut Option<EngineConfig>,
    virtual_time: bool,
) -> bool {
    match command {
        Command::Reset {
            generation,
            samplers,
        } => {
            let seed = config.map_or(1, |c| c.seed);
            // The old job goes first: two scenes' lanes are never held at once.
            *job = None;
            *job = Some(Job::new(generation, samplers, seed));
            false
        }
        Command::Config(new) => {
            let reseed = config.is_some_and(|old| old.seed != new.seed);
            *config = Some(new);
            if reseed && let Some(old) = job.take() {
                *job = Some(Job::new(old.generation, old.samplers, new.seed));
            }
            false
        }
        Command::Step => {
            if let (Some(job), Some(config)) = (job.as_mut(), config.as_ref()) {
                job.advance(config, virtual_time);
            }
            false
        }
        Command::Shown => false,
        Command::Release => {
            *job = None;
            false
        }
    }
}

/// The worker loop: waits for commands while paused; while running renders one batch at a
/// time ([`Job::advance_batch`]), each after the UI has taken the previous frame, on a rayon
/// pool that leaves one core to the window (whose frame, drawn by lavapipe on a machine
/// without a GPU, needs it).
fn worker(
    receiver: &mpsc::Receiver<Command>,
    shared: &Mutex<Option<Arc<Published>>>,
    bytes: &Mutex<RendererBytes>,
    ctx: &egui::Context,
) {
    let threads =
        std::thread::available_parallelism().map_or(1, |n| n.get().saturating_sub(1).max(1));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("lightpick-render-{i}"))
        .build()
        .ok();
    let mut job: Option<Job> = None;
    let mut config: Option<EngineConfig> = None;
    // Whether the UI has taken the last published frame.
    let mut shown = true;
    // After a long batch the worker rests as long, so the window keeps half the cores.
    let mut rest_until: Option<Instant> = None;
    loop {
        let running = job.is_some() && config.is_some_and(|c| c.running);
        // Block unless a frame is due (waiting out a rest for commands only); then take
        // whatever else arrived.
        let mut commands = Vec::new();
        let resting = rest_until.filter(|t| *t > Instant::now());
        if !(running && shown) || resting.is_some() {
            let received = match resting {
                Some(until) if running && shown => {
                    match receiver.recv_timeout(until - Instant::now()) {
                        Ok(c) => Some(c),
                        Err(mpsc::RecvTimeoutError::Timeout) => None,
                        Err(mpsc::RecvTimeoutError::Disconnected) => return,
                    }
                }
                _ => match receiver.recv() {
                    Ok(c) => Some(c),
                    Err(_) => return,
                },
            };
            commands.extend(received);
        }
        loop {
            match receiver.try_recv() {
                Ok(c) => commands.push(c),
                Err(mpsc::TryRecvError::Empty) => break,
                Err(mpsc::TryRecvError::Disconnected) => return,
            }
        }
        // Only the newest reset matters (a drag on a large scene sends one per frame).
        if let Some(last_reset) = commands
            .iter()
            .rposition(|c| matches!(c, Command::Reset { .. }))
        {
            let mut k = 0;
            commands.retain(|c| {
                k += 1;
                !matches!(c, Command::Reset { .. }) || k - 1 == last_reset
            });
        }
        let mut changed = false;
        for command in commands {
            match command {
                Command::Shown => shown = true,
                other => {
                    changed = true;
                    let work = || handle(other, &mut job, &mut config, false);
                    match &pool {
                        Some(pool) => {
                            pool.install(work);
                        }
                        None => {
                            work();
                        }
                    }
                }
            }
        }
        if changed && let Ok(mut slot) = bytes.lock() {
            *slot = job.as_ref().map(Job::bytes).unwrap_or_default();
        }
        if changed
            && job.is_none()
            && let Ok(mut slot) = shared.lock()
        {
            // Released: its last frame goes too.
            *slot = None;
        }
        let running = job.is_some() && config.is_some_and(|c| c.running);
        let rested = rest_until.is_none_or(|t| t <= Instant::now());
        if let (Some(job), Some(cfg)) = (job.as_mut(), config.as_ref()) {
            if running && shown && rested {
                let worked = match &pool {
                    Some(pool) => pool.install(|| job.advance_batch(cfg)),
                    None => job.advance_batch(cfg),
                };
                rest_until = (worked > 2.0 * WORKER_BATCH_S && threads > 1)
                    .then(|| Instant::now() + Duration::from_secs_f64(worked.min(MAX_REST_S)));
                changed = true;
            }
            if changed {
                let frame = Arc::new(match &pool {
                    Some(pool) => pool.install(|| job.publish(cfg, CPU_NOTE)),
                    None => job.publish(cfg, CPU_NOTE),
                });
                if let Ok(mut slot) = shared.lock() {
                    *slot = Some(frame);
                }
                shown = false;
                ctx.request_repaint_after(std::time::Duration::from_millis(16));
            }
        }
    }
}
