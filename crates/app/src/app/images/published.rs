//! What the image renderers are asked and what they show: the settings both the CPU engine
//! and the GPU runs render with ([`EngineConfig`]), and the frame they publish for the
//! panels ([`Published`]: one [`SchemeImage`] per scheme, with its numbers and convergence
//! series), and what they hold beside the scene ([`RendererBytes`]).

use lightpick_core::render::efficiency_of;

use crate::app::state::settings::BudgetMode;

/// What the engine renders with, as the UI set it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EngineConfig {
    /// Samples per pixel per frame (equal-samples mode).
    pub spp_per_frame: u32,
    /// Equal samples or equal time.
    pub budget: BudgetMode,
    /// Tonemap exposure.
    pub exposure: f64,
    /// The seed of the pixel streams.
    pub seed: u64,
    /// Whether frames accumulate continuously.
    pub running: bool,
}

/// One point of a convergence curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvergencePoint {
    /// Samples per pixel so far.
    pub spp: u32,
    /// Render seconds so far.
    pub seconds: f64,
    /// RMSE against the reference.
    pub rmse: f64,
}

/// One scheme's image and numbers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SchemeImage {
    /// Tonemapped RGBA8, row-major.
    pub rgba: Vec<u8>,
    /// Error map RGBA8 (|estimate − reference|), when a reference exists.
    pub error_rgba: Option<Vec<u8>>,
    /// Samples per pixel so far (complete passes).
    pub spp: u32,
    /// Rows of the next pass already rendered, as a fraction of the image, while a costly
    /// pass is split over frames (GPU images); 0 otherwise.
    pub pass_progress: f32,
    /// Render seconds so far.
    pub seconds: f64,
    /// Seconds of the last frame.
    pub last_frame_seconds: f64,
    /// RMSE against the reference.
    pub rmse: Option<f64>,
    /// Mean per-sample variance over the pixels `V`, in irradiance², whatever its
    /// magnitude ([`lightpick_core::render::mean_variance_scaled`]).
    pub variance: lightpick_core::Scaled,
    /// `V̂ = V/Φ_total²`, the same in units of the total power (for the efficiency
    /// `1/(V̂·T)`, [`lightpick_core::render::normalized_variance_per_sample`]), whatever its
    /// magnitude.
    pub normalized_variance: lightpick_core::Scaled,
    /// Convergence curve.
    pub series: Vec<ConvergencePoint>,
}

impl SchemeImage {
    /// Seconds per pixel sample `T`.
    pub fn seconds_per_sample(&self, pixels: usize) -> f64 {
        let samples = f64::from(self.spp) * pixels as f64;
        if samples > 0.0 {
            self.seconds / samples
        } else {
            0.0
        }
    }

    /// Efficiency `1/(V̂·T)` (normalized variance per sample times time per sample), the
    /// figure of [`lightpick_core::render::efficiency`] and `lightpick bench`, whatever its
    /// magnitude; `None` before a variance and a time are measured.
    pub fn efficiency(&self, pixels: usize) -> Option<lightpick_core::Scaled> {
        let t = self.seconds_per_sample(pixels);
        (self.normalized_variance > lightpick_core::Scaled::ZERO && t > 0.0)
            .then(|| efficiency_of(self.normalized_variance, t))
    }
}

/// The latest frame the engine published.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Published {
    /// The scene generation it renders.
    pub generation: u64,
    /// Counts published frames (the UI re-uploads textures when it changes).
    pub frame: u64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Uniform light selection.
    pub uniform: SchemeImage,
    /// Power-proportional selection (alias table).
    pub power: SchemeImage,
    /// Contribution-aware selection (exact for few lights, light tree for many).
    pub spatial: SchemeImage,
    /// Lights in the scene rendered (whether the spatial run is the exact pick).
    pub light_count: usize,
    /// The tonemapped exact reference.
    pub reference_rgba: Option<Vec<u8>>,
    /// Why there is no reference, when there is none.
    pub reference_note: Option<String>,
    /// Where it was rendered ("CPU (rayon, 2 threads)").
    pub device_note: String,
    /// What each run's time `T` measures, in words (for the figures' hover text).
    pub time_source: String,
}

impl Published {
    /// The mean samples per pixel of the three images, with the fraction of a pass in
    /// progress (row bands).
    pub fn mean_spp(&self) -> f64 {
        [&self.uniform, &self.power, &self.spatial]
            .iter()
            .map(|s| f64::from(s.spp) + f64::from(s.pass_progress))
            .sum::<f64>()
            / 3.0
    }

    /// Whether the spatial image is the exact contribution pick (few lights): zero variance
    /// by construction, so its measured variance and RMSE are rounding only.
    pub fn spatial_is_exact(&self) -> bool {
        self.light_count > 0 && lightpick_core::spatial::uses_exact_pick(self.light_count)
    }
}

/// What a scene's renderers hold beyond the scene, its table and its spatial sampler (which
/// the app's `Built` owns and counts), in heap bytes (on the GPU: device bytes, which a
/// software device such as lavapipe keeps in the process).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RendererBytes {
    /// Per light: what the runs hold beyond the scene's arrays (CPU: emission profiles'
    /// copies; GPU: uploaded lights and trees), each counted once where runs share them.
    pub lights: usize,
    /// Per pixel: the runs' sums and outputs and the exact reference.
    pub pixels: usize,
}
