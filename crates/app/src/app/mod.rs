//! The egui/eframe desktop app.
//!
//! One [`AppState`] (in [`state`]) holds everything the panels show; each panel is one file
//! with a `*_ui` function over it: [`lights_ui`], [`table_ui`] (table and diagram),
//! [`histogram_ui`] (sampling), [`render_ui`] (images), [`convergence_ui`], plus
//! [`trade_ui`] (speed against accuracy) and [`precision_ui`] (optional windows, from the
//! View menu), the classroom's [`walkthrough_ui`] and [`stepper_ui`] (windows too), the
//! [`inspector_ui`] (a window opened by clicking a pixel of an image),
//! [`controls_ui`] (menu, run controls, status bar) and [`file_dialog_ui`]; [`layout`]
//! decides where the five main panels go at the window's size and [`layout_ui`] draws them
//! there (columns, tabs, maximize and restore). Progressive
//! images come from the [`engine`], on a worker thread in the app and inline in tests.
//! [`LightpickApp::ui`] draws the whole window into any [`egui::Ui`], so tests drive it with
//! `egui_kittest` without eframe.

pub mod background;
pub mod colors;
pub mod controls_ui;
pub mod convergence_ui;
pub mod engine;
pub mod estimator_ui;
pub mod file_dialog_ui;
pub mod frame_budget;
pub mod gpu_images;
pub mod histogram_ui;
pub mod inspector_ui;
pub mod layout;
pub mod layout_ui;
pub mod lights_ui;
pub mod log_axes;
mod memory;
pub(crate) use memory::map_large_allocations;
pub mod placement;
pub mod precision_ui;
pub mod render_ui;
pub mod scene_io;
pub mod state;
pub mod stepper_ui;
pub mod table_ui;
pub mod trade_ui;
pub mod walkthrough_ui;

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use egui::{Key, KeyboardShortcut, Modifiers, Ui};

pub use state::{AppState, Settings};

use convergence_ui::ConvergenceAxis;
use engine::{Engine, EngineConfig, Published};
use render_ui::ImageTextures;
use state::{FileAction, MessageKind};

/// The shortest time between frames while running (about 60 frames per second).
const FRAME_PERIOD: std::time::Duration = std::time::Duration::from_millis(16);

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

/// The message for a machine without a display.
const NO_DISPLAY: &str = "no display found (neither DISPLAY nor WAYLAND_DISPLAY is set): \
     the desktop app needs one. Use the headless subcommands instead, e.g. \
     `lightpick table --powers 2,5,20` (see `lightpick --help`)";

/// Opens the app on the seed scene (or the last scene), or on a scene already read from a
/// file (`lightpick FILE`, what a desktop's "Open with" passes). Returns an error (exit code
/// 2) when no display exists.
pub fn run(
    opened: Option<(std::path::PathBuf, lightpick_core::scene::Loaded)>,
) -> anyhow::Result<()> {
    if !display_available() {
        anyhow::bail!(NO_DISPLAY);
    }
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_title("lightpick — point-light importance sampling")
            .with_inner_size([1440.0, 900.0])
            .with_min_inner_size([900.0, 600.0]),
        // Dithering costs a noise evaluation per fragment; on software rasterizers
        // (lavapipe) that is a large share of every frame, and the panels have no gradients.
        dithering: false,
        wgpu_options: wgpu_options(),
        ..Default::default()
    };
    eframe::run_native(
        "lightpick",
        options,
        Box::new(move |cc| {
            let mut app = LightpickApp::new(cc);
            if let Some((path, loaded)) = opened {
                app.open_loaded(&path.display().to_string(), loaded);
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| {
        anyhow::anyhow!(
            "cannot open the app window ({e}). Without a working display use the headless \
             subcommands, e.g. `lightpick table --powers 2,5,20` (see `lightpick --help`)"
        )
    })
}

/// eframe's wgpu setup with the adapter's own limits: the compute renderers need storage
/// buffers (and, for millions of lights, large ones) that egui's defaults, sized for drawing
/// (WebGL2's on a GL adapter), leave out; and timestamp queries where the adapter has them.
fn wgpu_options() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.device_descriptor = std::sync::Arc::new(device_descriptor);
    WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(setup),
        ..Default::default()
    }
}

