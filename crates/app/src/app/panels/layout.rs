//! Where the window's five panels go, decided from the size of the window alone (pure
//! logic: [`layout_ui`](super::layout_ui) draws it).
//!
//! Each panel has a least size at which it stays readable ([`min_width`], [`min_height`];
//! the Alias table's is [`TABLE_MIN_WIDTH`]). The [`Arrangement`] is the first of these
//! whose columns all fit the window's width at their least widths:
//!
//! - **three columns** (from about 1170 points wide: 1280×720, 1440×900, 1920×1080):
//!   Lights | Alias table over Sampling | Images over Convergence;
//! - **two columns** (from about 870 points: 1024×768): Lights over Alias table | Sampling,
//!   Images and Convergence;
//! - **one column** (narrower, e.g. a zoomed-in small screen): every panel a tab.
//!
//! In a column, the panels stand one over the other when their least heights fit the
//! window's height; otherwise they become tabs under one header, so that no panel is ever
//! squeezed to a sliver. Any one panel can be **maximized** (the button in its header;
//! Restore or Escape goes back). The maximized panel and the tabs last chosen are kept
//! between sessions ([`Layout`] is persisted); the rectangles drawn in the last frame are
//! not, and tests read them with [`Layout::pane_rect`].

use egui::{Rect, Vec2};

use super::panel_kind::PanelKind;

/// The five panels of the main window, in reading order.
pub const PANES: [PanelKind; 5] = [
    PanelKind::Lights,
    PanelKind::Table,
    PanelKind::Sampling,
    PanelKind::Images,
    PanelKind::Convergence,
];

/// Every panel the layout shows: the five of [`PANES`] and the tabs that share a place
/// with one of them ([`tabs_with`]); what a maximized panel's header offers.
pub const TABBED: [PanelKind; 6] = [
    PanelKind::Lights,
    PanelKind::Table,
    PanelKind::Sampling,
    PanelKind::Images,
    PanelKind::LightTree,
    PanelKind::Convergence,
];

/// The panels that share `pane`'s place as tabs under one header, wherever the arrangement
/// puts it: the light tree beside the images (both are pictures of the plane, and a
/// 1024×768 projector has no room for a sixth panel); every other panel alone.
pub fn tabs_with(pane: PanelKind) -> &'static [PanelKind] {
    match pane {
        PanelKind::Images => &[PanelKind::Images, PanelKind::LightTree],
        PanelKind::Lights => &[PanelKind::Lights],
        PanelKind::Table => &[PanelKind::Table],
        PanelKind::Sampling => &[PanelKind::Sampling],
        PanelKind::Convergence => &[PanelKind::Convergence],
        PanelKind::Controls => &[PanelKind::Controls],
        PanelKind::Trade => &[PanelKind::Trade],
        PanelKind::Precision => &[PanelKind::Precision],
        PanelKind::Inspector => &[PanelKind::Inspector],
        PanelKind::Estimator => &[PanelKind::Estimator],
        PanelKind::LightTree => &[PanelKind::LightTree],
    }
}

/// `panes` with the tabs that share their places ([`tabs_with`]), in order.
pub fn with_tabs(panes: &[PanelKind]) -> Vec<PanelKind> {
    panes.iter().flat_map(|&p| tabs_with(p)).copied().collect()
}

/// The least width of the Alias table panel: every column of the table at 90 % of its full
/// width (power, pmf and threshold fractions such as `15/27` unclipped) and a diagram whose
/// columns are wide enough to carry their labels.
pub const TABLE_MIN_WIDTH: f32 = 420.0;

/// The height of a panel's header (its title or tabs, and the maximize button).
pub const HEADER_HEIGHT: f32 = 30.0;

/// The room between two panels standing one over the other.
pub const PANE_GAP: f32 = 4.0;

/// The room a column takes around its panels: its frame's inner margin on both sides, and
/// two points for the separator line and rounding to pixels.
pub const COLUMN_MARGIN: f32 = 14.0;

