//! The scene file format (JSON) and scene validation.
//!
//! ```json
//! {
//!   "name": "worked-example",
//!   "plane": { "min": [-2, -2], "max": [2, 2], "width": 256, "height": 256 },
//!   "lights": [
//!     { "position": [-1.1, 0.7, 0.45], "power": 2 },
//!     { "position": [0.9, 0.9, 0.7], "power": 5 }
//!   ]
//! }
//! ```
//!
//! or, instead of `lights`, a `generator` (see [`super::Generator`]):
//!
//! ```json
//! "generator": {
//!   "count": 10000, "seed": 7,
//!   "power": { "distribution": "pareto", "scale": 1, "shape": 1.2 },
//!   "zero_fraction": 0.5,
//!   "dominant": { "index": 0, "factor": 1e6 },
//!   "placement": { "min": [-2, -2, 0.1], "max": [2, 2, 1] }
//! }
//! ```
//!
//! A light may also carry a `name`, a `spot` cone and a `range` (all optional; a scene
//! without spots or ranges stores no emission data, see [`super::Emission`]):
//!
//! ```json
//! { "name": "Key", "position": [0, 0, 3], "power": 1200,
//!   "spot": { "direction": [0, 0, -1], "inner_cone": 0.2, "outer_cone": 0.5 },
//!   "range": 10 }
//! ```
//!
//! Angles are half-angles in radians, `0 ≤ inner_cone < outer_cone ≤ π/2` (defaults 0 and
//! π/4, as glTF's); `power` is the emitted flux whatever the cone.
//!
//! `name` is optional (default `untitled`); unknown fields are refused, so a misspelt
//! field name is an error rather than silently ignored.

use std::fmt::Write as _;
use std::path::Path;

use glam::{DVec2, DVec3};

use super::error::SceneError;
use super::generator::{Generator, MAX_LIGHTS};
use super::{Emission, ReceiverPlane, Scene, Spot};
use crate::powers::{LightPowers, PowersError};

/// The largest accepted `plane.width` and `plane.height`.
pub const MAX_PLANE_SIDE: u32 = 16_384;

/// The largest accepted pixel count `width · height` (`2^26`, e.g. 8192 × 8192): the
/// accumulator holds 16 bytes per pixel, and renderers key random streams by a 32-bit pixel
/// index.
pub const MAX_PIXELS: usize = 1 << 26;

/// The name given to a scene file without one.
const DEFAULT_NAME: &str = "untitled";

fn default_name() -> String {
    DEFAULT_NAME.to_owned()
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    #[serde(default = "default_name")]
    name: String,
    plane: PlaneFile,
    #[serde(default)]
    lights: Option<Vec<LightFile>>,
    #[serde(default)]
    generator: Option<Generator>,
}

/// The plane as written: sizes as `u64` so that too-large values get our range message.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct PlaneFile {
    min: [f64; 2],
    max: [f64; 2],
    width: u64,
    height: u64,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    #[serde(default)]
    name: Option<String>,
    position: [f64; 3],
    power: f64,
    #[serde(default)]
    spot: Option<SpotFile>,
    #[serde(default)]
    range: Option<f64>,
}

/// A spot as written: the angles default as glTF's (`θi = 0`, `θo = π/4`).
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SpotFile {
    direction: [f64; 3],
    #[serde(default)]
    inner_cone: f64,
    #[serde(default = "default_outer_cone")]
    outer_cone: f64,
}

fn default_outer_cone() -> f64 {
    std::f64::consts::FRAC_PI_4
}

/// The optional parts of each light, beside its position and power.
#[derive(Clone, Debug, Default)]
pub(crate) struct LightExtras {
    /// Per light, its spot and range as given (all `None`: no emission data is kept).
    pub(crate) shapes: Vec<(Option<Spot>, Option<f64>)>,
    /// Per light, its name (all `None`: no names are kept).
    pub(crate) names: Vec<Option<String>>,
}

