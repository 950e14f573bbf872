//! The Light tree panel: the tree over the scene's lights seen from above (the groups at a
//! chosen depth as boxes, the lights as dots of area by power, optionally coloured by a pick
//! probability at the pick's pixel), one spatial pick stepped from the root to a light
//! (Next / Back, Page Down / Page Up), and a five-step guide to why the spatial scheme wins.
//!
//! The picture is the core's headless top view ([`tree_view_plane`], the plane alone: every
//! word is the panel's own text, at body size). A click on it, or on a pixel of the images,
//! moves the pick there.

use egui::{ColorImage, Key, Modifiers, RichText, Sense, TextureHandle, Ui, vec2};
use lightpick_core::draw::{
    LANE_COLORS, PlaneToPixels, Style, Theme, TreeView, pick_stages, tree_view_caption,
    tree_view_plane,
};
use lightpick_core::lesson::tree_pick::{Culled, TreePick};
use lightpick_core::spatial::SpatialSampler;

use crate::app::colors;
use crate::app::panels::probability_bar_ui::bar_ui;
use crate::app::panels::tree_cut_ui::cut_stage_ui;
use crate::app::state::AppState;
use crate::app::state::light_tree::{SteppedPick, TreeColoring};
use crate::numbers::{self, three_significant};

/// The letters a node's four groups are named by, lane by lane.
const LANE_LETTERS: [char; 4] = ['A', 'B', 'C', 'D'];

/// The picture's cached texture and what it was drawn for.
#[derive(Clone)]
struct Drawn {
    key: DrawnKey,
    texture: TextureHandle,
    map: PlaneToPixels,
    groups: usize,
}

/// What the picture shows: a new key draws it again.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DrawnKey {
    generation: u64,
    depth: usize,
    coloring: TreeColoring,
    pick: Option<([u32; 2], u64)>,
    stage: usize,
    size: [usize; 2],
    dark: bool,
}

/// The panel (see the module docs).
pub fn light_tree_ui(ui: &mut Ui, state: &mut AppState) {
    let built = std::sync::Arc::clone(&state.built);
    state.light_tree.adopt_inspected(state.inspector.pixel);
    let spatial = std::sync::Arc::clone(built.samplers.spatial());
    let max_depth = match &*spatial {
        SpatialSampler::Exact(_) => 0,
        SpatialSampler::Tree(tree) => tree.depth().saturating_sub(1) as usize,
    };
    state.light_tree.depth = state.light_tree.depth.min(max_depth);
    let pick = state.light_tree.pick(&built, state.settings.seed);
    if let Some(pick) = &pick {
        keys(ui, state, pick);
    }
    controls_ui(ui, state, max_depth, pick.is_some());
    let wide = ui.available_width() >= 760.0;
    let side = if wide {
        (0.5 * ui.available_width()).min(ui.available_height() - 60.0)
    } else {
        ui.available_width().min(0.5 * ui.available_height())
    }
    .max(120.0);
    let draw = |ui: &mut Ui, state: &mut AppState| {
        picture_ui(ui, state, &spatial, pick.as_deref(), side);
    };
    if wide {
        ui.horizontal_top(|ui| {
            ui.vertical(|ui| draw(ui, state));
            ui.vertical(|ui| steps_and_guide_ui(ui, state, pick.as_deref()));
        });
    } else {
        draw(ui, state);
        steps_and_guide_ui(ui, state, pick.as_deref());
    }
}

/// Page Down / Page Up step the pick while the walkthrough (whose keys they are too) is
/// closed.
fn keys(ui: &mut Ui, state: &mut AppState, pick: &SteppedPick) {
    if state.settings.show_walkthrough || ui.ctx().text_edit_focused() {
        return;
    }
    if ui.input_mut(|i| i.consume_key(Modifiers::NONE, Key::PageDown)) {
        state.light_tree.next(pick);
    }
    if ui.input_mut(|i| i.consume_key(Modifiers::NONE, Key::PageUp)) {
        state.light_tree.back();
    }
}

