//! The scene as the user edits it ([`SceneEdit`]: powers exactly as typed, valid or not)
//! and the edits the lights panel makes: one power, the powers text field, adding, removing
//! and duplicating lights, random powers, generated scenes, the receiver's height. Each edit
//! ends in [`AppState::powers_changed`] ([`super::rebuild`]), which validates and rebuilds.

use std::sync::Arc;

use glam::DVec3;
use lightpick_core::scene::{Emission, ReceiverPlane, Scene};
use lightpick_core::{LightPowers, PowersError};

use super::{AppState, MessageKind};

/// The scene as the user is editing it: powers exactly as typed, valid or not.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneEdit {
    /// Scene name.
    pub name: String,
    /// The receiver plane and its pixel grid.
    pub plane: ReceiverPlane,
    /// Light positions, shared with the scene they came from (or were last built into):
    /// writes go through [`SceneEdit::positions_mut`], which copies them only while a scene
    /// still shares them.
    pub positions: Arc<[DVec3]>,
    /// Light powers as typed (may hold NaN or negatives until corrected), shared like the
    /// positions ([`SceneEdit::powers_mut`]): a valid edit becomes the next scene's powers
    /// without a copy.
    pub powers: Arc<[f64]>,
    /// Each light's spot cone and range, when the scene has any (kept through edits).
    pub emission: Option<Vec<Emission>>,
    /// Each light's name, when the scene's source named its lights.
    pub names: Option<Vec<String>>,
    /// The receiver's height above the scene's ground as loaded (the Floor control): every
    /// light's `z` is its loaded height minus this.
    pub floor: f64,
}

impl SceneEdit {
    /// The editable copy of a scene.
    pub fn from_scene(scene: &Scene) -> Self {
        Self {
            name: scene.name.clone(),
            plane: scene.plane.clone(),
            positions: Arc::clone(&scene.positions),
            powers: Arc::clone(scene.powers.shared()),
            emission: scene.emission.clone(),
            names: scene.names.clone(),
            floor: 0.0,
        }
    }

    /// The positions to write to (copied first if a scene still shares them).
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        Arc::make_mut(&mut self.positions)
    }

    /// The powers to write to (copied first if a scene still shares them).
    pub fn powers_mut(&mut self) -> &mut [f64] {
        Arc::make_mut(&mut self.powers)
    }

    /// Changes the number of lights: `change` edits the positions and powers as vectors
    /// (one copy each, as any resize of a shared array takes).
    pub(super) fn resize_lights(&mut self, change: impl FnOnce(&mut Vec<DVec3>, &mut Vec<f64>)) {
        let mut positions = self.positions.to_vec();
        let mut powers = self.powers.to_vec();
        change(&mut positions, &mut powers);
        self.positions = positions.into();
        self.powers = powers.into();
    }

    /// Keeps one emission profile and one name per light: lights added get a point
    /// light's profile and no name, removed ones lose theirs.
    pub(super) fn fit_extras(&mut self, n: usize) {
        if let Some(e) = &mut self.emission {
            e.resize(n, Emission::POINT);
        }
        if let Some(names) = &mut self.names {
            names.resize(n, String::new());
        }
    }

    /// Removes light `i`'s profile and name.
    fn remove_extras(&mut self, i: usize) {
        if let Some(e) = self.emission.as_mut().filter(|e| i < e.len()) {
            e.remove(i);
        }
        if let Some(names) = self.names.as_mut().filter(|n| i < n.len()) {
            names.remove(i);
        }
    }

    /// Copies light `i`'s profile and name to a new light right after it.
    fn duplicate_extras(&mut self, i: usize) {
        if let Some(e) = self.emission.as_mut().filter(|e| i < e.len()) {
            e.insert(i + 1, e[i]);
        }
        if let Some(names) = self.names.as_mut().filter(|n| i < n.len()) {
            let copy = names[i].clone();
            names.insert(i + 1, copy);
        }
    }

    /// The light's name for display: its own, else `light k` (numbered from 1).
    pub fn display_name(&self, i: usize) -> String {
        self.names
            .as_ref()
            .and_then(|n| n.get(i))
            .filter(|n| !n.is_empty())
            .cloned()
            .unwrap_or_else(|| format!("light {}", i + 1))
    }
}

