//! The app's session between runs, in memory: eframe's storage as a map, and the app
//! eframe would create from it.

use std::collections::HashMap;

use lightpick::app::LightpickApp;

/// eframe's storage, in memory.
#[derive(Default)]
pub struct MemoryStorage(pub HashMap<String, String>);

impl eframe::Storage for MemoryStorage {
    fn get_string(&self, key: &str) -> Option<String> {
        self.0.get(key).cloned()
    }
    fn set_string(&mut self, key: &str, value: String) {
        self.0.insert(key.to_owned(), value);
    }
    fn remove_string(&mut self, key: &str) {
        self.0.remove(key);
    }
    fn flush(&mut self) {}
}

/// The app eframe creates from `storage`, without a session folder (tests never touch the
/// user's own).
pub fn restored(storage: &MemoryStorage) -> LightpickApp {
    let mut cc = eframe::CreationContext::_new_kittest(egui::Context::default());
    cc.storage = Some(storage);
    LightpickApp::restore(&cc, None)
}

/// [`restored`] with the session folder `dir` (where a large scene is kept and eframe's
/// session file is checked).
pub fn restored_in(storage: &MemoryStorage, dir: &std::path::Path) -> LightpickApp {
    let mut cc = eframe::CreationContext::_new_kittest(egui::Context::default());
    cc.storage = Some(storage);
    LightpickApp::restore(&cc, Some(dir.to_path_buf()))
}