/// The name in `pane`'s header and tab.
pub fn title(pane: PanelKind) -> &'static str {
    match pane {
        PanelKind::Lights => "Lights",
        PanelKind::Table => "Alias table",
        PanelKind::Sampling => "Sampling",
        PanelKind::Images => "Images",
        PanelKind::Convergence => "Convergence",
        PanelKind::Controls => "Controls",
        PanelKind::Trade => "Trade",
        PanelKind::Precision => "Precision",
        PanelKind::Inspector => "Inspector",
        PanelKind::Estimator => "Estimator",
        PanelKind::LightTree => "Light tree",
    }
}

/// The least width of `pane`'s content at which it stays readable.
pub fn min_width(pane: PanelKind) -> f32 {
    match pane {
        PanelKind::Table => TABLE_MIN_WIDTH,
        // Presets wrap; rows keep their power field, slider, dup and del.
        PanelKind::Lights => 290.0,
        // The figures table (Var/sample, T/sample, efficiency, vs uniform) unclipped.
        PanelKind::Convergence => 420.0,
        // Sampling: three bar groups and the chi-square lines; Images: four images of about
        // 100 points side by side.
        _ => 400.0,
    }
}

/// The least height of `pane`'s content (below its header) at which it stays readable.
pub fn min_height(pane: PanelKind) -> f32 {
    match pane {
        // Controls, one row of the table of lights and a few rows of lights.
        PanelKind::Lights => 300.0,
        // The N/ΣΦ line, the diagram at its least height (140) and three rows of the table.
        PanelKind::Table => 280.0,
        // Its controls, the chi-square lines and a plot of about 130 points.
        PanelKind::Sampling => 260.0,
        // The figures, the note and a plot of about 130 points.
        PanelKind::Convergence => 310.0,
        // The options line, images of about 110 points over their error maps, and their
        // captions unclipped.
        _ => 330.0,
    }
}

/// How the panels share the window.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Arrangement {
    /// Lights | Alias table over Sampling | Images over Convergence.
    #[default]
    ThreeColumns,
    /// Lights over Alias table | Sampling, Images, Convergence.
    TwoColumns,
    /// Every panel a tab.
    OneColumn,
}

impl Arrangement {
    /// Every arrangement, the most spread out first.
    pub const ALL: [Self; 3] = [Self::ThreeColumns, Self::TwoColumns, Self::OneColumn];

    /// The panels of each column, left to right.
    pub fn columns(self) -> &'static [&'static [PanelKind]] {
        match self {
            Self::ThreeColumns => &[
                &[PanelKind::Lights],
                &[PanelKind::Table, PanelKind::Sampling],
                &[PanelKind::Images, PanelKind::Convergence],
            ],
            Self::TwoColumns => &[
                &[PanelKind::Lights, PanelKind::Table],
                &[
                    PanelKind::Sampling,
                    PanelKind::Images,
                    PanelKind::Convergence,
                ],
            ],
            Self::OneColumn => &[&PANES],
        }
    }

    /// The width the columns need at their least (content and margins).
    pub fn min_width(self) -> f32 {
        self.columns().iter().map(|c| column_min_width(c)).sum()
    }

    /// The most spread-out arrangement whose columns fit `width` (points).
    pub fn for_width(width: f32) -> Self {
        Self::ALL
            .into_iter()
            .find(|a| a.min_width() <= width)
            .unwrap_or(Self::OneColumn)
    }

    /// A short name, for panel ids and messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::ThreeColumns => "three columns",
            Self::TwoColumns => "two columns",
            Self::OneColumn => "one column",
        }
    }

    /// The width a column (not the last) takes by default, as a share of the window's.
    pub fn default_share(self, column: usize) -> f32 {
        match (self, column) {
            (Self::ThreeColumns, 0) => 0.22,
            (Self::ThreeColumns, _) => 0.38,
            _ => 0.45,
        }
    }
}

/// The least width of a column holding `panes` (the widest least width, and margins).
pub fn column_min_width(panes: &[PanelKind]) -> f32 {
    panes.iter().copied().map(min_width).fold(0.0, f32::max) + COLUMN_MARGIN
}

