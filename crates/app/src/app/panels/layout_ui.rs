//! Draws the window's [`Layout`]: its columns of panels (resizable, never narrower than
//! their panels' least widths), the panels of a column one over the other or as tabs, each
//! under a header with its title (or tabs) and the maximize / restore button. It knows no
//! panel: it draws them through [`PaneContents`].

use egui::{Frame, Margin, Rect, Sense, Stroke, StrokeKind, Ui, Vec2, vec2};

use super::layout::{
    self, Arrangement, HEADER_HEIGHT, Layout, PANE_GAP, PANES, column_min_width, min_height,
    stacks, tabs_with, with_tabs,
};
use super::panel_kind::PanelKind;

/// What the layout draws in each place.
pub trait PaneContents {
    /// Draws `pane`'s content (below its header) into `ui`.
    fn pane_ui(&mut self, ui: &mut Ui, pane: PanelKind);

    /// The content height `pane` asks for at `width` when it stands over other panels (the
    /// images: as large as the width allows), or `None` when it fills what it is given and
    /// the presenter sizes it by dragging its edge.
    fn wanted_height(&self, ui: &Ui, pane: PanelKind, width: f32) -> Option<f32>;
}

/// Draws the five panels into the rest of `ui`, as [`Layout`] arranges them for its size,
/// each column in `frame`.
pub fn panes_ui(ui: &mut Ui, layout: &mut Layout, contents: &mut dyn PaneContents, frame: Frame) {
    let size = ui.available_rect_before_wrap().size();
    layout.begin(size);
    if layout.maximized.is_some() {
        egui::CentralPanel::default().frame(frame).show(ui, |ui| {
            tabs_ui(ui, layout, contents, &PANES);
        });
        return;
    }
    let arrangement = layout.arrangement;
    let columns = arrangement.columns();
    let mut remaining = size.x;
    for (k, panes) in columns.iter().enumerate() {
        if k + 1 == columns.len() {
            egui::CentralPanel::default().frame(frame).show(ui, |ui| {
                column_ui(ui, layout, contents, arrangement, panes);
            });
        } else {
            // Never so wide that a later column falls under its least width.
            let later: f32 = columns[k + 1..].iter().map(|c| column_min_width(c)).sum();
            let min = column_min_width(panes);
            let max = (remaining - later).max(min);
            let default = (arrangement.default_share(k) * size.x).clamp(min, max);
            let response = egui::Panel::left(("lightpick_column", arrangement.name(), k))
                .frame(frame)
                .resizable(true)
                .size_range(min..=max)
                .default_size(default)
                .show(ui, |ui| {
                    column_ui(ui, layout, contents, arrangement, panes);
                });
            remaining -= response.response.rect.width();
        }
    }
}

/// One column: its panels one over the other when they fit its height, else as tabs.
fn column_ui(
    ui: &mut Ui,
    layout: &mut Layout,
    contents: &mut dyn PaneContents,
    arrangement: Arrangement,
    panes: &[PanelKind],
) {
    if stacks(panes, ui.available_height()) {
        stacked_ui(ui, layout, contents, arrangement, panes);
    } else {
        tabs_ui(ui, layout, contents, panes);
    }
}

/// `panes` one over the other: the first in a top panel (its wanted height, or resizable
/// by its lower edge), the others in what is left.
fn stacked_ui(
    ui: &mut Ui,
    layout: &mut Layout,
    contents: &mut dyn PaneContents,
    arrangement: Arrangement,
    panes: &[PanelKind],
) {
    let [first, rest @ ..] = panes else {
        return;
    };
    let tabs = tabs_with(*first);
    let shown = layout.shown(tabs);
    if rest.is_empty() {
        pane_ui(ui, layout, contents, tabs, shown);
        return;
    }
    let height = ui.available_height();
    let below: f32 = rest
        .iter()
        .map(|&p| min_height(p) + HEADER_HEIGHT + PANE_GAP)
        .sum();
    let min = min_height(*first) + HEADER_HEIGHT + PANE_GAP;
    let max = (height - below).max(min);
    let panel = egui::Panel::top(("lightpick_pane", arrangement.name(), *first)).frame(
        Frame::NONE.inner_margin(Margin {
            bottom: PANE_GAP as i8,
            ..Margin::ZERO
        }),
    );
    let panel = match contents.wanted_height(ui, shown, ui.available_width()) {
        Some(wanted) => panel.exact_size((wanted + HEADER_HEIGHT + PANE_GAP).clamp(min, max)),
        None => panel
            .resizable(true)
            .size_range(min..=max)
            .default_size(layout::default_height(*first, height).clamp(min, max)),
    };
    panel.show(ui, |ui| pane_ui(ui, layout, contents, tabs, shown));
    egui::CentralPanel::no_frame().show(ui, |ui| {
        stacked_ui(ui, layout, contents, arrangement, rest);
    });
}

