//! The sampling panel: running histograms of uniform and power (alias-table) picks against the pmf each
//! realizes, their chi-square p-values, and "draw one sample" replayed on the diagram.

use egui::Ui;
use egui_plot::{Bar, BarChart, Plot, Points};
use lightpick_core::{ChiSquare, Scheme};

use super::table_words;
use crate::app::colors;
use crate::app::state::AppState;

/// The whole panel.
pub fn sampling_ui(ui: &mut Ui, state: &mut AppState) {
    let dark = state.dark();
    ui.horizontal(|ui| {
        ui.label(format!("{} picks per scheme", state.sampling.picks))
            .on_hover_text(
                "Light picks drawn so far by each scheme (both restart when the table changes)",
            );
    });
    ui.horizontal_wrapped(|ui| {
        let label = ui.label("picks/frame");
        ui.add(
            egui::DragValue::new(&mut state.settings.picks_per_frame)
                .range(1..=1_000_000)
                .speed(10.0),
        )
        .labelled_by(label.id)
        .on_hover_text("Light picks added to each histogram per frame while running");
        if ui
            .button("Draw one sample")
            .on_hover_text("Draw U1 (picks a column) and U2 (compared with its threshold); shown on the diagram")
            .clicked()
        {
            state.draw_one();
        }
        if ui
            .button("Clear")
            .on_hover_text("Clear the histograms")
            .clicked()
        {
            state.restart_sampling();
        }
    });
    if let Some(draw) = state.sampling.last_draw {
        ui.label(
            egui::RichText::new(table_words::draw_sentence(state, &draw)).color(colors::pick(dark)),
        );
    }
    ui.horizontal_wrapped(|ui| {
        chi_label(ui, "uniform", state.sampling.uniform_chi, dark);
        ui.separator();
        chi_label(ui, "power (alias)", state.sampling.alias_chi, dark);
    });
    histogram_plot_ui(ui, state);
}

fn chi_label(ui: &mut Ui, name: &str, chi: Option<ChiSquare>, dark: bool) {
    let Some(c) = chi else {
        ui.label(format!("{name}: no picks yet"));
        return;
    };
    let color = if c.p_value >= 0.001 {
        colors::good(dark)
    } else {
        colors::error(dark)
    };
    ui.colored_label(
        color,
        format!(
            "{name}: χ² = {:.2}, dof = {}, p = {:.3}",
            c.chi2, c.dof, c.p_value
        ),
    )
    .on_hover_text(
        "Pearson's chi-square test of the counts against the scheme's own pmf \
         (uniform: 1/N, alias: Φ_i/ΣΦ). p-values are uniform on [0, 1] when the sampler is right; \
         a p below 0.001 is shown in red. Cells whose expected count is below 5 are pooled with \
         their neighbours; above 65 536 lights the picks are counted per group of consecutive \
         lights (at most 65 536 groups, fixed before sampling).",
    );
}

