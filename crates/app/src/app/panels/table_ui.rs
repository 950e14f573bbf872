//! The alias-table panel: the interactive diagram ([`super::diagram_ui`]) over the live
//! table (i, power, pmf, threshold, alias).

use egui::{Rect, Sense, Stroke, StrokeKind, Ui, vec2};

use lightpick_core::walkthrough::{Highlight, TableField};

use crate::app::colors;
use crate::app::state::AppState;
use crate::numbers;

use super::table_words::ROW_HEIGHT;

/// The whole panel: heading, diagram, then the table.
pub fn table_panel_ui(ui: &mut Ui, state: &mut AppState) {
    let built = std::sync::Arc::clone(&state.built);
    ui.horizontal_wrapped(|ui| {
        ui.label(format!(
            "N = {}   ΣΦ = {}",
            built.len(),
            numbers::short(built.total_power)
        ))
        .on_hover_text("Number of lights and their total power");
        if state.is_building() {
            ui.spinner();
            ui.label("rebuilding…");
        }
        ui.toggle_value(&mut state.settings.show_walkthrough, "Walkthrough")
            .on_hover_text("The classic explanation (lights 2, 5, 20) step by step");
        ui.toggle_value(&mut state.settings.show_stepper, "Construction")
            .on_hover_text("Watch Vose's algorithm build this table, one pairing at a time");
    });
    super::diagram_ui::diagram_ui(ui, state, None);
    ui.add_space(4.0);
    table_ui(ui, state);
}

/// The table: one row per light (virtualized for large `N`).
pub fn table_ui(ui: &mut Ui, state: &AppState) {
    let built = &state.built;
    let den = built.denominator;
    let powers = built.scene.powers.as_slice();
    let table = &built.table;
    let highlight = state.table_highlight.as_ref();
    // Column widths at full size, narrowed (down to 55 %) to fit a narrow panel so that the
    // threshold and alias columns stay visible.
    // A named scene's first column shows the names too.
    let names = built.scene.names.as_deref();
    let first = if names.is_some() { 110.0 } else { 44.0 };
    let full = [first, 90.0_f32, 90.0, 90.0, 54.0];
    let room = ui.available_width() - 4.0 * ui.spacing().item_spacing.x;
    let fit = (room / full.iter().sum::<f32>()).clamp(0.55, 1.0);
    let widths = full.map(|w| w * fit);
    let header = ["i", "power Φ", "pmf p", "threshold", "alias"];
    let tips = [
        "Light / column number (1-based)",
        "The light's power Φ_i",
        "p_i = Φ_i / ΣΦ: the probability the table realizes (exact fraction for integer powers)",
        "Probability that column i keeps its own light (U2 < threshold)",
        "The light column i yields when U2 ≥ threshold",
    ];
    ui.horizontal(|ui| {
        for ((w, h), tip) in widths.iter().zip(header).zip(tips) {
            ui.add_sized(
                [*w, ROW_HEIGHT],
                egui::Label::new(egui::RichText::new(h).strong()),
            )
            .on_hover_text(tip);
        }
    });
    ui.separator();
    let n = built.len();
    let max_height = ui.available_height().max(ROW_HEIGHT * 3.0);
    egui::ScrollArea::vertical()
        .id_salt("alias_table_rows")
        .max_height(max_height)
        .auto_shrink([false, true])
        .show_rows(ui, ROW_HEIGHT, n, |ui, rows| {
            // The shown rows' pmf (a window of a large table's).
            let pmf = built.pmf_of(rows.clone());
            let first = rows.start;
            for i in rows {
                ui.horizontal(|ui| {
                    let (swatch, _) = ui.allocate_exact_size(vec2(10.0, 10.0), Sense::hover());
                    ui.painter().rect_filled(swatch, 2.0, colors::light(i));
                    let label = match names.and_then(|n| n.get(i)).filter(|n| !n.is_empty()) {
                        Some(name) => format!("{} {name}", i + 1),
                        None => format!("{}", i + 1),
                    };
                    ui.add_sized(
                        [widths[0] - 14.0, ROW_HEIGHT],
                        egui::Label::new(label).truncate(),
                    );
                    let power = ui.add_sized(
                        [widths[1], ROW_HEIGHT],
                        egui::Label::new(numbers::short(powers[i])),
                    );
                    mark_cell(ui, highlight, i, TableField::Power, power.rect);
                    let p = ui
                        .add_sized(
                            [widths[2], ROW_HEIGHT],
                            egui::Label::new(numbers::show(pmf[i - first], den)),
                        )
                        .on_hover_text(format!("p = {:.12}", pmf[i - first]));
                    mark_cell(ui, highlight, i, TableField::Pmf, p.rect);
                    let t = ui
                        .add_sized(
                            [widths[3], ROW_HEIGHT],
                            egui::Label::new(numbers::show(table.threshold(i), den)),
                        )
                        .on_hover_text(format!("threshold = {:.12}", table.threshold(i)));
                    mark_cell(ui, highlight, i, TableField::Threshold, t.rect);
                    let a = ui.add_sized(
                        [widths[4], ROW_HEIGHT],
                        egui::Label::new(format!("{}", table.alias(i) + 1)),
                    );
                    mark_cell(ui, highlight, i, TableField::Alias, a.rect);
                });
            }
        });
}

/// Outlines a table cell the walkthrough's current step talks about.
fn mark_cell(ui: &Ui, highlight: Option<&Highlight>, row: usize, field: TableField, rect: Rect) {
    if highlight.is_some_and(|h| h.has_cell(row, field)) {
        let color = colors::highlight(ui.visuals().dark_mode);
        ui.painter().rect_stroke(
            rect.shrink2(vec2(8.0, 0.0)),
            3.0,
            Stroke::new(2.5, color),
            StrokeKind::Inside,
        );
    }
}