impl AppState {
    /// Moves the receiver to height `floor` above the scene's ground as loaded: every light's
    /// `z` shifts by the change, and lights on or below the receiver light nothing.
    pub fn set_floor(&mut self, floor: f64) {
        if !floor.is_finite() || floor == self.edit.floor {
            return;
        }
        self.history.name_next(format!("floor {floor}"));
        let shift = floor - self.edit.floor;
        for p in self.edit.positions_mut() {
            p.z -= shift;
        }
        self.edit.floor = floor;
        self.unedited_preset = None;
        self.powers_changed();
        let above = self.edit.positions.iter().filter(|p| p.z > 0.0).count();
        self.message(
            format!(
                "receiver at height {floor}: {above} of {} lights above it",
                self.edit.positions.len()
            ),
            MessageKind::Info,
        );
    }

    /// Parses the powers text field ("2, 5, 20" or white space) and applies it; a word that
    /// is not a number is named and nothing changes.
    pub fn apply_powers_text(&mut self) {
        match parse_powers(&self.powers_text) {
            Ok(mut powers) => {
                // A word left as shown (a power written to 7 significant digits) keeps the
                // light's exact power: editing one number never rounds the others.
                let shown: Vec<&str> = power_words(&self.powers_text);
                for (i, power) in powers.iter_mut().enumerate() {
                    if let (Some(&exact), Some(word)) = (self.edit.powers.get(i), shown.get(i))
                        && *word == power_to_text(exact)
                    {
                        *power = exact;
                    }
                }
                let n = powers.len();
                self.history.name_next("Apply powers");
                self.edit.powers = powers.into();
                if self.edit.positions.len() > n {
                    self.edit
                        .resize_lights(|positions, _| positions.truncate(n));
                }
                self.powers_changed();
            }
            Err(message) => self.input_error = Some(message),
        }
    }

    /// Adds a light with power `power` at a fresh position.
    pub fn add_light(&mut self, power: f64) {
        let i = self.edit.powers.len();
        self.history.name_next(format!("add light {}", i + 1));
        let pos = crate::app::generated::random_positions(
            i + 1,
            &self.edit.plane,
            self.settings.seed ^ i as u64,
        )[i];
        self.edit.resize_lights(|positions, powers| {
            positions.push(pos);
            powers.push(power);
        });
        self.edit.fit_extras(i + 1);
        self.after_structure_change();
    }

    /// Removes light `i` (refused for the last light).
    pub fn remove_light(&mut self, i: usize) {
        if self.edit.powers.len() <= 1 || i >= self.edit.powers.len() {
            self.message("a scene needs at least one light", MessageKind::Error);
            return;
        }
        self.history.name_next(format!("delete light {}", i + 1));
        self.edit.resize_lights(|positions, powers| {
            powers.remove(i);
            if i < positions.len() {
                positions.remove(i);
            }
        });
        self.edit.remove_extras(i);
        self.after_structure_change();
    }

    /// Duplicates light `i` (same position and power) right after it.
    pub fn duplicate_light(&mut self, i: usize) {
        if i >= self.edit.powers.len() {
            return;
        }
        self.history.name_next(format!("duplicate light {}", i + 1));
        self.edit.resize_lights(|positions, powers| {
            powers.insert(i + 1, powers[i]);
            let pos = positions.get(i).copied().unwrap_or(DVec3::Z);
            positions.insert(i + 1, pos);
        });
        self.edit.duplicate_extras(i);
        self.after_structure_change();
    }

    /// Draws new powers for every light from the chosen distribution.
    pub fn randomize(&mut self) {
        let n = self.edit.powers.len();
        let scale = (self.settings.slider_max / 4.0).max(f64::MIN_POSITIVE);
        let seed = self.settings.seed.wrapping_add(self.frame);
        self.history.name_next("Randomize");
        self.edit.powers =
            crate::app::generated::random_powers(n, self.settings.distribution, scale, seed).into();
        self.after_structure_change();
    }

    /// Replaces the scene by `count` random lights over the current plane, `1 ..= 2^24`
    /// ([`lightpick_core::scene::MAX_LIGHTS`]); another count is refused with a message, never
    /// clamped.
    pub fn generate(&mut self, count: usize) {
        let max = lightpick_core::scene::MAX_LIGHTS;
        if !(1..=max).contains(&count) {
            self.message(
                format!("Generate: {count} lights is outside 1 ..= {max} (the scene limit 2^24)"),
                MessageKind::Error,
            );
            return;
        }
        let seed = self.settings.seed;
        let powers =
            crate::app::generated::random_powers(count, self.settings.distribution, 10.0, seed);
        let positions = crate::app::generated::random_positions(count, &self.edit.plane, seed);
        match LightPowers::new(powers) {
            Ok(powers) => {
                let scene = Scene::new(
                    format!("generated-{count}"),
                    self.edit.plane.clone(),
                    positions,
                    powers,
                );
                self.history.name_next(format!("Generate ({count} lights)"));
                self.load_scene(scene);
                self.message(format!("generated {count} lights"), MessageKind::Info);
            }
            Err(e) => self.message(describe_powers_error(&e), MessageKind::Error),
        }
    }

