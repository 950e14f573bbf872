//! The core time of a CPU render pass: the CPU time its render threads spent in it.
//!
//! A pass's wall time counts whatever else runs on the cores meanwhile: the app's window
//! (lavapipe drawing egui on the same two cores), another test, a compiler. The threads'
//! own CPU clocks (`CLOCK_THREAD_CPUTIME_ID`, `GetThreadTimes`) count only the time they
//! ran, so the sum over the render threads is the pass's cost whoever shares the machine,
//! and does not depend on how many threads the pool has: `lightpick bench` (every core) and
//! the app (one core left to its window) measure the same core time per sample. Where a
//! thread clock is not available the wall time times the pool's threads stands in.

use std::time::{Duration, Instant};

/// The calling thread's CPU time so far, when the platform has a thread clock.
fn thread_cpu() -> Option<Duration> {
    cpu_time::ThreadTime::try_now()
        .ok()
        .map(|t| t.as_duration())
}

/// Runs `f` (whose parallel work runs on the current rayon pool) and returns its result
/// with the CPU seconds the pool's threads spent meanwhile, summed. Called from inside a
/// pool (`install`), that pool; else rayon's global one.
pub fn pool_core_seconds<R>(f: impl FnOnce() -> R) -> (R, f64) {
    let before: Vec<Option<Duration>> = rayon::broadcast(|_| thread_cpu());
    let wall = Instant::now();
    let result = f();
    let wall = wall.elapsed();
    let after: Vec<Option<Duration>> = rayon::broadcast(|_| thread_cpu());
    let summed: Option<Duration> = before
        .iter()
        .zip(&after)
        .map(|(b, a)| Some(a.as_ref()?.saturating_sub((*b)?)))
        .sum();
    let seconds = summed.map_or_else(
        || wall.as_secs_f64() * before.len() as f64,
        |d| d.as_secs_f64(),
    );
    (result, seconds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    #[test]
    fn counts_the_work_of_every_pool_thread_and_not_a_sleep() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool");
        // Busy work on both threads: the core time is about twice the wall time of each
        // half, and far more than the 200 ms a sleeping caller would add to a wall clock.
        let ((), busy) = pool.install(|| {
            pool_core_seconds(|| {
                (0..2).into_par_iter().for_each(|_| {
                    let start = Instant::now();
                    let mut x = 0u64;
                    while start.elapsed() < Duration::from_millis(100) {
                        x = std::hint::black_box(x.wrapping_add(1));
                    }
                });
            })
        });
        assert!(busy > 0.15, "{busy}");
        let ((), idle) =
            pool.install(|| pool_core_seconds(|| std::thread::sleep(Duration::from_millis(200))));
        assert!(idle < 0.1, "a sleep costs no core time: {idle}");
    }
}
