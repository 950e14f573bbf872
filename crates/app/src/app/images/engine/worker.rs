//! The CPU engine's render thread: it applies the UI's [`Command`]s to the [`Job`] and,
//! while running, renders one batch at a time, each after the UI has taken the previous
//! frame, resting after long batches so the window keeps its share of the cores.

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::Command;
use super::job::{CPU_NOTE, Job, WORKER_BATCH_S};
use crate::app::images::published::{EngineConfig, Published, RendererBytes};

/// The longest rest after a long batch (a pass of the light tree on `million`).
const MAX_REST_S: f64 = 0.5;

/// Applies one command; returns whether a frame must be accumulated now (a step).
pub(super) fn handle(
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
            // The old job goes first: two scenes' runs are never held at once.
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

/// The commands that arrived, newest reset only; `None` once the UI has gone. Blocks unless
/// a frame is `due` (and then only while `resting`, for commands only).
fn receive(
    receiver: &mpsc::Receiver<Command>,
    due: bool,
    resting: Option<Instant>,
) -> Option<Vec<Command>> {
    let mut commands = Vec::new();
    if !due || resting.is_some() {
        let received = match resting {
            Some(until) if due => match receiver.recv_timeout(until - Instant::now()) {
                Ok(c) => Some(c),
                Err(mpsc::RecvTimeoutError::Timeout) => None,
                Err(mpsc::RecvTimeoutError::Disconnected) => return None,
            },
            _ => Some(receiver.recv().ok()?),
        };
        commands.extend(received);
    }
    loop {
        match receiver.try_recv() {
            Ok(c) => commands.push(c),
            Err(mpsc::TryRecvError::Empty) => break,
            Err(mpsc::TryRecvError::Disconnected) => return None,
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
    Some(commands)
}

/// The worker loop: waits for commands while paused; while running renders one batch at a
/// time ([`Job::advance_batch`]), each after the UI has taken the previous frame, on a rayon
/// pool that leaves one core to the window (whose frame, drawn by lavapipe on a machine
/// without a GPU, needs it).
pub(super) fn worker(
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
        let resting = rest_until.filter(|t| *t > Instant::now());
        let Some(commands) = receive(receiver, running && shown, resting) else {
            return;
        };
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
