//! The scene model: a receiving plane and point lights, and for the lights that have them a
//! spot cone or a range.
//!
//! A point light is a position and a power `Φ`. The receiver is the plane `z = 0` with
//! normal `+z`, seen through a rectangle split into pixels. The irradiance at `x` from
//! light `i` at distance `r` is
//!
//! `E_i(x) = Φ_i/(4π) · max(0, cos θ)/r² = Φ_i · G_i(x)`, with `G_i(x) = max(0, z_i)/(4π r³)`,
//!
//! since `cos θ = z_i / r` for the normal `+z`. A spot light or a light with a range
//! multiplies this by its emission factor `S_i(x)` ([`Emission`]); a scene without any keeps
//! no emission data at all ([`Scene::emission`] is `None`), and [`light_term`] is the one
//! definition of `G_i(x)·S_i(x)` every consumer evaluates.
//!
//! Scenes come from JSON files ([`Scene::from_json_str`], [`Scene::load`]; the format is
//! described in the `json` module docs), from the built-in presets ([`Scene::preset`],
//! [`PRESET_NAMES`]) or from explicit parts ([`Scene::from_parts`]); large scenes are
//! generated from a seed by a [`Generator`].

mod emission;
mod emission_shape;
mod error;
mod generator;
mod geometry;
mod import;
mod json;
mod presets;

pub use emission::{Emission, EmissionError, Spot};
pub use emission_shape::EmissionShape;
pub(crate) use emission_shape::{range_window, spot_falloff};
pub use error::SceneError;
pub use generator::{Dominant, Generator, MAX_LIGHTS, Placement, PowerDistribution};
pub(crate) use geometry::light_term_culled;
pub(crate) use geometry::{distance_squared, four_pi_r_cubed, four_pi_r2_times};
pub use geometry::{geometry_term, light_term, pixel_center};
pub use import::{
    IMPORT_PLANE_PIXELS, ImportReport, LoadOptions, Loaded, SceneFormat, SkippedLight,
    footprint_plane, load, load_bytes,
};
pub use json::{MAX_PIXELS, MAX_PLANE_SIDE};
pub use presets::PRESET_NAMES;

use std::sync::Arc;

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

    /// The point of the plane at pixel coordinates `pixels` (`x` from the left edge, `y`
    /// down from the top row, in pixels; `(px + 0.5, py + 0.5)` is the centre of pixel
    /// `(px, py)`, [`pixel_center`]).
    #[inline]
    pub fn point_at(&self, pixels: DVec2) -> DVec2 {
        let f = pixels / DVec2::new(f64::from(self.width), f64::from(self.height));
        DVec2::new(
            self.min.x + f.x * (self.max.x - self.min.x),
            self.max.y - f.y * (self.max.y - self.min.y),
        )
    }

    /// The pixel `[px, py]` whose cell holds `point_on_plane`, or the nearest edge pixel when
    /// it lies outside (the pixels form a regular grid, so the nearest one is nearest along
    /// each axis).
    pub fn pixel_at(&self, point_on_plane: DVec2) -> [u32; 2] {
        let cell = |offset: f64, extent: f64, count: u32| {
            // `as u32` truncates toward 0 and saturates (NaN to 0): for `v ≥ 0` that is the
            // floor, and a `v < 0` (a point before the first pixel) gives 0 as the floor's
            // saturation would; the clamp to the last pixel remains.
            ((offset / extent * f64::from(count)) as u32).min(count.saturating_sub(1))
        };
        [
            cell(
                point_on_plane.x - self.min.x,
                self.max.x - self.min.x,
                self.width,
            ),
            cell(
                self.max.y - point_on_plane.y,
                self.max.y - self.min.y,
                self.height,
            ),
        ]
    }

    /// The pixel centre ([`pixel_center`]) nearest to `point_on_plane`: that of
    /// [`ReceiverPlane::pixel_at`].
    pub fn nearest_pixel_center(&self, point_on_plane: DVec2) -> DVec2 {
        let [px, py] = self.pixel_at(point_on_plane);
        pixel_center(self, px, py)
    }
}

/// A scene: the receiver and the lights, as positions beside validated powers.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// A short name, shown in the app and in outputs.
    pub name: String,
    /// The receiving plane and its pixels.
    pub plane: ReceiverPlane,
    /// Light positions `(x, y, z)` in the world (the plane is `z = 0`), one per power,
    /// shared: a clone of the scene (or an editor's copy of its lights) costs no copy until
    /// one of them writes (`Arc::make_mut`).
    pub positions: Arc<[DVec3]>,
    /// Light powers `Φ_i`, validated.
    pub powers: LightPowers,
    /// Each light's emission profile (spot cone, range), one per light, only when some
    /// light of the scene has one: `None` for a scene of point lights, which pays nothing.
    pub emission: Option<Vec<Emission>>,
    /// Each light's name, one per light, only when the source named its lights.
    pub names: Option<Vec<String>>,
}

