//! The app's session between runs, in memory: eframe's storage as a map, and the app
//! eframe would create from it.

use lightpick::app::LightpickApp;

/// eframe's storage, in memory: the app's own map storage.
pub use lightpick::app::session_files::MapStorage as MemoryStorage;

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
