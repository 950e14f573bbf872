//! The in-app file chooser for opening and saving scenes and exporting PNGs: the current
//! folder's sub-folders and files (filtered to the action's types, or all), Up and Home, a
//! path field (absolute, or relative to the folder) filled by a click on a file, OK and
//! Cancel; a double click on a file confirms. It works wherever the app runs (no desktop
//! portal needed; egui-file-dialog has no egui 0.37 release). A failure is shown in the
//! dialog and in the status bar; the path stays as typed and the current scene is kept.

use std::path::{Path, PathBuf};

use egui::Ui;

use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::file_dialog::{FileAction, FileDialog, FolderEntry};

/// What the user confirmed in the dialog this frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Confirmed {
    /// The action.
    pub action: FileAction,
    /// The path to act on: the typed path, within the shown folder unless absolute.
    pub path: String,
}

/// The entries of `folder`: sub-folders first, then files, each by name; hidden ones (a
/// leading dot) left out.
pub fn list_folder(folder: &Path) -> Result<Vec<FolderEntry>, String> {
    let read = std::fs::read_dir(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
    let mut entries: Vec<FolderEntry> = read
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') {
                return None;
            }
            let meta = e.metadata().ok()?;
            Some(FolderEntry {
                name,
                is_dir: meta.is_dir(),
                bytes: meta.len(),
            })
        })
        .collect();
    entries.sort_by(|a, b| b.is_dir.cmp(&a.is_dir).then_with(|| a.name.cmp(&b.name)));
    Ok(entries)
}

/// Whether `name` has one of `extensions` (case-insensitive).
fn has_extension(name: &str, extensions: &[&str]) -> bool {
    Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| extensions.iter().any(|x| x.eq_ignore_ascii_case(e)))
}

/// "12.3 kB"-style sizes.
fn size_text(bytes: u64) -> String {
    let b = bytes as f64;
    if b < 1e3 {
        format!("{bytes} B")
    } else if b < 1e6 {
        format!("{:.1} kB", b / 1e3)
    } else if b < 1e9 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.2} GB", b / 1e9)
    }
}

/// Lists the dialog's folder again if it changed since the last listing.
fn refresh(dialog: &mut FileDialog) {
    let folder = dialog.folder();
    if dialog.listing.as_ref().is_none_or(|(f, _)| *f != folder) {
        let entries = list_folder(&folder);
        dialog.listing = Some((folder, entries));
    }
}

/// Moves the dialog to `folder`.
fn enter(dialog: &mut FileDialog, folder: PathBuf) {
    dialog.folder = Some(folder);
    dialog.listing = None;
}

/// Up, Home and the folder shown; the "All files" switch.
fn folder_ui(ui: &mut Ui, dialog: &mut FileDialog, folder: &Path, types_label: &str) {
    ui.horizontal(|ui| {
        let parent = folder.parent().map(Path::to_owned);
        if ui
            .add_enabled(parent.is_some(), egui::Button::new("Up"))
            .on_hover_text("The folder above")
            .clicked()
            && let Some(parent) = parent
        {
            enter(dialog, parent);
        }
        if let Some(home) = std::env::var_os("HOME").map(PathBuf::from)
            && ui
                .button("Home")
                .on_hover_text(home.display().to_string())
                .clicked()
        {
            enter(dialog, home);
        }
        ui.label(egui::RichText::new(folder.display().to_string()).monospace())
            .on_hover_text("The folder shown");
    });
    ui.horizontal(|ui| {
        ui.checkbox(&mut dialog.all_files, "All files")
            .on_hover_text(format!("Show every file, not only {types_label}"));
        if !dialog.all_files {
            ui.weak(format!("showing {types_label}"));
        }
    });
}

