//! Undo and redo over every scene edit: a power drag (one step for the whole drag), a typed
//! power, Apply, add, duplicate, delete, Randomize, Generate, a preset, an opened file, the
//! floor.
//!
//! A step is recorded when a new scene is installed ([`AppState`]'s build, in the frame or
//! from a worker), by comparing it with the scene it replaces:
//! - the same lights in the same places (and the same names and plane): only the powers
//!   that changed are kept, `(index, before, after)`, 24 bytes each, so a drag of one light
//!   of a `10^6`-light scene costs 24 bytes, not 8 MB;
//! - anything else (a preset, a file, Generate, a light added or removed, the floor): the
//!   scene before and after, as the shared `Arc` the app already holds (a scene is not
//!   copied; a step keeps the replaced one alive, counted in [`History::heap_bytes`]).
//!
//! The history keeps at most [`HISTORY_BUDGET`] bytes, dropping its oldest steps beyond.
//! egui's `Undoer` is not used: it clones and compares the whole state every frame, which at
//! `10^6` lights is 8 MB a frame of copies and comparisons, and it cannot share the scenes'
//! arrays.

use std::collections::BTreeMap;
use std::sync::Arc;

use lightpick_core::scene::Scene;

use super::{AppState, MessageKind};

/// The most heap bytes the history keeps (oldest steps dropped beyond).
pub const HISTORY_BUDGET: usize = 256 << 20;

/// A scene as a step restores it: the scene, the receiver's height and whether it is an
/// unedited preset.
#[derive(Clone, Debug)]
pub struct SceneState {
    /// The scene (shared with whatever else holds it).
    pub scene: Arc<Scene>,
    /// The Floor control's value with this scene.
    pub floor: f64,
    /// The preset it is, unedited.
    pub preset: Option<String>,
}

/// What a step changed.
#[derive(Clone, Debug)]
pub enum Change {
    /// Powers of the same lights: `(light, before, after)` per changed light.
    Powers(Vec<(u32, f64, f64)>),
    /// Most powers of the same lights (Randomize, a typed list): the powers before and
    /// after, shared with the scenes that hold them.
    AllPowers {
        /// The powers before the step.
        before: Arc<[f64]>,
        /// The powers after it.
        after: Arc<[f64]>,
    },
    /// A whole scene replaced.
    Scene {
        /// The scene before the step.
        before: SceneState,
        /// The scene after it.
        after: SceneState,
    },
}

/// One undoable step.
#[derive(Clone, Debug)]
pub struct Step {
    /// What the Edit menu calls it ("drag of light 3", "preset 'grid'").
    pub name: String,
    /// What it changed.
    pub change: Change,
    /// The gesture it belongs to (a drag): steps of one gesture merge into one.
    gesture: Option<u64>,
    /// The heap bytes it keeps alive ([`Change::heap_bytes`], counted once: a scene's names
    /// take `O(N)` to count).
    bytes: usize,
}

impl Change {
    /// Heap bytes this change keeps alive.
    fn heap_bytes(&self) -> usize {
        match self {
            Change::Powers(changes) => changes.capacity() * std::mem::size_of::<(u32, f64, f64)>(),
            // Both arrays, though one of them is usually the scene's own.
            Change::AllPowers { before, after } => {
                std::mem::size_of_val(&**before) + std::mem::size_of_val(&**after)
            }
            Change::Scene { before, .. } => before
                .scene
                .heap_bytes_by_part()
                .iter()
                .map(|(_, b)| b)
                .sum(),
        }
    }
}

/// The undo and redo stacks and what names the next step.
#[derive(Debug, Default)]
pub struct History {
    undo: Vec<Step>,
    redo: Vec<Step>,
    /// The name of the next recorded step (set by the edit that causes it).
    next_name: Option<String>,
    /// The drag in progress, if any: its steps merge.
    gesture: Option<u64>,
    gestures: u64,
    /// An undo or a redo is being applied from this scene generation on: its install is not
    /// a new step.
    pub(super) replaying: Option<u64>,
}

impl History {
    /// Names the step the next installed scene records.
    pub fn name_next(&mut self, name: impl Into<String>) {
        self.next_name = Some(name.into());
    }

    /// Starts a gesture (a drag): until [`History::end_gesture`], its steps are one.
    pub fn begin_gesture(&mut self) {
        self.gestures += 1;
        self.gesture = Some(self.gestures);
    }