impl Scene {
    /// A scene of point lights: `positions[i]` emits `powers[i]`, no emission profiles
    /// (spots, ranges) and no light names. The parts are taken as given (`powers` is
    /// validated already; the positions are not checked): give one position per power.
    /// [`Scene::from_parts`] validates raw positions and powers with a scene file's checks.
    ///
    /// The optional parts are added with [`Scene::with_emission`] and [`Scene::with_names`]:
    /// ```
    /// use glam::{dvec2, dvec3};
    /// use lightpick_core::LightPowers;
    /// use lightpick_core::scene::{ReceiverPlane, Scene};
    ///
    /// let plane = ReceiverPlane {
    ///     min: dvec2(-1.0, -1.0),
    ///     max: dvec2(1.0, 1.0),
    ///     width: 8,
    ///     height: 8,
    /// };
    /// let positions = vec![dvec3(0.0, 0.0, 1.0), dvec3(0.5, 0.0, 1.0)];
    /// let powers = LightPowers::new(vec![2.0, 5.0])?;
    /// let scene = Scene::new("two", plane, positions, powers)
    ///     .with_names(vec!["key".into(), "fill".into()]);
    /// assert_eq!(scene.light_count(), 2);
    /// assert_eq!(scene.name_of(1), Some("fill"));
    /// assert!(scene.emission.is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(
        name: impl Into<String>,
        plane: ReceiverPlane,
        positions: impl Into<Arc<[DVec3]>>,
        powers: LightPowers,
    ) -> Scene {
        Scene {
            name: name.into(),
            plane,
            positions: positions.into(),
            powers,
            emission: None,
            names: None,
        }
    }

    /// The scene with each light's emission profile (spot cone, range): `emission[i]` is
    /// light `i`'s, one per light ([`Scene::emission`]).
    #[must_use]
    pub fn with_emission(self, emission: Vec<Emission>) -> Scene {
        Scene {
            emission: Some(emission),
            ..self
        }
    }

    /// The scene with each light's name: `names[i]` is light `i`'s, one per light (an empty
    /// name counts as none, [`Scene::name_of`]).
    #[must_use]
    pub fn with_names(self, names: Vec<String>) -> Scene {
        Scene {
            names: Some(names),
            ..self
        }
    }

    /// Number of lights.
    pub fn light_count(&self) -> usize {
        self.positions.len()
    }

    /// The exact irradiance `E(x) = Σ_i Φ_i · G_i(x)·S_i(x)` at a point of the plane.
    pub fn exact_irradiance(&self, point_on_plane: DVec2) -> f64 {
        self.powers
            .as_slice()
            .iter()
            .enumerate()
            .map(|(i, &phi)| phi * self.light_term(i, point_on_plane))
            .sum()
    }

    /// `w_i·G_i(x)·S_i(x)` of every light at `point_on_plane`, for one weight per light: with
    /// the pmf `p` ([`LightPowers::pmf`]) the normalized contributions `c_i(x)`, with the
    /// powers `Φ` the contributions `f_i(x)`.
    ///
    /// # Panics
    /// If `weights` holds fewer values than the scene has lights.
    pub fn weighted_terms(&self, weights: &[f64], point_on_plane: DVec2) -> Vec<f64> {
        weights
            .iter()
            .enumerate()
            .take(self.light_count())
            .map(|(i, &w)| w * self.light_term(i, point_on_plane))
            .collect()
    }

    /// `s_i(x) = c_i(x) / Σ_j c_j(x)`: each light's share of the irradiance at
    /// `point_on_plane`, the ideal pick's pmf there (all 0 where no light reaches it).
    pub fn irradiance_shares(&self, point_on_plane: DVec2) -> Vec<f64> {
        let c = self.weighted_terms(&self.powers.pmf(), point_on_plane);
        let total: f64 = c.iter().sum();
        c.iter()
            .map(|&v| if total > 0.0 { v / total } else { 0.0 })
            .collect()
    }

    /// Light `i`'s emission profile, when the scene has any ([`Scene::emission`]).
    #[inline]
    pub fn emission_of(&self, i: usize) -> Option<&Emission> {
        self.emission.as_ref().map(|e| &e[i])
    }

    /// `G_i(x)·S_i(x)`, light `i`'s irradiance per unit power at `point_on_plane`
    /// ([`light_term`]).
    #[inline]
    pub fn light_term(&self, i: usize, point_on_plane: DVec2) -> f64 {
        light_term(
            self.positions[i],
            self.emission_of(i).map(Emission::shape),
            point_on_plane,
        )
    }

    /// The binary exponent `s` of the renderers' accumulation unit: the largest irradiance
    /// per unit power any light can deliver at a pixel centre, `max_i g_i·G_i(c_i)` over
    /// the lights above the plane (`c_i` the pixel centre nearest to light `i`,
    /// [`ReceiverPlane::nearest_pixel_center`]; `g_i` a spot's gain, 1 otherwise), is
    /// `≈ 2^s`. Estimates are summed as `ê·2^-s` so their squares stay in range for a light
    /// `10^-150` above a pixel centre as for one at height 1, and for one `10^-150` above a
    /// point between the centres too (where `1/(4π z²)` would be `10^298` times too large a
    /// unit, and every `ê'²` would underflow to a zero variance). It depends on positions,
    /// cones and the pixel grid only: scaling the powers leaves it unchanged. Clamped to
    /// `[-1000, 1000]`; 0 for a scene with no light above the plane. A light whose bound
    /// exceeds `f64` (`z ≲ 10^-154` above a centre) is left out: the irradiance under it
    /// does not fit `f64` in any unit, and the reference reports it
    /// ([`crate::render::Reference::overflow`]).
    pub fn irradiance_shift(&self) -> i32 {
        let mut max = 0.0f64;
        for (i, &p) in self.positions.iter().enumerate() {
            if p.z <= 0.0 {
                continue;
            }
            let gain = self.emission_of(i).map_or(1.0, |e| e.gain());
            // `g·G ≤ g/(4π z²)` anywhere (two divisions, without overflow for tiny z): the
            // light's own term, at its nearest centre, only where that bound exceeds the
            // largest so far — a few lights of a large scene, not all of them.
            let bound = (gain / p.z) / (4.0 * std::f64::consts::PI * p.z);
            if bound > max {
                // G finite down to z ≈ 10^-154 right above the centre (geometry_term).
                let g = gain * geometry_term(p, self.plane.nearest_pixel_center(p.truncate()));
                if g.is_finite() && g > max {
                    max = g;
                }
            }
        }
        if max > 0.0 {
            crate::Scaled::from_f64(max).exponent().clamp(-1000, 1000)
        } else {
            0
        }
    }

    /// Whether `other` has this scene's lights in the same places with the same emission
    /// profiles (cones and ranges), and, when the scene has emission profiles, the same
    /// receiver rectangle (`plane.min`, `plane.max`: a light tree over spots maps its lanes
    /// over it); its powers, names, name and pixel grid may differ, and so may its plane when
    /// neither scene has profiles. What a power edit keeps, so the light tree can be refitted
    /// instead of rebuilt. `O(N)`.
    pub fn same_geometry(&self, other: &Scene) -> bool {
        (Arc::ptr_eq(&self.positions, &other.positions) || self.positions == other.positions)
            && self.emission == other.emission
            // A light tree over spots maps its lanes over the receiver's rectangle.
            && (self.emission.is_none()
                || (self.plane.min == other.plane.min && self.plane.max == other.plane.max))
    }

    /// Heap bytes the scene holds, by part and by capacity: its positions (24 bytes per
    /// light), its powers (8), its emission profiles (only a scene with spots or ranges has
    /// any) and its names (each `String` and its text, only when the source named its
    /// lights).
    pub fn heap_bytes_by_part(&self) -> [(&'static str, usize); 4] {
        let names = self.names.as_ref().map_or(0, |names| {
            names.capacity() * std::mem::size_of::<String>()
                + names.iter().map(String::capacity).sum::<usize>()
        });
        [
            (
                "positions",
                std::mem::size_of_val::<[DVec3]>(&self.positions),
            ),
            ("powers", self.powers.heap_bytes()),
            (
                "emission profiles",
                self.emission
                    .as_ref()
                    .map_or(0, |e| e.capacity() * std::mem::size_of::<Emission>()),
            ),
            ("names", names),
        ]
    }

    /// Light `i`'s name, when the scene's source named it.
    pub fn name_of(&self, i: usize) -> Option<&str> {
        self.names
            .as_ref()
            .and_then(|n| n.get(i))
            .map(String::as_str)
            .filter(|n| !n.is_empty())
    }

    /// How many lights are spots (0 for a scene without emission data).
    pub fn spot_count(&self) -> usize {
        self.emission
            .as_ref()
            .map_or(0, |e| e.iter().filter(|e| e.spot().is_some()).count())
    }

    /// The scene with only the lights at `indices` (in that order), with their emission
    /// profiles and names; the plane unchanged. Errors as [`Scene::from_parts`].
    pub fn subset(&self, indices: &[usize]) -> Result<Scene, SceneError> {
        let mut scene = Scene::from_parts(
            self.name.clone(),
            self.plane.clone(),
            indices.iter().map(|&i| self.positions[i]).collect(),
            indices.iter().map(|&i| self.powers.as_slice()[i]).collect(),
        )?;
        scene.emission = self
            .emission
            .as_ref()
            .map(|e| indices.iter().map(|&i| e[i]).collect());
        scene.names = self
            .names
            .as_ref()
            .map(|n| indices.iter().map(|&i| n[i].clone()).collect());
        Ok(scene)
    }
}
