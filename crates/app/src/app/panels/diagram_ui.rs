//! The alias-table diagram: `N` unit-height columns split at their threshold into the
//! column's own light and its alias, over the pmf bars they were cut from (ghost outlines),
//! with the `1/N` line; the walkthrough's highlights, the last single draw replayed, and a
//! hover sentence per column. Large tables show a window of [`DIAGRAM_MAX_COLUMNS`] columns.

use egui::{Align2, FontId, Rect, Response, Sense, Stroke, StrokeKind, Ui, Vec2, pos2, vec2};
use lightpick_core::walkthrough::{ColumnPart, Highlight};

use super::table_words::{ROW_HEIGHT, column_sentence};
use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::built::Built;
use crate::app::state::sampling::{DIAGRAM_MAX_COLUMNS, OneDraw};
use crate::numbers;

/// Where the diagram's columns go: the plot area, the window of columns shown and the
/// vertical scale.
struct Geometry {
    /// The plot area (inside the axis labels).
    plot: Rect,
    /// The first column shown (0-based).
    first: usize,
    /// How many columns are shown.
    shown: usize,
    /// Lights in the table.
    n: usize,
    /// A column's width, gap included.
    col_w: f32,
    /// `1/N`, every column's height.
    avg: f64,
    /// The probability at the top of the plot.
    y_max: f64,
}

impl Geometry {
    /// The height of probability `p`.
    fn y_of(&self, p: f64) -> f32 {
        self.plot.bottom() - (p / self.y_max) as f32 * self.plot.height()
    }

    /// The top of every column (the `1/N` line).
    fn y_top(&self) -> f32 {
        self.y_of(self.avg)
    }
}

