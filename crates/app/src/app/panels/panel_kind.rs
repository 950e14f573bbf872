//! [`PanelKind`]: the names of the app's panels, which the layout places and persists and
//! the shell draws; it depends on nothing, so every layer can name a panel.

/// One panel of the app, for [`crate::app::LightpickApp::panel_ui`]; the first five are the
/// main window's ([`super::layout::PANES`]), which the [`layout`](super::layout) places and
/// the presenter can maximize.
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
    /// The light tree from above and one spatial pick stepped down it (`state.light_tree`):
    /// a tab beside the images ([`super::layout::tabs_with`]).
    LightTree,
}
