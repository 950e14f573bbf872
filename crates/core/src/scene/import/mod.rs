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

mod count;
mod csv;
mod format;
mod gltf;
mod plane;
mod report;

pub use format::SceneFormat;
pub use plane::{IMPORT_PLANE_PIXELS, footprint_plane};
pub use report::{ImportReport, SkippedLight};

use std::path::Path;

use super::{Scene, SceneError};

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

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

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