/// The depth slider and the colouring.
fn controls_ui(ui: &mut Ui, state: &mut AppState, max_depth: usize, has_pixel: bool) {
    ui.horizontal_wrapped(|ui| {
        ui.label("Groups at depth");
        ui.add(egui::Slider::new(
            &mut state.light_tree.depth,
            0..=max_depth,
        ))
        .on_hover_text("How many branch decisions below the root the outlined groups are");
        ui.separator();
        ui.label("Colour:");
        let choices = [
            (
                TreeColoring::Power,
                "power",
                "One colour: the dot's area is the light's power",
            ),
            (
                TreeColoring::Spatial,
                "spatial P(i | x)",
                "Each light's spatial pick probability at the pick's pixel",
            ),
            (
                TreeColoring::Ideal,
                "ideal s_i",
                "Each light's share of the irradiance at the pick's pixel",
            ),
        ];
        for (coloring, name, hover) in choices {
            let enabled = has_pixel || coloring == TreeColoring::Power;
            let selected = state.light_tree.coloring == coloring;
            if ui
                .add_enabled(enabled, egui::Button::selectable(selected, name))
                .on_hover_text(hover)
                .on_disabled_hover_text("Click a point of the plane first")
                .clicked()
            {
                state.light_tree.coloring = coloring;
            }
        }
    });
}

/// The top view, drawn once per change; a click picks its pixel.
fn picture_ui(
    ui: &mut Ui,
    state: &mut AppState,
    spatial: &SpatialSampler,
    pick: Option<&SteppedPick>,
    side: f32,
) {
    let built = std::sync::Arc::clone(&state.built);
    let scene = &built.scene;
    let ppp = ui.ctx().pixels_per_point();
    let size = [(side * ppp) as usize, (side * ppp) as usize];
    let coloring = match pick {
        Some(_) => state.light_tree.coloring,
        None => TreeColoring::Power,
    };
    let key = DrawnKey {
        generation: built.generation,
        depth: state.light_tree.depth,
        coloring,
        pick: pick.map(|p| (p.pixel, p.number)),
        stage: state.light_tree.stage,
        size,
        dark: state.dark(),
    };
    let id = egui::Id::unique("lightpick_light_tree_picture");
    let mut drawn: Option<Drawn> = ui.data(|d| d.get_temp(id));
    if drawn.as_ref().is_none_or(|d| d.key != key) {
        let overlay = state.light_tree.coloring_overlay(&built);
        let probabilities = overlay.as_deref().and_then(|o| coloring.probabilities(o));
        let view = TreeView {
            scene,
            sampler: spatial,
            depth: key.depth,
            pick: pick.and_then(|p| p.record.as_ref()),
            probabilities,
            region: None,
        };
        let style = Style {
            width: size[0] as u32,
            height: size[1] as u32,
            theme: if key.dark { Theme::Dark } else { Theme::Light },
        };
        match tree_view_plane(&view, &style, key.stage) {
            Ok(plane) => {
                let rgba = lightpick_core::draw::to_rgba8(&plane.pixmap);
                let image = ColorImage::from_rgba_unmultiplied(size, &rgba);
                let texture = match drawn {
                    Some(d) => {
                        let mut t = d.texture;
                        t.set(image, egui::TextureOptions::LINEAR);
                        t
                    }
                    None => ui.ctx().load_texture(
                        "lightpick_light_tree",
                        image,
                        egui::TextureOptions::LINEAR,
                    ),
                };
                drawn = Some(Drawn {
                    key,
                    texture,
                    map: plane.map,
                    groups: plane.groups,
                });
                ui.data_mut(|d| d.insert_temp(id, drawn.clone()));
            }
            Err(e) => {
                ui.colored_label(colors::error(state.dark()), format!("No picture: {e}"));
                return;
            }
        }
    }
    let Some(drawn) = drawn else {
        return;
    };
    let response =
        ui.add(egui::Image::new((drawn.texture.id(), vec2(side, side))).sense(Sense::click()));
    if response.clicked()
        && let Some(at) = response.interact_pointer_pos()
    {
        let local = (at - response.rect.min) * ppp;
        let x = drawn.map.plane_point((local.x, local.y));
        state.light_tree.select_pixel(scene.plane.pixel_at(x));
    }
    ui.label(tree_view_caption(
        key.depth,
        drawn.groups,
        scene.light_count(),
    ));
    ui.label(match pick {
        None => "Click a point of the plane (or a pixel of the images) to pick a light there."
            .to_owned(),
        Some(p) => format!(
            "The cross is the centre of pixel ({}, {}); a dot's area is its light's power.",
            p.pixel[0], p.pixel[1]
        ),
    });
}

/// The stepped pick, then the guide.
fn steps_and_guide_ui(ui: &mut Ui, state: &mut AppState, pick: Option<&SteppedPick>) {
    egui::ScrollArea::vertical()
        .id_salt("lightpick_light_tree_steps")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            if let Some(pick) = pick {
                stepped_pick_ui(ui, state, pick);
            }
            ui.separator();
            super::tree_guide_ui::guide_ui(ui, state);
        });
}

