//! One loader for every light set lightpick reads: lightpick's scene JSON, glTF 2.0
//! (`.gltf` / `.glb`, `KHR_lights_punctual`) and CSV or white-space light lists, told apart
//! by magic bytes and extension. Every consumer (the CLI's `--scene`, `lightpick FILE`, the
//! app's File → Open and a file dropped on its window) goes through [`load`], and gets the
//! same [`Scene`] and an [`ImportReport`] of what came in and what was skipped.
//!
//! # Receiver and floor
//! A lightpick JSON scene names its own plane. An imported light set (glTF, CSV) has none:
//! the receiver is the file's ground, `z = 0` (glTF's `y = 0`), and the plane covers the
//! footprint of the lights that can reach it with a margin ([`footprint_plane`]). A floor
//! height `H` ([`LoadOptions::floor`]) moves the receiver to `z = H` for any format: every
//! light's `z` becomes `z − H`, and lights on or below the receiver contribute nothing.

mod csv;
mod gltf;

use std::fmt::Write as _;
use std::path::Path;

use glam::{DVec2, DVec3};

use super::{MAX_LIGHTS, ReceiverPlane, Scene, SceneError};

/// The formats [`load`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SceneFormat {
    /// lightpick's scene JSON.
    Json,
    /// glTF 2.0, JSON form (`.gltf`).
    Gltf,
    /// glTF 2.0, binary form (`.glb`).
    Glb,
    /// A CSV or white-space list of `x, y, z, power`.
    Csv,
}

impl SceneFormat {
    /// The format's short name (`json`, `gltf`, `glb`, `csv`).
    pub fn name(self) -> &'static str {
        match self {
            SceneFormat::Json => "json",
            SceneFormat::Gltf => "gltf",
            SceneFormat::Glb => "glb",
            SceneFormat::Csv => "csv",
        }
    }

    /// The file extensions of each format, for file choosers.
    pub const EXTENSIONS: [&'static str; 6] = ["json", "gltf", "glb", "csv", "txt", "tsv"];

    /// The format a file of extension `ext` (lower case, no dot) holds, if known.
    pub fn from_extension(ext: &str) -> Option<SceneFormat> {
        match ext {
            "json" => Some(SceneFormat::Json),
            "gltf" => Some(SceneFormat::Gltf),
            "glb" => Some(SceneFormat::Glb),
            "csv" | "txt" | "tsv" => Some(SceneFormat::Csv),
            _ => None,
        }
    }

    /// The format of `bytes` read from a file with extension `ext`: the magic bytes first
    /// (`glTF` is a GLB whatever the name; a JSON object with a top-level `"asset"` is glTF),
    /// then the extension; a JSON object defaults to lightpick JSON and anything else to a
    /// light list.
    pub fn detect(bytes: &[u8], ext: Option<&str>) -> SceneFormat {
        if bytes.starts_with(b"glTF") {
            return SceneFormat::Glb;
        }
        if let Some(format) = ext.and_then(SceneFormat::from_extension) {
            return format;
        }
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
        if text.trim_start().starts_with('{') {
            if text.contains("\"asset\"") {
                SceneFormat::Gltf
            } else {
                SceneFormat::Json
            }
        } else {
            SceneFormat::Csv
        }
    }
}

/// A light of the file that is not in the scene, and why.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct SkippedLight {
    /// Its name (or where it is, when unnamed).
    pub name: String,
    /// Why it was left out.
    pub reason: String,
}

/// What a file held: its format, the lights taken by kind, and the lights skipped.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ImportReport {
    /// The format read.
    pub format: SceneFormat,
    /// Lights without a spot cone (points, with or without a range).
    pub points: usize,
    /// Spot lights.
    pub spots: usize,
    /// Lights of the file left out (directional lights).
    pub skipped: Vec<SkippedLight>,
}

impl ImportReport {
    /// The report of `scene` read from `format`, nothing skipped.
    pub fn of(scene: &Scene, format: SceneFormat) -> Self {
        let spots = scene.spot_count();
        ImportReport {
            format,
            points: scene.light_count() - spots,
            spots,
            skipped: Vec::new(),
        }
    }