impl LightExtras {
    /// Validates the shapes into emission profiles (errors name `lights[i].spot…`) and
    /// attaches them and the names to `scene`, each only if some light has one.
    pub(crate) fn attach(self, scene: &mut Scene, source: &str) -> Result<(), SceneError> {
        if self.shapes.iter().any(|(s, r)| s.is_some() || r.is_some()) {
            let emission = self
                .shapes
                .into_iter()
                .enumerate()
                .map(|(i, (spot, range))| {
                    Emission::new(spot, range).map_err(|e| {
                        SceneError::invalid(format!("{source}[{i}].{}", e.field()), e.to_string())
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            scene.emission = Some(emission);
        }
        if self.names.iter().any(Option::is_some) {
            scene.names = Some(
                self.names
                    .into_iter()
                    .map(Option::unwrap_or_default)
                    .collect(),
            );
        }
        Ok(())
    }
}

impl Scene {
    /// Parses and validates a scene file's text (see the module docs for the format).
    /// Errors name the field path: `lights[3].power: negative (-1)`.
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        let mut de = serde_json::Deserializer::from_str(text);
        let file: SceneFile = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            json_error(path, e.inner())
        })?;
        de.end().map_err(|e| json_error(".".into(), &e))?;
        file.into_scene()
    }

    /// Reads, parses and validates the scene file at `path`.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_owned(),
            source,
        })?;
        Scene::from_json_str(&text)
    }

    /// Builds a validated scene from explicit lights, with the same checks and messages as
    /// a scene file with a `lights` list (`lights[i].position`, `lights[i].power`).
    pub fn from_parts(
        name: impl Into<String>,
        plane: ReceiverPlane,
        positions: Vec<DVec3>,
        powers: Vec<f64>,
    ) -> Result<Scene, SceneError> {
        validate_plane(&plane)?;
        if positions.len() != powers.len() {
            return Err(SceneError::invalid(
                "lights",
                format!("{} positions but {} powers", positions.len(), powers.len()),
            ));
        }
        build_scene(name.into(), plane, positions, powers, "lights")
    }

    /// Sets the power of light `index` (the app's edit), with the checks of a scene file:
    /// on error the scene is unchanged. `O(N)` (the powers are revalidated).
    pub fn set_power(&mut self, index: usize, power: f64) -> Result<(), SceneError> {
        if index >= self.light_count() {
            return Err(SceneError::invalid(
                format!("lights[{index}]"),
                format!("no such light ({} lights)", self.light_count()),
            ));
        }
        let mut powers = self.powers.as_slice().to_vec();
        powers[index] = power;
        self.powers = validate_powers(powers, "lights")?;
        Ok(())
    }

    /// The scene as a file with explicit `lights` (one light per line), which
    /// [`Scene::from_json_str`] reads back to an equal scene: every `f64` is written in its
    /// shortest round-tripping form.
    pub fn to_json(&self) -> String {
        let mut out = String::with_capacity(128 + 64 * self.light_count());
        let name = serde_json::Value::String(self.name.clone());
        let p = &self.plane;
        // Writing into a String cannot fail.
        let _ = write!(
            out,
            "{{\n  \"name\": {name},\n  \"plane\": {{ \"min\": [{:?}, {:?}], \"max\": [{:?}, {:?}], \"width\": {}, \"height\": {} }},\n  \"lights\": [\n",
            p.min.x, p.min.y, p.max.x, p.max.y, p.width, p.height
        );
        let last = self.light_count().saturating_sub(1);
        for (i, (pos, power)) in self
            .positions
            .iter()
            .zip(self.powers.as_slice())
            .enumerate()
        {
            out.push_str("    { ");
            if let Some(name) = self.name_of(i) {
                let name = serde_json::Value::String(name.to_owned());
                let _ = write!(out, "\"name\": {name}, ");
            }
            let _ = write!(
                out,
                "\"position\": [{:?}, {:?}, {:?}], \"power\": {power:?}",
                pos.x, pos.y, pos.z
            );
            if let Some(e) = self.emission_of(i) {
                if let Some(s) = e.spot() {
                    let d = s.direction;
                    let _ = write!(
                        out,
                        ", \"spot\": {{ \"direction\": [{:?}, {:?}, {:?}], \"inner_cone\": {:?}, \"outer_cone\": {:?} }}",
                        d.x, d.y, d.z, s.inner_cone, s.outer_cone
                    );
                }
                if let Some(r) = e.range() {
                    let _ = write!(out, ", \"range\": {r:?}");
                }
            }
            out.push_str(if i == last { " }\n" } else { " },\n" });
        }
        out.push_str("  ]\n}\n");
        out
    }
}

/// A [`SceneError::Json`] from `serde_json`'s error, its position split off the message.
fn json_error(path: String, e: &serde_json::Error) -> SceneError {
    let full = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let message = full.strip_suffix(&suffix).unwrap_or(&full).to_owned();
    SceneError::Json {
        path,
        message,
        line: e.line(),
        column: e.column(),
    }
}

