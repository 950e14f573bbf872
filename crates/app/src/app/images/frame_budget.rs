//! How much GPU image work fits in a UI frame, so that the window keeps at least 30 frames
//! per second while the images render on the same device (on a software rasterizer such as
//! lavapipe, drawing egui and running the compute kernels share the same CPU cores).
//!
//! The UI's own cost `u` is measured as the interval between frames minus the GPU work done
//! in the previous one (an exponential moving average). The GPU work may take what the
//! target frame time `T` leaves, `b = max(T − u, b_min)`, and [`plan`] turns `b` into work:
//! whole sample passes when they fit, else a band of rows of one pass (a costly scheme on a
//! large image then advances a few rows per frame instead of stalling the window for one long
//! frame). On a real GPU `b` holds many passes and the images advance every frame.

use std::time::Instant;

use crate::app::state::settings::BudgetMode;

/// The frame time aimed at: 31 ms, a little under the 33 ms of 30 frames per second.
pub const TARGET_FRAME_S: f64 = 0.031;
/// The least GPU time per frame even when the UI alone nearly fills the target (so the
/// images keep advancing: on a software rasterizer a heavy scene's UI takes ~26 ms).
pub const MIN_GPU_SHARE_S: f64 = 0.004;
/// An interval longer than this (the window was idle or paused) counts as this.
const MAX_INTERVAL_S: f64 = 0.1;
/// Weight of the newest interval in the moving average.
const SMOOTHING: f64 = 0.2;

/// The measured UI cost per frame and the GPU work of the current frame.
#[derive(Clone, Debug, Default)]
pub struct FrameBudget {
    last_frame: Option<Instant>,
    /// Moving average of the UI's own seconds per frame (`None` before two frames).
    ui_seconds: Option<f64>,
    /// GPU seconds spent since the last [`FrameBudget::begin_frame`].
    gpu_seconds: f64,
}

impl FrameBudget {
    /// Starts a frame at `now`: the interval since the previous one, less that frame's GPU
    /// work, updates the UI cost.
    pub fn begin_frame(&mut self, now: Instant) {
        if let Some(last) = self.last_frame {
            let interval = (now - last).as_secs_f64().min(MAX_INTERVAL_S);
            let ui = (interval - self.gpu_seconds).max(0.0);
            self.ui_seconds = Some(match self.ui_seconds {
                Some(avg) => (1.0 - SMOOTHING) * avg + SMOOTHING * ui,
                None => ui,
            });
        }
        self.last_frame = Some(now);
        self.gpu_seconds = 0.0;
    }

    /// Records `seconds` of GPU work done in this frame.
    pub fn gpu_spent(&mut self, seconds: f64) {
        self.gpu_seconds += seconds;
    }

    /// The GPU seconds a frame may take on average: `max(T − u, b_min)` (`T − 0` before the
    /// UI cost is known).
    pub fn gpu_budget(&self) -> f64 {
        (TARGET_FRAME_S - self.ui_seconds.unwrap_or(0.0)).max(MIN_GPU_SHARE_S)
    }

    /// The measured UI seconds per frame, once known.
    pub fn ui_seconds(&self) -> Option<f64> {
        self.ui_seconds
    }
}

/// The GPU work of one run (one scheme's image) in one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunWork {
    /// This many whole sample passes (every pixel gets this many samples).
    Passes(u32),
    /// The next this many rows of the sample pass in progress.
    Rows(u32),
}

/// Rows a run renders in its first frame, before its cost per row is known.
pub const FIRST_ROWS: u32 = 8;
/// Most passes one run runs in a frame of equal-time mode.
pub const MAX_PASSES: u32 = 1 << 12;