/// The folder's entries (folders, then the action's files or all), scrolling in
/// `list_height`: returns a folder clicked and a file picked (`true`: double-clicked, to
/// confirm).
fn entries_ui(
    ui: &mut Ui,
    dialog: &FileDialog,
    folder: &Path,
    extensions: &[&str],
    (list_height, width): (f32, f32),
    dark: bool,
) -> (Option<PathBuf>, Option<(String, bool)>) {
    let mut open_folder = None;
    let mut picked = None;
    egui::ScrollArea::vertical()
        .id_salt("file_dialog_entries")
        .max_height(list_height)
        .min_scrolled_height(list_height)
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.set_min_width(480.0_f32.min(width - 80.0));
            match dialog.listing.as_ref().map(|(_, l)| l) {
                Some(Ok(entries)) => {
                    let shown = entries.iter().filter(|e| {
                        e.is_dir || dialog.all_files || has_extension(&e.name, extensions)
                    });
                    for entry in shown {
                        if entry.is_dir {
                            if ui
                                .selectable_label(false, format!("{}/", entry.name))
                                .on_hover_text("Open this folder")
                                .clicked()
                            {
                                open_folder = Some(folder.join(&entry.name));
                            }
                        } else {
                            let selected = dialog.path == entry.name;
                            let response = ui
                                .selectable_label(
                                    selected,
                                    format!("{}   {}", entry.name, size_text(entry.bytes)),
                                )
                                .on_hover_text("Click to choose, double-click to confirm");
                            if response.double_clicked() {
                                picked = Some((entry.name.clone(), true));
                            } else if response.clicked() {
                                picked = Some((entry.name.clone(), false));
                            }
                        }
                    }
                }
                Some(Err(e)) => {
                    ui.colored_label(colors::error(dark), e);
                }
                None => {}
            }
        });
    (open_folder, picked)
}

/// Shows the dialog when an action is pending; returns the action confirmed this frame.
pub fn file_dialog_ui(ui: &mut Ui, state: &mut AppState) -> Option<Confirmed> {
    let action = state.file_dialog.action?;
    let dark = state.dark();
    refresh(&mut state.file_dialog);
    let mut confirmed = None;
    let mut cancel = false;
    let (types_label, extensions) = action.file_types();
    let screen = ui.ctx().content_rect();
    egui::Window::new(action.title())
        .id(egui::Id::unique("lightpick_file_dialog"))
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .show(ui.ctx(), |ui| {
            let dialog = &mut state.file_dialog;
            let folder = dialog.folder();
            folder_ui(ui, dialog, &folder, types_label);
            let list_height = (screen.height() * 0.45).clamp(120.0, 360.0);
            let (open_folder, picked) = entries_ui(
                ui,
                dialog,
                &folder,
                extensions,
                (list_height, screen.width()),
                dark,
            );
            if let Some(f) = open_folder {
                enter(dialog, f);
            }
            if let Some((name, confirm)) = picked {
                dialog.path = name;
                if confirm {
                    confirmed = Some(action);
                }
            }
            ui.horizontal(|ui| {
                let label = ui.label("Path");
                let response = ui
                    .add(
                        egui::TextEdit::singleline(&mut dialog.path)
                            .desired_width(420.0_f32.min(screen.width() - 160.0)),
                    )
                    .labelled_by(label.id)
                    .on_hover_text("A file name in the folder above, or an absolute path");
                if response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                    confirmed = Some(action);
                }
            });
            if let Some(error) = &dialog.error {
                ui.colored_label(colors::error(dark), format!("Error: {error}"));
            }
            ui.horizontal(|ui| {
                if ui.button("OK").on_hover_text(action.title()).clicked() {
                    confirmed = Some(action);
                }
                if ui
                    .button("Cancel")
                    .on_hover_text("Close without doing anything")
                    .clicked()
                {
                    cancel = true;
                }
            });
        });
    if cancel || ui.input(|i| i.key_pressed(egui::Key::Escape)) {
        state.file_dialog.action = None;
        return None;
    }
    confirmed.map(|action| {
        // A refreshed listing shows a file just saved.
        state.file_dialog.listing = None;
        Confirmed {
            action,
            path: state.file_dialog.resolved().display().to_string(),
        }
    })
}

/// A veil over the window while files are dragged over it, saying what a drop does.
pub fn drop_hint_ui(ui: &Ui) {
    let rect = ui.ctx().content_rect();
    let painter = ui.ctx().layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::unique("lightpick_drop_hint"),
    ));
    painter.rect_filled(rect, 0.0, egui::Color32::from_black_alpha(170));
    painter.text(
        rect.center(),
        egui::Align2::CENTER_CENTER,
        "Drop a scene to open it: glTF (.gltf, .glb), CSV or lightpick JSON",
        egui::FontId::proportional(22.0),
        egui::Color32::WHITE,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_come_first_and_types_filter_files() {
        let dir = std::env::temp_dir().join(format!("lightpick-dialog-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).expect("dir");
        for f in ["b.glb", "a.csv", "notes.md", ".hidden.json"] {
            std::fs::write(dir.join(f), b"x").expect("write");
        }
        let entries = list_folder(&dir).expect("listing");
        let names: Vec<&str> = entries.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["sub", "a.csv", "b.glb", "notes.md"]);
        let (_, types) = FileAction::OpenScene.file_types();
        assert!(has_extension("Level.GLB", types) && !has_extension("notes.md", types));
        assert!(list_folder(&dir.join("missing")).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