/// The device the app asks of `adapter`: its own limits (large storage buffers, compute on
/// GL) and, when it has them, timestamp queries, so the images' pass times come from the
/// GPU's clock. Tests ask the same of kittest's adapter.
pub fn device_descriptor(
    adapter: &eframe::wgpu::Adapter,
) -> eframe::wgpu::DeviceDescriptor<'static> {
    eframe::wgpu::DeviceDescriptor {
        label: Some("lightpick device"),
        required_features: adapter.features() & lightpick_core::gpu::GpuContext::TIMING_FEATURES,
        required_limits: adapter.limits(),
        ..Default::default()
    }
}

/// Whether a window can be opened at all: on Linux and the BSDs, `DISPLAY` or
/// `WAYLAND_DISPLAY` must name a display.
fn display_available() -> bool {
    if cfg!(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "openbsd",
        target_os = "netbsd"
    )) {
        ["DISPLAY", "WAYLAND_DISPLAY"]
            .iter()
            .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
    } else {
        true
    }
}

/// One panel of the app, for [`LightpickApp::panel_ui`]; the first five are the main
/// window's ([`layout::PANES`]), which the [`layout`] places and the presenter can maximize.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum PanelKind {
    /// The lights editor.
    Lights,
    /// The alias table and its diagram.
    Table,
    /// Histograms and chi-square.
    Sampling,
    /// The progressive images.
    Images,
    /// RMSE curves and efficiency.
    Convergence,
    /// The run controls.
    Controls,
    /// Speed against accuracy of every scheme.
    Trade,
    /// The precision lab's figures for the current powers.
    Precision,
    /// The per-pixel inspector (of the pixel selected in `state.inspector`).
    Inspector,
    /// The running estimate at one shading point (`state.estimator`).
    Estimator,
}

/// The app: the state, the render engine and the textures of its latest frame.
pub struct LightpickApp {
    /// Everything the panels show.
    pub state: AppState,
    /// Where the main panels go, and which one is maximized (persisted).
    pub layout: layout::Layout,
    engine: Option<Engine>,
    threaded: bool,
    textures: ImageTextures,
    axis: ConvergenceAxis,
    applied_dark: Option<bool>,
    last_frame: Option<Instant>,
    frame_ms: f32,
    frame_log: Option<FrameLog>,
    /// eframe's wgpu device, when it runs on wgpu (not in tests).
    gpu: Option<gpu_images::GpuImages>,
    /// Why the GPU images stopped (shown in the status bar; the CPU takes over).
    gpu_error: Option<String>,
    /// Where the images render (measured in `Auto` on a software adapter).
    placement: placement::Placement,
    /// Gives freed memory back after a scene or renderer change ([`memory::Trim`]).
    trim: memory::Trim,
}

