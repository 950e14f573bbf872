//! The alias-table panel: the live table (i, power, pmf, threshold, alias) and the
//! interactive diagram — `N` unit-height columns split at their threshold into the column's
//! own light and its alias, over the pmf bars they were cut from, with the `1/N` line.

use egui::{Align2, FontId, Rect, Sense, Stroke, StrokeKind, Ui, Vec2, pos2, vec2};

use lightpick_core::walkthrough::{ColumnPart, Highlight, TableField};

use crate::app::colors;
use crate::app::state::AppState;
pub use crate::app::state::sampling::DIAGRAM_MAX_COLUMNS;
use crate::app::state::sampling::OneDraw;
use crate::numbers;

/// Rows of the table shown without scrolling when the table is small.
const ROW_HEIGHT: f32 = 18.0;

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
    diagram_ui(ui, state, None);
    ui.add_space(4.0);
    table_ui(ui, state);
}

/// The table: one row per light (virtualized for large `N`).
pub fn table_ui(ui: &mut Ui, state: &AppState) {
    let built = &state.built;
    let den = built.denominator;
    let powers = built.scene.powers.as_slice();
    let pmf = built.pmf();
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
                            egui::Label::new(numbers::show(pmf[i], den)),
                        )
                        .on_hover_text(format!("p = {:.12}", pmf[i]));
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

/// Outlines the parts of diagram column `i` the walkthrough's current step talks about, and
/// veils the column when the step points at other columns only.
#[allow(clippy::too_many_arguments)] // The column's geometry, as the diagram computed it.
fn mark_column(
    painter: &egui::Painter,
    highlight: &Highlight,
    i: usize,
    x: (f32, f32),
    split: f32,
    top: f32,
    bottom: f32,
    dark: bool,
) {
    if highlight.columns.is_empty() {
        return;
    }
    let (x0, x1) = x;
    let mut any = false;
    for part in highlight.parts(i) {
        any = true;
        let (y0, y1) = match part {
            ColumnPart::Whole => (top, bottom),
            ColumnPart::Own => (split, bottom),
            ColumnPart::Alias => (top, split),
        };
        painter.rect_stroke(
            Rect::from_min_max(pos2(x0, y0), pos2(x1, y1)),
            0.0,
            Stroke::new(3.5, colors::highlight(dark)),
            StrokeKind::Inside,
        );
    }
    if !any {
        painter.rect_filled(
            Rect::from_min_max(pos2(x0, top), pos2(x1, bottom)),
            0.0,
            colors::dim(dark),
        );
    }
}

/// The sentence that explains column `i`, in the seed example's words: "column 1 keeps
/// light 1 with probability 6/27, else light 3".
pub fn column_sentence(state: &AppState, i: usize) -> String {
    let built = &state.built;
    let t = built.table.threshold(i);
    let a = built.table.alias(i) as usize;
    let p = numbers::show(t, built.denominator);
    if t >= 1.0 || a == i {
        format!("column {} always keeps light {}", i + 1, i + 1)
    } else if t <= 0.0 {
        format!(
            "column {} always gives light {} (light {} has power 0)",
            i + 1,
            a + 1,
            i + 1
        )
    } else {
        format!(
            "column {} keeps light {} with probability {p}, else light {}",
            i + 1,
            i + 1,
            a + 1
        )
    }
}

