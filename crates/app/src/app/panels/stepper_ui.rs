//! The construction stepper: Vose's algorithm played on the diagram, one event at a time
//! ([`lightpick_core::construction`] records the events; its last state is exactly the
//! table the Table panel shows).
//!
//! The window shows the two work lists as chips (column number and current mass `q`), the
//! diagram in its partial state — assigned columns split at their threshold, the others a
//! bar of their remaining mass against the dashed line `q = 1` — with the current pairing
//! outlined and the remainder `1 − q_small` drawn moving from the large column onto the
//! small one (animated while playing). Step / Back / Play / Reset; tables of up to
//! [`STEPPER_MAX_LIGHTS`] lights.

use egui::{Align2, FontId, Rect, RichText, Sense, Stroke, StrokeKind, Ui, pos2, vec2};
use lightpick_core::construction::{ConstructionEvent, ConstructionState};

use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::stepper::{STEPPER_MAX_LIGHTS, StepperState};
use crate::numbers;

/// The tallest mass the diagram shows before clipping a bar.
const MAX_SHOWN_MASS: f64 = 4.0;

/// The stepper window's width.
const STEPPER_WIDTH: f32 = 520.0;

/// The Construction stepper window (View menu, or the table panel's button).
/// `table` is the table panel's place this frame: the stepper opens beside it, not over it.
pub fn stepper_window(ctx: &egui::Context, state: &mut AppState, table: Option<egui::Rect>) {
    let mut open = state.settings.show_stepper;
    let place = super::beside_table(ctx, "Construction stepper", open, table, STEPPER_WIDTH);
    let mut window = egui::Window::new("Construction stepper")
        .open(&mut open)
        .default_pos([super::walkthrough_ui::right_edge(ctx) - 540.0, 400.0])
        .default_width(STEPPER_WIDTH);
    if let Some(pos) = place {
        window = window.current_pos(pos);
    }
    let shown = window.show(ctx, |ui| stepper_ui(ui, state));
    super::raise_if_placed(ctx, place, shown.as_ref());
    state.settings.show_stepper = open;
    if !open {
        state.stepper.playing = false;
    }
}

/// The window's content: controls, the event, the work lists and the diagram.
pub fn stepper_ui(ui: &mut Ui, state: &mut AppState) {
    let Some(trace) = state.stepper_trace() else {
        ui.label(format!(
            "The stepper animates tables of up to {STEPPER_MAX_LIGHTS} lights; this scene \
             has {}. Load a smaller scene (e.g. the worked example) to watch the construction.",
            state.built.len()
        ));
        return;
    };
    let last = trace.len() - 1;
    let now = ui.input(|i| i.time);
    let s = &mut state.stepper;
    s.index = s.index.min(last);
    if s.playing {
        if s.index >= last {
            s.playing = false;
        } else if now - s.last_advance >= f64::from(s.seconds_per_step) {
            s.index += 1;
            s.last_advance = now;
        }
        ui.ctx().request_repaint();
    }
    controls_ui(ui, s, last, now);
    let k = s.index;
    let progress = if s.playing {
        ((now - s.last_advance) / (0.6 * f64::from(s.seconds_per_step))).clamp(0.0, 1.0) as f32
    } else {
        1.0
    };
    let current = &trace.states()[k];
    let den = state.built.denominator;
    let dark = state.dark();
    ui.label(RichText::new(event_sentence(current, den)).size(16.0));
    lists_ui(ui, current, den);
    diagram_ui(ui, current, den, dark, progress);
    if k == last {
        let same = trace.thresholds().as_slice() == state.built.table.thresholds()
            && trace.aliases().as_slice() == state.built.table.aliases();
        let text = if same {
            "Done: every column is full, and this is exactly the Table panel's table."
        } else {
            "Done (differs from the Table panel's table: it is being rebuilt)"
        };
        ui.label(RichText::new(text).size(15.0).color(colors::good(dark)));
    }
}

