//! What the Trade panel measures: for the current scene, what each sampling scheme costs and
//! buys — time per sample `T`, variance per sample `V`, efficiency `1/(V·T)` — on a small
//! copy of the scene (at most [`TRADE_SIDE`] pixels a side), one fresh [`CpuRenderer`] per
//! scheme run to [`TRADE_MAX_SPP`] samples per pixel (three times, keeping the fastest core
//! time of each point), against an exact [`Reference`]. The images pause while it runs. The
//! measurement runs on a background thread in the app and inline with virtual timings in
//! tests (deterministic snapshots).

use lightpick_core::Scheme;
use lightpick_core::render::{
    CpuRenderer, Efficiency, Reference, SeriesPoint, efficiency, pool_core_seconds, rmse,
    series_spp,
};
use lightpick_core::scene::Scene;

/// The measurement image is at most this many pixels a side.
pub const TRADE_SIDE: u32 = 64;
/// Samples per pixel of each scheme's series (`1, 2, 4, …, 64`).
pub const TRADE_MAX_SPP: u32 = 64;
/// Timed runs of each series (the fastest time of each point is kept).
const TRADE_REPEATS: u32 = 3;
/// Light-pixel evaluations of the measurement's reference (a pixel subset beyond it).
const TRADE_REFERENCE_BUDGET: u64 = 1 << 24;
/// Virtual seconds per pixel sample in inline (test) mode, the engine's figure.
const VIRTUAL_SECONDS_PER_SAMPLE: f64 = 1.0e-8;
/// The schemes measured, in display order.
pub const TRADE_SCHEMES: [Scheme; 5] = [
    Scheme::Uniform,
    Scheme::Cdf,
    Scheme::Alias,
    Scheme::AliasOneRandom,
    Scheme::Spatial,
];

/// The display name of a scheme in this panel.
pub fn scheme_label(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Uniform => "uniform",
        Scheme::Cdf => "cdf (binary search)",
        Scheme::Alias => "alias, two randoms",
        Scheme::AliasOneRandom => "alias, one random",
        Scheme::Spatial => "spatial (by contribution)",
    }
}

/// One scheme's measured figures.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeRow {
    /// The scheme.
    pub scheme: Scheme,
    /// RMSE and cumulative seconds at `1, 2, 4, …` samples per pixel.
    pub series: Vec<SeriesPoint>,
    /// Variance, time and efficiency at the last point.
    pub efficiency: Efficiency,
}

/// Every scheme measured on one scene generation.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeMeasurement {
    /// The scene generation measured.
    pub generation: u64,
    /// Image size measured.
    pub size: [u32; 2],
    /// Pixels the reference covers.
    pub reference_pixels: usize,
    /// Whether the timings are virtual (inline mode).
    pub virtual_time: bool,
    /// Render threads (rayon's global pool, as `lightpick bench` uses).
    pub threads: usize,
    /// One row per scheme of [`TRADE_SCHEMES`].
    pub rows: Vec<TradeRow>,
}

/// The panel's measurement: the latest result and the one being computed (inline mode
/// uses virtual timings).
pub type TradeRun = crate::app::background::Background<TradeMeasurement>;

impl crate::app::background::OfGeneration for TradeMeasurement {
    fn generation(&self) -> u64 {
        self.generation
    }
}

/// The scene at most [`TRADE_SIDE`] pixels a side (same plane extent, coarser pixels).
fn small_scene(scene: &Scene) -> Scene {
    let mut small = scene.clone();
    let (w, h) = (scene.plane.width.max(1), scene.plane.height.max(1));
    let scale = (f64::from(TRADE_SIDE) / f64::from(w.max(h))).min(1.0);
    small.plane.width = ((f64::from(w) * scale).round() as u32).max(1);
    small.plane.height = ((f64::from(h) * scale).round() as u32).max(1);
    small
}

