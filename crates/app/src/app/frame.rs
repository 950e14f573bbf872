//! What the app does each frame around the panels: background builds and polls, keyboard
//! shortcuts, the theme, feeding the image renderers and the histograms, texture uploads,
//! the renderer choice's measurement, and the frame-time log (`LIGHTPICK_FRAME_LOG=1`).

use std::sync::Arc;
use std::time::Instant;

use egui::{Key, KeyboardShortcut, Modifiers, Ui};

use super::LightpickApp;
use super::images::renderer_choice;
use super::images::{Engine, EngineConfig, GpuImages, Published};
use super::panels::{controls_ui, file_dialog_ui, shortcuts_ui};
use super::state::MessageKind;
use super::state::file_dialog::FileAction;
use super::window::install_fonts;

/// The shortest time between frames while running (about 60 frames per second).
const FRAME_PERIOD: std::time::Duration = std::time::Duration::from_millis(16);

/// Frame-time log to stderr (`LIGHTPICK_FRAME_LOG=1`), for measuring responsiveness.
pub(super) struct FrameLog {
    start: Instant,
    frames: u32,
    ui_seconds: f64,
    /// The mean samples per pixel of the three images when the interval started.
    spp: Option<f64>,
}

impl FrameLog {
    /// A log starting now.
    pub(super) fn new() -> Self {
        Self {
            start: Instant::now(),
            frames: 0,
            ui_seconds: 0.0,
            spp: None,
        }
    }
}

impl LightpickApp {
    /// Everything a frame does before drawing: background builds, shortcuts, theme, engine
    /// and histograms, texture uploads. Returns the latest image frame.
    pub(super) fn begin_frame(&mut self, ctx: &egui::Context) -> Option<Arc<Published>> {
        if self.state.frame == 0 {
            install_fonts(ctx);
            super::text_size::apply_minimum_text_size(ctx);
        }
        self.state.frame += 1;
        self.state.poll_build();
        self.state.update_scene_sentence();
        self.state.prepare_walkthrough();
        self.open_dropped(ctx);
        self.shortcuts(ctx);
        self.apply_theme(ctx);
        let (device, adapter) = (self.state.settings.device, self.adapter());
        self.renderer_choice
            .skip_trial_on_large_scene(device, adapter, self.state.built.len());
        self.advance(ctx);
        let published = self.published();
        self.observe_renderer_choice(published.as_deref());
        let (generation, gpu) = (self.state.built.generation, self.uses_gpu());
        self.trim.frame(generation, gpu, self.state.is_building());
        if let Some(p) = &published {
            self.textures.update(ctx, p);
        }
        self.textures.native = if self.uses_gpu() {
            self.gpu.as_ref().and_then(GpuImages::texture_ids)
        } else {
            None
        };
        published
    }

    /// The file dialog and the drop hint, drawn over everything.
    pub(super) fn end_frame(&mut self, ui: &mut Ui, published: Option<&Published>) {
        if ui.input(|i| !i.raw.hovered_files.is_empty()) {
            file_dialog_ui::drop_hint_ui(ui);
        }
        if let Some(confirmed) = file_dialog_ui::file_dialog_ui(ui, &mut self.state) {
            self.file_action(confirmed.action, &confirmed.path, published);
        }
    }

