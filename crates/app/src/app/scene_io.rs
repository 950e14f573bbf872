//! The app's access to scenes other than opened files: presets, the session's JSON, saving a
//! scene, and scenes generated from a count with random powers of a chosen [`PowerShape`].
//! (An opened file of any format goes through the core's one loader in `files.rs`.)
//!
//! Every scene format question is answered by `lightpick_core::scene`; this module only
//! adapts its errors to one-line messages for the status bar.

use std::path::Path;

use glam::{DVec3, dvec2, dvec3};
use lightpick_core::Rng;
use lightpick_core::scene::{ReceiverPlane, Scene};

/// The preset names, in menu order.
pub fn preset_names() -> Vec<&'static str> {
    lightpick_core::scene::PRESET_NAMES.to_vec()
}

/// The preset `name`, or a message saying why it could not be made.
pub fn preset(name: &str) -> Result<Scene, String> {
    Scene::preset(name).map_err(|e| format!("preset '{name}': {e}"))
}

/// The seed scene (powers 2, 5, 20): the app's first scene and its fallback.
pub fn seed_scene() -> Scene {
    preset("seed").unwrap_or_else(|_| fallback_seed_scene())
}

/// A seed scene made here, used only if the preset cannot be built.
fn fallback_seed_scene() -> Scene {
    Scene::new(
        "seed",
        ReceiverPlane {
            min: dvec2(-2.0, -2.0),
            max: dvec2(2.0, 2.0),
            width: 256,
            height: 256,
        },
        vec![
            dvec3(-1.2, 0.8, 0.8),
            dvec3(1.0, 1.0, 1.0),
            dvec3(0.0, -1.0, 1.5),
        ],
        lightpick_core::SeedExample::powers(),
    )
}

/// Parses scene JSON, or says (in one line) why the text is not a scene.
pub fn from_json_str(text: &str) -> Result<Scene, String> {
    Scene::from_json_str(text).map_err(|e| e.to_string())
}

/// The scene as JSON text.
pub fn to_json(scene: &Scene) -> String {
    scene.to_json()
}

/// Writes the scene as JSON to `path`.
pub fn save(path: &Path, scene: &Scene) -> Result<(), String> {
    let text = to_json(scene);
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The shape of the random powers that the lights panel's Randomize and Generate draw: a
/// fixed unit-scale density, times a scale ([`random_powers`]). Not the core's
/// `lightpick_core::scene::PowerDistribution`, the parameterized recipe of a scene file's
/// generator (another density family, drawn from another stream).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PowerShape {
    /// Uniform on `[0, 1)` times the scale.
    Uniform,
    /// Exponential with mean 1, times the scale.
    Exponential,
    /// Pareto with shape `α = 1.5` (heavy tail), times the scale.
    Pareto,
    /// Log-normal `exp(2·Z)` (powers spanning decades), times the scale.
    LogNormal,
}

impl PowerShape {
    /// Every distribution, in menu order.
    pub const ALL: [PowerShape; 4] = [
        PowerShape::Uniform,
        PowerShape::Exponential,
        PowerShape::Pareto,
        PowerShape::LogNormal,
    ];

    /// The menu label.
    pub fn label(self) -> &'static str {
        match self {
            PowerShape::Uniform => "uniform [0, 1)",
            PowerShape::Exponential => "exponential (mean 1)",
            PowerShape::Pareto => "Pareto (α = 1.5)",
            PowerShape::LogNormal => "log-normal (σ = 2)",
        }
    }

    /// One power from two independent uniforms in `[0, 1)` (inverse-CDF and Box–Muller
    /// transforms, so the shared counter-based RNG drives everything).
    pub fn draw(self, u1: f64, u2: f64) -> f64 {
        match self {
            PowerShape::Uniform => u1,
            PowerShape::Exponential => -(1.0 - u1).ln(),
            PowerShape::Pareto => (1.0 - u1).powf(-1.0 / 1.5),
            PowerShape::LogNormal => {
                let r = (-2.0 * (1.0 - u1).ln()).sqrt();
                (2.0 * r * (std::f64::consts::TAU * u2).cos()).exp()
            }
        }
    }
}

/// `count` powers drawn from `dist` with generator `seed`, scaled by `scale`.
pub fn random_powers(count: usize, dist: PowerShape, scale: f64, seed: u64) -> Vec<f64> {
    (0..count)
        .map(|i| {
            let mut rng = Rng::new(seed, i as u64);
            scale * dist.draw(rng.next_unit(), rng.next_unit())
        })
        .collect()
}

/// `count` light positions scattered above `plane` (heights between 5% and 40% of the
/// plane's extent), deterministic in `seed`.
pub fn random_positions(count: usize, plane: &ReceiverPlane, seed: u64) -> Vec<DVec3> {
    let extent = (plane.max - plane.min).max_element();
    (0..count)
        .map(|i| {
            let mut rng = Rng::new(seed ^ 0x05ee_d0f1_1167, i as u64);
            let x = plane.min.x + rng.next_unit() * (plane.max.x - plane.min.x);
            let y = plane.min.y + rng.next_unit() * (plane.max.y - plane.min.y);
            let z = extent * (0.05 + 0.35 * rng.next_unit());
            dvec3(x, y, z)
        })
        .collect()
}