/// Frame-time log to stderr (`LIGHTPICK_FRAME_LOG=1`), for measuring responsiveness.
struct FrameLog {
    start: Instant,
    frames: u32,
    ui_seconds: f64,
    /// The mean samples per pixel of the three images when the interval started.
    spp: Option<f64>,
}

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
            settings.exposure = state::auto_exposure(&seed);
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

    /// An app over `state`. With `threaded = false` the images render inline, only when
    /// running or stepped, with virtual timings (deterministic, for tests).
    pub fn with_state(mut state: AppState, threaded: bool) -> Self {
        state.trade.inline = !threaded;
        state.precision.inline = !threaded;
        Self {
            state,
            layout: layout::Layout::default(),
            engine: None,
            threaded,
            textures: ImageTextures::default(),
            axis: ConvergenceAxis::Spp,
            applied_dark: None,
            last_frame: None,
            frame_ms: 0.0,
            frame_log: std::env::var_os("LIGHTPICK_FRAME_LOG").map(|_| FrameLog {
                start: Instant::now(),
                frames: 0,
                ui_seconds: 0.0,
                spp: None,
            }),
            gpu: None,
            gpu_error: None,
            placement: placement::Placement::default(),
            trim: memory::Trim::default(),
        }
    }

    /// The seed scene, paused, rendering inline: the starting point of every UI test.
    pub fn for_tests() -> Self {
        let mut state = AppState::seed();
        state.settings.paused = true;
        // The GPU when the harness has one (kittest's wgpu device is lavapipe, where `Auto`
        // would measure both renderers first); tests of `Auto` set it themselves.
        state.settings.device = state::Device::Gpu;
        Self::with_state(state, false)
    }

    /// [`LightpickApp::for_tests`] on the bundled scene `name` (panics on an unknown name:
    /// for tests).
    ///
    /// # Panics
    /// If `name` is not a preset.
    pub fn for_tests_on(name: &str) -> Self {
        let mut app = Self::for_tests();
        match scene_io::preset(name) {
            Ok(scene) => app.state.load_scene(scene),
            Err(e) => panic!("{e}"),
        }
        app
    }

    /// Asks for one frame of images and histograms on the next frame (the Step button).
    pub fn step(&mut self) {
        self.state.step_requested = true;
    }

    /// The latest published image frame (from the GPU when it renders the images).
    pub fn published(&mut self) -> Option<Arc<Published>> {
        if self.uses_gpu() {
            return self.gpu.as_ref().and_then(gpu_images::GpuImages::latest);
        }
        self.engine.as_mut().and_then(Engine::latest)
    }

    /// Whether the GPU renders the images this frame ([`placement`]).
    fn uses_gpu(&self) -> bool {
        self.placement
            .renderer(self.state.settings.device, self.adapter())
            == placement::Renderer::Gpu
    }

    /// The wgpu compute device as the placement sees it.
    fn adapter(&self) -> placement::Adapter {
        match &self.gpu {
            Some(gpu) if self.gpu_error.is_none() => {
                if gpu.is_software() {
                    placement::Adapter::Software
                } else {
                    placement::Adapter::Hardware
                }
            }
            _ => placement::Adapter::None,
        }
    }

    /// Where the images render, and why (the status bar's words).
    pub fn placement_note(&self) -> String {
        let name = self
            .gpu
            .as_ref()
            .map_or_else(String::new, gpu_images::GpuImages::description);
        let mut note = self
            .placement
            .describe(self.state.settings.device, self.adapter(), &name);
        if let Some(e) = &self.gpu_error {
            let _ = write!(note, "; GPU failed: {e}");
        }
        note
    }

    /// Draws the whole app into `ui` and advances it by one frame.
    pub fn ui(&mut self, ui: &mut Ui) {
        let started = Instant::now();
        let published = self.begin_frame(ui.ctx());
        let device_note = self.placement_note();
        let frame_ms = if self.threaded {
            Some(self.frame_ms)
        } else {
            None
        };
        // Software rasterizers (lavapipe) pay for every filled pixel: the panels draw no
        // background of their own (no overdraw); the window's clear colour is the panel fill
        // (see `clear_color`), and inline (test) rendering paints it once here.
        if !self.threaded {
            ui.painter()
                .rect_filled(ui.max_rect(), 0.0, ui.visuals().panel_fill);
        }
        let frame = egui::Frame::NONE.inner_margin(6.0);
        egui::Panel::top("lightpick_menu")
            .frame(frame)
            .show(ui, |ui| {
                controls_ui::menu_ui(ui, &mut self.state);
            });
        egui::Panel::bottom("lightpick_status")
            .frame(frame)
            .show(ui, |ui| {
                controls_ui::status_ui(ui, &self.state, &device_note, frame_ms);
            });
        let mut panes = MainPanes {
            state: &mut self.state,
            textures: &self.textures,
            axis: &mut self.axis,
            published: published.as_deref(),
        };
        layout_ui::panes_ui(ui, &mut self.layout, &mut panes, frame);
        self.lab_windows(ui.ctx());
        self.end_frame(ui, published.as_deref());
        self.measure(started);
    }

    /// Draws one panel alone (filling `ui`), advancing the app by one frame like
    /// [`Self::ui`]: for tests and for embedding.
    pub fn panel_ui(&mut self, ui: &mut Ui, panel: PanelKind) {
        let published = self.begin_frame(ui.ctx());
        let mut panes = MainPanes {
            state: &mut self.state,
            textures: &self.textures,
            axis: &mut self.axis,
            published: published.as_deref(),
        };
        egui::CentralPanel::default().show(ui, |ui| {
            // The main panels' titles are their headers' in the window.
            if layout::PANES.contains(&panel) {
                ui.heading(layout::title(panel));
            }
            layout_ui::PaneContents::pane_ui(&mut panes, ui, panel);
        });
        self.end_frame(ui, published.as_deref());
    }

    /// The optional windows: speed against accuracy and precision (View menu), and the pixel
    /// inspector (a click on an image).
    fn lab_windows(&mut self, ctx: &egui::Context) {
        let mut open = self.state.settings.show_trade;
        egui::Window::new("Speed against accuracy")
            .open(&mut open)
            .default_size([620.0, 520.0])
            .default_pos([760.0, 60.0])
            .show(ctx, |ui| trade_ui::trade_ui(ui, &mut self.state));
        self.state.settings.show_trade = open;
        let mut open = self.state.settings.show_precision;
        egui::Window::new("Precision")
            .open(&mut open)
            .default_size([640.0, 420.0])
            .default_pos([20.0, 400.0])
            .show(ctx, |ui| precision_ui::precision_ui(ui, &mut self.state));
        self.state.settings.show_precision = open;
        inspector_ui::inspector_window(ctx, &mut self.state);
        walkthrough_ui::walkthrough_window(ctx, &mut self.state);
        stepper_ui::stepper_window(ctx, &mut self.state);
        estimator_ui::estimator_window(ctx, &mut self.state);
    }

    /// Everything a frame does before drawing: background builds, shortcuts, theme, engine
    /// and histograms, texture uploads. Returns the latest image frame.
    fn begin_frame(&mut self, ctx: &egui::Context) -> Option<Arc<Published>> {
        if self.state.frame == 0 {
            install_fonts(ctx);
        }
        self.state.frame += 1;
        self.state.poll_build();
        self.state.prepare_walkthrough();
        self.open_dropped(ctx);
        self.shortcuts(ctx);
        self.apply_theme(ctx);
        self.advance(ctx);
        let published = self.published();
        self.observe_placement(published.as_deref());
        let (generation, gpu) = (self.state.built.generation, self.uses_gpu());
        self.trim.frame(generation, gpu, self.state.is_building());
        if let Some(p) = &published {
            self.textures.update(ctx, p);
        }
        self.textures.native = if self.uses_gpu() {
            self.gpu
                .as_ref()
                .and_then(gpu_images::GpuImages::texture_ids)
        } else {
            None
        };
        published
    }

    /// The file dialog and the drop hint, drawn over everything.
    fn end_frame(&mut self, ui: &mut Ui, published: Option<&Published>) {
        if ui.input(|i| !i.raw.hovered_files.is_empty()) {
            drop_hint_ui(ui);
        }
        if let Some(confirmed) = file_dialog_ui::file_dialog_ui(ui, &mut self.state) {
            self.file_action(confirmed.action, &confirmed.path, published);
        }
    }

    /// Keyboard: Space pauses, R resets, N steps, Escape restores a maximized panel,
    /// Ctrl+O / Ctrl+S open and save.
    fn shortcuts(&mut self, ctx: &egui::Context) {
        let open = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
        let save = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
        if ctx.input_mut(|i| i.consume_shortcut(&open)) {
            controls_ui::open_dialog(&mut self.state, FileAction::OpenScene);
        }
        if ctx.input_mut(|i| i.consume_shortcut(&save)) {
            controls_ui::open_dialog(&mut self.state, FileAction::SaveScene);
        }
        // Plain keys only when no text field (or drag value being typed into) has focus.
        if ctx.text_edit_focused() || self.state.file_dialog.action.is_some() {
            return;
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
            .placement
            .is_measuring(self.state.settings.device, self.adapter());
        let threaded = self.threaded;
        let engine = self.engine.get_or_insert_with(|| {
            if threaded {
                Engine::threaded(ctx)
            } else {
                Engine::inline()
            }
        });
        let s = &self.state.settings;
        let running = !s.paused;
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

    /// Feeds the placement's measurement with the frame just taken.
    fn observe_placement(&mut self, published: Option<&Published>) {
        let shown = if self.uses_gpu() {
            placement::Renderer::Gpu
        } else {
            placement::Renderer::Cpu
        };
        let total_spp = published
            .filter(|p| p.generation == self.state.built.generation)
            .map(Published::mean_spp);
        self.placement.observe(
            self.state.settings.device,
            self.adapter(),
            shown,
            total_spp,
            !self.state.settings.paused,
            Instant::now(),
        );
    }

    fn measure(&mut self, started: Instant) {
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
        let note = self.placement_note();
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
                    start: Instant::now(),
                    frames: 0,
                    ui_seconds: 0.0,
                    spp,
                };
            }
        }
    }

    /// Opens the scene file at `path` (any format the loader reads, the receiver at the
    /// Floor control's height reset to the file's ground) and says what came in; on failure
    /// says why in the status bar and keeps the current scene.
    pub fn open_path(&mut self, path: &Path) {
        match self.open_scene(path) {
            Ok(message) => self.state.message(message, MessageKind::Success),
            Err(e) => self.state.message(
                format!("Open scene: {e} — nothing changed"),
                MessageKind::Error,
            ),
        }
    }

    /// Loads the scene at `path`: the status line ("opened level.glb: 402 lights: 362
    /// points, 40 spots; skipped 1 directional light 'Sun'"), or why not.
    fn open_scene(&mut self, path: &Path) -> Result<String, String> {
        let loaded = scene_io::load(path, None)?;
        let summary = loaded.report.summary();
        self.state.load_scene(loaded.scene);
        Ok(format!("opened {}: {summary}", path.display()))
    }

    /// Shows a scene read from `what` and says what came in.
    pub fn open_loaded(&mut self, what: &str, loaded: lightpick_core::scene::Loaded) {
        let summary = loaded.report.summary();
        self.state.load_scene(loaded.scene);
        self.state
            .message(format!("opened {what}: {summary}"), MessageKind::Success);
    }

    /// Opens a file dropped on the window (the first, when several are).
    fn open_dropped(&mut self, ctx: &egui::Context) {
        if let Some(file) = ctx.input(|i| i.raw.dropped_files.first().cloned()) {
            self.open_path(file.path());
        }
    }

    /// Carries out a confirmed file action; on failure the message is shown in the dialog
    /// and the status bar, and the current scene is kept.
    pub fn file_action(&mut self, action: FileAction, path: &str, published: Option<&Published>) {
        let result = match action {
            FileAction::OpenScene => self.open_scene(Path::new(path)),
            FileAction::SaveScene => scene_io::save(Path::new(path), &self.state.built.scene)
                .map(|()| format!("saved {path}")),
            FileAction::ExportImages => {
                // GPU images are native textures: read them back first.
                let exposure = self.state.settings.exposure;
                let from_gpu = if self.uses_gpu() {
                    self.gpu.as_mut().map(|gpu| gpu.frame_with_images(exposure))
                } else {
                    None
                };
                match from_gpu {
                    Some(Ok(frame)) => Ok(frame),
                    Some(Err(e)) => Err(e),
                    None => published
                        .cloned()
                        .ok_or_else(|| "no image has been rendered yet".to_owned()),
                }
                .and_then(|frame| export_images(Path::new(path), &frame))
                .map(|()| format!("exported {path}"))
            }
            FileAction::ExportDiagram => {
                export_diagram(Path::new(path), &self.state).map(|()| format!("exported {path}"))
            }
        };
        match result {
            Ok(message) => {
                self.state.file_dialog.action = None;
                self.state.file_dialog.error = None;
                self.state.message(message, MessageKind::Success);
            }
            Err(e) => {
                self.state.file_dialog.error = Some(e.clone());
                self.state.message(
                    format!("{}: {e} — nothing changed", action.title()),
                    MessageKind::Error,
                );
            }
        }
    }
}

