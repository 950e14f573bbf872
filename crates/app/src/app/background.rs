//! A measurement of one scene generation, computed on a worker thread so the UI never
//! waits (or inline, on the caller's thread, in tests).

use std::sync::mpsc;

/// The latest finished result of a background job and the one being computed, keyed by the
/// scene generation it measures.
#[derive(Debug)]
pub struct Background<T> {
    /// The latest finished result.
    pub result: Option<T>,
    /// Compute on the caller's thread (tests), else on a worker thread.
    pub inline: bool,
    pending: Option<(u64, mpsc::Receiver<T>)>,
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
    /// generation is already running; inline mode runs it at once.
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
        let (sender, receiver) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name(name.to_owned())
            .spawn(move || {
                let _ = sender.send(job(false));
            });
        if spawned.is_ok() {
            self.pending = Some((generation, receiver));
        }
    }

    /// Takes a finished job's result; call once per frame.
    pub fn poll(&mut self) {
        let Some((_, receiver)) = &self.pending else {
            return;
        };
        match receiver.try_recv() {
            Ok(result) => {
                self.result = Some(result);
                self.pending = None;
            }
            Err(mpsc::TryRecvError::Empty) => {}
            Err(mpsc::TryRecvError::Disconnected) => self.pending = None,
        }
    }
}
