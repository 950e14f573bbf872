//! The data behind the app's figures as CSV, for slides and spreadsheets (File → Export
//! data): the convergence series of the three images, the histograms' counts, the Trade
//! table and the pixel inspector's table, each a file beside the path chosen
//! (`NAME-convergence.csv`, `NAME-histogram.csv`, `NAME-trade.csv`, `NAME-inspector.csv`;
//! a figure not shown yet has no file). Every file is written whole or not at all.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::images::Published;
use super::state::AppState;

/// The CSV files of the figures there are data for; returns the paths written.
pub fn export_data(
    path: &Path,
    state: &mut AppState,
    published: Option<&Published>,
) -> Result<Vec<PathBuf>, String> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| format!("{}: no file name to export under", path.display()))?;
    let folder = path.parent().unwrap_or_else(|| Path::new("."));
    let mut files: Vec<(&str, String)> = Vec::new();
    if let Some(p) = published {
        files.push(("convergence", convergence_csv(p)));
    }
    if state.sampling.picks > 0 {
        files.push(("histogram", histogram_csv(state)));
    }
    if let Some(m) = state.trade.of_generation(state.built.generation) {
        files.push(("trade", trade_csv(m)));
    }
    let built = std::sync::Arc::clone(&state.built);
    if let Some(inspection) = state.inspector.inspection(&built) {
        files.push(("inspector", inspector_csv(inspection)));
    }
    if files.is_empty() {
        return Err("no figure has data yet: run the images or the histograms first".to_owned());
    }
    files
        .into_iter()
        .map(|(what, text)| {
            let out = folder.join(format!("{stem}-{what}.csv"));
            lightpick_core::atomic_file::write_bytes_atomically(&out, text.as_bytes()).map_err(
                |e| {
                    format!(
                        "cannot write {}: {e} — the old file is unchanged",
                        out.display()
                    )
                },
            )?;
            Ok(out)
        })
        .collect()
}

/// `scheme,spp,seconds,rmse`: each image's convergence series.
fn convergence_csv(p: &Published) -> String {
    let mut out = "scheme,spp,seconds,rmse\n".to_owned();
    for (name, image) in [
        ("uniform", &p.uniform),
        ("power", &p.power),
        ("spatial", &p.spatial),
    ] {
        for point in &image.series {
            let _ = writeln!(
                out,
                "{name},{},{:e},{:e}",
                point.spp, point.seconds, point.rmse
            );
        }
    }
    out
}

/// `first_light,lights,uniform_count,power_count,power_probability`: the histograms' cells
/// (one light each, or groups of consecutive lights on large scenes), lights numbered from 1.
fn histogram_csv(state: &AppState) -> String {
    let run = &state.sampling;
    let per = run.per_cell.max(1);
    let n = state.built.len();
    let mut out = "first_light,lights,uniform_count,power_count,power_probability\n".to_owned();
    for (cell, ((u, a), p)) in run
        .uniform_counts
        .iter()
        .zip(run.alias_counts.iter())
        .zip(run.alias_cell_pmf.iter())
        .enumerate()
    {
        let first = cell * per;
        let lights = run.cell_lights(cell, n);
        let _ = writeln!(out, "{},{lights},{u},{a},{p:e}", first + 1);
    }
    out
}

/// `scheme,seconds_per_sample,variance_per_sample,efficiency,rmse_at_last`: the Trade table.
fn trade_csv(m: &super::state::trade::TradeMeasurement) -> String {
    let mut out =
        "scheme,seconds_per_sample,variance_per_sample,efficiency,rmse_at_last\n".to_owned();
    for row in &m.rows {
        let e = row.efficiency;
        let rmse = row.series.last().map_or(f64::NAN, |p| p.rmse);
        let _ = writeln!(
            out,
            "{},{:e},{},{},{rmse:e}",
            super::state::trade::scheme_label(row.scheme).replace(',', ";"),
            e.seconds_per_sample,
            lightpick_core::Scaled::from_log10(e.variance_log10),
            e.efficiency,
        );
    }
    out
}

/// `light,power,pmf,share,spatial`: the inspector's table at its pixel (lights from 1; the
/// lights the inspector groups as "others" in one last row, `light` empty).
fn inspector_csv(inspection: &lightpick_core::inspect::PointInspection) -> String {
    let mut out = format!(
        "# x={:e},y={:e},irradiance={:e}\nlight,power,pmf,share,spatial\n",
        inspection.x.x, inspection.x.y, inspection.irradiance
    );
    let number = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:e}"));
    for l in &inspection.lights {
        let _ = writeln!(
            out,
            "{},{:e},{:e},{:e},{}",
            l.index + 1,
            l.power,
            l.pmf,
            l.share,
            number(l.spatial)
        );
    }
    let o = &inspection.others;
    if o.count > 0 {
        let _ = writeln!(out, ",,{:e},{:e},{}", o.pmf, o.share, number(o.spatial));
    }
    out
}
