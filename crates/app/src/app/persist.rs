//! What the app keeps between sessions through eframe's storage: the settings, the layout,
//! and the scene (light by light when small; by preset name when it is an unedited large
//! preset; otherwise none, and the seed scene opens next time).

use super::panels::layout;
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
/// Scenes with more lights are not persisted light by light.
const PERSIST_SCENE_LIMIT: usize = 20_000;

impl LightpickApp {
    /// The app as eframe creates it: restores the settings and the last scene.
    pub fn new(cc: &eframe::CreationContext<'_>) -> Self {
        let mut settings = Settings::default();
        let mut scene = None;
        let mut restore_error = None;
        let mut layout = None;
        if let Some(storage) = cc.storage {
            layout = eframe::get_value::<layout::Layout>(storage, LAYOUT_KEY);
            if let Some(s) = eframe::get_value::<Settings>(storage, SETTINGS_KEY) {
                settings = s;
            }
            if let Some(text) = storage.get_string(SCENE_KEY) {
                match scene_io::from_json_str(&text) {
                    Ok(s) => scene = Some(s),
                    Err(e) => restore_error = Some(format!("last scene not restored: {e}")),
                }
            } else if let Some(name) = storage.get_string(SCENE_PRESET_KEY) {
                match scene_io::preset(&name) {
                    Ok(s) => scene = Some(s),
                    Err(e) => restore_error = Some(format!("last scene not restored: {e}")),
                }
            }
        }
        // The exposure belongs to the scene it was set for: without that scene, the seed
        // scene's own.
        let scene = scene.unwrap_or_else(|| {
            let seed = scene_io::seed_scene();
            settings.exposure = auto_exposure(&seed);
            seed
        });
        let mut app = Self::with_state(AppState::new(scene, settings), true);
        if let Some(layout) = layout {
            app.layout = layout;
        }
        if let Some(e) = restore_error {
            app.state.message(e, MessageKind::Error);
        }
        app
    }

    /// Writes the settings, the layout and the scene to `storage`.
    pub(super) fn save_to(&self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, SETTINGS_KEY, &self.state.settings);
        eframe::set_value(storage, LAYOUT_KEY, &self.layout);
        // While the walkthrough shows the classic scene, the user's own scene is the one kept.
        let scene = self
            .state
            .walkthrough
            .saved_scene
            .as_ref()
            .unwrap_or(&self.state.built.scene);
        // Small scenes are kept light by light; a large one only when it is an unedited
        // preset (kept by name); otherwise none is kept, and the seed scene opens next time.
        if scene.light_count() <= PERSIST_SCENE_LIMIT {
            storage.set_string(SCENE_KEY, scene_io::to_json(scene));
            storage.remove_string(SCENE_PRESET_KEY);
        } else {
            storage.remove_string(SCENE_KEY);
            let preset = self
                .state
                .unedited_preset
                .as_ref()
                .filter(|_| self.state.walkthrough.saved_scene.is_none());
            match preset {
                Some(name) => storage.set_string(SCENE_PRESET_KEY, name.clone()),
                None => storage.remove_string(SCENE_PRESET_KEY),
            }
        }
    }
}
