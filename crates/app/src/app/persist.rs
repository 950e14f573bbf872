//! What the app keeps between sessions through eframe's storage: the settings, the layout,
//! and the scene: light by light when small; by preset name when it is an unedited large
//! preset; otherwise, when the app has a session folder, in a compact file beside the
//! session ([`session_files`]), so a scene of any size comes back. A session that cannot be
//! read (a damaged file, one written by a newer lightpick, settings an older one wrote that
//! no longer parse) is said in the status bar, kept aside, and the app starts on defaults.

use std::path::{Path, PathBuf};

use super::panels::layout;
use super::session_files;
use super::state::{AppState, MessageKind, Settings, auto_exposure};
use super::{LightpickApp, scene_io};

/// Storage key of the persisted [`Settings`].
const SETTINGS_KEY: &str = "lightpick.settings";
/// Storage key of the persisted [`layout::Layout`] (the maximized panel, the tabs chosen).
const LAYOUT_KEY: &str = "lightpick.layout";
/// Storage key of the persisted scene (JSON).
const SCENE_KEY: &str = "lightpick.scene";
/// Storage key of the preset name, for a large scene that is an unedited preset.
const SCENE_PRESET_KEY: &str = "lightpick.scene_preset";
/// Storage key of the compact scene file's path, for a large scene kept beside the session.
const SCENE_FILE_KEY: &str = "lightpick.scene_file";
/// Storage key of the session format's version ([`SESSION_VERSION`]).
const VERSION_KEY: &str = "lightpick.session_version";
/// The session format this build writes: a session of a later version is not read.
pub const SESSION_VERSION: u32 = 2;
/// Every key lightpick keeps in eframe's storage.
const ALL_KEYS: [&str; 6] = [
    VERSION_KEY,
    SETTINGS_KEY,
    LAYOUT_KEY,
    SCENE_KEY,
    SCENE_PRESET_KEY,
    SCENE_FILE_KEY,
];
/// Scenes with more lights are not persisted light by light in eframe's storage.
const PERSIST_SCENE_LIMIT: usize = 20_000;

impl LightpickApp {
    /// The app as eframe creates it: restores the settings and the last scene, with the
    /// platform's session folder ([`session_files::default_session_dir`]).
    pub fn new(cc: &eframe::CreationContext<'_>) -> Self {
        Self::restore(cc, session_files::default_session_dir())
    }

    /// [`LightpickApp::new`] with the session folder `session_dir` (where a large scene is
    /// kept, and where eframe's session file is checked for damage); `None`: no folder.
    pub fn restore(cc: &eframe::CreationContext<'_>, session_dir: Option<PathBuf>) -> Self {
        let mut settings = Settings::default();
        let mut scene = None;
        let mut problems: Vec<String> = Vec::new();
        let mut layout = None;
        let damaged = session_dir
            .as_deref()
            .and_then(session_files::damaged_session);
        // eframe's file damaged (or without lightpick's keys) while the session's own copy,
        // written whole or not at all, is there: restore from the copy.
        let eframe_has_settings = cc
            .storage
            .is_some_and(|s| s.get_string(SETTINGS_KEY).is_some());
        let copy = session_dir
            .as_deref()
            .filter(|_| damaged.is_some() || !eframe_has_settings)
            .and_then(session_files::read_session_copy)
            .map(session_files::MapStorage);
        if let Some(problem) = damaged {
            problems.push(if copy.is_some() {
                format!(
                    "{problem}; restored from its copy {}",
                    session_files::SESSION_COPY
                )
            } else {
                problem
            });
        }
        let from: Option<&dyn eframe::Storage> = match &copy {
            Some(copy) => Some(copy),
            None => cc.storage,
        };
        let storage = from.filter(|storage| match session_version(*storage) {
            Some(v) if v > SESSION_VERSION => {
                let kept = session_dir
                    .as_deref()
                    .map_or_else(String::new, |dir| keep_copy(dir, "newer"));
                problems.push(format!(
                    "last session could not be read: it was written by a newer lightpick \
                     (session version {v}, this one reads {SESSION_VERSION}){kept}; the app \
                     starts on defaults"
                ));
                false
            }
            _ => true,
        });
        if let Some(storage) = storage {
            layout = eframe::get_value::<layout::Layout>(storage, LAYOUT_KEY);
            match eframe::get_value::<Settings>(storage, SETTINGS_KEY) {
                Some(s) => settings = s,
                None if storage.get_string(SETTINGS_KEY).is_some() => {
                    let kept = session_dir
                        .as_deref()
                        .map_or_else(String::new, |dir| keep_copy(dir, "unread"));
                    problems.push(format!(
                        "last session's settings could not be read (an older lightpick's?){kept}; \
                         default settings"
                    ));
                }
                None => {}
            }
            match restore_scene(storage) {
                Ok(restored) => scene = restored,
                Err(e) => problems.push(format!("last scene not restored: {e}")),
            }
        }
        // The exposure belongs to the scene it was set for: without that scene, the worked
        // example's own.
        let scene = scene.unwrap_or_else(|| {
            let example = scene_io::worked_example_scene();
            settings.exposure = auto_exposure(&example);
            example
        });
        let mut app = Self::with_state(AppState::new(scene, settings), true);
        app.session_dir = session_dir;
        if let Some(layout) = layout {
            app.layout = layout;
        }
        if !problems.is_empty() {
            app.state.message(problems.join(" · "), MessageKind::Error);
        }
        app
    }

