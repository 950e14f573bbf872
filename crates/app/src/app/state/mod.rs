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

use std::sync::Arc;

use glam::DVec3;
use lightpick_core::scene::{Emission, ReceiverPlane, Scene};
use lightpick_core::{
    ChiSquare, LightPowers, PowersError, Rng, SceneSamplers, Uniform, chi_square_cells,
};

use super::background::{Polled, Worker};
use super::scene_io::{self, PowerDistribution};

pub mod animation_export;
pub mod built;
pub mod counts;
pub mod estimator;
pub mod inspector;
mod memory;
pub mod precision;
pub mod stepper;
pub mod trade;
pub mod walkthrough;

pub use built::{Built, EXACT_TABLE_MAX_LIGHTS, construction_for};
pub use counts::PickCounts;

/// Tables of at most this many lights are rebuilt on the UI thread, within the frame.
pub const SYNC_BUILD_LIMIT: usize = 50_000;

/// Where the progressive images are rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Device {
    /// The GPU when it is a hardware one; on a software rasterizer (lavapipe) whichever of
    /// the two renders the images faster, measured ([`crate::app::placement`]).
    Auto,
    /// wgpu compute on eframe's own device (falls back to the CPU without one).
    Gpu,
    /// The CPU renderer (rayon).
    Cpu,
}

/// How the two images share the work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BudgetMode {
    /// Every scheme takes the same samples per pixel per frame.
    EqualSamples,
    /// Every scheme gets the same compute time per frame.
    EqualTime,
}

/// The light-power slider scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SliderScale {
    /// Linear from 0 to the slider maximum.
    Linear,
    /// Logarithmic over six decades below the slider maximum.
    Log,
}

/// Settings kept between sessions (eframe persistence).
#[allow(clippy::struct_excessive_bools)] // Independent on/off switches of the UI, persisted as such.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Samples per pixel each scheme adds per frame (equal-samples mode).
    pub spp_per_frame: u32,
    /// The seed of every random stream (images, histograms, generated scenes).
    pub seed: u64,
    /// Whether sampling and accumulation are paused.
    pub paused: bool,
    /// The preferred render device.
    pub device: Device,
    /// Tonemap exposure (irradiance multiplier).
    pub exposure: f64,
    /// Equal samples or equal time.
    pub budget: BudgetMode,
    /// Show the exact reference image.
    pub show_reference: bool,
    /// Show the error maps under the images.
    pub show_error: bool,
    /// Power slider scale.
    pub slider_scale: SliderScale,
    /// Upper end of the power sliders.
    pub slider_max: f64,
    /// Light picks per frame for the histograms (each scheme).
    pub picks_per_frame: u32,
    /// Distribution for "randomize" and "generate".
    pub distribution: PowerDistribution,
    /// How many lights "generate" makes.
    pub generate_count: usize,
    /// Dark theme (else light).
    pub dark: bool,
    /// Show the speed-against-accuracy window.
    pub show_trade: bool,
    /// Show the precision window.
    pub show_precision: bool,
    /// Show the classroom walkthrough window.
    pub show_walkthrough: bool,
    /// Show the construction stepper window.
    pub show_stepper: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            spp_per_frame: 1,
            seed: 1,
            paused: false,
            device: Device::Auto,
            exposure: 1.0,
            budget: BudgetMode::EqualSamples,
            show_reference: true,
            show_error: true,
            slider_scale: SliderScale::Linear,
            slider_max: 40.0,
            picks_per_frame: 200,
            distribution: PowerDistribution::Exponential,
            generate_count: 16,
            dark: true,
            show_trade: false,
            show_precision: false,
            show_walkthrough: false,
            show_stepper: false,
        }
    }
}

/// The scene as the user is editing it: powers exactly as typed, valid or not.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneEdit {
    /// Scene name.
    pub name: String,
    /// The receiver plane and its pixel grid.
    pub plane: ReceiverPlane,
    /// Light positions, shared with the scene they came from (or were last built into):
    /// writes go through [`SceneEdit::positions_mut`], which copies them only while a scene
    /// still shares them.
    pub positions: Arc<[DVec3]>,
    /// Light powers as typed (may hold NaN or negatives until corrected), shared like the
    /// positions ([`SceneEdit::powers_mut`]): a valid edit becomes the next scene's powers
    /// without a copy.
    pub powers: Arc<[f64]>,
    /// Each light's spot cone and range, when the scene has any (kept through edits).
    pub emission: Option<Vec<Emission>>,
    /// Each light's name, when the scene's source named its lights.
    pub names: Option<Vec<String>>,
    /// The receiver's height above the scene's ground as loaded (the Floor control): every
    /// light's `z` is its loaded height minus this.
    pub floor: f64,
}

impl SceneEdit {
    /// The editable copy of a scene.
    pub fn from_scene(scene: &Scene) -> Self {
        Self {
            name: scene.name.clone(),
            plane: scene.plane.clone(),
            positions: Arc::clone(&scene.positions),
            powers: Arc::clone(scene.powers.shared()),
            emission: scene.emission.clone(),
            names: scene.names.clone(),
            floor: 0.0,
        }
    }