/// The height of `pane` (header included) when it stands over others in a column of
/// `height`, before the presenter drags the edge: the table leaves the histograms about 360
/// points; the lights leave the table below them most of the column (their rows scroll).
pub fn default_height(pane: PanelKind, height: f32) -> f32 {
    match pane {
        PanelKind::Table => height - 360.0,
        _ => 0.4 * height,
    }
}

/// Whether `panes` stand one over the other in `height` (each at least its least height,
/// under its own header); otherwise they are tabs.
pub fn stacks(panes: &[PanelKind], height: f32) -> bool {
    panes.len() <= 1
        || panes
            .iter()
            .map(|&p| min_height(p) + HEADER_HEIGHT + PANE_GAP)
            .sum::<f32>()
            <= height
}

/// The window's layout: what the presenter chose (kept between sessions) and what the last
/// frame drew (for tests).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Layout {
    /// The panel that fills the window, if any.
    pub maximized: Option<PanelKind>,
    /// The panels in the order their tabs were last chosen (most recent first): a group of
    /// tabs shows the first of its panels in this list.
    pub recent: Vec<PanelKind>,
    /// The arrangement of the last frame.
    #[serde(skip)]
    pub arrangement: Arrangement,
    /// The rectangle (header included) of each panel drawn in the last frame.
    #[serde(skip)]
    pub placed: Vec<(PanelKind, Rect)>,
}

impl Default for Layout {
    fn default() -> Self {
        Self {
            maximized: None,
            // What a lesson starts on when panels share a column: the table, then the images.
            recent: vec![
                PanelKind::Table,
                PanelKind::Images,
                PanelKind::Lights,
                PanelKind::Sampling,
                PanelKind::Convergence,
            ],
            arrangement: Arrangement::default(),
            placed: Vec::new(),
        }
    }
}

impl Layout {
    /// The panel a group of tabs over `panes` shows: the maximized one when it is among
    /// them, else the one whose tab was chosen last.
    ///
    /// # Panics
    /// If `panes` is empty.
    pub fn shown(&self, panes: &[PanelKind]) -> PanelKind {
        if let Some(m) = self.maximized.filter(|m| panes.contains(m)) {
            return m;
        }
        self.recent
            .iter()
            .copied()
            .find(|p| panes.contains(p))
            .unwrap_or(panes[0])
    }

    /// Shows `pane` in its group of tabs (and, while a panel is maximized, maximizes it).
    pub fn select(&mut self, pane: PanelKind) {
        self.recent.retain(|&p| p != pane);
        self.recent.insert(0, pane);
        if self.maximized.is_some() {
            self.maximized = Some(pane);
        }
    }

    /// Makes `pane` fill the window.
    pub fn maximize(&mut self, pane: PanelKind) {
        self.select(pane);
        self.maximized = Some(pane);
    }

    /// Back to the arrangement that fits the window. Returns whether a panel was maximized.
    pub fn restore(&mut self) -> bool {
        self.maximized.take().is_some()
    }

    /// The rectangle `pane` was drawn in on the last frame (header included), if it was.
    pub fn pane_rect(&self, pane: PanelKind) -> Option<Rect> {
        self.placed
            .iter()
            .find(|(p, _)| *p == pane)
            .map(|(_, r)| *r)
    }

