//! The egui/eframe desktop app, in layers (each imports only those below it):
//!
//! - small shared pieces: [`background`] (the one worker-thread mechanism), [`colors`] (the
//!   palette in egui's colours), [`scene_io`] (presets, the session's JSON, saving) and
//!   [`generated`] (random powers and positions);
//! - [`state`]: the one [`AppState`] every panel reads and edits, split by concept;
//! - [`images`]: where the progressive images are made (CPU engine, GPU runs, renderer choice,
//!   frame budget);
//! - [`panels`]: one `*_ui.rs` per panel or window, and the layout;
//! - the shell, here: [`LightpickApp`] wires them; [`window`] opens the eframe window
//!   ([`run`]), `frame` is what each frame does around the panels, `files` opens, saves and
//!   exports, `persist` keeps the settings, layout and scene between sessions, `memory`
//!   counts what the app holds and gives freed memory back.
//!
//! [`LightpickApp::ui`] draws the whole window into any [`egui::Ui`], so tests drive it with
//! `egui_kittest` without eframe. The app never imports `crate::cli`; what both need lives
//! below both ([`crate::recording`], [`crate::numbers`]).

pub mod background;
pub mod colors;
pub mod data_export;
mod figure_export;
mod files;
mod frame;
pub mod generated;
pub mod images;
mod memory;
pub mod panels;
mod persist;
pub mod scene_io;
pub mod session_files;
pub mod state;
pub mod text_size;
pub mod window;

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::Instant;

use egui::Ui;

pub(crate) use memory::map_large_allocations;
pub use panels::PanelKind;
pub use state::{AppState, Settings};
pub use window::{device_descriptor, run};

use frame::FrameLog;
use images::renderer_choice;
use images::{Engine, GpuImages, Published};
use panels::convergence_ui::ConvergenceAxis;
use panels::images_ui::ImageTextures;
use panels::{MainPanes, controls_ui, layout, layout_ui};

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
    gpu: Option<GpuImages>,
    /// Why the GPU images stopped (shown in the status bar; the CPU takes over).
    gpu_error: Option<String>,
    /// Where the images render (measured in `Auto` on a software adapter).
    renderer_choice: renderer_choice::RendererChoice,
    /// Gives freed memory back after a scene or renderer change ([`memory::Trim`]).
    trim: memory::Trim,
    /// Where the session keeps a large scene (`None`: not kept).
    session_dir: Option<std::path::PathBuf>,
    /// The scene generation (and whether the walkthrough held the user's scene) last
    /// written to the session folder.
    saved_scene: Option<(u64, bool)>,
}

impl LightpickApp {
    /// An app over `state`. With `threaded = false` the images render inline, only when
    /// running or stepped, with virtual timings (deterministic, for tests).
    pub fn with_state(mut state: AppState, threaded: bool) -> Self {
        state.trade.inline = !threaded;
        state.precision.inline = !threaded;
        state.scene_sentence.inline = !threaded;
        state.variance_maps.inline = !threaded;
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
            frame_log: std::env::var_os("LIGHTPICK_FRAME_LOG").map(|_| FrameLog::new()),
            gpu: None,
            gpu_error: None,
            renderer_choice: renderer_choice::RendererChoice::default(),
            trim: memory::Trim::default(),
            session_dir: None,
            saved_scene: None,
        }
    }

    /// The worked example, paused, rendering inline: the starting point of every UI test.
    pub fn for_tests() -> Self {
        let mut state = AppState::worked_example();
        state.settings.paused = true;
        // The GPU when the harness has one (kittest's wgpu device is lavapipe, where `Auto`
        // would measure both renderers first); tests of `Auto` set it themselves.
        state.settings.device = state::settings::Device::Gpu;
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
            return self.gpu.as_ref().and_then(GpuImages::latest);
        }
        self.engine.as_mut().and_then(Engine::latest)
    }

    /// Whether the GPU renders the images this frame ([`renderer_choice`]).
    fn uses_gpu(&self) -> bool {
        self.renderer_choice
            .renderer(self.state.settings.device, self.adapter())
            == renderer_choice::Renderer::Gpu
    }

    /// The wgpu compute device as the renderer choice sees it.
    fn adapter(&self) -> renderer_choice::Adapter {
        match &self.gpu {
            Some(gpu) if self.gpu_error.is_none() => {
                if gpu.is_software() {
                    renderer_choice::Adapter::Software
                } else {
                    renderer_choice::Adapter::Hardware
                }
            }
            _ => renderer_choice::Adapter::None,
        }
    }

    /// Where the images render, and why (the status bar's words).
    pub fn renderer_note(&self) -> String {
        let name = self
            .gpu
            .as_ref()
            .map_or_else(String::new, GpuImages::description);
        let mut note =
            self.renderer_choice
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
        let device_note = self.renderer_note();
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
        panels::windows_ui(ui.ctx(), &mut self.state, &self.layout.placed);
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
            if layout::TABBED.contains(&panel) {
                ui.heading(layout::title(panel));
            }
            layout_ui::PaneContents::pane_ui(&mut panes, ui, panel);
        });
        self.end_frame(ui, published.as_deref());
    }
}