    /// Keeps one position per power: lights added through the text field get fresh ones.
    pub(super) fn sync_positions(&mut self, n: usize) {
        let have = self.edit.positions.len();
        if have != n {
            let fresh = (have < n).then(|| {
                crate::app::generated::random_positions(n, &self.edit.plane, self.settings.seed)
            });
            self.edit.resize_lights(|positions, _| {
                if let Some(fresh) = &fresh {
                    positions.extend_from_slice(&fresh[have..]);
                }
                positions.truncate(n);
            });
        }
        self.edit.fit_extras(n);
    }

    pub(super) fn after_structure_change(&mut self) {
        self.powers_text = if self.edit.powers.len() <= 1000 {
            powers_to_text(&self.edit.powers)
        } else {
            String::new()
        };
        self.powers_changed();
    }
}

/// A one-line, 1-based description of a power problem, saying the last valid table is kept.
pub fn describe_powers_error(e: &PowersError) -> String {
    let problem = match e {
        PowersError::Empty => "there are no lights".to_owned(),
        PowersError::NotFinite { index, value } => {
            format!("light {}: power {value} is not a finite number", index + 1)
        }
        PowersError::Negative { index, value } => {
            format!("light {}: power {value} is negative", index + 1)
        }
        PowersError::AllZero { count } => {
            format!("all {count} powers are zero: nothing emits light")
        }
        PowersError::TooMany { .. } => e.to_string(),
    };
    format!("{problem} — keeping the last valid table")
}

/// Powers separated by commas, semicolons or white space; a word that is not a number is
/// named (1-based position). NaN and negative numbers parse here and are refused later with
/// the light's number.
pub fn parse_powers(text: &str) -> Result<Vec<f64>, String> {
    let words: Vec<&str> = text
        .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
        .filter(|w| !w.is_empty())
        .collect();
    if words.is_empty() {
        return Err("the powers field is empty — keeping the last valid table".to_owned());
    }
    words
        .iter()
        .enumerate()
        .map(|(i, w)| {
            w.replace('−', "-").parse::<f64>().map_err(|_| {
                format!(
                    "light {}: '{w}' is not a number — keeping the last valid table",
                    i + 1
                )
            })
        })
        .collect()
}

/// Most lights the powers text field lists; larger scenes leave it empty.
pub const POWERS_TEXT_MAX_LIGHTS: usize = 1000;

/// The powers as "2, 5, 20" (each by [`power_to_text`]); empty beyond
/// [`POWERS_TEXT_MAX_LIGHTS`] lights.
pub fn powers_to_text(powers: &[f64]) -> String {
    if powers.len() > POWERS_TEXT_MAX_LIGHTS {
        return String::new();
    }
    powers
        .iter()
        .map(|p| power_to_text(*p))
        .collect::<Vec<_>>()
        .join(", ")
}

/// One power as the text field shows it: its shortest exact form when that has at most 7
/// significant digits ("2", "0.25", "1e-30"), else rounded to 7 ("1234.568" for an
/// imported 1234.5678901234567); exponent form outside `[10^-4, 10^7)`.
/// [`AppState::apply_powers_text`] keeps the exact power of every word left as shown.
pub fn power_to_text(power: f64) -> String {
    if !power.is_finite() || power == 0.0 {
        return power.to_string();
    }
    let magnitude = power.abs().log10().floor();
    let plain = (-4.0..7.0).contains(&magnitude);
    let exact = if plain {
        power.to_string()
    } else {
        format!("{power:e}")
    };
    if significant_digits(&exact) <= 7 {
        exact
    } else if plain {
        let decimals = (6.0 - magnitude).max(0.0) as usize;
        let text = format!("{power:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            text
        }
    } else {
        format!("{power:.6e}")
    }
}

/// Significant digits of a number written in decimal or exponent form.
fn significant_digits(text: &str) -> usize {
    let mantissa = text.split(['e', 'E']).next().unwrap_or("");
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let digits = digits.trim_start_matches('0');
    // Trailing zeros of an integer part are significant only up to the decimal point; a
    // power like 1000000 counts as 1 digit here, which is what its shortest form shows.
    digits.trim_end_matches('0').len()
}

