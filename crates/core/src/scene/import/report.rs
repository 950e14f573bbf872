//! What a file held: its format, the lights taken by kind, and the lights skipped.

use std::fmt::Write as _;

use super::format::SceneFormat;
use crate::scene::Scene;

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