/// One pick at the pixel, stage by stage: a node's four groups, the leaf, the end.
fn stepped_pick_ui(ui: &mut Ui, state: &mut AppState, pick: &SteppedPick) {
    ui.strong(format!(
        "One spatial pick at pixel ({}, {}), pick {}",
        pick.pixel[0],
        pick.pixel[1],
        pick.number + 1
    ));
    let Some(record) = &pick.record else {
        ui.label(
            "No light reaches this point: the spatial scheme picks nothing and the estimate is 0.",
        );
        if ui.button("New pick").clicked() {
            state.light_tree.new_pick();
        }
        return;
    };
    let stages = pick_stages(record);
    let stage = state.light_tree.stage.min(stages - 1);
    ui.horizontal(|ui| {
        if ui
            .add_enabled(stage > 0, egui::Button::new("Back"))
            .on_hover_text("Page Up")
            .clicked()
        {
            state.light_tree.back();
        }
        if ui
            .add_enabled(stage + 1 < stages, egui::Button::new("Next"))
            .on_hover_text("Page Down")
            .clicked()
        {
            state.light_tree.next(pick);
        }
        if ui
            .button("New pick")
            .on_hover_text("Another pick at the same point (the next random numbers)")
            .clicked()
        {
            state.light_tree.new_pick();
        }
        ui.label(format!("stage {} of {stages}", stage + 1));
    });
    let dark = state.dark();
    let stage = match &record.cut {
        Some(cut) if stage == 0 => {
            cut_stage_ui(ui, cut, dark);
            return;
        }
        Some(_) => stage - 1,
        None => stage,
    };
    if let Some(step) = record.steps.get(stage) {
        let spatial = std::sync::Arc::clone(state.built.samplers.spatial());
        let (power_shares, mapped) = match &*spatial {
            SpatialSampler::Tree(tree) => {
                let node = &tree.nodes()[step.node];
                let powers: [f64; 4] = std::array::from_fn(|lane| node.power(lane));
                let total: f64 = powers.iter().sum();
                let shares = powers.map(|p| if total > 0.0 { p / total } else { 0.0 });
                (shares, tree.mapped(step.node).is_some())
            }
            SpatialSampler::Exact(_) => ([f64::NAN; 4], false),
        };
        node_stage_ui(ui, record, (stage, step, power_shares, mapped), dark);
    } else if stage == record.steps.len() {
        let powers = state.built.scene.powers.as_slice();
        leaf_stage_ui(ui, record, powers, pick.total_power, dark);
    } else {
        end_stage_ui(ui, record, pick);
    }
}

/// A node: its four groups' probabilities as bars, culled ones greyed with the reason, the
/// random number and the group it takes.
/// `power_shares`: each group's share of the node's power, where power picking would go;
/// `mapped`: whether the node's groups are weighed by their maps (spots and ranges).
fn node_stage_ui(
    ui: &mut Ui,
    record: &TreePick,
    (stage, step, power_shares, mapped): (
        usize,
        &lightpick_core::lesson::tree_pick::TreePickStep,
        [f64; 4],
        bool,
    ),
    dark: bool,
) {
    let weight = if mapped {
        "what its map says its lights give the floor at x, mixed with a share of their \
         peak intensity"
    } else {
        "its representative light's power over its distance, mixed with a share of its power"
    };
    ui.label(format!(
        "Node at depth {}: its four groups weighed at x (each group's weight is {weight}).",
        step.depth
    ));
    egui::Grid::new("lightpick_node_groups")
        .num_columns(4)
        .show(ui, |ui| {
            for (lane, (group, color)) in step.lanes.iter().zip(LANE_COLORS).enumerate() {
                let color = colors::to_color32(color);
                let name = format!("group {}", LANE_LETTERS[lane]);
                let name = if lane == step.lane {
                    RichText::new(format!("{name} ← picked")).strong()
                } else {
                    RichText::new(name)
                };
                ui.colored_label(color, name);
                if group.culled.is_some() {
                    // An empty bar; why it is empty is said below the grid, where it wraps.
                    bar_ui(ui, 0.0, color);
                    ui.colored_label(
                        colors::muted(dark),
                        format!("P = 0 · {} lights", group.light_count()),
                    );
                } else {
                    bar_ui(ui, group.probability, color);
                    ui.label(format!(
                        "P = {} · {} lights",
                        three_significant(group.probability),
                        group.light_count()
                    ));
                }
                let share = power_shares[lane];
                if share.is_finite() && group.light_count() > 0 {
                    ui.colored_label(
                        colors::muted(dark),
                        format!("by power: {}", three_significant(share)),
                    )
                    .on_hover_text(
                        "The group's share of the node's power: where picking by power alone \
                         would go, whatever the point",
                    );
                }
                ui.end_row();
            }
        });
    for (lane, group) in step.lanes.iter().enumerate() {
        if let Some(reason) = group.culled {
            ui.colored_label(
                colors::muted(dark),
                culled_words(LANE_LETTERS[lane], reason, group.light_count()),
            );
        }
    }
    let u = f64::from(step.random24) / 16_777_216.0;
    let before = match (stage, &record.cut) {
        (0, Some(cut)) => cut.pdf_after,
        (0, None) => 1.0,
        _ => record.steps[stage - 1].pdf_after,
    };
    ui.label(format!(
        "Random number u = {:.4} → group {}. P so far: {} × {} = {}",
        u,
        LANE_LETTERS[step.lane],
        three_significant(before),
        three_significant(step.lanes[step.lane].probability),
        three_significant(step.pdf_after)
    ));
}

