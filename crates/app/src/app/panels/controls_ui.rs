//! The menu bar, the run controls (samples per frame, seed, pause/step/reset, device,
//! exposure, budget mode, theme) and the status bar.

use egui::Ui;

use crate::app::colors;
use crate::app::state::file_dialog::FileAction;
use crate::app::state::settings::{BudgetMode, Device};
use crate::app::state::{AppState, MessageKind};

/// The menu bar: File (open, save, export) and View (theme, optional windows). It also
/// draws the animation export window
/// ([`animation_export_ui`](super::animation_export_ui)): a window floats over the
/// panels wherever it is declared, and the menu bar is drawn every frame.
pub fn menu_ui(ui: &mut Ui, state: &mut AppState) {
    super::animation_export_ui::animation_export_ui(ui.ctx(), state);
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            for (action, shortcut) in [
                (FileAction::OpenScene, "Ctrl+O"),
                (FileAction::SaveScene, "Ctrl+S"),
                (FileAction::ExportImages, ""),
                (FileAction::ExportData, ""),
            ] {
                if ui
                    .add(egui::Button::new(format!("{}…", action.title())).shortcut_text(shortcut))
                    .on_hover_text(action.title())
                    .clicked()
                {
                    open_dialog(state, action);
                    ui.close();
                }
            }
            ui.menu_button("Export figure (PNG)", |ui| figure_menu_ui(ui, state));
            if ui
                .button("Export animation…")
                .on_hover_text(
                    "A looping GIF of the uniform, alias and spatial images converging side \
                     by side (for slides)",
                )
                .clicked()
            {
                state.animation_export.open = true;
                ui.close();
            }
        });
        ui.menu_button("Edit", |ui| edit_menu_ui(ui, state));
        ui.menu_button("View", |ui| {
            if ui
                .selectable_label(state.settings.dark, "Dark theme")
                .on_hover_text("Dark background")
                .clicked()
            {
                state.settings.dark = true;
            }
            if ui
                .selectable_label(!state.settings.dark, "Light theme")
                .on_hover_text("Light background (projectors in bright rooms)")
                .clicked()
            {
                state.settings.dark = false;
            }
            ui.separator();
            ui.checkbox(&mut state.settings.show_trade, "Trade")
                .on_hover_text(
                    "Speed against accuracy: time per sample, variance and efficiency of every \
                     scheme, and the error-against-time plot",
                );
            ui.checkbox(&mut state.settings.show_precision, "Precision")
                .on_hover_text(
                    "What f32, one random or an f32 column pick would cost on these powers",
                );
            ui.separator();
            ui.checkbox(&mut state.settings.show_walkthrough, "Walkthrough")
                .on_hover_text(
                    "The classic explanation (lights 2, 5, 20) step by step on the live table",
                );
            ui.checkbox(&mut state.settings.show_stepper, "Construction stepper")
                .on_hover_text("Vose's algorithm building the alias table, one pairing at a time");
            if ui
                .button("Light tree")
                .on_hover_text(
                    "The spatial scheme's tree from above and one pick stepped down it (key 6)",
                )
                .clicked()
            {
                state.show_panel = Some(crate::app::panels::PanelKind::LightTree);
                ui.close();
            }
            ui.checkbox(&mut state.settings.show_shortcuts, "Keyboard shortcuts")
                .on_hover_text("Every key the app has, for a presenter (F1 or ?)");
            ui.checkbox(&mut state.estimator.open, "Estimator at one point")
                .on_hover_text(
                    "The running estimate at the worked example's shading point (or a clicked pixel), \
                     sample by sample, under each scheme",
                );
        });
        ui.separator();
        controls_ui(ui, state);
    });
}

/// The Edit menu: Undo and Redo, each with the name of its step ("Undo drag of light 3").
fn edit_menu_ui(ui: &mut Ui, state: &mut AppState) {
    let undo = state.history.undo_name().map(str::to_owned);
    if history_item_ui(ui, "Undo", undo.as_deref(), "Ctrl+Z") {
        state.undo();
    }
    let redo = state.history.redo_name().map(str::to_owned);
    if history_item_ui(ui, "Redo", redo.as_deref(), "Ctrl+Shift+Z") {
        state.redo();
    }
}

/// One item of the Edit menu: `verb` and the step's name, greyed without a step; returns
/// whether it was clicked (the menu then closes).
fn history_item_ui(ui: &mut Ui, verb: &str, step: Option<&str>, shortcut: &str) -> bool {
    let text = step.map_or_else(|| verb.to_owned(), |name| format!("{verb} {name}"));
    let clicked = ui
        .add_enabled(
            step.is_some(),
            egui::Button::new(text).shortcut_text(shortcut),
        )
        .clicked();
    if clicked {
        ui.close();
    }
    clicked
}

/// File → Export figure: the size, then one item per figure.
fn figure_menu_ui(ui: &mut Ui, state: &mut AppState) {
    let sides = crate::app::figure_export::FIGURE_SIDES;
    ui.horizontal(|ui| {
        ui.label("Size");
        let [w, h] = &mut state.settings.figure_size;
        ui.add(egui::DragValue::new(w).range(sides.clone()).suffix(" px"))
            .on_hover_text("Width of the exported picture");
        ui.label("×");
        ui.add(egui::DragValue::new(h).range(sides).suffix(" px"))
            .on_hover_text("Height of the exported picture");
    });
    ui.separator();
    for figure in crate::app::state::figure::Figure::ALL {
        if ui.button(format!("{}…", figure.title())).clicked() {
            open_dialog(state, FileAction::ExportFigure(figure));
            ui.close();
        }
    }
}