impl SceneFile {
    fn into_scene(self) -> Result<Scene, SceneError> {
        let p = &self.plane;
        for (field, value) in [("plane.width", p.width), ("plane.height", p.height)] {
            if value < 1 || value > u64::from(MAX_PLANE_SIDE) {
                return Err(SceneError::out_of_range(field, value, 1, MAX_PLANE_SIDE));
            }
        }
        let plane = ReceiverPlane {
            min: DVec2::from_array(p.min),
            max: DVec2::from_array(p.max),
            width: p.width as u32,
            height: p.height as u32,
        };
        validate_plane(&plane)?;
        match (self.lights, self.generator) {
            (Some(_), Some(_)) => Err(SceneError::invalid(
                ".",
                "give either \"lights\" or \"generator\", not both",
            )),
            (None, None) => Err(SceneError::invalid(
                ".",
                "missing light source: give \"lights\" or \"generator\"",
            )),
            (Some(lights), None) => {
                if lights.len() > MAX_LIGHTS {
                    return Err(SceneError::out_of_range(
                        "lights (count)",
                        lights.len(),
                        1,
                        MAX_LIGHTS,
                    ));
                }
                let mut extras = LightExtras::default();
                let (positions, powers) = lights
                    .into_iter()
                    .map(|l| {
                        extras.names.push(l.name);
                        let spot = l.spot.map(|s| Spot {
                            direction: DVec3::from_array(s.direction),
                            inner_cone: s.inner_cone,
                            outer_cone: s.outer_cone,
                        });
                        extras.shapes.push((spot, l.range));
                        (DVec3::from_array(l.position), l.power)
                    })
                    .unzip();
                let mut scene = build_scene(self.name, plane, positions, powers, "lights")?;
                extras.attach(&mut scene, "lights")?;
                Ok(scene)
            }
            (None, Some(generator)) => {
                let (positions, powers) = generator.generate()?;
                build_scene(self.name, plane, positions, powers, "generator")
            }
        }
    }
}

/// Checks the plane's sizes, corners and pixel count.
fn validate_plane(plane: &ReceiverPlane) -> Result<(), SceneError> {
    for (field, value) in [("plane.width", plane.width), ("plane.height", plane.height)] {
        if !(1..=MAX_PLANE_SIDE).contains(&value) {
            return Err(SceneError::out_of_range(field, value, 1, MAX_PLANE_SIDE));
        }
    }
    if plane.pixel_count() > MAX_PIXELS {
        return Err(SceneError::invalid(
            "plane",
            format!(
                "{} × {} = {} pixels exceed the limit of {MAX_PIXELS}",
                plane.width,
                plane.height,
                plane.pixel_count()
            ),
        ));
    }
    for axis in 0..2 {
        for (name, corner) in [("min", plane.min), ("max", plane.max)] {
            if !corner[axis].is_finite() {
                return Err(SceneError::NotFinite {
                    field: format!("plane.{name}[{axis}]"),
                    value: corner[axis],
                });
            }
        }
        if plane.max[axis] <= plane.min[axis] {
            return Err(SceneError::invalid(
                format!("plane.max[{axis}]"),
                format!(
                    "must be greater than plane.min[{axis}] ({} ≤ {})",
                    plane.max[axis], plane.min[axis]
                ),
            ));
        }
    }
    Ok(())
}

/// Validates positions and powers and assembles the scene. `source` is `lights` (errors
/// name `lights[i].…`) or `generator` (errors name the generated light's index).
fn build_scene(
    name: String,
    plane: ReceiverPlane,
    positions: Vec<DVec3>,
    powers: Vec<f64>,
    source: &str,
) -> Result<Scene, SceneError> {
    if positions.len() > MAX_LIGHTS {
        return Err(SceneError::out_of_range(
            format!("{source} (count)"),
            positions.len(),
            1,
            MAX_LIGHTS,
        ));
    }
    let light_field = |i: usize, what: &str| {
        if source == "lights" {
            format!("lights[{i}].{what}")
        } else {
            format!("{source} (light {i}).{what}")
        }
    };
    for (i, pos) in positions.iter().enumerate() {
        if let Some(axis) = pos.to_array().iter().position(|c| !c.is_finite()) {
            return Err(SceneError::NotFinite {
                field: light_field(i, &format!("position[{axis}]")),
                value: pos[axis],
            });
        }
    }
    let powers = validate_powers(powers, source)?;
    Ok(Scene::new(name, plane, positions, powers))
}

/// Validates powers as [`LightPowers`] and checks that their total is finite; errors name
/// `lights[i].power` (or the generated light's index when `source` is `generator`).
fn validate_powers(powers: Vec<f64>, source: &str) -> Result<LightPowers, SceneError> {
    let light_field = |i: usize| {
        if source == "lights" {
            format!("lights[{i}].power")
        } else {
            format!("{source} (light {i}).power")
        }
    };
    let count = powers.len();
    let powers = LightPowers::new(powers).map_err(|e| match e {
        PowersError::Empty => SceneError::invalid(source, "no lights"),
        PowersError::NotFinite { index, value } => SceneError::NotFinite {
            field: light_field(index),
            value,
        },
        PowersError::Negative { index, value } => SceneError::Negative {
            field: light_field(index),
            value,
        },
        PowersError::AllZero { count } => SceneError::AllZero {
            field: source.to_owned(),
            count,
        },
        PowersError::TooMany { count, max } => {
            SceneError::out_of_range(format!("{source} (count)"), count, 1, max)
        }
    })?;
    if !powers.total().is_finite() {
        return Err(SceneError::TotalPowerOverflow {
            field: source.to_owned(),
            count,
        });
    }
    Ok(powers)
}
