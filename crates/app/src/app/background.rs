//! The app's one way to run work off the UI thread: a [`Worker`] is a named thread whose
//! result the UI takes once it is ready, polling once per frame and never waiting; a
//! [`Background`] keeps the latest result of a measurement per scene generation on top of
//! it (or computes it inline, on the caller's thread, in tests).
//!
//! Every thread the app starts is a [`Worker`]: the table builder, the GPU uploads and
//! references, the animation export, the measurements and the CPU render loop (whose
//! result is `()`: it talks to the UI through its own channels). Dropping a worker detaches
//! its thread: what it returns later is dropped, and nothing waits for it (a scene replaced
//! mid-build never blocks the window).

use std::sync::mpsc;

/// A job running on its own named thread, and the way to its result.
#[derive(Debug)]
pub struct Worker<T> {
    receiver: mpsc::Receiver<T>,
}

/// What [`Worker::poll`] found.
#[derive(Debug, PartialEq)]
pub enum Polled<T> {
    /// The job is still running.
    Running,
    /// The job's result (taken: a later poll finds [`Polled::Lost`]).
    Done(T),
    /// The thread ended without a result (the job panicked), or it was taken already.
    Lost,
}

impl<T: Send + 'static> Worker<T> {
    /// Runs `job` on a new thread named `name`; the error is the system's refusal to start
    /// one.
    ///
    /// # Errors
    /// When the thread cannot be started.
    pub fn spawn(name: &str, job: impl FnOnce() -> T + Send + 'static) -> std::io::Result<Self> {
        let (sender, receiver) = mpsc::channel();
        std::thread::Builder::new()
            .name(name.to_owned())
            .spawn(move || {
                // Nobody waits any more when the worker was dropped: the result goes too.
                let _ = sender.send(job());
            })?;
        Ok(Self { receiver })
    }

    /// The result when it is ready, without waiting.
    pub fn poll(&self) -> Polled<T> {
        match self.receiver.try_recv() {
            Ok(result) => Polled::Done(result),
            Err(mpsc::TryRecvError::Empty) => Polled::Running,
            Err(mpsc::TryRecvError::Disconnected) => Polled::Lost,
        }
    }

    /// Waits for the result; `None` when the thread ended without one.
    pub fn wait(self) -> Option<T> {
        self.receiver.recv().ok()
    }
}

/// A background result that says which scene generation it measures.
pub trait OfGeneration {
    /// The scene generation the result was computed for.
    fn generation(&self) -> u64;
}

/// The latest finished result of a background job and the one being computed, keyed by the
/// scene generation it measures.
#[derive(Debug)]
pub struct Background<T> {
    /// The latest finished result.
    pub result: Option<T>,
    /// Compute on the caller's thread (tests), else on a worker thread.
    pub inline: bool,
    pending: Option<(u64, Worker<T>)>,
}

impl<T> Default for Background<T> {
    fn default() -> Self {
        Self {
            result: None,
            inline: false,
            pending: None,
        }
    }
}

impl<T: Send + 'static> Background<T> {
    /// Whether a job is running.
    pub fn is_measuring(&self) -> bool {
        self.pending.is_some()
    }

    /// Starts `job(inline)` for `generation` on a thread named `name`, unless a job for that
    /// generation is already running; inline mode runs it at once. A job of another
    /// generation still running is dropped (its result is never shown).
    pub fn start(
        &mut self,
        generation: u64,
        name: &str,
        job: impl FnOnce(bool) -> T + Send + 'static,
    ) {
        if self.pending.as_ref().is_some_and(|(g, _)| *g == generation) {
            return;
        }
        if self.inline {
            self.result = Some(job(true));
            return;
        }
        if let Ok(worker) = Worker::spawn(name, move || job(false)) {
            self.pending = Some((generation, worker));
        }
    }

    /// Takes a finished job's result; call once per frame.
    pub fn poll(&mut self) {
        let Some((_, worker)) = &self.pending else {
            return;
        };
        match worker.poll() {
            Polled::Running => {}
            Polled::Done(result) => {
                self.result = Some(result);
                self.pending = None;
            }
            Polled::Lost => self.pending = None,
        }
    }
}

impl<T: OfGeneration> Background<T> {
    /// Whether there is no result for scene `generation`: none yet, or one of an earlier
    /// scene.
    pub fn is_stale(&self, generation: u64) -> bool {
        self.result
            .as_ref()
            .is_none_or(|m| m.generation() != generation)
    }
}
