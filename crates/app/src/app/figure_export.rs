//! Every figure the app draws, as a PNG at a chosen size, for slides (File → Export
//! figure): the alias-table diagram, the histogram of picks, the convergence plot (error
//! against samples), the Trade plot (error against time) and the light tree from above. Each
//! is the core's headless drawing ([`lightpick_core::draw`]) of the data the panel shows now,
//! with its title and labels written at a size read from across a room. The images with
//! their captions are exported from the frame (`files.rs`), scaled to the size.

use lightpick_core::Scheme;
use lightpick_core::draw::{
    ConvergenceAxis, ConvergencePoint, ConvergenceSeries, HistogramData, Pixmap, SchemeCounts,
    Style, Theme, TreeView, convergence, histogram, table_diagram, tree_view,
};

use super::images::Published;
use super::state::AppState;
use super::state::figure::Figure;

/// The smallest and largest side of an exported figure, in pixels.
pub const FIGURE_SIDES: std::ops::RangeInclusive<u32> = 320..=4096;

/// `figure` of the app's current state drawn at `size` (clamped to [`FIGURE_SIDES`]); an
/// error saying what to do first when the figure has no data yet.
pub fn figure_pixmap(
    figure: Figure,
    state: &mut AppState,
    published: Option<&Published>,
    size: [u32; 2],
) -> Result<Pixmap, String> {
    let style = Style {
        width: size[0].clamp(*FIGURE_SIDES.start(), *FIGURE_SIDES.end()),
        height: size[1].clamp(*FIGURE_SIDES.start(), *FIGURE_SIDES.end()),
        theme: if state.dark() {
            Theme::Dark
        } else {
            Theme::Light
        },
    };
    let drawn = match figure {
        Figure::AliasTable => table_diagram(&state.built.table, state.built.denominator, &style),
        Figure::Histogram => histogram(&histogram_data(state)?, &style),
        Figure::Convergence => {
            let p = published.ok_or("no image has been rendered yet")?;
            let series = [
                (Scheme::Uniform, &p.uniform.series),
                (Scheme::Alias, &p.power.series),
                (Scheme::Spatial, &p.spatial.series),
            ]
            .map(|(scheme, points)| {
                series_of(scheme, points.iter().map(|q| (q.spp, q.seconds, q.rmse)))
            });
            convergence(&with_points(&series)?, ConvergenceAxis::Spp, &style)
        }
        Figure::Trade => {
            let m = state
                .trade
                .of_generation(state.built.generation)
                .ok_or("the Trade window has not measured this scene yet")?;
            let series: Vec<ConvergenceSeries> = m
                .rows
                .iter()
                .map(|row| ConvergenceSeries::of_measured(row.scheme, &row.series))
                .collect();
            convergence(&with_points(&series)?, ConvergenceAxis::Seconds, &style)
        }
        Figure::LightTree => return light_tree(state, &style),
        // The images come from the frame (read back from the GPU where they live there):
        // `files.rs` exports them.
        Figure::Images => return Err("the images are exported from the frame".to_owned()),
    };
    drawn.map_err(|e| e.to_string())
}

/// The series that have points, or an error when none has.
fn with_points(series: &[ConvergenceSeries]) -> Result<Vec<ConvergenceSeries>, String> {
    let kept: Vec<ConvergenceSeries> = series
        .iter()
        .filter(|s| !s.points.is_empty())
        .cloned()
        .collect();
    if kept.is_empty() {
        return Err("no convergence point yet: run the images first".to_owned());
    }
    Ok(kept)
}

/// A scheme's series from `(spp, seconds, rmse)` points.
fn series_of(scheme: Scheme, points: impl Iterator<Item = (u32, f64, f64)>) -> ConvergenceSeries {
    ConvergenceSeries::for_scheme(
        scheme,
        points
            .map(|(spp, seconds, rmse)| ConvergencePoint {
                spp: u64::from(spp),
                rmse,
                seconds,
            })
            .collect(),
    )
}

/// The Sampling panel's counts per cell (a light, or a group of consecutive lights on large
/// scenes) against the pmf each scheme realizes there.
fn histogram_data(state: &AppState) -> Result<HistogramData, String> {
    let run = &state.sampling;
    if run.picks == 0 || run.generation != state.built.generation {
        return Err("no picks yet: run the histograms (Sampling panel) first".to_owned());
    }
    let uniform_pmf: Vec<f64> = run.uniform_cell_pmf(state.built.len()).collect();
    let counts = |c: &super::state::counts::PickCounts| c.iter().collect::<Vec<u64>>();
    let schemes = vec![
        SchemeCounts::new(Scheme::Uniform, counts(&run.uniform_counts), uniform_pmf)
            .map_err(|e| e.to_string())?,
        SchemeCounts::new(
            Scheme::Alias,
            counts(&run.alias_counts),
            run.alias_cell_pmf.to_vec(),
        )
        .map_err(|e| e.to_string())?,
    ];
    Ok(HistogramData {
        pmf: run.alias_cell_pmf.to_vec(),
        schemes,
    })
}

/// The Light tree panel's view, titled, with its pick and colouring.
fn light_tree(state: &mut AppState, style: &Style) -> Result<Pixmap, String> {
    let built = std::sync::Arc::clone(&state.built);
    let spatial = std::sync::Arc::clone(built.samplers.spatial());
    let pick = state.light_tree.pick(&built, state.settings.seed);
    let overlay = state.light_tree.coloring_overlay(&built);
    let coloring = state.light_tree.coloring;
    let probabilities = overlay.as_deref().and_then(|o| coloring.probabilities(o));
    let view = TreeView {
        scene: &built.scene,
        sampler: &spatial,
        depth: state.light_tree.depth,
        pick: pick.as_deref().and_then(|p| p.record.as_ref()),
        probabilities,
        region: None,
    };
    tree_view(&view, style).map_err(|e| e.to_string())
}