/// The interactive diagram. `height` defaults to a third of the available height.
pub fn diagram_ui(ui: &mut Ui, state: &mut AppState, height: Option<f32>) {
    let built = std::sync::Arc::clone(&state.built);
    let n = built.len();
    let dark = state.dark();
    if n > DIAGRAM_MAX_COLUMNS {
        window_ui(ui, state, n);
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
    let body = crate::app::text_size::body_size(ui);
    let font = FontId::proportional((height / 24.0).clamp(body, 16.0_f32.max(body)));
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
    // The shown columns' lights' pmf (a window of a large table's).
    let pmf = built.pmf_of(first..first + shown);
    let avg = 1.0 / n as f64;
    let max_p = pmf.iter().copied().fold(avg, f64::max);
    let geometry = Geometry {
        plot,
        first,
        shown,
        n,
        col_w: plot.width() / shown as f32,
        avg,
        y_max: max_p * 1.08,
    };
    for k in 0..shown {
        column_ui(&painter, &geometry, (&built, pmf[k]), k, &font, state, dark);
    }
    axis_ui(&painter, &geometry, &font, dark);
    if let Some(draw) = state.sampling.last_draw
        && draw.column >= first
        && draw.column < first + shown
    {
        draw_pick(&painter, &geometry, &draw, &font, dark);
    }
    hover_ui(&painter, &geometry, response, state, &built);
}

/// The slider that scrolls the window of columns a large table shows.
fn window_ui(ui: &mut Ui, state: &mut AppState, n: usize) {
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

/// The `k`-th column shown: its own light's share at the bottom and the alias's on top
/// (numbered when there is room), the ghost of its pmf bar (`p`, its light's probability),
/// the walkthrough's marks and its label under the axis.
fn column_ui(
    painter: &egui::Painter,
    g: &Geometry,
    (built, p): (&Built, f64),
    k: usize,
    font: &FontId,
    state: &AppState,
    dark: bool,
) {
    let table = &built.table;
    let (plot, col_w) = (g.plot, g.col_w);
    let fg = colors::foreground(dark);
    let muted = colors::muted(dark);
    let gap = (col_w * 0.12).min(4.0);
    let i = g.first + k;
    let x0 = plot.left() + k as f32 * col_w + gap / 2.0;
    let x1 = x0 + col_w - gap;
    let t = table.threshold(i);
    let split = g.y_of(g.avg * t);
    // Own light's share at the bottom, the alias's on top, total height 1/N.
    painter.rect_filled(
        Rect::from_min_max(pos2(x0, split), pos2(x1, plot.bottom())),
        0.0,
        colors::light(i),
    );
    if t < 1.0 {
        let a = table.alias(i) as usize;
        painter.rect_filled(
            Rect::from_min_max(pos2(x0, g.y_top()), pos2(x1, split)),
            0.0,
            colors::light(a),
        );
        painter.line_segment([pos2(x0, split), pos2(x1, split)], Stroke::new(1.0, fg));
        if col_w > 26.0 {
            let mid = pos2(x0.midpoint(x1), g.y_top().midpoint(split));
            if split - g.y_top() > 14.0 {
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
    let ghost = Rect::from_min_max(pos2(x0, g.y_of(p)), pos2(x1, plot.bottom()));
    painter.rect_stroke(ghost, 0.0, Stroke::new(1.0, muted), StrokeKind::Middle);
    if let Some(h) = &state.table_highlight {
        let column = Rect::from_min_max(pos2(x0, g.y_top()), pos2(x1, plot.bottom()));
        mark_column(painter, h, i, column, split, dark);
    }
    // Column label.
    if col_w > 14.0 || k.is_multiple_of((g.shown / 16).max(1)) {
        painter.text(
            pos2(x0.midpoint(x1), plot.bottom() + 3.0),
            Align2::CENTER_TOP,
            format!("{}", i + 1),
            font.clone(),
            muted,
        );
    }
}

/// The `1/N` average line (dashed) with its label, and the `0` at the bottom.
fn axis_ui(painter: &egui::Painter, g: &Geometry, font: &FontId, dark: bool) {
    let (plot, fg, muted) = (g.plot, colors::foreground(dark), colors::muted(dark));
    let y_avg = g.y_top();
    painter.extend(egui::Shape::dashed_line(
        &[pos2(plot.left(), y_avg), pos2(plot.right(), y_avg)],
        Stroke::new(1.5, fg),
        6.0,
        4.0,
    ));
    // On one-sided scenes the 1/N line sits near the bottom: its label stays above the "0"
    // (a line of text apart), never on or below it.
    let label_y = y_avg.min(plot.bottom() - 2.0 * font.size);
    painter.text(
        pos2(plot.left() - 4.0, label_y),
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
}

/// Hover: outlines the column under the pointer and explains it in words.
fn hover_ui(
    painter: &egui::Painter,
    g: &Geometry,
    response: Response,
    state: &AppState,
    built: &Built,
) {
    let plot = g.plot;
    let Some(pointer) = response.hover_pos().filter(|p| plot.contains(*p)) else {
        return;
    };
    let k = (((pointer.x - plot.left()) / g.col_w) as usize).min(g.shown - 1);
    let i = g.first + k;
    let x0 = plot.left() + k as f32 * g.col_w;
    painter.rect_stroke(
        Rect::from_min_max(pos2(x0, g.y_top()), pos2(x0 + g.col_w, plot.bottom())),
        0.0,
        Stroke::new(2.0, colors::pick(state.dark())),
        StrokeKind::Outside,
    );
    let sentence = column_sentence(state, i);
    // The window the columns were drawn with (kept: no pass over the table again).
    let p = built.pmf_of(g.first..g.first + g.shown)[i - g.first];
    response.on_hover_ui_at_pointer(|ui| {
        ui.label(sentence);
        ui.label(format!(
            "light {}: p = {}  (ghost outline)",
            i + 1,
            numbers::show(p, built.denominator)
        ));
    });
}

/// Outlines the parts of diagram column `i` (its whole `column`, split at `split` into the
/// alias's share above and its own below) the walkthrough's current step talks about, and
/// veils the column when the step points at other columns only.
fn mark_column(
    painter: &egui::Painter,
    highlight: &Highlight,
    i: usize,
    column: Rect,
    split: f32,
    dark: bool,
) {
    if highlight.columns.is_empty() {
        return;
    }
    let (x0, x1, top, bottom) = (column.left(), column.right(), column.top(), column.bottom());
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
        painter.rect_filled(column, 0.0, colors::dim(dark));
    }
}

/// Replays a single draw: `U1` picks the column (a marker on the axis), `U2` is a level in
/// that column compared with the threshold.
fn draw_pick(painter: &egui::Painter, g: &Geometry, draw: &OneDraw, font: &FontId, dark: bool) {
    let (plot, col_w, first, y_top) = (g.plot, g.col_w, g.first, g.y_top());
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
        font.clone(),
        hi,
    );
    // U1 marker under the axis.
    let x_u1 = plot.left() + ((draw.u1 * g.n as f64) as f32 - first as f32) * col_w;
    let tip = pos2(x_u1.clamp(plot.left(), plot.right()), plot.bottom() + 2.0);
    painter.add(egui::Shape::convex_polygon(
        vec![tip, tip + Vec2::new(-5.0, 9.0), tip + Vec2::new(5.0, 9.0)],
        hi,
        Stroke::NONE,
    ));
}
