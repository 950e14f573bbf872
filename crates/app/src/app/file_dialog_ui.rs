//! The in-app path dialog for opening and saving scenes and exporting PNGs: a text field
//! for the path, OK and Cancel. A failure is shown in the dialog and in the status bar; the
//! path stays as typed and the current scene is kept.

use egui::Ui;

use super::colors;
use super::state::{AppState, FileAction};

/// What the user confirmed in the dialog this frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Confirmed {
    /// The action.
    pub action: FileAction,
    /// The path as typed (trimmed).
    pub path: String,
}

/// Shows the dialog when an action is pending; returns the action confirmed this frame.
pub fn file_dialog_ui(ui: &mut Ui, state: &mut AppState) -> Option<Confirmed> {
    let action = state.file_dialog.action?;
    let dark = state.dark();
    let mut confirmed = None;
    let mut cancel = false;
    egui::Window::new(action.title())
        .id(egui::Id::unique("lightpick_file_dialog"))
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .show(ui.ctx(), |ui| {
            ui.horizontal(|ui| {
                let label = ui.label("Path");
                let response = ui
                    .add(
                        egui::TextEdit::singleline(&mut state.file_dialog.path)
                            .desired_width(420.0),
                    )
                    .labelled_by(label.id)
                    .on_hover_text("File path, absolute or relative to the working directory");
                if response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                    confirmed = Some(action);
                }
            });
            if let Some(error) = &state.file_dialog.error {
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
    confirmed.map(|action| Confirmed {
        action,
        path: state.file_dialog.path.trim().to_owned(),
    })
}
