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

    /// Spins the calling thread until its own CPU clock has advanced by `work`, and returns
    /// what that clock measured (at least `work`). Load on the machine stretches the wall
    /// time this takes, never the CPU time it counts.
    fn spin_for_cpu(work: Duration) -> Duration {
        let start = thread_cpu().expect("a thread CPU clock on this platform");
        let mut x = 0u64;
        loop {
            x = std::hint::black_box(x.wrapping_add(1));
            let spent = thread_cpu()
                .expect("a thread CPU clock")
                .saturating_sub(start);
            if spent >= work {
                return spent;
            }
        }
    }

    /// The verdicts hold whatever else shares the cores: each thread measures its own work
    /// with its own CPU clock, and `pool_core_seconds` reads the same clocks before and
    /// after on every pool thread, so its sum contains each thread's self-measured interval
    /// (`after − before ≥ end − start` for readings nested in that order on one monotonic
    /// clock): no tolerance is needed below. Above, no thread can run longer than the wall
    /// time of the whole call.
    #[test]
    fn counts_the_work_of_every_pool_thread_and_not_a_sleep() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool");
        let wall = Instant::now();
        let (measured, busy) = pool.install(|| {
            pool_core_seconds(|| {
                (0..2)
                    .into_par_iter()
                    .map(|_| spin_for_cpu(Duration::from_millis(100)))
                    .sum::<Duration>()
            })
        });
        let wall = wall.elapsed().as_secs_f64();
        assert!(measured >= Duration::from_millis(200), "{measured:?}");
        assert!(
            busy >= measured.as_secs_f64(),
            "the pool's count {busy} s misses work its threads measured: {measured:?}"
        );
        assert!(
            busy <= 2.0 * wall,
            "two threads cannot spend {busy} s of CPU in {wall} s"
        );

        // A sleep costs no core time: far less than a tenth of its 200 ms, however busy the
        // machine (the only CPU counted is the broadcasts' and the sleep call's own).
        let ((), idle) =
            pool.install(|| pool_core_seconds(|| std::thread::sleep(Duration::from_millis(200))));
        assert!(idle < 0.02, "a sleep costs no core time: {idle}");
    }
}