/// Back, Step, Play / Pause, Reset and the speed.
fn controls_ui(ui: &mut Ui, s: &mut StepperState, last: usize, now: f64) {
    ui.horizontal(|ui| {
        let k = s.index;
        if ui
            .add_enabled(k > 0, egui::Button::new(RichText::new("← Back").size(16.0)))
            .on_hover_text("Undo the last event")
            .clicked()
        {
            s.index = k - 1;
            s.playing = false;
        }
        if ui
            .add_enabled(
                k < last,
                egui::Button::new(RichText::new("Step →").size(16.0)),
            )
            .on_hover_text("Do the next event: one pairing, or one leftover set to 1")
            .clicked()
        {
            s.index = k + 1;
            s.playing = false;
        }
        let play_text = if s.playing { "Pause" } else { "Play" };
        if ui
            .button(RichText::new(play_text).size(16.0))
            .on_hover_text(
                "Play the construction, one event per interval (from the start when finished)",
            )
            .clicked()
        {
            s.playing = !s.playing;
            if s.playing && s.index >= last {
                s.index = 0;
            }
            s.last_advance = now;
        }
        if ui
            .button(RichText::new("Reset stepper").size(16.0))
            .on_hover_text("Back to the start: masses scaled, nothing assigned")
            .clicked()
        {
            s.index = 0;
            s.playing = false;
        }
        ui.label(RichText::new(format!("event {k} of {last}")).size(16.0))
            .on_hover_text("Events so far: pairings and leftovers");
        ui.add(
            egui::Slider::new(&mut s.seconds_per_step, 0.3..=4.0)
                .suffix(" s")
                .max_decimals(1),
        )
        .on_hover_text("Seconds per event while playing")
        .accessible_name("seconds per event");
    });
}

/// One sentence for the event that led to `state`.
pub fn event_sentence(state: &ConstructionState, den: Option<u64>) -> String {
    let show = |v: f64| numbers::show(v, den);
    match state.event {
        ConstructionEvent::Scaled => "Start: q = N·p, mean 1. Columns with q < 1 wait in the \
                                      small list, the others in the large list."
            .to_owned(),
        ConstructionEvent::Pair {
            small,
            large,
            threshold,
            moved,
            large_before,
            large_after,
            large_became_small,
        } => {
            let fate = if large_became_small {
                "drops below 1: it moves to the small list"
            } else {
                "stays large"
            };
            format!(
                "Column {s} (q = {t}) takes {m} from column {l}: threshold {t}, alias {l}. \
                 Column {l}: ({b} + {t}) − 1 = {a}, {fate}.",
                s = small + 1,
                l = large + 1,
                t = show(threshold),
                m = show(moved),
                b = show(large_before),
                a = show(large_after),
            )
        }
        ConstructionEvent::Leftover {
            column,
            threshold,
            alias,
        } => {
            if threshold > 0.0 {
                format!(
                    "Leftover column {}: its q is 1 (up to rounding), so threshold 1, alias \
                     itself.",
                    column + 1
                )
            } else {
                format!(
                    "Leftover column {} has power 0: threshold 0, alias {}.",
                    column + 1,
                    alias + 1
                )
            }
        }
    }
}

/// The two work lists as chips `column: q`.
fn lists_ui(ui: &mut Ui, state: &ConstructionState, den: Option<u64>) {
    for (name, tip, list) in [
        (
            "small (q < 1):",
            "Columns that still need filling up, in the order they are taken",
            &state.small,
        ),
        (
            "large (q ≥ 1):",
            "Columns with mass to give, the active one first",
            &state.large,
        ),
    ] {
        ui.horizontal_wrapped(|ui| {
            ui.add_sized(
                [110.0, 22.0],
                egui::Label::new(RichText::new(name).size(15.0)),
            )
            .on_hover_text(tip);
            if list.is_empty() {
                ui.label(RichText::new("empty").size(15.0).italics());
            }
            for &i in list {
                let text = format!(" {}: {} ", i + 1, numbers::show(state.mass[i], den));
                ui.label(
                    RichText::new(text)
                        .size(15.0)
                        .background_color(colors::light(i))
                        .color(colors::on_light(i)),
                )
                .on_hover_text(format!(
                    "column {}, mass q = {:.12}",
                    i + 1,
                    state.mass[i]
                ));
            }
        });
    }
}

