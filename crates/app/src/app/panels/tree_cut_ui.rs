//! The Light tree panel's first stage of a pick: the pixel's tile and its cut of the tree
//! (the groups and single lights weighed once for the whole tile), the largest few as bars,
//! and the entry one random number takes.

use egui::{RichText, Ui};
use lightpick_core::lesson::tree_pick::CutStep;

use crate::app::colors;
use crate::app::panels::probability_bar_ui::bar_ui;
use crate::numbers::{self, three_significant};

/// Entries of a tile's cut listed by name (the picked one always among them).
const CUT_ROWS: usize = 6;

/// The tile's cut: the groups and single lights fixed for the whole tile, the largest few as
/// bars (the picked one among them), the random number and the entry it takes.
pub fn cut_stage_ui(ui: &mut Ui, cut: &CutStep, dark: bool) {
    let [[x0, y0], [x1, y1]] = cut.pixels;
    let singles = cut.entries.iter().filter(|e| e.light.is_some()).count();
    let groups = cut.entries.len() - singles;
    let held = match (groups, singles) {
        (_, 0) => numbers::count(groups, "group", "groups"),
        (0, _) => numbers::count(singles, "single light", "single lights"),
        _ => format!(
            "{} and {}",
            numbers::count(groups, "group", "groups"),
            numbers::count(singles, "single light", "single lights")
        ),
    };
    ui.label(format!(
        "This pixel's tile (pixels {x0}–{} across, {y0}–{} down) keeps a cut of the tree: \
         {held} that hold every light able to reach it, each weighed once for the whole tile \
         by what it gives nine points of the tile: a single light by its own contribution, a \
         group by its estimate (its representative light, or its map for spots). The pick \
         starts by drawing one of them, with no work at x.",
        x1 - 1,
        y1 - 1,
    ));
    let mut order: Vec<usize> = (0..cut.entries.len()).collect();
    order.sort_by(|&a, &b| cut.entries[b].mass.cmp(&cut.entries[a].mass));
    let mut shown: Vec<usize> = order.iter().copied().take(CUT_ROWS).collect();
    if !shown.contains(&cut.entry) {
        shown.pop();
        shown.push(cut.entry);
    }
    let ink = colors::foreground(dark);
    egui::Grid::new("lightpick_cut_groups")
        .num_columns(3)
        .show(ui, |ui| {
            for &k in &shown {
                let entry = &cut.entries[k];
                let name = format!("{} (depth {})", entry_name(cut, k), entry.depth);
                if k == cut.entry {
                    ui.label(RichText::new(format!("{name} ← picked")).strong());
                } else {
                    ui.label(name);
                }
                bar_ui(ui, entry.probability, ink);
                let p = three_significant(entry.probability);
                ui.label(match entry.light {
                    Some(_) => format!("P = {p}"),
                    None => format!("P = {p} · {} lights", entry.lights.len()),
                });
                ui.end_row();
            }
        });
    if cut.entries.len() > shown.len() {
        let more = cut.entries.len() - shown.len();
        ui.colored_label(
            colors::muted(dark),
            format!(
                "… and {more} smaller {}",
                if more == 1 { "one" } else { "ones" }
            ),
        );
    }
    let u = f64::from(cut.random24) / 16_777_216.0;
    let then = if cut.entries[cut.entry].light.is_some() {
        "The pick is that light: at x only its own contribution is evaluated."
    } else {
        "Below it the descent weighs each node at x itself."
    };
    ui.label(format!(
        "Random number u = {u:.4} → {}. P so far: {}. {then}",
        entry_name(cut, cut.entry),
        three_significant(cut.pdf_after)
    ));
}

/// Entry `k` of a tile's cut as the panel names it: "light 7" (numbered from 1, as the
/// Lights panel does) or "group 3" (its place in the cut).
fn entry_name(cut: &CutStep, k: usize) -> String {
    match cut.entries[k].light {
        Some(light) => format!("light {}", light + 1),
        None => format!("group {}", k + 1),
    }
}