    /// The positions to write to (copied first if a scene still shares them).
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        Arc::make_mut(&mut self.positions)
    }

    /// The powers to write to (copied first if a scene still shares them).
    pub fn powers_mut(&mut self) -> &mut [f64] {
        Arc::make_mut(&mut self.powers)
    }

    /// Changes the number of lights: `change` edits the positions and powers as vectors
    /// (one copy each, as any resize of a shared array takes).
    fn resize_lights(&mut self, change: impl FnOnce(&mut Vec<DVec3>, &mut Vec<f64>)) {
        let mut positions = self.positions.to_vec();
        let mut powers = self.powers.to_vec();
        change(&mut positions, &mut powers);
        self.positions = positions.into();
        self.powers = powers.into();
    }

    /// Keeps one emission profile and one name per light: lights added get a point
    /// light's profile and no name, removed ones lose theirs.
    fn fit_extras(&mut self, n: usize) {
        if let Some(e) = &mut self.emission {
            e.resize(n, Emission::POINT);
        }
        if let Some(names) = &mut self.names {
            names.resize(n, String::new());
        }
    }

    /// Removes light `i`'s profile and name.
    fn remove_extras(&mut self, i: usize) {
        if let Some(e) = self.emission.as_mut().filter(|e| i < e.len()) {
            e.remove(i);
        }
        if let Some(names) = self.names.as_mut().filter(|n| i < n.len()) {
            names.remove(i);
        }
    }

    /// Copies light `i`'s profile and name to a new light right after it.
    fn duplicate_extras(&mut self, i: usize) {
        if let Some(e) = self.emission.as_mut().filter(|e| i < e.len()) {
            e.insert(i + 1, e[i]);
        }
        if let Some(names) = self.names.as_mut().filter(|n| i < n.len()) {
            let copy = names[i].clone();
            names.insert(i + 1, copy);
        }
    }

    /// The light's name for display: its own, else `light k` (numbered from 1).
    pub fn display_name(&self, i: usize) -> String {
        self.names
            .as_ref()
            .and_then(|n| n.get(i))
            .filter(|n| !n.is_empty())
            .cloned()
            .unwrap_or_else(|| format!("light {}", i + 1))
    }
}

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

/// One "draw one sample" step, for the diagram to replay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneDraw {
    /// First 32-bit random: picks the column by multiply-high.
    pub r1: u32,
    /// Second 32-bit random: compared with the column's threshold.
    pub r2: u32,
    /// The column `⌊r1·N/2^32⌋` (0-based).
    pub column: usize,
    /// `U1 = r1/2^32`.
    pub u1: f64,
    /// `U2 = r2/2^32`.
    pub u2: f64,
    /// The column's threshold.
    pub threshold: f64,
    /// Whether `U2 < threshold` (keep the column's own light).
    pub kept: bool,
    /// The light returned (0-based).
    pub light: u32,
}

/// Running histograms of uniform and alias picks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SamplingRun {
    /// Generation of the table the counts belong to.
    pub generation: u64,
    /// Lights per chi-square cell: 1 up to [`MAX_CHI_CELLS`] lights, else the lights are
    /// grouped (consecutive, fixed before any pick) into at most that many cells.
    pub per_cell: usize,
    /// Picks per cell by uniform selection.
    pub uniform_counts: PickCounts,
    /// Picks per cell by the alias table.
    pub alias_counts: PickCounts,
    /// Each cell's probability under the alias table, `Σ p_i` over its lights (the table's
    /// pmf itself when a cell is one light).
    pub alias_cell_pmf: Vec<f64>,
    /// Picks so far (each scheme).
    pub picks: u64,
    /// Chi-square of the uniform counts against `1/N`.
    pub uniform_chi: Option<ChiSquare>,
    /// Chi-square of the alias counts against the pmf.
    pub alias_chi: Option<ChiSquare>,
    /// The last "draw one sample".
    pub last_draw: Option<OneDraw>,
    /// How many single draws were made (their stream index).
    pub draws: u64,
    /// Lights per histogram bar (1 for small tables).
    pub per_bin: usize,
    /// Uniform picks per bar.
    pub uniform_bins: Vec<u64>,
    /// Alias picks per bar.
    pub alias_bins: Vec<u64>,
    /// Expected alias frequency per bar (`Σ p_i` over its lights).
    pub expected_bins: Vec<f64>,
    /// Expected uniform frequency per bar (its share of the lights).
    pub flat_bins: Vec<f64>,
}

/// The alias-table diagram shows at most this many columns (a window of a larger table).
pub const DIAGRAM_MAX_COLUMNS: usize = 64;

/// Histograms group lights into at most this many bars.
pub const MAX_BARS: usize = 48;

/// The chi-square tests count picks per light up to this many lights (`2^16`, the
/// classroom's exact tables), and per group of consecutive lights above, in at most this
/// many cells: the cells are fixed before sampling, so the test stays Pearson's, and the
/// counts cost 8 bytes per cell instead of per light.
pub const MAX_CHI_CELLS: usize = 1 << 16;

/// A file action waiting for its path in the in-app dialog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileAction {
    /// Open a scene file (lightpick JSON, glTF/GLB, CSV).
    OpenScene,
    /// Save the scene as JSON.
    SaveScene,
    /// Export the images as PNG files.
    ExportImages,
    /// Export the alias-table diagram as a PNG file.
    ExportDiagram,
}