/// Where the stepper's bars go: the plot area and the vertical scale.
struct Bars {
    plot: Rect,
    /// A column's width, gap included.
    col_w: f32,
    gap: f32,
    /// The mass at the top of the plot.
    y_max: f64,
}

impl Bars {
    /// The height of mass `v` (clipped to the plot).
    fn y_of(&self, v: f64) -> f32 {
        self.plot.bottom() - (v.min(self.y_max) / self.y_max) as f32 * self.plot.height()
    }

    /// Column `j`'s left and right edges.
    fn x_of(&self, j: usize) -> (f32, f32) {
        let x0 = self.plot.left() + j as f32 * self.col_w + self.gap / 2.0;
        (x0, x0 + self.col_w - self.gap)
    }

    /// Column `j` between masses `lo` and `top`.
    fn rect(&self, j: usize, lo: f64, top: f64) -> Rect {
        let (x0, x1) = self.x_of(j);
        Rect::from_min_max(pos2(x0, self.y_of(top)), pos2(x1, self.y_of(lo)))
    }
}

/// The diagram in its partial state.
fn diagram_ui(ui: &mut Ui, state: &ConstructionState, den: Option<u64>, dark: bool, progress: f32) {
    let n = state.mass.len();
    let height = ui.available_height().clamp(280.0, 340.0);
    let (response, painter) = ui.allocate_painter(
        vec2(ui.available_width().max(300.0), height),
        Sense::hover(),
    );
    let outer = response.rect;
    let plot = Rect::from_min_max(outer.min + vec2(30.0, 18.0), outer.max - vec2(6.0, 22.0));
    let bg = colors::grid(dark).gamma_multiply(0.35);
    painter.rect_filled(plot, 0.0, bg);
    // The scale fits every bar, and the large column's mass before the pairing (the
    // remainder's origin), up to a clip.
    let before = match state.event {
        ConstructionEvent::Pair { large_before, .. } => large_before,
        _ => 1.0,
    };
    let y_max = state
        .mass
        .iter()
        .copied()
        .fold(before.max(1.0), f64::max)
        .min(MAX_SHOWN_MASS)
        * 1.1;
    let col_w = plot.width() / n as f32;
    let bars = Bars {
        plot,
        col_w,
        gap: (col_w * 0.15).min(10.0),
        y_max,
    };
    let body = crate::app::text_size::body_size(ui);
    let font = FontId::proportional(if col_w > 40.0 {
        15.0_f32.max(body)
    } else {
        body
    });
    for j in 0..n {
        column_ui(&painter, &bars, state, j, den, &font, dark);
    }
    // The line every column is levelled to.
    let fg = colors::foreground(dark);
    let y_one = bars.y_of(1.0);
    painter.extend(egui::Shape::dashed_line(
        &[pos2(plot.left(), y_one), pos2(plot.right(), y_one)],
        Stroke::new(1.5, fg),
        6.0,
        4.0,
    ));
    painter.text(
        pos2(plot.left() - 4.0, y_one),
        Align2::RIGHT_CENTER,
        "1",
        font.clone(),
        fg,
    );
    event_ui(
        &painter,
        &bars,
        &state.event,
        den,
        &font,
        (dark, bg),
        progress,
    );
}

