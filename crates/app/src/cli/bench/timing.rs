//! How a figure is timed: the median of several repetitions, each timing a batch of many
//! operations (`std::time::Instant`, results through `std::hint::black_box`).

use std::hint::black_box;
use std::time::Instant;

use lightpick_core::{Rng, Sampler};

/// Timing plan: repetitions and batch sizes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan {
    /// Repetitions of each timing (the median is kept).
    pub(super) repetitions: usize,
    /// Picks timed in each repetition.
    pub(super) samples_per_batch: usize,
    /// Lights built per repetition of a build timing (`build_budget / N` builds).
    pub(super) build_budget: usize,
}

impl Plan {
    /// The plan of a full or a `--quick` run.
    pub(super) fn new(quick: bool) -> Self {
        if quick {
            Self {
                repetitions: 5,
                samples_per_batch: 1 << 19,
                build_budget: 1 << 20,
            }
        } else {
            Self {
                repetitions: 7,
                samples_per_batch: 1 << 21,
                build_budget: 1 << 22,
            }
        }
    }
}

/// The median of `times` (sorted in place).
fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The median of `repetitions` timings of `batch` calls of `f`, per call, in nanoseconds.
pub(super) fn median_ns<T>(repetitions: usize, batch: usize, mut f: impl FnMut(usize) -> T) -> f64 {
    median(
        (0..repetitions)
            .map(|rep| {
                let start = Instant::now();
                for i in 0..batch {
                    black_box(f(rep * batch + i));
                }
                start.elapsed().as_secs_f64() * 1e9 / batch as f64
            })
            .collect(),
    )
}

/// Like [`median_ns`], for an `f` that consumes an input: the `batch` inputs of each
/// repetition are made by `input` before its clock starts.
pub(super) fn median_with_inputs<I, T>(
    repetitions: usize,
    batch: usize,
    mut input: impl FnMut() -> I,
    mut f: impl FnMut(I) -> T,
) -> f64 {
    median(
        (0..repetitions)
            .map(|_| {
                let inputs: Vec<I> = (0..batch).map(|_| input()).collect();
                let start = Instant::now();
                for x in inputs {
                    black_box(f(x));
                }
                start.elapsed().as_secs_f64() * 1e9 / batch as f64
            })
            .collect(),
    )
}

/// Time per pick of `sampler`, drawing from one stream of the project's [`Rng`] per
/// repetition.
pub(super) fn time_picks(sampler: &Sampler, seed: u64, reps: usize, samples: usize) -> f64 {
    median(
        (0..reps)
            .map(|rep| {
                let mut rng = Rng::new(seed, rep as u64);
                let start = Instant::now();
                let mut acc = 0u32;
                for _ in 0..samples {
                    acc = acc.wrapping_add(sampler.pick_light(&mut rng));
                }
                black_box(acc);
                start.elapsed().as_secs_f64() * 1e9 / samples as f64
            })
            .collect(),
    )
}