/// The convergence series of `renderer` at `1, 2, 4, …` [`TRADE_MAX_SPP`] samples per pixel,
/// each point's seconds the core time of the passes up to it (cumulative; the RMSE between
/// points is not timed).
fn timed_series(renderer: &mut CpuRenderer, reference: &Reference) -> Vec<SeriesPoint> {
    let mut seconds = 0.0;
    series_spp(TRADE_MAX_SPP)
        .into_iter()
        .map(|target| {
            let have = renderer.accumulator().samples_per_pixel;
            if target > have {
                seconds += pool_core_seconds(|| renderer.accumulate(target - have)).1;
            }
            let acc = renderer.accumulator();
            SeriesPoint {
                spp: acc.samples_per_pixel,
                rmse: rmse(acc, reference),
                seconds,
            }
        })
        .collect()
}

/// Measures every scheme of [`TRADE_SCHEMES`] on a small copy of `scene`.
///
/// Each point of a series is the core time of the passes alone up to it
/// ([`pool_core_seconds`] around each `accumulate`: the CPU time of the render threads,
/// without the RMSE computed between points), the fastest of three runs, so the
/// plot's curve and the table's `T` (its last point over its pixel samples) are one
/// measurement. The app pauses its images while this runs ([`AppState::trade_pauses_images`]),
/// so no live render shares the threads being timed.
///
/// [`AppState::trade_pauses_images`]: crate::app::state::AppState::trade_pauses_images
pub fn measure(generation: u64, scene: &Scene, virtual_time: bool) -> TradeMeasurement {
    let small = small_scene(scene);
    let reference = Reference::with_budget(&small, TRADE_REFERENCE_BUDGET);
    let pixels = small.plane.pixel_count() as f64;
    let rows = TRADE_SCHEMES
        .iter()
        .map(|&scheme| {
            let mut renderer = CpuRenderer::new(&small, scheme, 1);
            let mut series = timed_series(&mut renderer, &reference);
            // The same (deterministic) series again: the fastest time of each point, so a
            // cold cache or a busy core does not bend one curve.
            for _ in 1..TRADE_REPEATS {
                renderer.reset();
                let again = timed_series(&mut renderer, &reference);
                for (p, q) in series.iter_mut().zip(&again) {
                    p.seconds = p.seconds.min(q.seconds);
                }
            }
            if virtual_time {
                for p in &mut series {
                    p.seconds = f64::from(p.spp) * pixels * VIRTUAL_SECONDS_PER_SAMPLE;
                }
            }
            let seconds = series.last().map_or(0.0, |p| p.seconds);
            TradeRow {
                scheme,
                efficiency: efficiency(renderer.accumulator(), seconds),
                series,
            }
        })
        .collect();
    TradeMeasurement {
        generation,
        size: [small.plane.width, small.plane.height],
        reference_pixels: reference.pixels().len(),
        virtual_time,
        threads: rayon::current_num_threads(),
        rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plot_and_the_table_are_one_measurement() {
        let scene = crate::app::scene_io::worked_example_scene();
        let m = measure(1, &scene, false);
        let pixels = f64::from(m.size[0] * m.size[1]);
        for row in &m.rows {
            let last = row.series.last().expect("points");
            // The table's T is the last point's time over its pixel samples.
            let t = last.seconds / (f64::from(last.spp) * pixels);
            let table = row.efficiency.seconds_per_sample;
            assert!(
                (t - table).abs() <= 1e-12 * table,
                "{:?}: {t} vs {table}",
                row.scheme
            );
            // Cumulative pass times: nondecreasing, positive, the first a small share.
            assert!(row.series.windows(2).all(|w| w[0].seconds <= w[1].seconds));
            let first = row.series[0].seconds;
            assert!(first > 0.0 && first <= last.seconds, "{:?}", row.series);
        }
    }

    #[test]
    fn the_images_pause_while_a_measurement_runs() {
        let mut state = crate::app::state::AppState::worked_example();
        state.trade.inline = false;
        let (go, wait) = std::sync::mpsc::channel::<()>();
        let scene = std::sync::Arc::clone(&state.built.scene);
        state.trade.start(1, "test-trade", move |_| {
            let _ = wait.recv();
            measure(1, &scene, true)
        });
        assert!(state.trade_pauses_images());
        go.send(()).expect("the worker waits");
        let deadline = std::time::Instant::now() + std::time::Duration::from_mins(1);
        while state.trade.is_measuring() {
            assert!(
                std::time::Instant::now() < deadline,
                "the measurement never ended"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
            state.trade.poll();
        }
        assert!(!state.trade_pauses_images());
        assert!(state.trade.result.is_some());
    }
}
