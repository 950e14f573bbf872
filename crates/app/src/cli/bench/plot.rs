//! `bench --plot FILE`: RMSE against rendering time per scheme of one preset's render (the
//! heavy-tail preset, or the first rendered), as a PNG.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use lightpick_core::draw::{self, ConvergenceAxis, ConvergenceSeries};
use serde::Serialize;

use super::renders::PresetRender;

/// What `--plot` drew (`"plot"` in the JSON, `null` without `--plot`).
#[derive(Clone, Debug, Serialize)]
pub struct PlotInfo {
    /// The PNG written.
    pub file: PathBuf,
    /// The preset whose render series it shows.
    pub preset: String,
    /// Schemes left off the axes as zero-variance series
    /// ([`draw::zero_variance_series`]: the exact spatial pick on ≤ 16 lights, whose RMSE
    /// is rounding); the legend names them.
    pub zero_variance: Vec<&'static str>,
}

/// Draws RMSE against seconds per scheme of the heavy-tail render (or the first one), a
/// zero-variance series left off the axes by [`draw::convergence`].
pub(super) fn write_plot(path: &Path, renders: &[PresetRender]) -> anyhow::Result<PlotInfo> {
    let Some(render) = renders
        .iter()
        .find(|r| r.preset == "heavy-tail")
        .or_else(|| renders.first())
    else {
        bail!("--plot {}: no render to plot", path.display());
    };
    let series: Vec<ConvergenceSeries> = render
        .schemes
        .iter()
        .map(|s| ConvergenceSeries::of_measured(s.scheme, &s.series))
        .collect();
    let pixmap = draw::convergence(&series, ConvergenceAxis::Seconds, &draw::Style::default())
        .with_context(|| format!("--plot: drawing {}", render.preset))?;
    draw::write_png(&pixmap, path).with_context(|| format!("--plot {}", path.display()))?;
    let zero_variance = render
        .schemes
        .iter()
        .zip(draw::zero_variance_series(&series))
        .filter(|(_, zero)| *zero)
        .map(|(s, _)| s.scheme.name())
        .collect();
    Ok(PlotInfo {
        file: path.to_owned(),
        preset: render.preset.clone(),
        zero_variance,
    })
}
