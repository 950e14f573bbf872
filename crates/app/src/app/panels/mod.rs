//! The panels and windows, one `*_ui.rs` each, over the [`AppState`] (which imports no panel):
//! [`lights_ui`], [`table_ui`] (table, over the [`diagram_ui`]), [`sampling_ui`] (sampling),
//! [`images_ui`] (images) with [`light_tree_ui`] (the light tree, a tab beside them, and its
//! [`tree_guide_ui`]),
//! [`convergence_ui`], and the windows [`trade_ui`] (speed against
//! accuracy), [`precision_ui`], [`walkthrough_ui`] and [`stepper_ui`] (the classroom),
//! [`inspector_ui`] (a clicked pixel), [`estimator_ui`], [`animation_export_ui`]; the
//! [`controls_ui`] (menu, run controls, status bar) and the [`file_dialog_ui`]. [`layout`] decides
//! where the five main panels go at the window's size (pure logic) and [`layout_ui`] draws them
//! there; [`log_axes`] is the plots' log-log paper.

pub mod animation_export_ui;
pub mod controls_ui;
pub mod convergence_ui;
pub mod diagram_ui;
pub mod estimator_ui;
pub mod file_dialog_ui;
pub mod images_ui;
pub mod inspector_ui;
pub mod layout;
pub mod layout_ui;
pub mod light_tree_ui;
pub mod lights_ui;
pub mod log_axes;
pub mod panel_kind;
pub mod pick_overlay_ui;
pub mod precision_ui;
pub mod probability_bar_ui;
pub mod sampling_ui;
pub mod shortcuts_ui;
pub mod stepper_ui;
pub mod table_ui;
pub mod table_words;
pub mod trade_ui;
pub mod tree_cut_ui;
pub mod tree_guide_ui;
pub mod walkthrough_ui;

use egui::Ui;

pub use panel_kind::PanelKind;

use crate::app::images::Published;
use crate::app::state::AppState;
use convergence_ui::ConvergenceAxis;
use images_ui::ImageTextures;

/// The panels' contents, drawn by the layout (and by
/// [`crate::app::LightpickApp::panel_ui`]) over the app's state for one frame.
pub(crate) struct MainPanes<'a> {
    pub(crate) state: &'a mut AppState,
    pub(crate) textures: &'a ImageTextures,
    pub(crate) axis: &'a mut ConvergenceAxis,
    pub(crate) published: Option<&'a Published>,
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
                    .show(ui, |ui| sampling_ui::sampling_ui(ui, state));
            }
            PanelKind::Images => {
                images_ui::images_ui(ui, state, self.published, self.textures);
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
            PanelKind::LightTree => light_tree_ui::light_tree_ui(ui, state),
        }
    }

    fn wanted_height(&self, ui: &Ui, pane: PanelKind, width: f32) -> Option<f32> {
        // The images take the height their width allows (every frame, so a resized window
        // keeps them as large as it can); the panel under them fills the rest.
        (pane == PanelKind::Images)
            .then(|| images_ui::wanted_height(ui, width, self.state, self.textures))
    }
}

/// The optional windows: trade and precision (View menu), the pixel inspector (a click on an
/// image), the walkthrough, the stepper and the estimator. `placed` is where the main panels
/// stand this frame: a window that explains the table opens beside it, not over it.
pub fn windows_ui(ctx: &egui::Context, state: &mut AppState, placed: &[(PanelKind, egui::Rect)]) {
    let table = placed
        .iter()
        .find(|(kind, _)| *kind == PanelKind::Table)
        .map(|(_, rect)| *rect);
    let mut open = state.settings.show_trade;
    egui::Window::new("Trade")
        .open(&mut open)
        .default_size([620.0, 520.0])
        .default_pos([760.0, 60.0])
        .show(ctx, |ui| trade_ui::trade_ui(ui, state));
    state.settings.show_trade = open;
    let mut open = state.settings.show_precision;
    let place = beside_table(ctx, "Precision", open, table, PRECISION_WIDTH);
    let mut window = egui::Window::new("Precision")
        .open(&mut open)
        .default_size([PRECISION_WIDTH, 420.0])
        .default_pos([20.0, 400.0]);
    if let Some(pos) = place {
        // Within the strip beside the table: narrower, its grid scrolls sideways.
        let strip = (ctx.content_rect().right() - pos.x - 8.0).max(320.0);
        window = window
            .current_pos(pos)
            .default_width(PRECISION_WIDTH.min(strip))
            .max_width(strip);
    }
    let shown = window.show(ctx, |ui| {
        egui::ScrollArea::horizontal()
            .auto_shrink([false, true])
            .show(ui, |ui| precision_ui::precision_ui(ui, state));
    });
    raise_if_placed(ctx, place, shown.as_ref());
    state.settings.show_precision = open;
    inspector_ui::inspector_window(ctx, state);
    walkthrough_ui::walkthrough_window(ctx, state);
    stepper_ui::stepper_window(ctx, state, table);
    shortcuts_ui::shortcuts_window(ctx, state);
    estimator_ui::estimator_window(ctx, state);
}

/// The Precision window's width.
const PRECISION_WIDTH: f32 = 640.0;

/// Where the window titled `title` (`width` wide) goes on the frame it opens: beside the
/// table panel (`table`), in the wider free strip right or left of it. `None` on later
/// frames (it stays where the user drags it), while it is closed, or without a table.
pub fn beside_table(
    ctx: &egui::Context,
    title: &str,
    open: bool,
    table: Option<egui::Rect>,
    width: f32,
) -> Option<egui::Pos2> {
    let placed_id = egui::Id::unique(("lightpick_window_placed", title));
    if !open {
        ctx.data_mut(|d| d.remove::<bool>(placed_id));
        return None;
    }
    if ctx.data(|d| d.get_temp::<bool>(placed_id)).unwrap_or(false) {
        return None;
    }
    let table = table?;
    ctx.data_mut(|d| d.insert_temp(placed_id, true));
    let screen = ctx.content_rect();
    let margin = 8.0;
    let right = screen.right() - table.right();
    let left = table.left() - screen.left();
    let x = if right >= left {
        // Right beside the table; a window wider than the strip is narrowed by its caller.
        table.right() + margin
    } else {
        (table.left() - width - margin).max(screen.left() + margin)
    };
    Some(egui::pos2(x.max(screen.left() + margin), table.top()))
}

/// Brings a window just placed by [`beside_table`] (`place` is `Some`) to the front.
pub fn raise_if_placed<R>(
    ctx: &egui::Context,
    place: Option<egui::Pos2>,
    shown: Option<&egui::InnerResponse<R>>,
) {
    if let (Some(_), Some(shown)) = (place, shown) {
        ctx.move_to_top(shown.response.layer_id);
    }
}
