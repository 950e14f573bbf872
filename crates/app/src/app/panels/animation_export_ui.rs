//! The animation export window that File → "Export animation…" opens: the file, frames and
//! samples of the GIF, the size it will have, Export, the progress of a running export and
//! how the last one ended (the recording itself is [`crate::recording`]'s, on a worker).

use crate::app::state::animation_export::{AnimationExport, MAX_EXPORT_SIDE, export_size};
use crate::app::state::{AppState, MessageKind};

/// The animation export window (File → "Export animation…"): the file, frames and
/// samples, the Export button, the progress of a running export and how the last one ended.
/// Collects a finished export into the status bar even when the window is closed.
pub fn animation_export_ui(ctx: &egui::Context, state: &mut AppState) {
    let finished = state.animation_export.poll().map(|outcome| match outcome {
        Ok(exported) => (exported.message(), MessageKind::Success),
        Err(e) => (format!("Export animation: {e}"), MessageKind::Error),
    });
    if let Some((text, kind)) = finished {
        state.message(text, kind);
    }
    if state.animation_export.is_running() {
        // Progress arrives from the worker: look again while nothing else asks to.
        ctx.request_repaint_after(std::time::Duration::from_millis(100));
    }
    let mut open = state.animation_export.open;
    if !open {
        return;
    }
    let dark = state.dark();
    let default_path = AnimationExport::default_path(&state.edit.name);
    let plane = &state.built.scene.plane;
    let (w, h) = export_size(plane.width, plane.height);
    egui::Window::new("Export animation")
        .open(&mut open)
        .collapsible(false)
        .resizable(false)
        .show(ctx, |ui| {
            ui.label(
                "The uniform, alias and spatial images converging side by side, as a \
                 looping GIF: this scene, seed, exposure and theme; every frame shows each \
                 image's spp and RMSE.",
            );
            let export = &mut state.animation_export;
            let running = export.is_running();
            egui::Grid::new("animation_export_grid")
                .num_columns(2)
                .show(ui, |ui| {
                    let label = ui.label("file");
                    ui.add_enabled(
                        !running,
                        egui::TextEdit::singleline(&mut export.path)
                            .hint_text(&default_path)
                            .desired_width(260.0),
                    )
                    .labelled_by(label.id)
                    .on_hover_text("The GIF to write (relative to the working directory)");
                    ui.end_row();
                    let label = ui.label("frames");
                    ui.add_enabled(
                        !running,
                        egui::DragValue::new(&mut export.frames)
                            .range(1..=crate::recording::MAX_FRAMES),
                    )
                    .labelled_by(label.id)
                    .on_hover_text("Frames, spaced geometrically in samples per pixel from 1");
                    ui.end_row();
                    let label = ui.label("last frame spp");
                    let least = export.frames.max(1);
                    export.max_spp = export.max_spp.max(least);
                    ui.add_enabled(
                        !running,
                        egui::DragValue::new(&mut export.max_spp)
                            .range(least..=crate::recording::MAX_SPP),
                    )
                    .labelled_by(label.id)
                    .on_hover_text("Samples per pixel of the last frame");
                    ui.end_row();
                    ui.label("images");
                    ui.label(format!("{w}×{h} px")).on_hover_text(format!(
                        "The scene's image size, at most {MAX_EXPORT_SIDE} pixels a side"
                    ));
                    ui.end_row();
                });
            if let Some((path, done, total)) = export.progress() {
                ui.add(
                    egui::ProgressBar::new(done as f32 / total.max(1) as f32)
                        .text(format!("frame {done} of {total} → {}", path.display())),
                );
            } else if ui
                .button("Export")
                .on_hover_text("Record the animation on a background thread")
                .clicked()
            {
                let path = state.animation_path();
                let job = state.animation_job(path);
                state.animation_export.start(job);
            }
            match &state.animation_export.last {
                Some(Ok(exported)) => {
                    ui.colored_label(crate::app::colors::good(dark), exported.message());
                }
                Some(Err(e)) => {
                    ui.colored_label(crate::app::colors::error(dark), e);
                }
                None => {}
            }
        });
    state.animation_export.open = open;
}