impl FileAction {
    /// The dialog title.
    pub fn title(self) -> &'static str {
        match self {
            FileAction::OpenScene => "Open scene",
            FileAction::SaveScene => "Save scene",
            FileAction::ExportImages => "Export images (PNG)",
            FileAction::ExportDiagram => "Export alias-table diagram (PNG)",
        }
    }

    /// The file types the action reads or writes: a label and the extensions.
    pub fn file_types(self) -> (&'static str, &'static [&'static str]) {
        match self {
            FileAction::OpenScene => (
                "Scenes (glTF, GLB, CSV, JSON)",
                &lightpick_core::scene::SceneFormat::EXTENSIONS,
            ),
            FileAction::SaveScene => ("lightpick JSON", &["json"]),
            FileAction::ExportImages | FileAction::ExportDiagram => ("PNG images", &["png"]),
        }
    }
}

/// One entry of the folder the file dialog shows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FolderEntry {
    /// The file or folder name.
    pub name: String,
    /// Whether it is a folder.
    pub is_dir: bool,
    /// Size in bytes (files).
    pub bytes: u64,
}

/// The in-app file chooser: a folder to browse, a path to type or pick.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FileDialog {
    /// The pending action, `None` when the dialog is closed.
    pub action: Option<FileAction>,
    /// The path being typed or picked: absolute, or relative to `folder`.
    pub path: String,
    /// Why the last attempt failed (shown in the dialog, the path stays as typed).
    pub error: Option<String>,
    /// The folder shown (`None`: the working directory).
    pub folder: Option<std::path::PathBuf>,
    /// Show every file, not only the action's types.
    pub all_files: bool,
    /// The folder's entries as last listed (folders first, then by name), or why it could
    /// not be read.
    pub listing: Option<(std::path::PathBuf, Result<Vec<FolderEntry>, String>)>,
}

impl FileDialog {
    /// The folder shown.
    pub fn folder(&self) -> std::path::PathBuf {
        self.folder
            .clone()
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| std::path::PathBuf::from("."))
    }

    /// The full path of what is typed: itself when absolute, else within the folder.
    pub fn resolved(&self) -> std::path::PathBuf {
        let typed = std::path::Path::new(self.path.trim());
        if typed.is_absolute() {
            typed.to_owned()
        } else {
            self.folder().join(typed)
        }
    }
}

/// A table (with its samplers) being built on a worker for one scene generation.
struct TableBuild {
    generation: u64,
    worker: Worker<Built>,
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
    next_generation: u64,
    pending: Option<TableBuild>,
    rebuild_queued: bool,
    /// The samplers a large scene's last install replaced, and when: the next power edit
    /// rebuilds into their table and tree ([`Built::repowered`]) instead of copying the
    /// current ones. Dropped [`EARLIER_KEPT_S`] after the install (a drag's edits come
    /// faster), so an idle app holds one generation.
    earlier: Option<(std::time::Instant, SceneSamplers)>,
}

/// Seconds the replaced samplers of a large scene are kept for the next power edit.
const EARLIER_KEPT_S: f64 = 1.0;

impl AppState {
    /// A state showing `scene` with `settings`.
    pub fn new(scene: Scene, settings: Settings) -> Self {
        let edit = SceneEdit::from_scene(&scene);
        let powers_text = powers_to_text(&edit.powers);
        let built = Arc::new(Built::new(1, scene));
        let mut state = Self {
            settings,
            edit,
            built,
            input_error: None,
            powers_text,
            status: None,
            sampling: SamplingRun::default(),
            file_dialog: FileDialog::default(),
            diagram_offset: 0,
            frame: 0,
            step_requested: false,
            reset_requested: false,
            trade: trade::TradeRun::default(),
            precision: precision::PrecisionRun::default(),
            inspector: inspector::Inspector::default(),
            walkthrough: walkthrough::WalkthroughState::default(),
            stepper: stepper::StepperState::default(),
            estimator: estimator::EstimatorState::default(),
            animation_export: animation_export::AnimationExport::default(),
            table_highlight: None,
            unedited_preset: None,
            next_generation: 2,
            pending: None,
            rebuild_queued: false,
            earlier: None,
        };
        state.restart_sampling();
        state
    }

    /// The seed scene (powers 2, 5, 20) with default settings.
    pub fn seed() -> Self {
        Self::new(scene_io::seed_scene(), Settings::default())
    }

    /// Whether the theme is dark.
    pub fn dark(&self) -> bool {
        self.settings.dark
    }

    /// Whether a table is being built in the background.
    pub fn is_building(&self) -> bool {
        self.pending.is_some()
    }

    /// Sets a status message.
    pub fn message(&mut self, text: impl Into<String>, kind: MessageKind) {
        self.status = Some((text.into(), kind));
    }

    /// Replaces the whole scene (preset, file, generated): the edit, the text field and the
    /// table, and a slider range that fits it.
    pub fn load_scene(&mut self, scene: Scene) {
        self.unedited_preset = None;
        self.edit = SceneEdit::from_scene(&scene);
        self.powers_text = powers_to_text(&self.edit.powers);
        self.input_error = None;
        self.diagram_offset = 0;
        self.settings.slider_max = nice_ceiling(2.0 * scene.powers.max());
        self.settings.exposure = auto_exposure(&scene);
        let n = scene.light_count();
        self.pending = None;
        self.rebuild_queued = false;
        if n <= SYNC_BUILD_LIMIT {
            let generation = self.take_generation();
            self.install(Built::new(generation, scene));
        } else {
            self.spawn_build(scene);
        }
    }