/// Opens the path dialog for `action` with a sensible default path.
pub fn open_dialog(state: &mut AppState, action: FileAction) {
    let default = match action {
        // Open names no file of its own: the dialog lists the last folder's scenes.
        FileAction::OpenScene => String::new(),
        FileAction::SaveScene => format!("{}.json", state.edit.name),
        FileAction::ExportImages => format!("{}-images.png", state.edit.name),
        FileAction::ExportFigure(figure) => {
            format!("{}-{}.png", state.edit.name, figure.file_suffix())
        }
        // NAME.csv gives NAME-convergence.csv, NAME-histogram.csv, …
        FileAction::ExportData => format!("{}.csv", state.edit.name),
    };
    if state.file_dialog.path.is_empty() || state.file_dialog.action != Some(action) {
        state.file_dialog.path = default;
    }
    state.file_dialog.action = Some(action);
    state.file_dialog.error = None;
}

/// Run controls, on one line.
pub fn controls_ui(ui: &mut Ui, state: &mut AppState) {
    let s = &mut state.settings;
    let pause_text = if s.paused { "Run" } else { "Pause" };
    if ui
        .button(pause_text)
        .on_hover_text("Pause or resume sampling and accumulation (Space)")
        .clicked()
    {
        s.paused = !s.paused;
    }
    if ui
        .add_enabled(s.paused, egui::Button::new("Step"))
        .on_hover_text("Accumulate one frame while paused (N)")
        .on_disabled_hover_text("Pause first to step frame by frame")
        .clicked()
    {
        state.step_requested = true;
    }
    if ui
        .button("Reset")
        .on_hover_text("Clear the images, curves and histograms and start again (R)")
        .clicked()
    {
        state.reset_requested = true;
    }
    let s = &mut state.settings;
    ui.separator();
    let label = ui.label("spp/frame");
    ui.add(egui::DragValue::new(&mut s.spp_per_frame).range(1..=256))
        .labelled_by(label.id)
        .on_hover_text("Samples per pixel each scheme adds per frame (equal-samples mode)");
    let label = ui.label("seed");
    ui.add(egui::DragValue::new(&mut s.seed).range(0..=u64::from(u32::MAX)))
        .labelled_by(label.id)
        .on_hover_text(
            "Seed of every random stream: the same seed gives the same images and histograms",
        );
    let label = ui.label("exposure");
    let speed = s.exposure * 0.01;
    ui.add(
        egui::DragValue::new(&mut s.exposure)
            .range(1e-300..=1e300)
            .speed(speed)
            .custom_formatter(|v, _| crate::numbers::three_significant(v)),
    )
    .labelled_by(label.id)
    .on_hover_text("Tonemap exposure: irradiance is multiplied by this before display");
    ui.separator();
    ui.selectable_value(&mut s.budget, BudgetMode::EqualSamples, "equal samples")
        .on_hover_text("Every scheme adds the same samples per pixel per frame");
    ui.selectable_value(&mut s.budget, BudgetMode::EqualTime, "equal time")
        .on_hover_text("Every scheme gets the same compute time per frame (about 12 ms), so a cheaper scheme adds more samples");
    ui.separator();
    ui.selectable_value(&mut s.device, Device::Auto, "auto")
        .on_hover_text(
            "A hardware GPU renders the images; on a software rasterizer (llvmpipe) the app \
             measures the GPU and the CPU renderer for a few seconds and keeps the faster",
        );
    ui.selectable_value(&mut s.device, Device::Gpu, "GPU")
        .on_hover_text(
            "Render with wgpu compute on the window's device (CPU fallback without one)",
        );
    ui.selectable_value(&mut s.device, Device::Cpu, "CPU")
        .on_hover_text("Render with the CPU renderer");
}

/// The status bar: the last message, the device in use and the frame rate.
pub fn status_ui(ui: &mut Ui, state: &AppState, device_note: &str, frame_ms: Option<f32>) {
    let dark = state.dark();
    // Wrapped: a long message (what a file held) takes a second line rather than being cut.
    ui.horizontal_wrapped(|ui| {
        // Paused, frames come only with input: their spacing is no frame time.
        let timing = match frame_ms {
            None => "inline".to_owned(),
            Some(_) if state.settings.paused => "paused".to_owned(),
            Some(ms) => format!("{ms:.1} ms/frame"),
        };
        ui.label(format!("{device_note} · {timing}"))
            .on_hover_text("Where the images are rendered, and the UI's time per frame");
        ui.separator();
        ui.label(format!(
            "scene '{}' · {} lights",
            state.edit.name,
            state.built.len()
        ));
        if let Some((path, done, total)) = state.animation_export.progress() {
            ui.separator();
            ui.label(format!(
                "exporting animation {}: frame {done} of {total}",
                path.display()
            ));
        }
        if let Some((text, kind)) = &state.status {
            ui.separator();
            let color = match kind {
                MessageKind::Info => colors::foreground(dark),
                MessageKind::Success => colors::good(dark),
                MessageKind::Error => colors::error(dark),
            };
            ui.colored_label(color, text);
        }
    });
}