    /// Ends the gesture in progress.
    pub fn end_gesture(&mut self) {
        self.gesture = None;
    }

    /// The name of the step Undo would take back.
    pub fn undo_name(&self) -> Option<&str> {
        self.undo.last().map(|s| s.name.as_str())
    }

    /// The name of the step Redo would apply again.
    pub fn redo_name(&self) -> Option<&str> {
        self.redo.last().map(|s| s.name.as_str())
    }

    /// Steps that can be undone.
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }

    /// Heap bytes the history keeps (its steps' own, and the replaced scenes they keep).
    pub fn heap_bytes(&self) -> usize {
        self.undo.iter().chain(&self.redo).map(|s| s.bytes).sum()
    }

    /// Records the change from `before` to `after` (called when `after` is installed),
    /// unless it is an undo or redo being applied; a new step clears the redo stack.
    pub(super) fn record(&mut self, before: SceneState, after: SceneState, generation: u64) {
        let name = self.next_name.take().unwrap_or_else(|| "edit".to_owned());
        // The scene an undo or a redo asked for (its generation or a later one) is no new
        // step; an older build finishing meanwhile still is.
        if self.replaying.is_some_and(|from| generation >= from) {
            self.replaying = None;
            return;
        }
        let Some(change) = change_between(before, after) else {
            return;
        };
        let gesture = self.gesture;
        if let (Some(g), Some(last)) = (gesture, self.undo.last_mut())
            && last.gesture == Some(g)
            && let (Change::Powers(old), Change::Powers(new)) = (&mut last.change, &change)
        {
            merge(old, new);
            let back_where_it_started = old.is_empty();
            last.bytes = last.change.heap_bytes();
            if back_where_it_started {
                // The drag came back to where it started: nothing to undo.
                self.undo.pop();
            }
            self.redo.clear();
            return;
        }
        let bytes = change.heap_bytes();
        self.undo.push(Step {
            name,
            change,
            gesture,
            bytes,
        });
        self.redo.clear();
        self.trim();
    }

    /// Drops the oldest steps until the history fits [`HISTORY_BUDGET`].
    fn trim(&mut self) {
        while self.heap_bytes() > HISTORY_BUDGET && !self.undo.is_empty() {
            self.undo.remove(0);
        }
    }

    /// Marks the last step's scene as the unedited preset `name` (a preset is known as one
    /// only once it is installed).
    pub(super) fn set_last_preset(&mut self, name: &str) {
        if let Some(Step {
            change: Change::Scene { after, .. },
            ..
        }) = self.undo.last_mut()
        {
            after.preset = Some(name.to_owned());
        }
    }

    /// Takes the step to undo (moved to the redo stack).
    pub(super) fn take_undo(&mut self) -> Option<Step> {
        let step = self.undo.pop()?;
        self.redo.push(step.clone());
        self.gesture = None;
        Some(step)
    }

    /// Takes the step to redo (moved back to the undo stack).
    pub(super) fn take_redo(&mut self) -> Option<Step> {
        let step = self.redo.pop()?;
        self.undo.push(step.clone());
        self.gesture = None;
        Some(step)
    }
}

impl AppState {
    /// Takes back the last scene edit (Ctrl+Z): the powers it changed, or the scene it
    /// replaced, bit for bit.
    pub fn undo(&mut self) {
        if let Some(step) = self.history.take_undo() {
            self.apply_step(&step.change, true);
            self.message(format!("undid {}", step.name), MessageKind::Info);
        }
    }

    /// Applies again the last undone edit (Ctrl+Shift+Z, Ctrl+Y).
    pub fn redo(&mut self) {
        if let Some(step) = self.history.take_redo() {
            self.apply_step(&step.change, false);
            self.message(format!("redid {}", step.name), MessageKind::Info);
        }
    }

