//! The progressive-image engine: three renderers (uniform, power and spatial) over the
//! last valid scene, their reference, errors, timings and convergence series. The runs
//! share the scene's alias table and spatial sampler ([`SceneSamplers`], built once per
//! scene generation with the app's `Built`) rather than building their own.
//!
//! It runs on its own thread in the app (so rendering never blocks the window) or inline
//! (`threaded = false`, for tests: every step is deterministic and timings are virtual).
//! The UI sends [`Command`]s and reads the latest [`Published`] frame; every published frame
//! carries the scene generation it belongs to, so a frame of an old scene is never shown as
//! the new one's.

mod job;
mod worker;

use std::sync::mpsc;
use std::sync::{Arc, Mutex};

use lightpick_core::SceneSamplers;

use crate::app::background::Worker;
use crate::app::images::published::{EngineConfig, Published, RendererBytes};
use job::{INLINE_NOTE, Job};
use worker::{handle, worker};

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