    /// One line for a status bar: "402 lights: 362 points, 40 spots; skipped 1
    /// directional light 'Sun'".
    pub fn summary(&self) -> String {
        let n = self.points + self.spots;
        let mut out = format!("{n} {}", plural(n, "light", "lights"));
        if self.spots > 0 {
            let _ = write!(
                out,
                ": {} {}, {} {}",
                self.points,
                plural(self.points, "point", "points"),
                self.spots,
                plural(self.spots, "spot", "spots")
            );
        }
        if !self.skipped.is_empty() {
            let names: Vec<String> = self
                .skipped
                .iter()
                .take(3)
                .map(|s| format!("'{}'", s.name))
                .collect();
            let more = self.skipped.len().saturating_sub(3);
            let k = self.skipped.len();
            let _ = write!(
                out,
                "; skipped {k} {} {}{}",
                plural(k, "directional light", "directional lights"),
                names.join(", "),
                if more > 0 {
                    format!(" and {more} more")
                } else {
                    String::new()
                }
            );
        }
        out
    }
}

fn plural<'a>(n: usize, one: &'a str, many: &'a str) -> &'a str {
    if n == 1 { one } else { many }
}

/// How to read a file.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// The receiver's height `H` in the file's units (lightpick's `z`, glTF's `y`): every
    /// light's `z` becomes `z − H`. `None`: the file's ground (`z = 0`).
    pub floor: Option<f64>,
}

/// A scene as read from a file, and what the file held.
#[derive(Clone, Debug, PartialEq)]
pub struct Loaded {
    /// The scene (positions after the floor).
    pub scene: Scene,
    /// What came in and what was skipped.
    pub report: ImportReport,
}

/// Reads the file at `path` in whichever format it holds (module docs).
pub fn load(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Loaded, SceneError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
        path: path.to_owned(),
        source,
    })?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("untitled");
    load_bytes(&bytes, name, ext.as_deref(), options)
}

/// [`load`] of a file's contents: `name` names the scene when the format has no name of
/// its own, `ext` (lower case, no dot) helps tell the format.
pub fn load_bytes(
    bytes: &[u8],
    name: &str,
    ext: Option<&str>,
    options: &LoadOptions,
) -> Result<Loaded, SceneError> {
    if let Some(h) = options.floor
        && !h.is_finite()
    {
        return Err(SceneError::NotFinite {
            field: "floor".to_owned(),
            value: h,
        });
    }
    let format = SceneFormat::detect(bytes, ext);
    let (mut scene, report) = match format {
        SceneFormat::Json => {
            let text = std::str::from_utf8(bytes).map_err(|e| SceneError::Import {
                format: "json",
                message: format!("not UTF-8 text ({e})"),
            })?;
            let scene = Scene::from_json_str(text)?;
            let report = ImportReport::of(&scene, format);
            (scene, report)
        }
        SceneFormat::Gltf | SceneFormat::Glb => gltf::read(bytes, name, format)?,
        SceneFormat::Csv => {
            let scene = csv::read(bytes, name)?;
            let report = ImportReport::of(&scene, format);
            (scene, report)
        }
    };
    if let Some(h) = options.floor
        && h != 0.0
    {
        for p in std::sync::Arc::make_mut(&mut scene.positions) {
            p.z -= h;
            if !p.z.is_finite() {
                return Err(SceneError::NotFinite {
                    field: "floor".to_owned(),
                    value: h,
                });
            }
        }
        if format != SceneFormat::Json {
            scene.plane =
                footprint_plane(&scene.positions, scene.plane.width.max(scene.plane.height));
        }
    }
    Ok(Loaded { scene, report })
}

/// Pixels on the longer side of an imported scene's plane.
pub const IMPORT_PLANE_PIXELS: u32 = 256;

