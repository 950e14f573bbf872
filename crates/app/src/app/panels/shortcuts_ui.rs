//! The presenter's keys, in one list: the shortcuts overlay (F1 or ?) shows it, the shell
//! acts on it ([`PANEL_KEYS`], [`preset_key`]), and the README's lesson plan quotes it.

use egui::{Key, Ui};

use super::panel_kind::PanelKind;
use crate::app::state::AppState;

/// Plain digit keys that bring a main panel to the front (its tab chosen): 1 to 6.
pub const PANEL_KEYS: [(Key, PanelKind); 6] = [
    (Key::Num1, PanelKind::Lights),
    (Key::Num2, PanelKind::Table),
    (Key::Num3, PanelKind::Sampling),
    (Key::Num4, PanelKind::Images),
    (Key::Num5, PanelKind::Convergence),
    (Key::Num6, PanelKind::LightTree),
];

/// The digit keys that, with Alt, load the presets in their menu order (Alt+1 the first,
/// Alt+0 the tenth).
pub const PRESET_DIGITS: [Key; 10] = [
    Key::Num1,
    Key::Num2,
    Key::Num3,
    Key::Num4,
    Key::Num5,
    Key::Num6,
    Key::Num7,
    Key::Num8,
    Key::Num9,
    Key::Num0,
];

/// The preset Alt+`key` loads, in the order of `names` (the Lights panel's preset row).
pub fn preset_key<'a>(key: Key, names: &[&'a str]) -> Option<&'a str> {
    PRESET_DIGITS
        .iter()
        .position(|k| *k == key)
        .and_then(|i| names.get(i).copied())
}

/// Every shortcut the app has, as the overlay lists it: (keys, what they do).
pub fn shortcut_rows(presets: &[&str]) -> Vec<(String, String)> {
    let mut rows: Vec<(String, String)> = [
        ("F1 or ?", "show or hide this list"),
        ("Space", "run or pause the images and histograms"),
        ("N", "one frame while paused"),
        ("R", "clear the images and start again"),
        ("Ctrl+Z", "undo the last scene edit"),
        ("Ctrl+Shift+Z or Ctrl+Y", "redo it"),
        ("Ctrl+O / Ctrl+S", "open / save a scene"),
        (
            "Ctrl + / Ctrl − / Ctrl+0",
            "zoom the whole window in / out / back",
        ),
        ("Escape", "restore a maximized panel"),
        (
            "Page Down / Page Up",
            "next / previous step of the walkthrough (or of the light tree's pick)",
        ),
    ]
    .iter()
    .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
    .collect();
    for (key, panel) in PANEL_KEYS {
        rows.push((
            key.name().to_owned(),
            format!("show the {} panel", super::layout::title(panel)),
        ));
    }
    for (key, name) in PRESET_DIGITS.iter().zip(presets) {
        rows.push((format!("Alt+{}", key.name()), format!("preset '{name}'")));
    }
    rows
}

/// The shortcuts overlay: a window listing [`shortcut_rows`], open while
/// `state.settings.show_shortcuts`.
pub fn shortcuts_window(ctx: &egui::Context, state: &mut AppState) {
    let mut open = state.settings.show_shortcuts;
    let presets = crate::app::scene_io::preset_names();
    egui::Window::new("Keyboard shortcuts")
        .open(&mut open)
        .collapsible(false)
        .default_width(460.0)
        // Below the menu bar, which it would otherwise cover.
        .default_pos([40.0, 60.0])
        .show(ctx, |ui| shortcuts_ui(ui, &presets));
    state.settings.show_shortcuts = open;
}

/// The list itself, in two columns.
fn shortcuts_ui(ui: &mut Ui, presets: &[&str]) {
    ui.label("Plain keys work while no text field has the focus.");
    egui::ScrollArea::vertical().show(ui, |ui| {
        egui::Grid::new("shortcuts")
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                for (keys, what) in shortcut_rows(presets) {
                    ui.strong(keys);
                    ui.label(what);
                    ui.end_row();
                }
            });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_has_its_key_in_menu_order() {
        let names: &[&str] = &lightpick_core::scene::PRESET_NAMES;
        assert_eq!(preset_key(Key::Num1, names), Some(names[0]));
        assert_eq!(preset_key(Key::Num0, names), names.get(9).copied());
        assert_eq!(preset_key(Key::A, names), None);
        let rows = shortcut_rows(names);
        assert!(
            rows.iter()
                .any(|(k, v)| k == "Alt+1" && v.contains(names[0]))
        );
        assert!(rows.iter().any(|(k, v)| k == "4" && v.contains("Images")));
    }
}
