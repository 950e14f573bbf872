//! How much GPU image work fits in a UI frame, so that the window keeps at least 30 frames
//! per second while the images render on the same device (on a software rasterizer such as
//! lavapipe, drawing egui and running the compute kernels share the same CPU cores).
//!
//! The UI's own cost `u` is measured as the interval between frames minus the GPU work done
//! in the previous one (an exponential moving average). The GPU work may take what the
//! target frame time `T` leaves, `b = max(T − u, b_min)`; a frame whose GPU work took `g`
//! is followed by `⌈g/b⌉ − 1` frames without any, so the GPU's average share per frame stays
//! within `b`. On a real GPU `g ≪ b` and the images advance every frame.

use std::time::Instant;

/// The frame time aimed at: 30 ms, a little under the 33 ms of 30 frames per second.
pub const TARGET_FRAME_S: f64 = 0.030;
/// The least GPU time per frame, on average, even when the UI alone exceeds the target (so
/// the images never stop).
pub const MIN_GPU_SHARE_S: f64 = 0.002;
/// The most frames skipped in a row (the images update at least this often).
pub const MAX_COOLDOWN: u32 = 15;
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

    /// Frames to skip after a frame whose GPU work took `gpu_seconds`: `⌈g/b⌉ − 1`, at most
    /// [`MAX_COOLDOWN`].
    pub fn cooldown_after(&self, gpu_seconds: f64) -> u32 {
        let frames = (gpu_seconds / self.gpu_budget()).ceil();
        (frames - 1.0).clamp(0.0, f64::from(MAX_COOLDOWN)) as u32
    }

    /// The measured UI seconds per frame, once known.
    pub fn ui_seconds(&self) -> Option<f64> {
        self.ui_seconds
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
    fn a_fast_ui_leaves_the_gpu_every_frame() {
        // A real GPU: 16 ms frames (the repaint cap), 1 ms of compute.
        let b = settle(0.016, 0.001);
        let ui = b.ui_seconds().expect("measured");
        assert!((ui - 0.015).abs() < 1e-9, "{ui}");
        assert_eq!(b.cooldown_after(0.001), 0);
    }

    #[test]
    fn a_slow_ui_spreads_the_gpu_work_over_frames() {
        // lavapipe: 33 ms frames of which 5.5 ms compute: the UI alone takes 27.5 ms, the
        // GPU may take 2.5 ms per frame, so 5.5 ms of work runs every third frame.
        let b = settle(0.033, 0.0055);
        assert!((b.gpu_budget() - 0.0025).abs() < 1e-9);
        assert_eq!(b.cooldown_after(0.0055), 2);
    }

    #[test]
    fn a_ui_over_the_target_still_gets_images_and_idle_gaps_are_capped() {
        let b = settle(0.050, 0.0);
        assert_eq!(b.gpu_budget(), MIN_GPU_SHARE_S);
        assert_eq!(b.cooldown_after(0.005), 2);
        assert_eq!(b.cooldown_after(10.0), MAX_COOLDOWN);
        // A paused window (seconds between frames) counts as 0.1 s, not as its idle time.
        let b = settle(5.0, 0.0);
        assert!((b.ui_seconds().expect("measured") - MAX_INTERVAL_S).abs() < 1e-12);
        // Before two frames nothing is known: the whole target is the GPU's.
        assert_eq!(FrameBudget::default().gpu_budget(), TARGET_FRAME_S);
    }
}