/// The panels' contents, drawn by the layout (and by [`LightpickApp::panel_ui`]) over the
/// app's state for one frame.
struct MainPanes<'a> {
    state: &'a mut AppState,
    textures: &'a ImageTextures,
    axis: &'a mut ConvergenceAxis,
    published: Option<&'a Published>,
}

impl layout_ui::PaneContents for MainPanes<'_> {
    fn pane_ui(&mut self, ui: &mut Ui, pane: PanelKind) {
        let state = &mut *self.state;
        match pane {
            PanelKind::Lights => lights_ui::lights_ui(ui, state),
            PanelKind::Table => table_ui::table_panel_ui(ui, state),
            PanelKind::Sampling => {
                // A little room on the left for the plot's rotated axis label.
                egui::Frame::NONE
                    .inner_margin(egui::Margin {
                        left: 4,
                        ..egui::Margin::ZERO
                    })
                    .show(ui, |ui| histogram_ui::sampling_ui(ui, state));
            }
            PanelKind::Images => {
                render_ui::images_ui(ui, state, self.published, self.textures);
            }
            PanelKind::Convergence => {
                convergence_ui::convergence_ui(ui, state, self.published, self.axis);
            }
            PanelKind::Controls => {
                ui.horizontal_wrapped(|ui| controls_ui::controls_ui(ui, state));
            }
            PanelKind::Trade => trade_ui::trade_ui(ui, state),
            PanelKind::Precision => precision_ui::precision_ui(ui, state),
            PanelKind::Inspector => inspector_ui::inspector_ui(ui, state),
            PanelKind::Estimator => estimator_ui::estimator_ui(ui, state),
        }
    }

    fn wanted_height(&self, ui: &Ui, pane: PanelKind, width: f32) -> Option<f32> {
        // The images take the height their width allows (every frame, so a resized window
        // keeps them as large as it can); the panel under them fills the rest.
        (pane == PanelKind::Images)
            .then(|| render_ui::wanted_height(ui, width, self.state, self.textures))
    }
}

