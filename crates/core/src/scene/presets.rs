//! The built-in scenes of `assets/scenes/` (stored in the core crate, `crates/core/assets/scenes`,
//! so that the published crate has them; the root path links there), compiled into the binary so it
//! runs from any directory.

use super::Scene;
use super::error::SceneError;

/// Every preset name, in display order.
pub const PRESET_NAMES: [&str; 10] = [
    "worked-example",
    "equal",
    "dominant",
    "zeros",
    "heavy-tail",
    "million",
    "extreme-range",
    "grid",
    "stage",
    "gallery",
];

/// The embedded text of each preset, in the order of [`PRESET_NAMES`].
const PRESET_FILES: [&str; 10] = [
    include_str!("../../assets/scenes/worked-example.json"),
    include_str!("../../assets/scenes/equal.json"),
    include_str!("../../assets/scenes/dominant.json"),
    include_str!("../../assets/scenes/zeros.json"),
    include_str!("../../assets/scenes/heavy-tail.json"),
    include_str!("../../assets/scenes/million.json"),
    include_str!("../../assets/scenes/extreme-range.json"),
    include_str!("../../assets/scenes/grid.json"),
    include_str!("../../assets/scenes/stage.json"),
    include_str!("../../assets/scenes/gallery.json"),
];

impl Scene {
    /// The preset `name` (one of [`PRESET_NAMES`]), parsed from its embedded file and, for
    /// the large ones, generated from the seed the file holds:
    ///
    /// * `worked-example`: three lights of powers 2, 5 and 20 (also found by `seed`, the name
    ///   it had before "seed" was kept for random streams alone);
    /// * `equal`: 64 lights of power 1;
    /// * `dominant`: 64 lights, one of power `10^6`, the others 1;
    /// * `zeros`: 64 lights, powers uniform on `[0.5, 2)`, exactly half of them 0;
    /// * `heavy-tail`: 10 000 lights, Pareto powers (`scale 1`, `shape 1.2`: infinite variance);
    /// * `million`: `10^6` lights, exponential powers, on a 512 × 512 plane;
    /// * `extreme-range`: 4096 lights, log-uniform powers on `[1e-30, 1e30]`;
    /// * `grid`: 1024 lights of power 1 scattered over the plane `[-8, 8]²` at heights
    ///   `z ∈ [0.2, 0.4]`, low next to their spacing (`16/√1024 = 0.5`), so only the few
    ///   lights near a pixel matter there (`G ∝ z/r³`): where contribution-aware (spatial)
    ///   sampling beats power sampling by two orders of magnitude in variance;
    /// * `stage`: 300 named spot lights over a 16 × 10 m stage: three trusses of 80 narrow
    ///   spots 6 m up, each aimed at its own mark, 40 footlights grazing the floor from its
    ///   edges and 20 wide washes with a range: each spot lights a small part of the floor,
    ///   so its power says little about what it gives a point (power sampling is poor);
    /// * `gallery`: 1356 named spot lights in twelve 12 × 10 m rooms of a 48 × 30 m museum
    ///   floor: in each room 15 exhibits, each lit by 7 narrow spots (outer cones 4–12°)
    ///   hung on three ceiling tracks 4.2 m up and aimed at their own marks around it, and
    ///   8 wide washes (outer cones 43–60°) with a range of 7–9 m.
    pub fn preset(name: &str) -> Result<Scene, SceneError> {
        let index = preset_index(name).ok_or_else(|| SceneError::UnknownPreset {
            name: name.to_owned(),
            expected: PRESET_NAMES.join(", "),
        })?;
        Scene::from_json_str(PRESET_FILES[index])
    }

    /// The embedded file text of preset `name`, if there is one (for showing or saving the
    /// recipe rather than the generated lights).
    pub fn preset_source(name: &str) -> Option<&'static str> {
        preset_index(name).map(|i| PRESET_FILES[i])
    }
}

/// The worked example's former preset name, still accepted by [`Scene::preset`] (saved
/// sessions and scripts use it).
const FORMER_NAME: &str = "seed";

/// The index in [`PRESET_NAMES`] of `name` (or of the worked example for [`FORMER_NAME`]).
fn preset_index(name: &str) -> Option<usize> {
    let name = if name == FORMER_NAME {
        PRESET_NAMES[0]
    } else {
        name
    };
    PRESET_NAMES.iter().position(|&n| n == name)
}