    /// Loads the bundled scene `name` ([`scene_io::preset`]), or says why it cannot.
    pub fn load_preset(&mut self, name: &str) {
        match scene_io::preset(name) {
            Ok(scene) => {
                self.load_scene(scene);
                self.unedited_preset = Some(name.to_owned());
                self.message(format!("loaded preset '{name}'"), MessageKind::Info);
            }
            Err(e) => self.message(e, MessageKind::Error),
        }
    }

    /// Call after any change of `edit.powers`: validates and rebuilds, or names the problem
    /// and keeps the last good table.
    pub fn powers_changed(&mut self) {
        self.unedited_preset = None;
        if self.edit.powers.len() > SYNC_BUILD_LIMIT && self.pending.is_some() {
            // One background build at a time: this edit is validated and built as soon as
            // the running build lands (the latest values win; intermediate ones are skipped).
            self.rebuild_queued = true;
            return;
        }
        match LightPowers::from_shared(Arc::clone(&self.edit.powers)) {
            Err(e) => {
                self.input_error = Some(describe_powers_error(&e));
            }
            Ok(powers) => {
                self.input_error = None;
                self.sync_positions(powers.len());
                let mut scene = scene_io::assemble(
                    &self.edit.name,
                    self.edit.plane.clone(),
                    Arc::clone(&self.edit.positions),
                    powers,
                );
                scene.emission.clone_from(&self.edit.emission);
                scene.names.clone_from(&self.edit.names);
                if scene.light_count() <= SYNC_BUILD_LIMIT {
                    self.pending = None;
                    self.rebuild_queued = false;
                    let generation = self.take_generation();
                    let built = Built::from_edit(generation, scene, &self.built.samplers, None);
                    self.install(built);
                } else if self.pending.is_some() {
                    self.rebuild_queued = true;
                } else {
                    // A power edit keeps the geometry: the worker refits the tree, into the
                    // one two edits back if nothing holds it any more.
                    let earlier = self.earlier.take().map(|(_, samplers)| samplers);
                    self.spawn_build_from(scene, Some((self.built.samplers.clone(), earlier)));
                }
            }
        }
    }

    /// Moves the receiver to height `floor` above the scene's ground as loaded: every light's
    /// `z` shifts by the change, and lights on or below the receiver light nothing.
    pub fn set_floor(&mut self, floor: f64) {
        if !floor.is_finite() || floor == self.edit.floor {
            return;
        }
        let shift = floor - self.edit.floor;
        for p in self.edit.positions_mut() {
            p.z -= shift;
        }
        self.edit.floor = floor;
        self.unedited_preset = None;
        self.powers_changed();
        let above = self.edit.positions.iter().filter(|p| p.z > 0.0).count();
        self.message(
            format!(
                "receiver at height {floor}: {above} of {} lights above it",
                self.edit.positions.len()
            ),
            MessageKind::Info,
        );
    }

    /// Parses the powers text field ("2, 5, 20" or white space) and applies it; a word that
    /// is not a number is named and nothing changes.
    pub fn apply_powers_text(&mut self) {
        match parse_powers(&self.powers_text) {
            Ok(powers) => {
                let n = powers.len();
                self.edit.powers = powers.into();
                if self.edit.positions.len() > n {
                    self.edit
                        .resize_lights(|positions, _| positions.truncate(n));
                }
                self.powers_changed();
            }
            Err(message) => self.input_error = Some(message),
        }
    }

    /// Adds a light with power `power` at a fresh position.
    pub fn add_light(&mut self, power: f64) {
        let i = self.edit.powers.len();
        let pos =
            scene_io::random_positions(i + 1, &self.edit.plane, self.settings.seed ^ i as u64)[i];
        self.edit.resize_lights(|positions, powers| {
            positions.push(pos);
            powers.push(power);
        });
        self.edit.fit_extras(i + 1);
        self.after_structure_change();
    }

    /// Removes light `i` (refused for the last light).
    pub fn remove_light(&mut self, i: usize) {
        if self.edit.powers.len() <= 1 || i >= self.edit.powers.len() {
            self.message("a scene needs at least one light", MessageKind::Error);
            return;
        }
        self.edit.resize_lights(|positions, powers| {
            powers.remove(i);
            if i < positions.len() {
                positions.remove(i);
            }
        });
        self.edit.remove_extras(i);
        self.after_structure_change();
    }

    /// Duplicates light `i` (same position and power) right after it.
    pub fn duplicate_light(&mut self, i: usize) {
        if i >= self.edit.powers.len() {
            return;
        }
        self.edit.resize_lights(|positions, powers| {
            powers.insert(i + 1, powers[i]);
            let pos = positions.get(i).copied().unwrap_or(DVec3::Z);
            positions.insert(i + 1, pos);
        });
        self.edit.duplicate_extras(i);
        self.after_structure_change();
    }