/// A veil over the window while files are dragged over it, saying what a drop does.
fn drop_hint_ui(ui: &Ui) {
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

/// `DejaVu Sans` (the subset the headless drawings bundle) as a fallback after egui's own
/// font, for the arrows, `≥` and math signs the panels write.
static DEJAVU_SANS: &[u8] = lightpick_core::draw::text::REGULAR_FONT;

fn install_fonts(ctx: &egui::Context) {
    use egui::epaint::text::{FontInsert, FontPriority, InsertFontFamily};
    ctx.add_font(FontInsert::new(
        "DejaVuSans",
        egui::FontData::from_static(DEJAVU_SANS),
        vec![
            InsertFontFamily {
                family: egui::FontFamily::Proportional,
                priority: FontPriority::Lowest,
            },
            InsertFontFamily {
                family: egui::FontFamily::Monospace,
                priority: FontPriority::Lowest,
            },
        ],
    ));
}

/// Writes uniform | importance | spatial | reference side by side as one PNG, with the
/// three error maps in a second row when there is a reference image.
fn export_images(path: &Path, p: &Published) -> Result<(), String> {
    let pixels = p.width as usize * p.height as usize * 4;
    if [&p.uniform, &p.importance, &p.spatial]
        .iter()
        .any(|s| s.rgba.len() != pixels)
    {
        return Err("the images are not ready yet".into());
    }
    let (w, h) = (p.width as usize, p.height as usize);
    let schemes = [&p.uniform, &p.importance, &p.spatial];
    let mut top: Vec<&[u8]> = schemes.iter().map(|s| s.rgba.as_slice()).collect();
    if let Some(r) = &p.reference_rgba {
        top.push(r);
    }
    let errors: Option<Vec<&[u8]>> = schemes.iter().map(|s| s.error_rgba.as_deref()).collect();
    let columns = top.len();
    let rows = if errors.is_some() { 2 } else { 1 };
    let total_w = w * columns;
    // Opaque black where a row has no image (under the reference).
    let mut out: Vec<u8> = [0, 0, 0, 255].repeat(total_w * h * rows);
    let mut place = |row: usize, column: usize, part: &[u8]| {
        for y in 0..h {
            let src = &part[y * w * 4..(y + 1) * w * 4];
            let dst = ((row * h + y) * total_w + column * w) * 4;
            out[dst..dst + w * 4].copy_from_slice(src);
        }
    };
    for (k, part) in top.iter().enumerate() {
        place(0, k, part);
    }
    for (k, part) in errors.iter().flatten().enumerate() {
        place(1, k, part);
    }
    image::save_buffer(
        path,
        &out,
        total_w as u32,
        (h * rows) as u32,
        image::ExtendedColorType::Rgba8,
    )
    .map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes the alias-table diagram as a PNG (the headless drawing of `lightpick plot table`).
fn export_diagram(path: &Path, state: &AppState) -> Result<(), String> {
    let theme = if state.dark() {
        lightpick_core::draw::Theme::Dark
    } else {
        lightpick_core::draw::Theme::Light
    };
    let style = lightpick_core::draw::Style {
        theme,
        ..Default::default()
    };
    let pixmap =
        lightpick_core::draw::table_diagram(&state.built.table, state.built.denominator, &style)
            .map_err(|e| e.to_string())?;
    lightpick_core::draw::write_png(&pixmap, path).map_err(|e| e.to_string())
}

impl eframe::App for LightpickApp {
    fn ui(&mut self, ui: &mut Ui, frame: &mut eframe::Frame) {
        if self.gpu.is_none()
            && self.gpu_error.is_none()
            && let Some(render_state) = frame.wgpu_render_state()
        {
            self.gpu = Some(gpu_images::GpuImages::new(render_state));
            // A software rasterizer (lavapipe) pays per triangle: without feathering every
            // rectangle is 2 triangles instead of 10, which roughly halves the cost of a
            // frame of this text-and-plot-heavy window. Real GPUs keep anti-aliasing.
            if render_state.adapter.get_info().device_type == eframe::wgpu::DeviceType::Cpu {
                ui.ctx().tessellation_options_mut(|o| o.feathering = false);
            }
        }
        LightpickApp::ui(self, ui);
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
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
