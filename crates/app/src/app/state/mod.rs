//! The one `AppState` every panel reads and edits: the scene being edited, the last valid
//! table built from it, the running histograms and the persisted settings.
//!
//! # Edits and the last good state
//! The powers the user edits live in [`SceneEdit`] exactly as typed, valid or not. Each change
//! is validated at once; a valid list rebuilds [`Built`] (the scene, its alias table and its
//! exact denominator) and bumps its generation, which restarts the histograms here and the
//! progressive images in the engine. An invalid list leaves [`Built`] untouched and sets
//! [`AppState::input_error`], a sentence naming the light (1-based, as the panels number
//! them). Tables of up to [`SYNC_BUILD_LIMIT`] lights are built within the same frame;
//! larger ones on a background thread, so dragging a power of the `million` preset never
//! freezes the window (the old table stays on screen until the new one is ready).
//!
//! # Where each concept lives
//! [`settings`] (persisted), [`edit`] (the scene as typed and its edits), [`rebuild`] (from
//! an edit to [`Built`], in the frame or on a worker), [`built`] (the last valid scene and
//! its samplers), [`sampling`] (histograms, chi-square, one draw), [`file_dialog`],
//! [`animation_export`], and one file per window's state (trade, precision, inspector,
//! estimator, walkthrough, stepper) or computed figure ([`scene_sentence`],
//! [`variance_maps`]); `memory` counts what each part holds.

use std::sync::Arc;

use lightpick_core::SceneSamplers;
use lightpick_core::scene::Scene;

pub mod animation_export;
pub mod built;
pub mod counts;
pub mod edit;
pub mod estimator;
pub mod figure;
pub mod file_dialog;
pub mod history;
pub mod inspector;
pub mod light_tree;
mod memory;
pub mod pick_overlay;
pub mod precision;
pub mod rebuild;
pub mod sampling;
pub mod scene_sentence;
pub mod settings;
pub mod stepper;
pub mod trade;
pub mod variance_maps;
pub mod walkthrough;

pub use built::{Built, EXACT_TABLE_MAX_LIGHTS, construction_for};
pub use counts::PickCounts;
pub use edit::{SceneEdit, describe_powers_error, parse_powers, powers_to_text};
pub use file_dialog::{FileAction, FileDialog, FolderEntry};
pub use rebuild::SYNC_BUILD_LIMIT;
pub use sampling::{DIAGRAM_MAX_COLUMNS, MAX_BARS, MAX_CHI_CELLS, OneDraw, SamplingRun};
pub use settings::{BudgetMode, Device, Settings, SliderScale, auto_exposure, nice_ceiling};

use crate::app::scene_io;
use rebuild::TableBuild;

/// How a status message should look.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MessageKind {
    /// Neutral information.
    Info,
    /// Something worked (a file was saved).
    Success,
    /// Something failed; the previous state was kept.
    Error,
}

/// Everything the panels show and edit.
pub struct AppState {
    /// Persisted settings.
    pub settings: Settings,
    /// The scene as edited.
    pub edit: SceneEdit,
    /// The last valid scene and table.
    pub built: Arc<Built>,
    /// Why the edited powers are not valid (names the light), `None` when they are.
    pub input_error: Option<String>,
    /// The powers text field ("2, 5, 20"), kept as typed.
    pub powers_text: String,
    /// The last status message.
    pub status: Option<(String, MessageKind)>,
    /// Histograms and the last single draw.
    pub sampling: SamplingRun,
    /// The path dialog.
    pub file_dialog: FileDialog,
    /// First column shown by the alias-table diagram (large tables show a window).
    pub diagram_offset: usize,
    /// Frames drawn (for throttled work).
    pub frame: u64,
    /// Render one frame while paused (the "step" button or key).
    pub step_requested: bool,
    /// Clear the images and restart accumulation.
    pub reset_requested: bool,
    /// The speed-against-accuracy measurement.
    pub trade: trade::TradeRun,
    /// The precision measurement.
    pub precision: precision::PrecisionRun,
    /// The sentence under the images, computed for the current scene in the background.
    pub scene_sentence: crate::app::background::Background<scene_sentence::SceneSentence>,
    /// The images panel's per-pixel variance maps, computed for the current scene in the
    /// background while they are shown.
    pub variance_maps: crate::app::background::Background<variance_maps::VarianceMaps>,
    /// The pixel inspector (a clicked pixel of the images).
    pub inspector: inspector::Inspector,
    /// The classroom walkthrough (step, saved scene).
    pub walkthrough: walkthrough::WalkthroughState,
    /// The construction stepper (trace, position, playback).
    pub stepper: stepper::StepperState,
    /// The estimator view (one shading point, sample by sample).
    pub estimator: estimator::EstimatorState,
    /// File → "Export animation…": its window, the export running and the last outcome.
    pub animation_export: animation_export::AnimationExport,
    /// What the table and its diagram highlight this frame (set by the walkthrough).
    pub table_highlight: Option<lightpick_core::walkthrough::Highlight>,
    /// The preset the scene is, unedited (set by [`AppState::load_preset`], cleared by any
    /// edit): how a scene too large to store light by light is persisted.
    pub unedited_preset: Option<String>,
    /// Undo and redo over the scene edits.
    pub history: history::History,
    /// The Light tree panel: depth, colouring, the stepped pick.
    pub light_tree: light_tree::LightTreeState,
    /// A panel to bring to the front on the next frame (a menu asked for it).
    pub show_panel: Option<crate::app::panels::panel_kind::PanelKind>,
    /// The Floor control's value and the unedited preset of the installed scene (what an
    /// undo of the next scene change restores).
    installed: (f64, Option<String>),
    next_generation: u64,
    pending: TableBuild,
    rebuild_queued: bool,
    /// The samplers a large scene's last install replaced, and when: the next power edit
    /// rebuilds into their table and tree ([`Built::repowered`]) instead of copying the
    /// current ones. Dropped [`EARLIER_KEPT_S`] after the install (a drag's edits come
    /// faster), so an idle app holds one generation.
    earlier: Option<(std::time::Instant, SceneSamplers)>,
}

