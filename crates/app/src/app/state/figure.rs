//! The figures the app draws and exports as PNG (`crate::app::figure_export` draws them).

/// A figure of the app.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Figure {
    /// The alias table's columns split at their thresholds.
    AliasTable,
    /// The picks of uniform and power sampling against the pmf.
    Histogram,
    /// Each image's RMSE against samples per pixel.
    Convergence,
    /// The Trade window's RMSE against seconds.
    Trade,
    /// The light tree from above, with the stepped pick and the colouring shown.
    LightTree,
    /// The three images (and the reference) over their error maps, with their captions.
    Images,
}

impl Figure {
    /// Every figure, in the menu's order.
    pub const ALL: [Figure; 6] = [
        Figure::Images,
        Figure::AliasTable,
        Figure::Histogram,
        Figure::Convergence,
        Figure::Trade,
        Figure::LightTree,
    ];

    /// The menu's name.
    pub fn title(self) -> &'static str {
        match self {
            Figure::AliasTable => "Alias-table diagram",
            Figure::Histogram => "Histogram of picks",
            Figure::Convergence => "Convergence (error against samples)",
            Figure::Trade => "Trade (error against time)",
            Figure::LightTree => "Light tree",
            Figure::Images => "Images with their captions",
        }
    }

    /// The file name's suffix (`SCENE-SUFFIX.png`).
    pub fn file_suffix(self) -> &'static str {
        match self {
            Figure::AliasTable => "alias-table",
            Figure::Histogram => "histogram",
            Figure::Convergence => "convergence",
            Figure::Trade => "trade",
            Figure::LightTree => "light-tree",
            Figure::Images => "images",
        }
    }
}