    /// Writes the settings, the layout and the scene to `storage` (a large scene to the
    /// compact file in the session folder, when it changed since the last save).
    pub fn save_to(&mut self, storage: &mut dyn eframe::Storage) {
        let mut keys = session_files::MapStorage::default();
        self.save_keys(&mut keys);
        for key in ALL_KEYS {
            match keys.0.get(key) {
                Some(value) => storage.set_string(key, value.clone()),
                None => storage.remove_string(key),
            }
        }
        // The session's own copy, written whole or not at all.
        if let Some(dir) = &self.session_dir
            && let Err(e) = session_files::write_session_copy(dir, &keys.0)
        {
            self.state.message(
                format!("the session could not be kept: {e}"),
                MessageKind::Error,
            );
        }
    }

    /// Writes the settings, the layout and the scene's key to `storage`.
    fn save_keys(&mut self, storage: &mut dyn eframe::Storage) {
        storage.set_string(VERSION_KEY, SESSION_VERSION.to_string());
        eframe::set_value(storage, SETTINGS_KEY, &self.state.settings);
        eframe::set_value(storage, LAYOUT_KEY, &self.layout);
        // While the walkthrough shows the classic scene, the user's own scene is the one kept.
        let built = std::sync::Arc::clone(&self.state.built.scene);
        let saved = self.state.walkthrough.saved_scene.as_ref();
        let scene = saved.unwrap_or(&built);
        let preset = self
            .state
            .unedited_preset
            .as_ref()
            .filter(|_| saved.is_none());
        if scene.light_count() <= PERSIST_SCENE_LIMIT {
            storage.set_string(SCENE_KEY, scene_io::to_json(scene));
        } else if let Some(name) = preset {
            storage.set_string(SCENE_PRESET_KEY, name.clone());
        } else if let Some(dir) = &self.session_dir {
            let path = dir.join(session_files::SCENE_FILE);
            // The compact file is written again only for a new scene.
            let key = (self.state.built.generation, saved.is_some());
            let written = if self.saved_scene == Some(key) && path.exists() {
                Ok(())
            } else {
                std::fs::create_dir_all(dir).and_then(|()| session_files::write_scene(&path, scene))
            };
            match written {
                Ok(()) => {
                    self.saved_scene = Some(key);
                    storage.set_string(SCENE_FILE_KEY, path.display().to_string());
                }
                Err(e) => self.state.message(
                    format!("the scene could not be kept for the next session: {e}"),
                    MessageKind::Error,
                ),
            }
        }
    }
}

/// The session format version in `storage` (`Some(1)` for a session written before
/// versions were kept).
fn session_version(storage: &dyn eframe::Storage) -> Option<u32> {
    match storage.get_string(VERSION_KEY) {
        Some(v) => v.trim().parse().ok().or(Some(u32::MAX)),
        None => storage.get_string(SETTINGS_KEY).map(|_| 1),
    }
}

/// The scene `storage` names: light by light, a preset, or the compact file beside the
/// session; `None` when it names none.
fn restore_scene(
    storage: &dyn eframe::Storage,
) -> Result<Option<lightpick_core::scene::Scene>, String> {
    if let Some(text) = storage.get_string(SCENE_KEY) {
        return scene_io::from_json_str(&text).map(Some);
    }
    if let Some(name) = storage.get_string(SCENE_PRESET_KEY) {
        return scene_io::preset(&name).map(Some);
    }
    if let Some(path) = storage.get_string(SCENE_FILE_KEY) {
        return session_files::read_scene(Path::new(&path)).map(Some);
    }
    Ok(None)
}

/// Copies eframe's session file in `dir` aside (`app.ron.WHY-SECONDS`) before it is
/// overwritten; the words that say where (or why not), starting with "; ".
fn keep_copy(dir: &Path, why: &str) -> String {
    let from = dir.join("app.ron");
    let seconds = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let to = dir.join(format!("app.ron.{why}-{seconds}"));
    match std::fs::copy(&from, &to) {
        Ok(_) => format!("; kept as {}", to.display()),
        Err(_) => String::new(),
    }
}
