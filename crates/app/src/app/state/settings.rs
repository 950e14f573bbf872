//! The settings kept between sessions (eframe persistence): the run controls, where and how
//! the images render, the sliders, the generator's shape of random powers, the theme and
//! which windows are open; and the two a new scene sets from itself ([`auto_exposure`],
//! the slider range through [`nice_ceiling`]).

use lightpick_core::scene::Scene;

use crate::app::generated::PowerShape;

/// Where the progressive images are rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Device {
    /// The GPU when it is a hardware one; on a software rasterizer (lavapipe) whichever of
    /// the two renders the images faster, measured ([`crate::app::images::renderer_choice`]).
    Auto,
    /// wgpu compute on eframe's own device (falls back to the CPU without one).
    Gpu,
    /// The CPU renderer (rayon).
    Cpu,
}

/// How the two images share the work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BudgetMode {
    /// Every scheme takes the same samples per pixel per frame.
    EqualSamples,
    /// Every scheme gets the same compute time per frame.
    EqualTime,
}

/// The light-power slider scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SliderScale {
    /// Linear from 0 to the slider maximum.
    Linear,
    /// Logarithmic over six decades below the slider maximum.
    Log,
}

/// Settings kept between sessions (eframe persistence).
#[allow(clippy::struct_excessive_bools)] // Independent on/off switches of the UI, persisted as such.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Samples per pixel each scheme adds per frame (equal-samples mode).
    pub spp_per_frame: u32,
    /// The seed of every random stream (images, histograms, generated scenes).
    pub seed: u64,
    /// Whether sampling and accumulation are paused.
    pub paused: bool,
    /// The preferred render device.
    pub device: Device,
    /// Tonemap exposure (irradiance multiplier).
    pub exposure: f64,
    /// Equal samples or equal time.
    pub budget: BudgetMode,
    /// Show the exact reference image.
    pub show_reference: bool,
    /// Show the error maps under the images.
    pub show_error: bool,
    /// Show each scheme's per-pixel variance map of one sample under the images.
    pub show_variance: bool,
    /// Power slider scale.
    pub slider_scale: SliderScale,
    /// Upper end of the power sliders.
    pub slider_max: f64,
    /// Light picks per frame for the histograms (each scheme).
    pub picks_per_frame: u32,
    /// Distribution for "randomize" and "generate".
    pub distribution: PowerShape,
    /// How many lights "generate" makes.
    pub generate_count: usize,
    /// Dark theme (else light).
    pub dark: bool,
    /// Show the speed-against-accuracy window.
    pub show_trade: bool,
    /// Show the precision window.
    pub show_precision: bool,
    /// Show the classroom walkthrough window.
    pub show_walkthrough: bool,
    /// Show the construction stepper window.
    pub show_stepper: bool,
    /// Show the keyboard shortcuts overlay (F1 or ?).
    pub show_shortcuts: bool,
    /// The folder of the last file opened or saved: where File → Open starts.
    pub last_folder: Option<std::path::PathBuf>,
    /// The size of an exported figure, width and height in pixels (File → Export figure).
    pub figure_size: [u32; 2],
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            spp_per_frame: 1,
            seed: 1,
            paused: false,
            device: Device::Auto,
            exposure: 1.0,
            budget: BudgetMode::EqualSamples,
            show_reference: true,
            show_error: true,
            show_variance: false,
            slider_scale: SliderScale::Linear,
            slider_max: 40.0,
            picks_per_frame: 200,
            distribution: PowerShape::Exponential,
            generate_count: 16,
            dark: true,
            show_trade: false,
            show_shortcuts: false,
            last_folder: None,
            figure_size: [1600, 1000],
            show_precision: false,
            show_walkthrough: false,
            show_stepper: false,
        }
    }
}

/// The smallest of 1, 2, 5 × 10^k at or above `x` (at least 1e-300).
pub fn nice_ceiling(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let decade = 10f64.powf(x.log10().floor());
    for m in [1.0, 2.0, 5.0, 10.0] {
        if m * decade >= x {
            return m * decade;
        }
    }
    10.0 * decade
}

/// An exposure that maps the scene's mean irradiance to about 1 (Reinhard's mid-grey), from
/// the exact irradiance at 8×8 pixel centres (at most 4096 lights, scaled up for more).
pub fn auto_exposure(scene: &Scene) -> f64 {
    let n = scene.light_count();
    let stride = n.div_ceil(4096).max(1);
    let mut sum = 0.0;
    let mut count = 0.0;
    for gy in 0..8u32 {
        for gx in 0..8u32 {
            let px = (gx * scene.plane.width) / 8 + scene.plane.width / 16;
            let py = (gy * scene.plane.height) / 8 + scene.plane.height / 16;
            let x = lightpick_core::scene::pixel_center(&scene.plane, px, py);
            let e: f64 = (0..n)
                .step_by(stride)
                .map(|i| scene.powers.as_slice()[i] * scene.light_term(i, x))
                .sum::<f64>()
                * stride as f64;
            sum += e;
            count += 1.0;
        }
    }
    let mean = sum / count;
    if mean.is_finite() && mean > 0.0 {
        1.0 / mean
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ceilings() {
        assert_eq!(nice_ceiling(40.0), 50.0);
        assert_eq!(nice_ceiling(3.0), 5.0);
        assert_eq!(nice_ceiling(1.0), 1.0);
    }
}