    /// Draws new powers for every light from the chosen distribution.
    pub fn randomize(&mut self) {
        let n = self.edit.powers.len();
        let scale = (self.settings.slider_max / 4.0).max(f64::MIN_POSITIVE);
        let seed = self.settings.seed.wrapping_add(self.frame);
        self.edit.powers =
            scene_io::random_powers(n, self.settings.distribution, scale, seed).into();
        self.after_structure_change();
    }

    /// Replaces the scene by `count` random lights over the current plane, `1 ..= 2^24`
    /// ([`lightpick_core::scene::MAX_LIGHTS`]); another count is refused with a message, never
    /// clamped.
    pub fn generate(&mut self, count: usize) {
        let max = lightpick_core::scene::MAX_LIGHTS;
        if !(1..=max).contains(&count) {
            self.message(
                format!("Generate: {count} lights is outside 1 ..= {max} (the scene limit 2^24)"),
                MessageKind::Error,
            );
            return;
        }
        let seed = self.settings.seed;
        let powers = scene_io::random_powers(count, self.settings.distribution, 10.0, seed);
        let positions = scene_io::random_positions(count, &self.edit.plane, seed);
        match LightPowers::new(powers) {
            Ok(powers) => {
                let scene = scene_io::assemble(
                    &format!("generated-{count}"),
                    self.edit.plane.clone(),
                    positions,
                    powers,
                );
                self.load_scene(scene);
                self.message(format!("generated {count} lights"), MessageKind::Info);
            }
            Err(e) => self.message(describe_powers_error(&e), MessageKind::Error),
        }
    }

    /// Keeps one position per power: lights added through the text field get fresh ones.
    fn sync_positions(&mut self, n: usize) {
        let have = self.edit.positions.len();
        if have != n {
            let fresh = (have < n)
                .then(|| scene_io::random_positions(n, &self.edit.plane, self.settings.seed));
            self.edit.resize_lights(|positions, _| {
                if let Some(fresh) = &fresh {
                    positions.extend_from_slice(&fresh[have..]);
                }
                positions.truncate(n);
            });
        }
        self.edit.fit_extras(n);
    }

    fn after_structure_change(&mut self) {
        self.powers_text = if self.edit.powers.len() <= 1000 {
            powers_to_text(&self.edit.powers)
        } else {
            String::new()
        };
        self.powers_changed();
    }

    fn take_generation(&mut self) -> u64 {
        let g = self.next_generation;
        self.next_generation += 1;
        g
    }

    fn install(&mut self, built: Built) {
        let replaced = std::mem::replace(&mut self.built, Arc::new(built));
        self.earlier = (self.built.len() > SYNC_BUILD_LIMIT
            && replaced.scene.same_geometry(&self.built.scene))
        .then(|| Arc::try_unwrap(replaced).ok())
        .flatten()
        .map(|replaced| (std::time::Instant::now(), replaced.samplers));
        if self.diagram_offset >= self.built.len() {
            self.diagram_offset = 0;
        }
        self.restart_sampling();
    }

    fn spawn_build(&mut self, scene: Scene) {
        self.spawn_build_from(scene, None);
    }

    /// Builds on a worker thread: [`Built::from_edit`] when the previous samplers are given
    /// (a refit when the geometry is kept; into the earlier ones where given and unshared),
    /// else [`Built::new`].
    fn spawn_build_from(
        &mut self,
        scene: Scene,
        previous: Option<(SceneSamplers, Option<SceneSamplers>)>,
    ) {
        let generation = self.take_generation();
        let spawned = Worker::spawn("lightpick-table", move || match previous {
            Some((previous, earlier)) => Built::from_edit(generation, scene, &previous, earlier),
            None => Built::new(generation, scene),
        });
        match spawned {
            Ok(worker) => self.pending = Some(TableBuild { generation, worker }),
            Err(e) => self.message(
                format!("cannot start the table builder: {e}"),
                MessageKind::Error,
            ),
        }
    }

    /// Installs a table finished in the background; call once per frame.
    pub fn poll_build(&mut self) {
        if self
            .earlier
            .as_ref()
            .is_some_and(|(at, _)| at.elapsed().as_secs_f64() > EARLIER_KEPT_S)
        {
            self.earlier = None;
        }
        let Some(pending) = &self.pending else {
            return;
        };
        match pending.worker.poll() {
            Polled::Done(built) => {
                debug_assert_eq!(built.generation, pending.generation);
                self.pending = None;
                self.install(built);
                if std::mem::take(&mut self.rebuild_queued) {
                    self.powers_changed();
                }
            }
            Polled::Running => {}
            Polled::Lost => {
                self.pending = None;
                self.message("the table builder stopped unexpectedly", MessageKind::Error);
            }
        }
    }

    /// Clears the histograms for the current table.
    pub fn restart_sampling(&mut self) {
        let n = self.built.len();
        let per_bin = n.div_ceil(MAX_BARS).max(1);
        let bars = n.div_ceil(per_bin);
        let pmf = self.built.pmf();
        let expected_bins = pmf.chunks(per_bin).map(|c| c.iter().sum()).collect();
        let per_cell = n.div_ceil(MAX_CHI_CELLS).max(1);
        let alias_cell_pmf: Vec<f64> = if per_cell == 1 {
            pmf.to_vec()
        } else {
            pmf.chunks(per_cell).map(|c| c.iter().sum()).collect()
        };
        let cells = alias_cell_pmf.len();
        let flat_bins = (0..bars)
            .map(|b| (((b + 1) * per_bin).min(n) - b * per_bin) as f64 / n as f64)
            .collect();
        self.sampling = SamplingRun {
            generation: self.built.generation,
            per_cell,
            uniform_counts: PickCounts::zeros(cells),
            alias_counts: PickCounts::zeros(cells),
            alias_cell_pmf,
            per_bin,
            uniform_bins: vec![0; bars],
            alias_bins: vec![0; bars],
            expected_bins,
            flat_bins,
            ..SamplingRun::default()
        };
    }