/// The interactive diagram. `height` defaults to a third of the available height.
pub fn diagram_ui(ui: &mut Ui, state: &mut AppState, height: Option<f32>) {
    let built = std::sync::Arc::clone(&state.built);
    let n = built.len();
    let dark = state.dark();
    if n > DIAGRAM_MAX_COLUMNS {
        ui.horizontal(|ui| {
            ui.label(format!(
                "columns {}–{} of {n}",
                state.diagram_offset + 1,
                (state.diagram_offset + DIAGRAM_MAX_COLUMNS).min(n)
            ));
            let max = n - DIAGRAM_MAX_COLUMNS;
            ui.add(egui::Slider::new(&mut state.diagram_offset, 0..=max).show_value(false))
                .on_hover_text("Scroll the window of columns the diagram shows")
                .accessible_name("diagram first column");
        });
    }
    let first = state.diagram_offset.min(n.saturating_sub(1));
    let shown = (n - first).min(DIAGRAM_MAX_COLUMNS);
    // Small tables need few rows: the diagram takes what the table leaves.
    let table_height = (n.min(12) as f32 + 2.5) * (ROW_HEIGHT + ui.spacing().item_spacing.y);
    // A small table's rows are all reserved: the diagram takes the rest, however large (a
    // maximized panel on a projector); a large table keeps the rest for its rows.
    let most = if n <= 12 { f32::INFINITY } else { 380.0 };
    let height =
        height.unwrap_or_else(|| (ui.available_height() - table_height).clamp(140.0, most));
    let (response, painter) =
        ui.allocate_painter(vec2(ui.available_width(), height), Sense::hover());
    let outer = response.rect;
    // Labels grow with the diagram (up to 16 points), for the back of a classroom.
    let font = FontId::proportional((height / 24.0).clamp(12.0, 16.0));
    let fg = colors::foreground(dark);
    let muted = colors::muted(dark);
    // Plot area: leave room for the axis labels.
    let plot = Rect::from_min_max(outer.min + vec2(36.0, 8.0), outer.max - vec2(8.0, 22.0));
    // The plot area is outlined, not filled: on a software rasterizer (lavapipe) every
    // filled pixel costs, and this one is redrawn every frame.
    painter.rect_stroke(
        plot,
        0.0,
        Stroke::new(1.0, colors::grid(dark)),
        StrokeKind::Inside,
    );
    let pmf = built.pmf();
    let table = &built.table;
    let avg = 1.0 / n as f64;
    let max_p = pmf[first..first + shown]
        .iter()
        .copied()
        .fold(avg, f64::max);
    let y_max = max_p * 1.08;
    let y_of = |p: f64| plot.bottom() - (p / y_max) as f32 * plot.height();
    let col_w = plot.width() / shown as f32;
    let gap = (col_w * 0.12).min(4.0);
    for k in 0..shown {
        let i = first + k;
        let x0 = plot.left() + k as f32 * col_w + gap / 2.0;
        let x1 = x0 + col_w - gap;
        let t = table.threshold(i);
        let split = y_of(avg * t);
        // Own light's share at the bottom, the alias's on top, total height 1/N.
        painter.rect_filled(
            Rect::from_min_max(pos2(x0, split), pos2(x1, plot.bottom())),
            0.0,
            colors::light(i),
        );
        if t < 1.0 {
            let a = table.alias(i) as usize;
            painter.rect_filled(
                Rect::from_min_max(pos2(x0, y_of(avg)), pos2(x1, split)),
                0.0,
                colors::light(a),
            );
            painter.line_segment([pos2(x0, split), pos2(x1, split)], Stroke::new(1.0, fg));
            if col_w > 26.0 {
                let mid = pos2(x0.midpoint(x1), y_of(avg).midpoint(split));
                if split - y_of(avg) > 14.0 {
                    painter.text(
                        mid,
                        Align2::CENTER_CENTER,
                        format!("{}", a + 1),
                        font.clone(),
                        colors::on_light(a),
                    );
                }
            }
        }
        if col_w > 26.0 && plot.bottom() - split > 14.0 {
            painter.text(
                pos2(x0.midpoint(x1), plot.bottom().midpoint(split)),
                Align2::CENTER_CENTER,
                format!("{}", i + 1),
                font.clone(),
                colors::on_light(i),
            );
        }
        // Ghost of the original pmf bar this column's light had.
        let ghost = Rect::from_min_max(pos2(x0, y_of(pmf[i])), pos2(x1, plot.bottom()));
        painter.rect_stroke(ghost, 0.0, Stroke::new(1.0, muted), StrokeKind::Middle);
        if let Some(h) = &state.table_highlight {
            mark_column(
                &painter,
                h,
                i,
                (x0, x1),
                split,
                y_of(avg),
                plot.bottom(),
                dark,
            );
        }
        // Column label.
        if col_w > 14.0 || k % (shown / 16).max(1) == 0 {
            painter.text(
                pos2(x0.midpoint(x1), plot.bottom() + 3.0),
                Align2::CENTER_TOP,
                format!("{}", i + 1),
                font.clone(),
                muted,
            );
        }
    }
    // The 1/N average line (dashed) with its label.
    let y_avg = y_of(avg);
    painter.extend(egui::Shape::dashed_line(
        &[pos2(plot.left(), y_avg), pos2(plot.right(), y_avg)],
        Stroke::new(1.5, fg),
        6.0,
        4.0,
    ));
    painter.text(
        pos2(plot.left() - 4.0, y_avg),
        Align2::RIGHT_CENTER,
        "1/N",
        font.clone(),
        fg,
    );
    painter.text(
        pos2(plot.left() - 4.0, plot.bottom()),
        Align2::RIGHT_BOTTOM,
        "0",
        font.clone(),
        muted,
    );
    if let Some(draw) = state.sampling.last_draw
        && draw.column >= first
        && draw.column < first + shown
    {
        draw_pick(&painter, plot, &draw, n, first, col_w, y_of(avg), dark);
    }
    // Hover: explain the column in words.
    if let Some(pointer) = response.hover_pos()
        && plot.contains(pointer)
    {
        let k = (((pointer.x - plot.left()) / col_w) as usize).min(shown - 1);
        let i = first + k;
        let x0 = plot.left() + k as f32 * col_w;
        painter.rect_stroke(
            Rect::from_min_max(pos2(x0, y_of(avg)), pos2(x0 + col_w, plot.bottom())),
            0.0,
            Stroke::new(2.0, colors::pick(dark)),
            StrokeKind::Outside,
        );
        let sentence = column_sentence(state, i);
        response.on_hover_ui_at_pointer(|ui| {
            ui.label(sentence);
            ui.label(format!(
                "light {}: p = {}  (ghost outline)",
                i + 1,
                numbers::show(pmf[i], built.denominator)
            ));
        });
    }
}