    /// Starts a frame over a content area of `size`: forgets the last frame's rectangles
    /// and picks the arrangement.
    pub fn begin(&mut self, size: Vec2) {
        self.placed.clear();
        self.arrangement = Arrangement::for_width(size.x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The content area of a window: the menu and the status bar take about 60 points.
    fn content(w: f32, h: f32) -> Vec2 {
        Vec2::new(w, h - 60.0)
    }

    #[test]
    fn arrangements_by_screen() {
        assert_eq!(
            Arrangement::for_width(content(1920.0, 1080.0).x),
            Arrangement::ThreeColumns
        );
        assert_eq!(
            Arrangement::for_width(content(1280.0, 720.0).x),
            Arrangement::ThreeColumns
        );
        assert_eq!(
            Arrangement::for_width(content(1024.0, 768.0).x),
            Arrangement::TwoColumns
        );
        // The window's least size (900×600) still has two columns; a zoomed-in one, one.
        assert_eq!(Arrangement::for_width(900.0), Arrangement::TwoColumns);
        assert_eq!(Arrangement::for_width(700.0), Arrangement::OneColumn);
        assert_eq!(Arrangement::for_width(10.0), Arrangement::OneColumn);
    }

    #[test]
    fn every_arrangement_holds_every_panel_once() {
        for a in Arrangement::ALL {
            let mut all: Vec<PanelKind> =
                a.columns().iter().flat_map(|c| c.iter()).copied().collect();
            all.sort_by_key(|p| PANES.iter().position(|q| q == p));
            assert_eq!(all, PANES, "{a:?}");
        }
    }

    #[test]
    fn columns_stack_when_tall_enough() {
        let [_, middle, right] = Arrangement::ThreeColumns.columns() else {
            panic!("three columns");
        };
        // 1280×720: the table over the histograms; the images and the curves are tabs,
        // one over the other from 1440×900.
        assert!(stacks(middle, content(1280.0, 720.0).y));
        assert!(!stacks(right, content(1280.0, 720.0).y));
        assert!(stacks(right, content(1440.0, 900.0).y));
        // 1024×768: the lights over the table; the three others are tabs.
        let [left, right] = Arrangement::TwoColumns.columns() else {
            panic!("two columns");
        };
        assert!(stacks(left, content(1024.0, 768.0).y));
        assert!(!stacks(right, content(1024.0, 768.0).y));
        assert!(!stacks(middle, 500.0));
    }

    #[test]
    fn the_light_tree_is_a_tab_beside_the_images_in_every_arrangement() {
        for a in Arrangement::ALL {
            let shown: Vec<PanelKind> = a.columns().iter().flat_map(|c| with_tabs(c)).collect();
            let mut sorted = shown.clone();
            sorted.sort_by_key(|p| TABBED.iter().position(|q| q == p));
            assert_eq!(sorted, TABBED, "{a:?}");
            let images = shown.iter().position(|&p| p == PanelKind::Images);
            assert_eq!(
                images.map(|i| shown[i + 1]),
                Some(PanelKind::LightTree),
                "{a:?}"
            );
        }
        let mut layout = Layout::default();
        let place = tabs_with(PanelKind::Images);
        assert_eq!(layout.shown(place), PanelKind::Images);
        layout.select(PanelKind::LightTree);
        assert_eq!(layout.shown(place), PanelKind::LightTree);
    }

    #[test]
    fn tabs_show_the_last_chosen_and_maximize_follows_the_tabs() {
        let mut layout = Layout::default();
        let group = [
            PanelKind::Sampling,
            PanelKind::Images,
            PanelKind::Convergence,
        ];
        assert_eq!(layout.shown(&group), PanelKind::Images);
        layout.select(PanelKind::Convergence);
        assert_eq!(layout.shown(&group), PanelKind::Convergence);
        assert_eq!(
            layout.shown(&[PanelKind::Table, PanelKind::Sampling]),
            PanelKind::Table
        );
        layout.maximize(PanelKind::Sampling);
        assert_eq!(layout.shown(&group), PanelKind::Sampling);
        layout.select(PanelKind::Table);
        assert_eq!(layout.maximized, Some(PanelKind::Table));
        assert!(layout.restore());
        assert!(!layout.restore());
        assert_eq!(layout.shown(&group), PanelKind::Sampling);
    }

    #[test]
    fn persisted_layout_round_trips_and_old_files_load() {
        let mut layout = Layout::default();
        layout.maximize(PanelKind::Convergence);
        let json = serde_json::to_string(&layout).expect("serialize");
        let back: Layout = serde_json::from_str(&json).expect("deserialize");
        assert_eq!(back.maximized, Some(PanelKind::Convergence));
        assert_eq!(back.recent, layout.recent);
        let empty: Layout = serde_json::from_str("{}").expect("defaults");
        assert_eq!(empty.maximized, None);
        assert_eq!(empty.recent, Layout::default().recent);
    }
}