/// The frame's work for each run, within `budget` GPU seconds: `row_seconds[l]` is run
/// `l`'s measured time per row of one sample pass (`None` before it is measured), `height`
/// the image's rows.
///
/// * Any cost unknown: [`FIRST_ROWS`] rows each (a cheap first measurement).
/// * Equal samples: every run does the same work, so they stay at the same samples per
///   pixel. `spp_per_frame` passes each if they fit in the budget, else as many passes as
///   fit, else the rows that fit, `⌊b / Σ_l t_l⌋` (at least one).
/// * Equal time: each run gets a slice of `b`: the passes of its own cost that fit (at least
///   one), or the rows that fit (at least one), so a cheaper scheme gets more samples. The
///   slices follow the runs' totals so far (`seconds`): run `l` wants `m + b/3 − t_l`
///   (`m` the largest total), scaled so they add up to `b`. Equal totals give `b/3` each; a
///   run behind (a whole pass that did not fit its slice last frame) gets more until it
///   has caught up, so the totals stay equal over the run, not only frame by frame.
pub fn plan(
    budget: f64,
    row_seconds: [Option<f64>; 3],
    height: u32,
    mode: BudgetMode,
    spp_per_frame: u32,
    seconds: [f64; 3],
) -> [RunWork; 3] {
    let Some(rows) = row_seconds
        .iter()
        .map(|t| t.filter(|t| *t > 0.0))
        .collect::<Option<Vec<f64>>>()
    else {
        return [RunWork::Rows(FIRST_ROWS); 3];
    };
    let height_f = f64::from(height.max(1));
    let fit = |seconds: f64, unit: f64, max: f64| (seconds / unit).floor().clamp(1.0, max) as u32;
    match mode {
        BudgetMode::EqualSamples => {
            let row_all: f64 = rows.iter().sum();
            let pass_all = row_all * height_f;
            let work = if pass_all <= budget {
                RunWork::Passes(fit(budget, pass_all, f64::from(spp_per_frame.max(1))))
            } else {
                RunWork::Rows(fit(budget, row_all, height_f))
            };
            [work; 3]
        }
        BudgetMode::EqualTime => {
            let ahead = seconds.iter().copied().fold(0.0, f64::max);
            let want = seconds.map(|t| (ahead + budget / 3.0 - t).max(0.0));
            let total: f64 = want.iter().sum();
            let slices = want.map(|w| {
                if total > 0.0 {
                    w * budget / total
                } else {
                    budget / 3.0
                }
            });
            let work = |row: f64, slice: f64| {
                let pass = row * height_f;
                if pass <= slice {
                    RunWork::Passes(fit(slice, pass, f64::from(MAX_PASSES)))
                } else {
                    RunWork::Rows(fit(slice, row, height_f))
                }
            };
            [
                work(rows[0], slices[0]),
                work(rows[1], slices[1]),
                work(rows[2], slices[2]),
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    /// Frames every `interval` seconds, each with `gpu` seconds of GPU work.
    fn settle(interval: f64, gpu: f64) -> FrameBudget {
        let mut budget = FrameBudget::default();
        let mut now = Instant::now();
        for _ in 0..100 {
            budget.begin_frame(now);
            budget.gpu_spent(gpu);
            now += Duration::from_secs_f64(interval);
        }
        budget
    }

    #[test]
    fn a_fast_ui_leaves_the_gpu_most_of_the_frame() {
        // A real GPU: 16 ms frames (the repaint cap), 1 ms of compute.
        let b = settle(0.016, 0.001);
        let ui = b.ui_seconds().expect("measured");
        assert!((ui - 0.015).abs() < 1e-9, "{ui}");
        assert!((b.gpu_budget() - (TARGET_FRAME_S - 0.015)).abs() < 1e-9);
    }

    #[test]
    fn a_slow_ui_leaves_what_the_target_allows() {
        // lavapipe: 30 ms frames of which 5 ms compute: the UI alone takes 25 ms.
        let b = settle(0.030, 0.005);
        assert!((b.gpu_budget() - (TARGET_FRAME_S - 0.025)).abs() < 1e-9);
        // A heavier UI leaves the minimum share.
        let b = settle(0.033, 0.005);
        assert_eq!(b.gpu_budget(), MIN_GPU_SHARE_S);
    }

    #[test]
    fn a_ui_over_the_target_still_gets_images_and_idle_gaps_are_capped() {
        let b = settle(0.050, 0.0);
        assert_eq!(b.gpu_budget(), MIN_GPU_SHARE_S);
        // A paused window (seconds between frames) counts as 0.1 s, not as its idle time.
        let b = settle(5.0, 0.0);
        assert!((b.ui_seconds().expect("measured") - MAX_INTERVAL_S).abs() < 1e-12);
        // Before two frames nothing is known: the whole target is the GPU's.
        assert_eq!(FrameBudget::default().gpu_budget(), TARGET_FRAME_S);
    }

    const H: u32 = 512;

    #[test]
    fn unknown_costs_start_with_a_few_rows() {
        let work = plan(
            0.01,
            [Some(1e-6), None, Some(1e-6)],
            H,
            BudgetMode::EqualSamples,
            4,
            [0.0; 3],
        );
        assert_eq!(work, [RunWork::Rows(FIRST_ROWS); 3]);
    }

    #[test]
    fn equal_samples_runs_whole_passes_when_they_fit() {
        // 1 µs per row and run: a pass of the three runs is 1.5 ms.
        let rows = [Some(1e-6); 3];
        let work = plan(0.010, rows, H, BudgetMode::EqualSamples, 4, [0.0; 3]);
        assert_eq!(work, [RunWork::Passes(4); 3]);
        // A budget for two passes only: two, not the four asked for.
        let work = plan(0.0035, rows, H, BudgetMode::EqualSamples, 4, [0.0; 3]);
        assert_eq!(work, [RunWork::Passes(2); 3]);
    }

    #[test]
    fn equal_samples_splits_a_costly_pass_into_rows_alike_for_every_run() {
        // The million-light case: the tree run costs 0.18 ms per row, a pass 94 ms.
        let rows = [Some(18e-6), Some(21e-6), Some(180e-6)];
        let work = plan(0.005, rows, H, BudgetMode::EqualSamples, 1, [0.0; 3]);
        // ⌊5 ms / 219 µs⌋ = 22 rows of every run: they stay at equal samples.
        assert_eq!(work, [RunWork::Rows(22); 3]);
        // Even a tiny budget advances by a row.
        let work = plan(1e-6, rows, H, BudgetMode::EqualSamples, 1, [0.0; 3]);
        assert_eq!(work, [RunWork::Rows(1); 3]);
    }

    #[test]
    fn equal_time_gives_each_run_a_third_of_the_budget() {
        // 12 ms budget, 4 ms per run. SchemeRun 0: 1 µs per row, a 0.512 ms pass: 7 passes;
        // run 1 four times as costly: 1 pass; run 2: 50 µs per row: 80 rows.
        let rows = [Some(1e-6), Some(4e-6), Some(50e-6)];
        let work = plan(0.012, rows, H, BudgetMode::EqualTime, 1, [0.0; 3]);
        assert_eq!(
            work,
            [RunWork::Passes(7), RunWork::Passes(1), RunWork::Rows(80)]
        );
        // Very cheap runs are capped.
        let work = plan(1.0, [Some(1e-12); 3], H, BudgetMode::EqualTime, 1, [0.0; 3]);
        assert_eq!(work, [RunWork::Passes(MAX_PASSES); 3]);
    }

    #[test]
    fn equal_time_keeps_the_totals_equal_over_the_run() {
        // SchemeRun 0's pass takes 0.6 of a third of the budget (one pass a frame would give it
        // 60 % of the others' time), run 1's 1.5 thirds (never a whole pass: rows), run 2
        // is cheap. Over many frames the totals stay within one frame's budget of each other.
        let budget = 0.012;
        let third = budget / 3.0;
        let row_seconds = [0.6 * third, 1.5 * third, 0.01 * third].map(|p| p / f64::from(H));
        let mut totals = [0.0; 3];
        for _ in 0..500 {
            let work = plan(
                budget,
                row_seconds.map(Some),
                H,
                BudgetMode::EqualTime,
                1,
                totals,
            );
            for (l, w) in work.iter().enumerate() {
                totals[l] += match w {
                    RunWork::Passes(p) => f64::from(*p) * row_seconds[l] * f64::from(H),
                    RunWork::Rows(r) => f64::from(*r) * row_seconds[l],
                };
            }
        }
        let most = totals.iter().copied().fold(f64::MIN, f64::max);
        let least = totals.iter().copied().fold(f64::MAX, f64::min);
        assert!(most - least <= budget, "{totals:?}");
        // Whole passes no longer than the slice fill at least half of it (`⌊s/p⌋·p ≥ s/2`), and
        // rows lose less than a row: the runs, kept equal, use at least half the budget.
        assert!(
            least >= 0.5 * 500.0 * third,
            "{totals:?}: the budget is used"
        );
    }
}
