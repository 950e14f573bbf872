//! The app's one way to run work off the UI thread: a [`Worker`] is a named thread whose
//! result the UI takes once it is ready, polling once per frame and never waiting; a
//! [`Job`] is the one job running for a key (a scene generation, and a seed), one at a time,
//! the newest request waiting for it; a [`Background`] keeps the latest result of a
//! measurement per scene generation on top of them (or computes it inline, on the caller's
//! thread, in tests). The table builds, the GPU uploads and references, and the
//! measurements all run as a [`Job`].
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

/// The one job running for the key `K` (a scene generation; a generation and a seed), if
/// any: "one background job at a time, the newest request wins" in one place. A request
/// while a job runs for another key waits ([`Job::is_running`]); when the job's result is
/// taken ([`Job::poll`]) the caller asks again for the newest key.
#[derive(Debug)]
pub struct Job<K, T> {
    running: Option<(K, Worker<T>)>,
}

impl<K, T> Default for Job<K, T> {
    fn default() -> Self {
        Self { running: None }
    }
}

/// What [`Job::poll`] found.
#[derive(Debug, PartialEq)]
pub enum JobPolled<K, T> {
    /// No job, or the job still running.
    Idle,
    /// The job for `K` finished with `T` (and is gone).
    Done(K, T),
    /// The job's thread ended without a result (it panicked); it is gone.
    Lost(K),
}

impl<K: PartialEq, T: Send + 'static> Job<K, T> {
    /// Whether a job is running.
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// The key of the running job.
    pub fn running_key(&self) -> Option<&K> {
        self.running.as_ref().map(|(k, _)| k)
    }

    /// Starts `job` for `key` on a thread named `name`, dropping a running job (its result
    /// is never taken); the error is the system's refusal to start a thread.
    ///
    /// # Errors
    /// When the thread cannot be started.
    pub fn start(
        &mut self,
        key: K,
        name: &str,
        job: impl FnOnce() -> T + Send + 'static,
    ) -> std::io::Result<()> {
        self.running = Some((key, Worker::spawn(name, job)?));
        Ok(())
    }

    /// Drops the running job, if any (its result is never taken).
    pub fn cancel(&mut self) {
        self.running = None;
    }

    /// Takes the running job's result when it is ready, without waiting.
    pub fn poll(&mut self) -> JobPolled<K, T> {
        let Some((key, worker)) = self.running.take() else {
            return JobPolled::Idle;
        };
        match worker.poll() {
            Polled::Running => {
                self.running = Some((key, worker));
                JobPolled::Idle
            }
            Polled::Done(result) => JobPolled::Done(key, result),
            Polled::Lost => JobPolled::Lost(key),
        }
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
    pending: Job<u64, T>,
}

impl<T> Default for Background<T> {
    fn default() -> Self {
        Self {
            result: None,
            inline: false,
            pending: Job::default(),
        }
    }
}

impl<T: Send + 'static> Background<T> {
    /// Whether a job is running.
    pub fn is_measuring(&self) -> bool {
        self.pending.is_running()
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
        if self.pending.running_key() == Some(&generation) {
            return;
        }
        if self.inline {
            self.result = Some(job(true));
            return;
        }
        if self
            .pending
            .start(generation, name, move || job(false))
            .is_err()
        {
            self.pending.cancel();
        }
    }

    /// Takes a finished job's result; call once per frame.
    pub fn poll(&mut self) {
        if let JobPolled::Done(_, result) = self.pending.poll() {
            self.result = Some(result);
        }
    }
}

impl<T: OfGeneration> Background<T> {
    /// Whether there is no result for scene `generation`: none yet, or one of an earlier
    /// scene.
    pub fn is_stale(&self, generation: u64) -> bool {
        self.of_generation(generation).is_none()
    }

    /// The result if it is of scene `generation` (never one left from an earlier scene).
    pub fn of_generation(&self, generation: u64) -> Option<&T> {
        self.result
            .as_ref()
            .filter(|m| m.generation() == generation)
    }

    /// Once per frame: takes a finished result ([`Background::poll`]) and, when there is
    /// none for `generation`, starts `job` for it ([`Background::start`]).
    pub fn refresh(
        &mut self,
        generation: u64,
        name: &str,
        job: impl FnOnce(bool) -> T + Send + 'static,
    ) where
        T: Send + 'static,
    {
        self.poll();
        if self.is_stale(generation) {
            self.start(generation, name, job);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Polls `job` until it is no longer running (a test's own guard against a hang).
    fn settle<K: PartialEq, T: Send + 'static>(job: &mut Job<K, T>) -> JobPolled<K, T> {
        let deadline = std::time::Instant::now() + std::time::Duration::from_mins(1);
        loop {
            match job.poll() {
                JobPolled::Idle if job.is_running() => {
                    assert!(std::time::Instant::now() < deadline, "the job never ended");
                    std::thread::sleep(std::time::Duration::from_millis(1));
                }
                polled => return polled,
            }
        }
    }

    #[test]
    fn a_job_hands_back_its_key_with_its_result_once() {
        let mut job: Job<u64, u32> = Job::default();
        assert_eq!(job.poll(), JobPolled::Idle);
        let (go, wait) = mpsc::channel::<()>();
        job.start(7, "test-job", move || {
            let _ = wait.recv();
            42
        })
        .expect("a thread");
        assert!(job.is_running());
        assert_eq!(job.running_key(), Some(&7));
        assert_eq!(job.poll(), JobPolled::Idle, "still running");
        go.send(()).expect("the job waits");
        assert_eq!(settle(&mut job), JobPolled::Done(7, 42));
        assert!(!job.is_running());
        assert_eq!(job.poll(), JobPolled::Idle, "taken once");
    }

    #[test]
    fn a_newer_start_drops_the_older_job_and_a_panic_is_lost() {
        let mut job: Job<u64, u32> = Job::default();
        let (_hold, wait) = mpsc::channel::<()>();
        job.start(1, "test-old", move || {
            let _ = wait.recv();
            1
        })
        .expect("a thread");
        job.start(2, "test-new", || 2).expect("a thread");
        assert_eq!(
            settle(&mut job),
            JobPolled::Done(2, 2),
            "the old one's result never shows"
        );
        job.start(3, "test-panic", || panic!("a job that fails"))
            .expect("a thread");
        assert_eq!(settle(&mut job), JobPolled::Lost(3));
        job.start(4, "test-cancel", || 4).expect("a thread");
        job.cancel();
        assert_eq!(job.poll(), JobPolled::Idle);
    }
}