impl AppState {
    /// A state showing `scene` with `settings`.
    pub fn new(scene: Scene, settings: Settings) -> Self {
        let edit = SceneEdit::from_scene(&scene);
        let powers_text = powers_to_text(&edit.powers);
        let built = Arc::new(Built::new(1, scene));
        let last_folder = settings.last_folder.clone().filter(|f| f.is_dir());
        let mut state = Self {
            settings,
            edit,
            built,
            input_error: None,
            powers_text,
            status: None,
            sampling: SamplingRun::default(),
            file_dialog: FileDialog {
                folder: last_folder,
                ..FileDialog::default()
            },
            diagram_offset: 0,
            frame: 0,
            step_requested: false,
            reset_requested: false,
            trade: trade::TradeRun::default(),
            precision: precision::PrecisionRun::default(),
            scene_sentence: crate::app::background::Background::default(),
            variance_maps: crate::app::background::Background::default(),
            inspector: inspector::Inspector::default(),
            walkthrough: walkthrough::WalkthroughState::default(),
            stepper: stepper::StepperState::default(),
            estimator: estimator::EstimatorState::default(),
            animation_export: animation_export::AnimationExport::default(),
            table_highlight: None,
            unedited_preset: None,
            history: history::History::default(),
            light_tree: light_tree::LightTreeState::default(),
            show_panel: None,
            installed: (0.0, None),
            next_generation: 2,
            pending: TableBuild::default(),
            rebuild_queued: false,
            earlier: None,
        };
        state.restart_sampling();
        state
    }

    /// The worked example (powers 2, 5, 20) with default settings.
    pub fn worked_example() -> Self {
        Self::new(scene_io::worked_example_scene(), Settings::default())
    }

    /// Once per frame: takes the sentence under the images when its worker is done, and
    /// starts it for a new scene generation.
    pub fn update_scene_sentence(&mut self) {
        let generation = self.built.generation;
        let samplers = self.built.samplers.clone();
        self.scene_sentence
            .refresh(generation, "lightpick-sentence", move |_| {
                scene_sentence::scene_sentence(generation, &samplers)
            });
    }

    /// The sentence under the images if it describes the current scene (never one left
    /// from an earlier scene).
    pub fn current_scene_sentence(&self) -> Option<&scene_sentence::SceneSentence> {
        self.scene_sentence.of_generation(self.built.generation)
    }

    /// Takes the variance maps when their job is done, and starts it for a new scene
    /// generation; the images panel calls it each frame while the maps are shown.
    pub fn update_variance_maps(&mut self) {
        let generation = self.built.generation;
        let samplers = self.built.samplers.clone();
        self.variance_maps
            .refresh(generation, "lightpick-variance", move |_| {
                variance_maps::variance_maps(generation, &samplers)
            });
    }

    /// The variance maps if they describe the current scene (never maps of an earlier one).
    pub fn current_variance_maps(&self) -> Option<&variance_maps::VarianceMaps> {
        self.variance_maps.of_generation(self.built.generation)
    }

    /// Whether the images wait for the Trade measurement: while it runs, no live render
    /// shares the threads it times (its plot and its table are one measurement).
    pub fn trade_pauses_images(&self) -> bool {
        self.trade.is_measuring()
    }

    /// Whether the theme is dark.
    pub fn dark(&self) -> bool {
        self.settings.dark
    }

    /// Sets a status message.
    pub fn message(&mut self, text: impl Into<String>, kind: MessageKind) {
        self.status = Some((text.into(), kind));
    }
}