/// `panes` (and the tabs that share their places, [`with_tabs`]) as tabs: one header, the
/// chosen panel under it.
fn tabs_ui(ui: &mut Ui, layout: &mut Layout, contents: &mut dyn PaneContents, panes: &[PanelKind]) {
    let tabs = with_tabs(panes);
    let shown = layout.shown(&tabs);
    pane_ui(ui, layout, contents, &tabs, shown);
}

/// One place of the layout: the header over `tabs` (or `shown`'s title alone), then
/// `shown`'s content.
fn pane_ui(
    ui: &mut Ui,
    layout: &mut Layout,
    contents: &mut dyn PaneContents,
    tabs: &[PanelKind],
    shown: PanelKind,
) {
    let rect = ui.available_rect_before_wrap();
    layout.placed.push((shown, rect));
    header_ui(ui, layout, tabs, shown);
    contents.pane_ui(ui, shown);
    // The pane fills its place even when its content is shorter: a panel stores the size of
    // what it drew, so a shorter content would shrink it frame after frame.
    ui.expand_to_include_rect(rect);
}

/// The header: the title (or the tabs, the shown one selected) on the left; on the right
/// the maximize button, or Restore while a panel is maximized.
fn header_ui(ui: &mut Ui, layout: &mut Layout, tabs: &[PanelKind], shown: PanelKind) {
    let height = HEADER_HEIGHT - ui.spacing().item_spacing.y;
    let (rect, _) = ui.allocate_exact_size(vec2(ui.available_width(), height), Sense::hover());
    let mut header = ui.new_child(
        egui::UiBuilder::new()
            .max_rect(rect)
            .layout(egui::Layout::left_to_right(egui::Align::Center)),
    );
    let maximized = layout.maximized.is_some();
    let (chosen, button) = egui::Sides::new().shrink_left().show(
        &mut header,
        |ui| {
            let mut chosen = None;
            if tabs.len() == 1 {
                ui.heading(layout::title(shown));
            } else {
                for &pane in tabs {
                    let text = egui::RichText::new(layout::title(pane)).heading();
                    if ui
                        .selectable_label(pane == shown, text)
                        .on_hover_text(format!("Show the {} panel here", layout::title(pane)))
                        .clicked()
                    {
                        chosen = Some(pane);
                    }
                }
            }
            chosen
        },
        |ui| {
            if maximized {
                ui.button("Restore")
                    .on_hover_text("Back to every panel (Esc)")
                    .clicked()
            } else {
                maximize_button_ui(ui)
                    .on_hover_text(format!(
                        "Maximize the {} panel (Restore or Esc goes back)",
                        layout::title(shown)
                    ))
                    .accessible_name(format!("Maximize {}", layout::title(shown)))
                    .clicked()
            }
        },
    );
    if let Some(pane) = chosen {
        layout.select(pane);
    }
    if button {
        if maximized {
            layout.restore();
        } else {
            layout.maximize(shown);
        }
    }
    // The header's lower edge, as a panel's separator line.
    let y = rect.bottom() + 0.5 * ui.spacing().item_spacing.y;
    ui.painter().hline(
        rect.x_range(),
        y,
        ui.visuals().widgets.noninteractive.bg_stroke,
    );
}

/// A small button showing a window outline (a title bar's maximize icon).
fn maximize_button_ui(ui: &mut Ui) -> egui::Response {
    let side = ui.spacing().interact_size.y + 4.0;
    let (rect, response) = ui.allocate_exact_size(Vec2::splat(side), Sense::click());
    response.widget_info(|| egui::WidgetInfo::new(egui::Role::Button));
    if ui.is_rect_visible(rect) {
        let visuals = ui.style().interact(&response);
        let painter = ui.painter();
        if response.hovered() || response.has_focus() {
            painter.rect(
                rect,
                visuals.corner_radius,
                visuals.weak_bg_fill,
                visuals.bg_stroke,
                StrokeKind::Inside,
            );
        }
        let icon = Rect::from_center_size(rect.center(), Vec2::splat(0.5 * side));
        let stroke = Stroke::new(1.5, visuals.fg_stroke.color);
        painter.rect_stroke(icon, 1.0, stroke, StrokeKind::Middle);
        // The title bar of the window outline.
        painter.hline(icon.x_range(), icon.top() + 2.5, stroke);
    }
    response
}