/// A plane over the footprint of the lights above `z = 0` (all lights when none is): their
/// `(x, y)` box widened on every side by a margin of a quarter of its larger side, at least
/// the lights' median height (a light lights the plane out to a few times its height), and
/// `side` pixels along the longer side.
pub fn footprint_plane(positions: &[DVec3], side: u32) -> ReceiverPlane {
    let above: Vec<DVec3> = positions.iter().copied().filter(|p| p.z > 0.0).collect();
    let lights = if above.is_empty() {
        positions.to_vec()
    } else {
        above
    };
    let (mut min, mut max) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for p in &lights {
        min = min.min(p.truncate());
        max = max.max(p.truncate());
    }
    if !(min.x.is_finite() && max.x.is_finite() && min.y.is_finite() && max.y.is_finite()) {
        min = DVec2::splat(-1.0);
        max = DVec2::splat(1.0);
    }
    let mut heights: Vec<f64> = lights.iter().map(|p| p.z.abs()).collect();
    heights.sort_by(f64::total_cmp);
    let median = heights.get(heights.len() / 2).copied().unwrap_or(1.0);
    let extent = max - min;
    let margin = (0.25 * extent.max_element())
        .max(median)
        .max(f64::MIN_POSITIVE * 1e10);
    let (min, max) = (min - margin, max + margin);
    let size = max - min;
    let side = side.clamp(1, super::MAX_PLANE_SIDE);
    let (width, height) = if size.x >= size.y {
        (
            side,
            ((f64::from(side) * size.y / size.x).round() as u32).clamp(1, side),
        )
    } else {
        (
            ((f64::from(side) * size.x / size.y).round() as u32).clamp(1, side),
            side,
        )
    };
    ReceiverPlane {
        min,
        max,
        width,
        height,
    }
}

/// Refuses more lights than a scene may hold, before they are read one by one.
fn check_count(count: usize, what: &str) -> Result<(), SceneError> {
    if count > MAX_LIGHTS {
        return Err(SceneError::out_of_range(
            format!("{what} (count)"),
            count,
            1,
            MAX_LIGHTS,
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_are_told_by_magic_then_extension() {
        assert_eq!(
            SceneFormat::detect(b"glTF\x02\0\0\0", Some("json")),
            SceneFormat::Glb
        );
        assert_eq!(SceneFormat::detect(b"{}", Some("gltf")), SceneFormat::Gltf);
        assert_eq!(
            SceneFormat::detect(b" {\"asset\": {\"version\": \"2.0\"}}", None),
            SceneFormat::Gltf
        );
        assert_eq!(
            SceneFormat::detect(b"{\"plane\": 1}", None),
            SceneFormat::Json
        );
        assert_eq!(SceneFormat::detect(b"1 2 3 4", None), SceneFormat::Csv);
        assert_eq!(
            SceneFormat::detect(b"x,y,z,power", Some("txt")),
            SceneFormat::Csv
        );
    }

    #[test]
    fn the_summary_reads_as_a_sentence() {
        let report = ImportReport {
            format: SceneFormat::Glb,
            points: 362,
            spots: 40,
            skipped: vec![SkippedLight {
                name: "Sun".into(),
                reason: "directional".into(),
            }],
        };
        assert_eq!(
            report.summary(),
            "402 lights: 362 points, 40 spots; skipped 1 directional light 'Sun'"
        );
        let one = ImportReport {
            format: SceneFormat::Csv,
            points: 1,
            spots: 0,
            skipped: Vec::new(),
        };
        assert_eq!(one.summary(), "1 light");
    }

    #[test]
    fn the_footprint_plane_covers_the_lights_with_a_margin() {
        let plane = footprint_plane(
            &[
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::new(4.0, 2.0, 1.0),
                DVec3::new(50.0, 50.0, -1.0),
            ],
            256,
        );
        // The light below the plane is left out; the margin is max(4/4, median 1) = 1.
        assert_eq!(plane.min, DVec2::new(-1.0, -1.0));
        assert_eq!(plane.max, DVec2::new(5.0, 3.0));
        assert_eq!((plane.width, plane.height), (256, 171));
        let single = footprint_plane(&[DVec3::new(3.0, 3.0, 2.0)], 256);
        assert_eq!(single.min, DVec2::new(1.0, 1.0));
        assert_eq!((single.width, single.height), (256, 256));
    }
}