    /// Puts the scene of `change` back (`back`) or forward; the install it causes is no
    /// new step.
    fn apply_step(&mut self, change: &Change, back: bool) {
        self.history.replaying = Some(self.next_generation());
        match change {
            Change::Powers(changes) => {
                let n = self.edit.powers.len();
                if changes.iter().any(|&(i, ..)| i as usize >= n) {
                    self.history.replaying = None;
                    self.message(
                        "cannot undo: the scene has changed under it",
                        MessageKind::Error,
                    );
                    return;
                }
                let powers = self.edit.powers_mut();
                for &(i, before, after) in changes {
                    powers[i as usize] = if back { before } else { after };
                }
                self.unedited_preset = None;
                self.after_structure_change();
            }
            Change::AllPowers { before, after } => {
                if before.len() != self.edit.powers.len() {
                    self.history.replaying = None;
                    self.message(
                        "cannot undo: the scene has changed under it",
                        MessageKind::Error,
                    );
                    return;
                }
                self.edit.powers = Arc::clone(if back { before } else { after });
                self.unedited_preset = None;
                self.after_structure_change();
            }
            Change::Scene { before, after } => {
                let state = if back { before } else { after };
                self.load_scene((*state.scene).clone());
                self.edit.floor = state.floor;
                self.unedited_preset.clone_from(&state.preset);
                self.installed = (state.floor, state.preset.clone());
            }
        }
    }
}

/// A power edit that changes more than one light in this many (and at least
/// [`DENSE_CHANGE_MIN`]) is kept as the powers before and after it (8 bytes a light each, shared with the scenes) rather than as its changes
/// (24 bytes a changed light, written out on the UI thread as the edit is installed: 15 ms
/// for 10^6 lights).
const DENSE_CHANGE_PER_LIGHTS: usize = 3;

/// Fewer changed lights than this are always kept as their changes: a drag's steps merge
/// into one gesture ([`merge`]) on a scene of any size, and the changes stay small.
const DENSE_CHANGE_MIN: usize = 1 << 12;

/// The change from `before` to `after`: the powers that differ when nothing else does and
/// at most one light in [`DENSE_CHANGE_PER_LIGHTS`] changed, all the powers when more did,
/// the whole scenes otherwise;
/// `None` when they are the same (bit for bit).
fn change_between(before: SceneState, after: SceneState) -> Option<Change> {
    let (a, b) = (&before.scene, &after.scene);
    if Arc::ptr_eq(a, b) {
        return None;
    }
    let same_lights = a.light_count() == b.light_count()
        && a.same_geometry(b)
        && a.name == b.name
        && a.names == b.names
        && a.plane == b.plane
        && before.floor == after.floor;
    if same_lights {
        let (old, new) = (a.powers.as_slice(), b.powers.as_slice());
        let changed = old
            .iter()
            .zip(new)
            .filter(|(x, y)| x.to_bits() != y.to_bits())
            .count();
        if changed >= DENSE_CHANGE_MIN && changed * DENSE_CHANGE_PER_LIGHTS > old.len() {
            // Most powers changed (Randomize, a typed list): both arrays, shared (8 bytes a
            // light each), not 24 bytes a changed light.
            return Some(Change::AllPowers {
                before: Arc::clone(a.powers.shared()),
                after: Arc::clone(b.powers.shared()),
            });
        }
        // Counted above: the changes fill their allocation exactly.
        let mut changes: Vec<(u32, f64, f64)> = Vec::with_capacity(changed);
        changes.extend(
            old.iter()
                .zip(new)
                .enumerate()
                .filter(|(_, (x, y))| x.to_bits() != y.to_bits())
                .map(|(i, (x, y))| (i as u32, *x, *y)),
        );
        return (!changes.is_empty()).then_some(Change::Powers(changes));
    }
    Some(Change::Scene { before, after })
}

/// `old` followed by `new`, as one change: each light's first `before` and last `after`.
fn merge(old: &mut Vec<(u32, f64, f64)>, new: &[(u32, f64, f64)]) {
    let mut by_light: BTreeMap<u32, (f64, f64)> =
        old.iter().map(|&(i, b, a)| (i, (b, a))).collect();
    for &(i, b, a) in new {
        by_light
            .entry(i)
            .and_modify(|(_, after)| *after = a)
            .or_insert((b, a));
    }
    *old = by_light
        .into_iter()
        .filter(|(_, (b, a))| b.to_bits() != a.to_bits())
        .map(|(i, (b, a))| (i, b, a))
        .collect();
    old.shrink_to_fit();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gesture_is_one_step_with_the_first_before_and_the_last_after() {
        let mut old = vec![(2, 1.0, 2.0)];
        merge(&mut old, &[(2, 2.0, 3.0), (4, 5.0, 6.0)]);
        assert_eq!(old, [(2, 1.0, 3.0), (4, 5.0, 6.0)]);
        // Back where it started: nothing left to undo for that light.
        merge(&mut old, &[(4, 6.0, 5.0)]);
        assert_eq!(old, [(2, 1.0, 3.0)]);
    }
}
