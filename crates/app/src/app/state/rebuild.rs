//! From an edit or a new scene to the [`Built`] the panels show: validation, the next scene
//! generation, and the build itself — within the frame for up to [`SYNC_BUILD_LIMIT`]
//! lights, on a worker beyond (one at a time; the newest edit waits for the running build
//! and wins), rebuilding a large scene's power edit into the samplers two edits back.

use std::sync::Arc;

use lightpick_core::scene::Scene;
use lightpick_core::{LightPowers, SceneSamplers};

use super::built::Built;
use super::edit::{SceneEdit, describe_powers_error, powers_to_text};
use super::history::SceneState;
use super::settings::{auto_exposure, nice_ceiling};
use super::{AppState, MessageKind};
use crate::app::background::{Job, JobPolled};
use crate::app::scene_io;

/// Tables of at most this many lights are rebuilt on the UI thread, within the frame.
pub const SYNC_BUILD_LIMIT: usize = 50_000;

/// The table (with its samplers) being built on a worker, keyed by its scene generation.
pub(super) type TableBuild = Job<u64, Built>;

/// Seconds the replaced samplers of a large scene are kept for the next power edit.
const EARLIER_KEPT_S: f64 = 1.0;

impl AppState {
    /// Whether a table is being built in the background.
    pub fn is_building(&self) -> bool {
        self.pending.is_running()
    }

    /// Replaces the whole scene (preset, file, generated): the edit, the text field and the
    /// table, and a slider range that fits it.
    pub fn load_scene(&mut self, scene: Scene) {
        self.unedited_preset = None;
        self.edit = SceneEdit::from_scene(&scene);
        self.powers_text = powers_to_text(&self.edit.powers);
        self.input_error = None;
        self.diagram_offset = 0;
        self.settings.slider_max = nice_ceiling(2.0 * scene.powers.max());
        self.settings.exposure = auto_exposure(&scene);
        let n = scene.light_count();
        self.pending.cancel();
        self.rebuild_queued = false;
        if n <= SYNC_BUILD_LIMIT {
            let generation = self.take_generation();
            self.install(Built::new(generation, scene));
        } else {
            self.spawn_build(scene);
        }
    }

    /// Loads the bundled scene `name` ([`scene_io::preset`]), or says why it cannot.
    pub fn load_preset(&mut self, name: &str) {
        match scene_io::preset(name) {
            Ok(scene) => {
                self.history.name_next(format!("preset '{name}'"));
                self.load_scene(scene);
                self.unedited_preset = Some(name.to_owned());
                self.installed.1 = Some(name.to_owned());
                if !self.is_building() {
                    self.history.set_last_preset(name);
                }
                self.message(format!("loaded preset '{name}'"), MessageKind::Info);
            }
            Err(e) => self.message(e, MessageKind::Error),
        }
    }

    /// Call after any change of `edit.powers`: validates and rebuilds, or names the problem
    /// and keeps the last good table.
    pub fn powers_changed(&mut self) {
        self.unedited_preset = None;
        if self.edit.powers.len() > SYNC_BUILD_LIMIT && self.pending.is_running() {
            // One background build at a time: this edit is validated and built as soon as
            // the running build lands (the latest values win; intermediate ones are skipped).
            self.rebuild_queued = true;
            return;
        }
        match LightPowers::from_shared(Arc::clone(&self.edit.powers)) {
            Err(e) => {
                self.input_error = Some(describe_powers_error(&e));
            }
            Ok(powers) => {
                self.input_error = None;
                self.sync_positions(powers.len());
                let mut scene = Scene::new(
                    &self.edit.name,
                    self.edit.plane.clone(),
                    Arc::clone(&self.edit.positions),
                    powers,
                );
                scene.emission.clone_from(&self.edit.emission);
                scene.names.clone_from(&self.edit.names);
                if scene.light_count() <= SYNC_BUILD_LIMIT {
                    self.pending.cancel();
                    self.rebuild_queued = false;
                    let generation = self.take_generation();
                    let built = Built::from_edit(generation, scene, &self.built.samplers, None);
                    self.install(built);
                } else if self.pending.is_running() {
                    self.rebuild_queued = true;
                } else {
                    // A power edit keeps the geometry: the worker refits the tree, into the
                    // one two edits back if nothing holds it any more.
                    let earlier = self.earlier.take().map(|(_, samplers)| samplers);
                    self.spawn_build_from(scene, Some((self.built.samplers.clone(), earlier)));
                }
            }
        }
    }

    /// The generation the next scene built will have.
    pub(super) fn next_generation(&self) -> u64 {
        self.next_generation
    }

    fn take_generation(&mut self) -> u64 {
        let g = self.next_generation;
        self.next_generation += 1;
        g
    }

    fn install(&mut self, built: Built) {
        let replaced = std::mem::replace(&mut self.built, Arc::new(built));
        let before = SceneState {
            scene: Arc::clone(&replaced.scene),
            floor: self.installed.0,
            preset: self.installed.1.take(),
        };
        self.installed = (self.edit.floor, self.unedited_preset.clone());
        let after = SceneState {
            scene: Arc::clone(&self.built.scene),
            floor: self.edit.floor,
            preset: self.unedited_preset.clone(),
        };
        self.history.record(before, after, self.built.generation);
        self.earlier = (self.built.len() > SYNC_BUILD_LIMIT
            && replaced.scene.same_geometry(&self.built.scene))
        .then(|| Arc::try_unwrap(replaced).ok())
        .flatten()
        .map(|replaced| (std::time::Instant::now(), replaced.samplers));
        if self.diagram_offset >= self.built.len() {
            self.diagram_offset = 0;
        }
        self.restart_sampling();
    }

    fn spawn_build(&mut self, scene: Scene) {
        self.spawn_build_from(scene, None);
    }

    /// Builds on a worker thread: [`Built::from_edit`] when the previous samplers are given
    /// (a refit when the geometry is kept; into the earlier ones where given and unshared),
    /// else [`Built::new`].
    fn spawn_build_from(
        &mut self,
        scene: Scene,
        previous: Option<(SceneSamplers, Option<SceneSamplers>)>,
    ) {
        let generation = self.take_generation();
        let spawned = self
            .pending
            .start(generation, "lightpick-table", move || match previous {
                Some((previous, earlier)) => {
                    Built::from_edit(generation, scene, &previous, earlier)
                }
                None => Built::new(generation, scene),
            });
        if let Err(e) = spawned {
            self.message(
                format!("cannot start the table builder: {e}"),
                MessageKind::Error,
            );
        }
    }

    /// Installs a table finished in the background; call once per frame.
    pub fn poll_build(&mut self) {
        if self
            .earlier
            .as_ref()
            .is_some_and(|(at, _)| at.elapsed().as_secs_f64() > EARLIER_KEPT_S)
        {
            self.earlier = None;
        }
        match self.pending.poll() {
            JobPolled::Done(generation, built) => {
                debug_assert_eq!(built.generation, generation);
                self.install(built);
                if std::mem::take(&mut self.rebuild_queued) {
                    self.powers_changed();
                }
            }
            JobPolled::Idle => {}
            JobPolled::Lost(_) => {
                self.message("the table builder stopped unexpectedly", MessageKind::Error);
            }
        }
    }
}