    /// Keyboard: Space pauses, R resets, N steps, Escape restores a maximized panel,
    /// Ctrl+O / Ctrl+S open and save, Ctrl+Z undoes, Ctrl+Shift+Z and Ctrl+Y redo, F1 or ?
    /// shows the shortcuts, 1–5 bring a panel to the front, Alt+1…Alt+0 load the presets
    /// ([`shortcuts_ui`]).
    fn shortcuts(&mut self, ctx: &egui::Context) {
        let open = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
        let save = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
        if ctx.input_mut(|i| i.consume_shortcut(&open)) {
            controls_ui::open_dialog(&mut self.state, FileAction::OpenScene);
        }
        if ctx.input_mut(|i| i.consume_shortcut(&save)) {
            controls_ui::open_dialog(&mut self.state, FileAction::SaveScene);
        }
        if let Some(panel) = self.state.show_panel.take() {
            self.layout.select(panel);
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::F1)) {
            self.state.settings.show_shortcuts = !self.state.settings.show_shortcuts;
        }
        // Plain keys only when no text field (or drag value being typed into) has focus:
        // a text field keeps its own undo.
        if ctx.text_edit_focused() || self.state.file_dialog.action.is_some() {
            return;
        }
        if ctx.input_mut(|i| {
            i.consume_key(Modifiers::NONE, Key::Questionmark)
                || i.consume_key(Modifiers::SHIFT, Key::Questionmark)
        }) {
            self.state.settings.show_shortcuts = !self.state.settings.show_shortcuts;
        }
        for (key, panel) in shortcuts_ui::PANEL_KEYS {
            if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, key)) {
                self.layout.select(panel);
            }
        }
        // The presets' keys only while Alt is held (no list made every frame).
        if ctx.input(|i| i.modifiers.alt) {
            let presets = super::scene_io::preset_names();
            for key in shortcuts_ui::PRESET_DIGITS {
                if ctx.input_mut(|i| i.consume_key(Modifiers::ALT, key))
                    && let Some(name) = shortcuts_ui::preset_key(key, &presets)
                {
                    self.state.load_preset(name);
                }
            }
        }
        let undo = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
        let redo = KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
        let redo_y = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
        // The longer shortcut first: Ctrl+Shift+Z also matches Ctrl+Z's keys.
        if ctx.input_mut(|i| i.consume_shortcut(&redo) || i.consume_shortcut(&redo_y)) {
            self.state.redo();
        } else if ctx.input_mut(|i| i.consume_shortcut(&undo)) {
            self.state.undo();
        }
        if self.layout.maximized.is_some()
            && ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape))
        {
            self.layout.restore();
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Space)) {
            self.state.settings.paused = !self.state.settings.paused;
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::R)) {
            self.state.reset_requested = true;
        }
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::N)) {
            self.state.step_requested = true;
        }
    }

    fn apply_theme(&mut self, ctx: &egui::Context) {
        let dark = self.state.settings.dark;
        if self.applied_dark != Some(dark) {
            ctx.set_theme(if dark {
                egui::Theme::Dark
            } else {
                egui::Theme::Light
            });
            self.applied_dark = Some(dark);
        }
    }

    /// Feeds the engine and the histograms: restarts on a new table or a reset, runs a
    /// frame when running or stepped.
    fn advance(&mut self, ctx: &egui::Context) {
        let use_gpu = self.uses_gpu();
        // Once the renderer is chosen, the idle one holds nothing (its per-light copies
        // would double what the images cost); while `Auto` measures, both keep theirs.
        let keep_idle = self
            .renderer_choice
            .is_measuring(self.state.settings.device, self.adapter());
        let threaded = self.threaded;
        let engine = self.engine.get_or_insert_with(|| {
            if threaded {
                Engine::threaded(ctx)
            } else {
                Engine::inline()
            }
        });
        let trade_measuring = self.state.trade_pauses_images();
        let s = &self.state.settings;
        let running = !s.paused && !trade_measuring;
        let config = EngineConfig {
            spp_per_frame: s.spp_per_frame,
            budget: s.budget,
            exposure: s.exposure,
            seed: s.seed,
            running,
        };
        // The CPU engine idles while the GPU renders.
        engine.sync_config(EngineConfig {
            running: running && !use_gpu,
            ..config
        });
        let reset = std::mem::take(&mut self.state.reset_requested);
        let built = Arc::clone(&self.state.built);
        if use_gpu && !keep_idle {
            engine.release();
        } else {
            engine.sync_scene(built.generation, &built.samplers, reset);
        }
        if reset {
            self.state.restart_sampling();
        }
        let step = std::mem::take(&mut self.state.step_requested);
        if use_gpu {
            if let Some(gpu) = self.gpu.as_mut()
                && let Err(e) = gpu.frame(built.generation, &built.samplers, &config, reset, step)
            {
                self.state
                    .message(format!("GPU renderer stopped: {e}"), MessageKind::Error);
                self.gpu_error = Some(e);
            }
        } else {
            if !keep_idle && let Some(gpu) = self.gpu.as_mut() {
                gpu.release();
            }
            if step {
                engine.step();
            }
            engine.tick();
        }
        if running || step {
            let picks = self.state.settings.picks_per_frame;
            self.state.sample_picks(picks);
        }
        if running {
            // At most ~60 frames per second while running: faster repaints would only take
            // CPU from the renderers (input still repaints at once).
            let since_last = self.last_frame.map_or(FRAME_PERIOD, |t| t.elapsed());
            ctx.request_repaint_after(FRAME_PERIOD.saturating_sub(since_last));
        }
    }

    /// Feeds the renderer choice's measurement with the frame just taken.
    fn observe_renderer_choice(&mut self, published: Option<&Published>) {
        let shown = if self.uses_gpu() {
            renderer_choice::Renderer::Gpu
        } else {
            renderer_choice::Renderer::Cpu
        };
        let total_spp = published
            .filter(|p| p.generation == self.state.built.generation)
            .map(Published::mean_spp);
        self.renderer_choice.observe(
            self.state.settings.device,
            self.adapter(),
            shown,
            total_spp,
            !self.state.settings.paused,
            Instant::now(),
        );
    }

    pub(super) fn measure(&mut self, started: Instant) {
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            let ms = (now - last).as_secs_f32() * 1e3;
            self.frame_ms = if self.frame_ms == 0.0 {
                ms
            } else {
                0.9 * self.frame_ms + 0.1 * ms
            };
        }
        self.last_frame = Some(now);
        if self.frame_log.is_none() {
            return;
        }
        let spp = self.published().map(|p| p.mean_spp());
        let note = self.renderer_note();
        let accounted: usize = self.memory_by_part().iter().map(|(_, b)| b).sum();
        if let Some(log) = &mut self.frame_log {
            log.frames += 1;
            log.ui_seconds += (now - started).as_secs_f64();
            let elapsed = log.start.elapsed().as_secs_f64();
            if elapsed >= 2.0 {
                let rate = match (log.spp, spp) {
                    (Some(a), Some(b)) if b >= a => {
                        format!("{:.2} spp/s per image", (b - a) / elapsed)
                    }
                    _ => "images restarted".to_owned(),
                };
                eprintln!(
                    "lightpick frames: {:.1} fps, {:.2} ms/frame, ui() {:.2} ms/frame, {} lights, {rate}; {note}; heap by part (memory_by_part) {:.1} MiB",
                    f64::from(log.frames) / elapsed,
                    elapsed * 1e3 / f64::from(log.frames),
                    log.ui_seconds * 1e3 / f64::from(log.frames),
                    self.state.built.len(),
                    accounted as f64 / f64::from(1u32 << 20)
                );
                *log = FrameLog {
                    spp,
                    ..FrameLog::new()
                };
            }
        }
    }
}