/// Why group `letter`, culled, has probability 0, in a student's words (one sentence).
fn culled_words(letter: char, reason: Culled, lights: usize) -> String {
    let why = match reason {
        Culled::Empty => return format!("Group {letter} is empty."),
        Culled::OutsideFootprint => "x is outside where its lights shine",
        Culled::BeyondRange => "x is beyond its lights' range",
        Culled::OutsideCone => "x is outside its spots' cones",
        Culled::NoPower => "its lights have no power",
    };
    let lights = numbers::count(lights, "light", "lights");
    format!("Group {letter} is culled: {why}, so its {lights} get P = 0.")
}

/// The leaf cluster: its lights, each by its exact contribution at x.
fn leaf_stage_ui(ui: &mut Ui, record: &TreePick, powers: &[f64], total_power: f64, dark: bool) {
    ui.label(match record.leaf.lights.len() {
        1 => "The leaf: the one light the cut took, picked with probability 1 where it \
              gives x anything."
            .to_string(),
        count => {
            format!("The leaf: {count} lights, each picked by its exact contribution f_i at x.")
        }
    });
    egui::Grid::new("lightpick_leaf_lights")
        .num_columns(4)
        .striped(true)
        .show(ui, |ui| {
            ui.strong("light");
            ui.strong("f_i at x");
            ui.strong("P in the leaf");
            ui.strong("power p_i");
            ui.end_row();
            for (k, light) in record.leaf.lights.iter().enumerate() {
                let text = format!("{}", light.light + 1);
                if k == record.leaf.picked {
                    ui.strong(format!("{text} ← picked"));
                } else {
                    ui.label(text);
                }
                ui.label(numbers::short(light.contribution * total_power));
                ui.horizontal(|ui| {
                    bar_ui(ui, light.probability, colors::foreground(dark));
                    ui.label(three_significant(light.probability));
                });
                ui.label(three_significant(
                    powers[light.light as usize] / total_power,
                ));
                ui.end_row();
            }
        });
    let u = f64::from(record.leaf.random24) / 16_777_216.0;
    ui.label(format!(
        "Random number u = {u:.4} → light {}.",
        record.light + 1
    ));
}

/// The end: the pdf as the product of the steps, the renderer's equal to it, the estimate
/// against the exact irradiance, and what power picking would have paid.
fn end_stage_ui(ui: &mut Ui, record: &TreePick, pick: &SteppedPick) {
    let factors: Vec<String> = record
        .cut
        .iter()
        .map(|c| three_significant(c.pdf_after))
        .chain(
            record
                .steps
                .iter()
                .map(|s| three_significant(s.lanes[s.lane].probability)),
        )
        .chain(std::iter::once(three_significant(
            record.picked().probability,
        )))
        .collect();
    ui.label(format!(
        "P(i | x) = {} = {}",
        factors.join(" × "),
        three_significant(record.pdf)
    ));
    if let Some(renderer) = pick.renderer_pdf {
        let same = renderer.to_bits() == record.pdf.to_bits();
        ui.label(format!(
            "The renderer's P(i | x) of light {}: {} ({})",
            record.light + 1,
            three_significant(renderer),
            if same {
                "the same, bit for bit"
            } else {
                "different!"
            }
        ));
    }
    let phi = pick.total_power;
    let f = record.contribution * phi;
    ui.label(format!(
        "Estimate f_i / P = {} / {} = {}; the exact irradiance here is {}.",
        numbers::short(f),
        three_significant(record.pdf),
        numbers::short(f / record.pdf),
        numbers::short(record.irradiance * phi)
    ));
    ui.label(format!(
        "Power picking would pick light {} with p_i = {}: estimate f_i / p_i = {}.",
        record.light + 1,
        three_significant(record.power_pmf),
        numbers::short(f / record.power_pmf)
    ));
}
