//! The scene model: a receiving plane and point lights, nothing more.
//!
//! A point light is a position and a power `Φ`. The receiver is the plane `z = 0` with
//! normal `+z`, seen through a rectangle split into pixels. The irradiance at `x` from
//! light `i` at distance `r` is
//!
//! `E_i(x) = Φ_i/(4π) · max(0, cos θ)/r² = Φ_i · G_i(x)`, with `G_i(x) = max(0, z_i)/(4π r³)`,
//!
//! since `cos θ = z_i / r` for the normal `+z`.
//!
//! Scenes come from JSON files ([`Scene::from_json_str`], [`Scene::load`]; the format is
//! described in the `json` module docs), from the built-in presets ([`Scene::preset`],
//! [`PRESET_NAMES`]) or from explicit parts ([`Scene::from_parts`]); large scenes are
//! generated from a seed by a [`Generator`].

mod error;
mod generator;
mod geometry;
mod json;
mod presets;

pub use error::SceneError;
pub use generator::{Dominant, Generator, MAX_LIGHTS, Placement, PowerDistribution};
pub use geometry::{geometry_term, pixel_center};
pub use json::{MAX_PIXELS, MAX_PLANE_SIDE};
pub use presets::PRESET_NAMES;

use glam::{DVec2, DVec3};

use crate::powers::LightPowers;

/// The receiving rectangle on `z = 0` and its pixel grid. Pixel `(0, 0)` is the top-left
/// corner: `x` grows to the right from `min.x`, `y` grows upwards from `min.y`, so row 0 is
/// at `y = max.y`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReceiverPlane {
    /// Lower-left corner `(x, y)` on the plane.
    pub min: DVec2,
    /// Upper-right corner `(x, y)` on the plane.
    pub max: DVec2,
    /// Pixel columns.
    pub width: u32,
    /// Pixel rows.
    pub height: u32,
}

impl ReceiverPlane {
    /// Number of pixels `width · height`.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }
}

/// A scene: the receiver and the lights, as positions beside validated powers.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// A short name, shown in the app and in outputs.
    pub name: String,
    /// The receiving plane and its pixels.
    pub plane: ReceiverPlane,
    /// Light positions `(x, y, z)` in the world (the plane is `z = 0`), one per power.
    pub positions: Vec<DVec3>,
    /// Light powers `Φ_i`, validated.
    pub powers: LightPowers,
}

impl Scene {
    /// Number of lights.
    pub fn light_count(&self) -> usize {
        self.positions.len()
    }

    /// The exact irradiance `E(x) = Σ_i Φ_i · G_i(x)` at a point of the plane.
    pub fn exact_irradiance(&self, point_on_plane: DVec2) -> f64 {
        self.positions
            .iter()
            .zip(self.powers.as_slice())
            .map(|(&light_in_world, &phi)| phi * geometry_term(light_in_world, point_on_plane))
            .sum()
    }
}