/// Column `j`: split at its threshold once assigned, else a bar of its remaining mass
/// (labelled with it); its number under the axis.
fn column_ui(
    painter: &egui::Painter,
    bars: &Bars,
    state: &ConstructionState,
    j: usize,
    den: Option<u64>,
    font: &FontId,
    dark: bool,
) {
    let fg = colors::foreground(dark);
    let label = |r: Rect, text: String, color| {
        if r.height() > 16.0 && bars.col_w > 22.0 {
            painter.text(r.center(), Align2::CENTER_CENTER, text, font.clone(), color);
        }
    };
    let (x0, x1) = bars.x_of(j);
    if let (Some(t), Some(a)) = (state.threshold[j], state.alias[j]) {
        let a = a as usize;
        let own = bars.rect(j, 0.0, t);
        painter.rect_filled(own, 0.0, colors::light(j));
        label(own, format!("{}", j + 1), colors::on_light(j));
        if t < 1.0 {
            let top = bars.rect(j, t, 1.0);
            painter.rect_filled(top, 0.0, colors::light(a));
            label(top, format!("{}", a + 1), colors::on_light(a));
            painter.line_segment(
                [pos2(x0, bars.y_of(t)), pos2(x1, bars.y_of(t))],
                Stroke::new(1.0, fg),
            );
        }
    } else {
        let bar = bars.rect(j, 0.0, state.mass[j]);
        painter.rect_filled(bar, 0.0, colors::light(j).gamma_multiply(0.8));
        painter.rect_stroke(bar, 0.0, Stroke::new(1.0, fg), StrokeKind::Inside);
        painter.text(
            pos2(x0.midpoint(x1), bar.top() - 2.0),
            Align2::CENTER_BOTTOM,
            numbers::show(state.mass[j], den),
            font.clone(),
            fg,
        );
    }
    painter.text(
        pos2(x0.midpoint(x1), bars.plot.bottom() + 3.0),
        Align2::CENTER_TOP,
        format!("{}", j + 1),
        font.clone(),
        colors::muted(dark),
    );
}

/// The current event: a pairing outlines its two columns and moves the remainder from the
/// large one onto the small one (`progress` of the way, eased); a leftover is outlined.
fn event_ui(
    painter: &egui::Painter,
    bars: &Bars,
    event: &ConstructionEvent,
    den: Option<u64>,
    font: &FontId,
    (dark, bg): (bool, egui::Color32),
    progress: f32,
) {
    let hi = colors::highlight(dark);
    let outline = |r: Rect| painter.rect_stroke(r, 0.0, Stroke::new(3.0, hi), StrokeKind::Outside);
    match *event {
        ConstructionEvent::Pair {
            small,
            large,
            threshold,
            large_before,
            large_after,
            moved,
            ..
        } => {
            let from = bars.rect(large, large_after, large_before);
            let to = bars.rect(small, threshold, 1.0);
            outline(bars.rect(small, 0.0, 1.0));
            outline(bars.rect(large, 0.0, large_after.max(1.0)));
            painter.rect_filled(from, 0.0, colors::light(large).gamma_multiply(0.3));
            painter.rect_stroke(from, 0.0, Stroke::new(1.5, hi), StrokeKind::Inside);
            let t = progress.clamp(0.0, 1.0);
            let ease = t * t * (3.0 - 2.0 * t);
            if t < 1.0 {
                // The remainder is on its way: the destination is still empty.
                painter.rect_filled(to, 0.0, bg);
                let moving = Rect::from_center_size(
                    from.center().lerp(to.center(), ease),
                    from.size() + (to.size() - from.size()) * ease,
                );
                painter.rect_filled(moving, 0.0, colors::light(large));
                painter.rect_stroke(moving, 0.0, Stroke::new(2.0, hi), StrokeKind::Outside);
            }
            let start = from.center();
            let end = to.center();
            if (end - start).length() > 20.0 {
                arrow(painter, start, start.lerp(end, 0.88), Stroke::new(2.5, hi));
                painter.text(
                    start.lerp(end, 0.5) - vec2(0.0, 4.0),
                    Align2::CENTER_BOTTOM,
                    numbers::show(moved, den),
                    font.clone(),
                    hi,
                );
            }
        }
        ConstructionEvent::Leftover { column, .. } => {
            outline(bars.rect(column, 0.0, 1.0));
        }
        ConstructionEvent::Scaled => {}
    }
}

/// A straight arrow from `start` to `end` with a head of fixed size.
fn arrow(painter: &egui::Painter, start: egui::Pos2, end: egui::Pos2, stroke: Stroke) {
    let dir = (end - start).normalized();
    let normal = vec2(-dir.y, dir.x);
    let tip = end - dir * 4.0;
    let back = tip - dir * 14.0;
    painter.line_segment([start, back], stroke);
    painter.add(egui::Shape::convex_polygon(
        vec![tip, back + normal * 7.0, back - normal * 7.0],
        stroke.color,
        Stroke::NONE,
    ));
}