    /// Adds `count` picks of each scheme to the histograms (streams continue where the last
    /// call stopped, so the counts are reproducible from the seed).
    pub fn sample_picks(&mut self, count: u32) {
        if self.sampling.generation != self.built.generation {
            self.restart_sampling();
        }
        let built = Arc::clone(&self.built);
        let n = built.len() as u32;
        let uniform = Uniform::new(n);
        let seed = self.settings.seed;
        let start = self.sampling.picks;
        for k in start..start + u64::from(count) {
            // The exact picks of `Sampler::pick_light` (rejection keeps columns uniform).
            let mut rng = Rng::new(seed, k);
            let u = uniform.sample(&mut rng) as usize;
            self.sampling.uniform_counts.add(u / self.sampling.per_cell);
            self.sampling.uniform_bins[u / self.sampling.per_bin] += 1;
            let mut rng = Rng::new(seed ^ 0xA11A5, k);
            let a = built.table.sample(&mut rng) as usize;
            self.sampling.alias_counts.add(a / self.sampling.per_cell);
            self.sampling.alias_bins[a / self.sampling.per_bin] += 1;
        }
        self.sampling.picks += u64::from(count);
        // Chi-square is O(N): every frame for small tables, every 16th frame for large ones.
        if n <= 10_000 || self.frame.is_multiple_of(16) || count == 0 {
            self.update_chi_square();
        }
    }

    /// Recomputes both chi-square tests from the counts.
    pub fn update_chi_square(&mut self) {
        if self.sampling.picks == 0 {
            self.sampling.uniform_chi = None;
            self.sampling.alias_chi = None;
            return;
        }
        let n = self.built.len();
        let sampling = &self.sampling;
        let per_cell = sampling.per_cell;
        // Cell c holds lights c·k .. min((c + 1)·k, N): its uniform probability is its size
        // over N (1/N for every cell of one light).
        let flat = (0..sampling.uniform_counts.len())
            .map(|c| (((c + 1) * per_cell).min(n) - c * per_cell) as f64 / n as f64);
        let uniform = chi_square_cells(sampling.uniform_counts.iter().zip(flat));
        let alias = chi_square_cells(
            sampling
                .alias_counts
                .iter()
                .zip(sampling.alias_cell_pmf.iter().copied()),
        );
        self.sampling.uniform_chi = Some(uniform);
        self.sampling.alias_chi = Some(alias);
    }

    /// Draws one sample with two fresh randoms and records how the table answered.
    pub fn draw_one(&mut self) {
        let mut rng = Rng::new(self.settings.seed ^ 0xD12A_0001, self.sampling.draws);
        self.sampling.draws += 1;
        let table = &self.built.table;
        // U1 is the accepted draw of the exact column pick (a draw in the rare band that
        // would make columns unequal is redrawn); U2 is the next draw.
        let columns = Uniform::new(table.len() as u32);
        let (r1, column) = loop {
            let r = rng.next_u32();
            if let Some(c) = columns.accept(r) {
                break (r, c as usize);
            }
        };
        let r2 = rng.next_u32();
        let light = table.resolve(column, r2);
        let draw = OneDraw {
            r1,
            r2,
            column,
            u1: lightpick_core::unit_f64(r1),
            u2: lightpick_core::unit_f64(r2),
            threshold: table.threshold(column),
            kept: light as usize == column,
            light,
        };
        // Large tables show a window of columns: move it to the picked one.
        if table.len() > DIAGRAM_MAX_COLUMNS {
            self.diagram_offset = column.saturating_sub(DIAGRAM_MAX_COLUMNS / 2);
        }
        self.sampling.last_draw = Some(draw);
    }
}

impl AppState {
    /// Once per frame, before the panels: restores the user's scene when the walkthrough
    /// was just closed, and sets the table highlight of the current step (or clears it).
    pub fn prepare_walkthrough(&mut self) {
        let open = self.settings.show_walkthrough;
        if self.walkthrough.was_open && !open {
            self.restore_scene();
        }
        self.walkthrough.was_open = open;
        self.table_highlight = None;
        if let Some(walk) = self.walkthrough_lesson() {
            let k = self.walkthrough.step.min(walk.1.len() - 1);
            self.walkthrough.step = k;
            self.table_highlight = Some(walk.1[k].highlight.clone());
        }
    }

    /// The walkthrough of the current powers, `None` when its window is closed or the scene
    /// does not have three lights.
    pub fn walkthrough_lesson(&mut self) -> Option<walkthrough::Lesson> {
        if !self.settings.show_walkthrough {
            return None;
        }
        let built = Arc::clone(&self.built);
        self.walkthrough.lesson(&built)
    }