/// The words of the powers field, as [`parse_powers`] splits them.
fn power_words(text: &str) -> Vec<&str> {
    text.split(|c: char| c == ',' || c == ';' || c.is_whitespace())
        .filter(|w| !w.is_empty())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::scene_io;
    use crate::app::state::Settings;

    #[test]
    fn parse_names_the_bad_word() {
        assert_eq!(parse_powers("2, 5 20").unwrap(), vec![2.0, 5.0, 20.0]);
        let err = parse_powers("2, five, 20").unwrap_err();
        assert!(err.contains("light 2"), "{err}");
        assert!(parse_powers("nan").unwrap()[0].is_nan());
    }

    #[test]
    fn imported_powers_show_seven_digits_and_keep_their_bits() {
        assert_eq!(power_to_text(2.0), "2");
        assert_eq!(power_to_text(0.25), "0.25");
        assert_eq!(power_to_text(1e-30), "1e-30");
        assert_eq!(power_to_text(1e30), "1e30");
        assert_eq!(power_to_text(1_000_000.0), "1000000");
        assert_eq!(power_to_text(1_234.567_890_123_456_7), "1234.568");
        assert_eq!(power_to_text(0.1 + 0.2), "0.3");
        assert_eq!(power_to_text(std::f64::consts::PI * 1e20), "3.141593e20");
        let imported = [1_234.567_890_123_456_7, 2.0, 0.1 + 0.2];
        let mut state = AppState::new(scene_io::worked_example_scene(), Settings::default());
        state.edit.powers = imported.to_vec().into();
        state.powers_changed();
        state.powers_text = powers_to_text(&state.edit.powers);
        assert_eq!(state.powers_text, "1234.568, 2, 0.3");
        // The second power edited by hand: the others keep every bit.
        state.powers_text = "1234.568, 7, 0.3".to_owned();
        state.apply_powers_text();
        assert_eq!(
            state.built.scene.powers.as_slice(),
            [1_234.567_890_123_456_7, 7.0, 0.1 + 0.2]
        );
        // A word typed anew is taken as typed.
        state.powers_text = "1234.5, 7, 0.3".to_owned();
        state.apply_powers_text();
        assert_eq!(state.built.scene.powers.as_slice()[0], 1234.5);
    }

    #[test]
    fn errors_are_one_based() {
        let e = LightPowers::new(vec![1.0, -2.0]).unwrap_err();
        assert!(describe_powers_error(&e).starts_with("light 2: power -2 is negative"));
    }

    #[test]
    fn generate_refuses_counts_beyond_the_scene_limit_by_name() {
        let mut state = AppState::new(scene_io::worked_example_scene(), Settings::default());
        let max = lightpick_core::scene::MAX_LIGHTS;
        for count in [0, max + 1] {
            state.generate(count);
            let (text, kind) = state.status.clone().expect("a message");
            assert_eq!(kind, MessageKind::Error);
            assert!(
                text.contains(&count.to_string()) && text.contains("2^24"),
                "{text}"
            );
            assert_eq!(state.built.len(), 3, "the worked example stays");
        }
        state.generate(5);
        assert_eq!(state.built.len(), 5);
    }

    #[test]
    fn the_edit_shares_the_scenes_arrays_and_copies_only_what_it_writes() {
        let mut state = AppState::new(scene_io::worked_example_scene(), Settings::default());
        let scene = Arc::clone(&state.built.scene);
        assert!(Arc::ptr_eq(&state.edit.positions, &scene.positions));
        assert!(Arc::ptr_eq(&state.edit.powers, scene.powers.shared()));
        // A refused value: the edit holds its own copy, the last good scene is untouched.
        state.edit.powers_mut()[1] = f64::NAN;
        assert!(!Arc::ptr_eq(&state.edit.powers, scene.powers.shared()));
        state.powers_changed();
        assert!(state.input_error.is_some());
        assert_eq!(state.built.scene.powers.as_slice(), [2.0, 5.0, 20.0]);
        // A valid value: the new scene takes the edit's arrays as they are.
        state.edit.powers_mut()[1] = 7.0;
        state.powers_changed();
        assert!(state.input_error.is_none());
        assert_eq!(state.built.scene.powers.as_slice(), [2.0, 7.0, 20.0]);
        assert!(Arc::ptr_eq(
            &state.edit.powers,
            state.built.scene.powers.shared()
        ));
        assert!(Arc::ptr_eq(
            &state.edit.positions,
            &state.built.scene.positions
        ));
        assert!(Arc::ptr_eq(&state.built.scene.positions, &scene.positions));
    }
}