/// Replays a single draw: `U1` picks the column (a marker on the axis), `U2` is a level in
/// that column compared with the threshold.
#[allow(clippy::too_many_arguments)] // The diagram's geometry, passed as the caller computed it.
fn draw_pick(
    painter: &egui::Painter,
    plot: Rect,
    draw: &OneDraw,
    n: usize,
    first: usize,
    col_w: f32,
    y_top: f32,
    dark: bool,
) {
    let hi = colors::pick(dark);
    let n_shown_x = plot.left() + (draw.column - first) as f32 * col_w;
    let column_rect = Rect::from_min_max(
        pos2(n_shown_x, y_top),
        pos2(n_shown_x + col_w, plot.bottom()),
    );
    painter.rect_stroke(column_rect, 0.0, Stroke::new(3.0, hi), StrokeKind::Outside);
    // U2 level: 0 at the bottom, 1 at the column's top (the 1/N line).
    let y = plot.bottom() - draw.u2 as f32 * (plot.bottom() - y_top);
    let stroke = Stroke::new(2.0, hi);
    painter.line_segment(
        [pos2(n_shown_x - 6.0, y), pos2(n_shown_x + col_w + 6.0, y)],
        stroke,
    );
    painter.circle_filled(pos2(n_shown_x + col_w / 2.0, y), 4.0, hi);
    painter.text(
        pos2(n_shown_x + col_w + 8.0, y),
        Align2::LEFT_CENTER,
        format!("U2 = {:.3}", draw.u2),
        FontId::proportional(12.0),
        hi,
    );
    // U1 marker under the axis.
    let x_u1 = plot.left() + ((draw.u1 * n as f64) as f32 - first as f32) * col_w;
    let tip = pos2(x_u1.clamp(plot.left(), plot.right()), plot.bottom() + 2.0);
    painter.add(egui::Shape::convex_polygon(
        vec![tip, tip + Vec2::new(-5.0, 9.0), tip + Vec2::new(5.0, 9.0)],
        hi,
        Stroke::NONE,
    ));
}

/// The sentence describing a single draw for the Sampling panel.
pub fn draw_sentence(state: &AppState, draw: &OneDraw) -> String {
    let den = state.built.denominator;
    let n = state.built.len();
    let t = numbers::show(draw.threshold, den);
    let verdict = if draw.kept {
        format!("U2 = {:.4} < {t} → keep light {}", draw.u2, draw.column + 1)
    } else {
        format!("U2 = {:.4} ≥ {t} → alias light {}", draw.u2, draw.light + 1)
    };
    format!(
        "U1 = {:.4} → column floor(U1·{n}) + 1 = {};  {verdict}",
        draw.u1,
        draw.column + 1
    )
}