    /// The construction of the current table for the stepper (`None` beyond
    /// [`stepper::STEPPER_MAX_LIGHTS`] lights).
    pub fn stepper_trace(
        &mut self,
    ) -> Option<Arc<lightpick_core::construction::ConstructionTrace>> {
        let built = Arc::clone(&self.built);
        self.stepper.trace(&built)
    }

    /// Loads the seed scene (2, 5, 20), keeping the user's scene for later.
    pub fn load_classic(&mut self) {
        if self.walkthrough.saved_scene.is_none() {
            self.walkthrough.saved_scene = Some((*self.built.scene).clone());
        }
        self.load_scene(scene_io::seed_scene());
        self.walkthrough.step = 0;
        self.message(
            "classic scene loaded (powers 2, 5, 20); your scene comes back when the \
             walkthrough closes",
            MessageKind::Info,
        );
    }

    /// Puts the scene kept by the walkthrough back, if any.
    pub fn restore_scene(&mut self) {
        if let Some(scene) = self.walkthrough.saved_scene.take() {
            let text = format!(
                "restored your scene \"{}\" ({} lights)",
                scene.name,
                scene.light_count()
            );
            self.load_scene(scene);
            self.message(text, MessageKind::Success);
        }
    }
}

/// A one-line, 1-based description of a power problem, saying the last valid table is kept.
pub fn describe_powers_error(e: &PowersError) -> String {
    let problem = match e {
        PowersError::Empty => "there are no lights".to_owned(),
        PowersError::NotFinite { index, value } => {
            format!("light {}: power {value} is not a finite number", index + 1)
        }
        PowersError::Negative { index, value } => {
            format!("light {}: power {value} is negative", index + 1)
        }
        PowersError::AllZero { count } => {
            format!("all {count} powers are zero: nothing emits light")
        }
        PowersError::TooMany { .. } => e.to_string(),
    };
    format!("{problem} — keeping the last valid table")
}

/// Powers separated by commas, semicolons or white space; a word that is not a number is
/// named (1-based position). NaN and negative numbers parse here and are refused later with
/// the light's number.
pub fn parse_powers(text: &str) -> Result<Vec<f64>, String> {
    let words: Vec<&str> = text
        .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
        .filter(|w| !w.is_empty())
        .collect();
    if words.is_empty() {
        return Err("the powers field is empty — keeping the last valid table".to_owned());
    }
    words
        .iter()
        .enumerate()
        .map(|(i, w)| {
            w.replace('−', "-").parse::<f64>().map_err(|_| {
                format!(
                    "light {}: '{w}' is not a number — keeping the last valid table",
                    i + 1
                )
            })
        })
        .collect()
}