fn histogram_plot_ui(ui: &mut Ui, state: &AppState) {
    let run = &state.sampling;
    let per = run.per_bin;
    let picks = run.picks.max(1) as f64;
    let uniform_color = colors::scheme(Scheme::Uniform);
    let alias_color = colors::scheme(Scheme::Alias);
    let width = 0.38;
    let x = |b: usize, side: f64| b as f64 + 1.0 + side * width / 2.0;
    let uniform_bars: Vec<Bar> = run
        .uniform_bins
        .iter()
        .enumerate()
        .map(|(b, &c)| {
            Bar::new(x(b, -1.0), c as f64 / picks)
                .width(width)
                .fill(uniform_color)
        })
        .collect();
    let alias_bars: Vec<Bar> = run
        .alias_bins
        .iter()
        .enumerate()
        .map(|(b, &c)| {
            Bar::new(x(b, 1.0), c as f64 / picks)
                .width(width)
                .fill(alias_color)
        })
        .collect();
    let expected_alias: Vec<[f64; 2]> = run
        .expected_bins
        .iter()
        .enumerate()
        .map(|(b, &p)| [x(b, 1.0), p])
        .collect();
    let expected_uniform: Vec<[f64; 2]> = run
        .flat_bins
        .iter()
        .enumerate()
        .map(|(b, &p)| [x(b, -1.0), p])
        .collect();
    let n = state.built.len();
    // The last bar holds what is left: fewer lights, so a shorter bar. Said in the label.
    let last = n - per * n.div_ceil(per.max(1)).saturating_sub(1);
    let x_label = if per == 1 {
        "light".to_owned()
    } else if last != per && last > 0 {
        format!("lights, {per} per bar (the last bar {last}: shorter by as much)")
    } else {
        format!("lights, {per} per bar")
    };
    let fg = colors::foreground(state.dark());
    // The key sits above the plot, where it never covers a bar.
    key_row_ui(ui, fg);
    Plot::new("histograms")
        .show_background(false)
        .height(ui.available_height().max(140.0))
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .include_y(0.0)
        .x_axis_label(x_label)
        .y_axis_label("frequency")
        .show(ui, |plot_ui| {
            plot_ui.bar_chart(BarChart::new("uniform picks", uniform_bars).color(uniform_color));
            plot_ui.bar_chart(BarChart::new("power picks (alias)", alias_bars).color(alias_color));
            plot_ui.points(
                Points::new("expected pmf", expected_alias)
                    .shape(egui_plot::MarkerShape::Diamond)
                    .radius(5.0)
                    .color(fg),
            );
            plot_ui.points(
                Points::new("expected 1/N", expected_uniform)
                    .shape(egui_plot::MarkerShape::Circle)
                    .radius(3.5)
                    .color(colors::reference()),
            );
        });
}

/// The plot's key: the two schemes' bars and the two expected markers (`fg`: the pmf's).
fn key_row_ui(ui: &mut Ui, fg: egui::Color32) {
    ui.horizontal_wrapped(|ui| {
        key_ui(
            ui,
            Marker::Bar,
            colors::scheme(Scheme::Uniform),
            "uniform picks",
            "Share of the uniform picks per light",
        );
        key_ui(
            ui,
            Marker::Bar,
            colors::scheme(Scheme::Alias),
            "power picks (alias)",
            "Share of the power picks (drawn from the alias table) per light",
        );
        key_ui(
            ui,
            Marker::Diamond,
            fg,
            "pmf",
            "Expected share under alias sampling: Φ_i/ΣΦ",
        );
        key_ui(
            ui,
            Marker::Circle,
            colors::reference(),
            "1/N",
            "Expected share under uniform picking",
        );
    });
}

/// The mark drawn before an entry of the histogram's key.
#[derive(Clone, Copy)]
enum Marker {
    Bar,
    Diamond,
    Circle,
}

/// One entry of the key above the histogram: the plot's mark, painted, then its name.
fn key_ui(ui: &mut Ui, marker: Marker, color: egui::Color32, text: &str, tip: &str) {
    let side = ui.text_style_height(&egui::TextStyle::Body) * 0.7;
    let (rect, _) = ui.allocate_exact_size(egui::vec2(side, side), egui::Sense::hover());
    let painter = ui.painter();
    let c = rect.center();
    let r = side / 2.0;
    match marker {
        Marker::Bar => {
            painter.rect_filled(rect, 1.0, color);
        }
        Marker::Diamond => {
            let points = vec![
                c + egui::vec2(0.0, -r),
                c + egui::vec2(r, 0.0),
                c + egui::vec2(0.0, r),
                c + egui::vec2(-r, 0.0),
            ];
            painter.add(egui::Shape::convex_polygon(
                points,
                color,
                egui::Stroke::NONE,
            ));
        }
        Marker::Circle => {
            painter.circle_filled(c, r * 0.8, color);
        }
    }
    ui.label(text).on_hover_text(tip);
}