/// The powers as "2, 5, 20".
pub fn powers_to_text(powers: &[f64]) -> String {
    if powers.len() > 1000 {
        return String::new();
    }
    powers
        .iter()
        .map(f64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The smallest of 1, 2, 5 × 10^k at or above `x` (at least 1e-300).
pub fn nice_ceiling(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let decade = 10f64.powf(x.log10().floor());
    for m in [1.0, 2.0, 5.0, 10.0] {
        if m * decade >= x {
            return m * decade;
        }
    }
    10.0 * decade
}

/// An exposure that maps the scene's mean irradiance to about 1 (Reinhard's mid-grey), from
/// the exact irradiance at 8×8 pixel centres (at most 4096 lights, scaled up for more).
pub fn auto_exposure(scene: &Scene) -> f64 {
    let n = scene.light_count();
    let stride = n.div_ceil(4096).max(1);
    let mut sum = 0.0;
    let mut count = 0.0;
    for gy in 0..8u32 {
        for gx in 0..8u32 {
            let px = (gx * scene.plane.width) / 8 + scene.plane.width / 16;
            let py = (gy * scene.plane.height) / 8 + scene.plane.height / 16;
            let x = lightpick_core::scene::pixel_center(&scene.plane, px, py);
            let e: f64 = (0..n)
                .step_by(stride)
                .map(|i| scene.powers.as_slice()[i] * scene.light_term(i, x))
                .sum::<f64>()
                * stride as f64;
            sum += e;
            count += 1.0;
        }
    }
    let mean = sum / count;
    if mean.is_finite() && mean > 0.0 {
        1.0 / mean
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_names_the_bad_word() {
        assert_eq!(parse_powers("2, 5 20").unwrap(), vec![2.0, 5.0, 20.0]);
        let err = parse_powers("2, five, 20").unwrap_err();
        assert!(err.contains("light 2"), "{err}");
        assert!(parse_powers("nan").unwrap()[0].is_nan());
    }

    #[test]
    fn errors_are_one_based() {
        let e = LightPowers::new(vec![1.0, -2.0]).unwrap_err();
        assert!(describe_powers_error(&e).starts_with("light 2: power -2 is negative"));
    }

    #[test]
    fn generate_refuses_counts_beyond_the_scene_limit_by_name() {
        let mut state = AppState::new(scene_io::seed_scene(), Settings::default());
        let max = lightpick_core::scene::MAX_LIGHTS;
        for count in [0, max + 1] {
            state.generate(count);
            let (text, kind) = state.status.clone().expect("a message");
            assert_eq!(kind, MessageKind::Error);
            assert!(
                text.contains(&count.to_string()) && text.contains("2^24"),
                "{text}"
            );
            assert_eq!(state.built.len(), 3, "the seed scene stays");
        }
        state.generate(5);
        assert_eq!(state.built.len(), 5);
    }

    #[test]
    fn the_edit_shares_the_scenes_arrays_and_copies_only_what_it_writes() {
        let mut state = AppState::new(scene_io::seed_scene(), Settings::default());
        let scene = Arc::clone(&state.built.scene);
        assert!(Arc::ptr_eq(&state.edit.positions, &scene.positions));
        assert!(Arc::ptr_eq(&state.edit.powers, scene.powers.shared()));
        // A refused value: the edit holds its own copy, the last good scene is untouched.
        state.edit.powers_mut()[1] = f64::NAN;
        assert!(!Arc::ptr_eq(&state.edit.powers, scene.powers.shared()));
        state.powers_changed();
        assert!(state.input_error.is_some());
        assert_eq!(state.built.scene.powers.as_slice(), [2.0, 5.0, 20.0]);
        // A valid value: the new scene takes the edit's arrays as they are.
        state.edit.powers_mut()[1] = 7.0;
        state.powers_changed();
        assert!(state.input_error.is_none());
        assert_eq!(state.built.scene.powers.as_slice(), [2.0, 7.0, 20.0]);
        assert!(Arc::ptr_eq(
            &state.edit.powers,
            state.built.scene.powers.shared()
        ));
        assert!(Arc::ptr_eq(
            &state.edit.positions,
            &state.built.scene.positions
        ));
        assert!(Arc::ptr_eq(&state.built.scene.positions, &scene.positions));
    }

    /// The picks of `sample_picks` recounted per light from the same streams.
    fn picks_per_light(state: &AppState, count: u64) -> (Vec<u64>, Vec<u64>) {
        let n = state.built.len();
        let uniform = Uniform::new(n as u32);
        let (mut u, mut a) = (vec![0u64; n], vec![0u64; n]);
        for k in 0..count {
            u[uniform.sample(&mut Rng::new(state.settings.seed, k)) as usize] += 1;
            let mut rng = Rng::new(state.settings.seed ^ 0xA11A5, k);
            a[state.built.table.sample(&mut rng) as usize] += 1;
        }
        (u, a)
    }

    #[test]
    fn chi_square_cells_are_lights_up_to_the_limit_and_fixed_groups_above() {
        // Small: one cell per light, the pmf itself, the counts per light.
        let mut state = AppState::new(scene_io::seed_scene(), Settings::default());
        state.sample_picks(2000);
        assert_eq!(state.sampling.per_cell, 1);
        assert_eq!(state.sampling.alias_cell_pmf, state.built.pmf());
        let (u, a) = picks_per_light(&state, 2000);
        assert_eq!(state.sampling.uniform_counts.iter().collect::<Vec<_>>(), u);
        assert_eq!(state.sampling.alias_counts.iter().collect::<Vec<_>>(), a);
        // Above 2^16 lights: groups of ⌈N / 2^16⌉ consecutive lights, each cell's count the
        // sum of its lights' and its probability the sum of theirs.
        let n = 3 * MAX_CHI_CELLS + 5;
        state.generate(n);
        while state.is_building() {
            std::thread::sleep(std::time::Duration::from_millis(5));
            state.poll_build();
        }
        assert_eq!(state.built.len(), n);
        state.sample_picks(50_000);
        let per_cell = n.div_ceil(MAX_CHI_CELLS);
        assert_eq!(state.sampling.per_cell, per_cell);
        let cells = n.div_ceil(per_cell);
        assert!(cells <= MAX_CHI_CELLS);
        assert_eq!(state.sampling.uniform_counts.len(), cells);
        let (u, a) = picks_per_light(&state, 50_000);
        let grouped = |v: &[u64]| v.chunks(per_cell).map(|c| c.iter().sum()).collect();
        let grouped_u: Vec<u64> = grouped(&u);
        let grouped_a: Vec<u64> = grouped(&a);
        assert_eq!(
            state.sampling.uniform_counts.iter().collect::<Vec<_>>(),
            grouped_u
        );
        assert_eq!(
            state.sampling.alias_counts.iter().collect::<Vec<_>>(),
            grouped_a
        );
        let pmf = state.built.pmf();
        for (c, &p) in state.sampling.alias_cell_pmf.iter().enumerate() {
            let lights = &pmf[c * per_cell..((c + 1) * per_cell).min(n)];
            assert_eq!(p, lights.iter().sum::<f64>(), "cell {c}");
        }
        // The tests run over the cells (dof below the cell count) and the samplers are right:
        // with these fixed seeds neither p-value is below 10^-3.
        for chi in [state.sampling.uniform_chi, state.sampling.alias_chi] {
            let chi = chi.expect("computed");
            assert!(chi.dof < cells && chi.dof > 100, "{chi:?}");
            assert!(chi.p_value > 1e-3, "{chi:?}");
        }
    }

    #[test]
    fn nice_ceilings() {
        assert_eq!(nice_ceiling(40.0), 50.0);
        assert_eq!(nice_ceiling(3.0), 5.0);
        assert_eq!(nice_ceiling(1.0), 1.0);
    }
}
