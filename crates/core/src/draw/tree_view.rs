//! The light tree seen from above: the lights on the plane as dots whose area is their
//! power, the tree's groups at one depth as the boxes of their lights, spot footprints, and
//! optionally one recorded pick ([`TreePick`]) and a colouring of the lights by a pick
//! probability (`p_i`, `P(i | x)` or the ideal `s_i`).
//!
//! # What is drawn
//! * The region: the scene's image rectangle widened to hold every light (or a given one;
//!   what falls outside is cut at the frame), mapped with equal scales on both axes (`+y`
//!   up); the image rectangle outlined in grey.
//! * Lights: light `i` is a dot of area `A·p_i` pixels (`A` = [`DOT_AREA_SHARE`] of the
//!   region's pixels, `p_i = Φ_i/ΣΦ`, radius at most [`MAX_DOT_RADIUS`]); a light under one
//!   pixel is blended into its pixel with coverage `max(A·p_i, 0.15)`, with no path, so a
//!   million lights cost no allocation each (at most `A` dots are paths).
//! * Colour: one light colour, or with a probability vector `q` the viridis colour of
//!   `log10(q_i / max q)` over [`PROBABILITY_DECADES`] decades (grey where `q_i = 0`).
//! * Groups ([`tree_groups`]): after `d` branch decisions from the root, each subtree (or a
//!   leaf cluster reached sooner) outlined as the box of its lights' `(x, y)`.
//! * Spot footprints ([`crate::scene::EmissionShape::footprint`]): faint boxes, up to
//!   [`FOOTPRINT_LIMIT`] lights.
//! * A recorded pick: each chosen lane's box outlined strongly, the shading point as a
//!   cross, the picked light circled; shown up to a stage ([`tree_view_plane`]), a node's
//!   four lanes in [`LANE_COLORS`] and, for spots and ranges, the chosen lane's map of what
//!   its lights give the plane.

use std::ops::Range;

use glam::DVec2;
use tiny_skia::{PathBuilder, Pixmap, Stroke, Transform};

use super::canvas;
use super::image_sheet::viridis;
use super::palette::{self, Rgba8};
use super::text::{self, HAlign, TextStyle, VAlign};
use super::{DrawError, Style};
use crate::lesson::tree_pick::{CutStep, TreePick, plane_box};
use crate::scene::Scene;
use crate::spatial::grid::GRID_SIDE;
use crate::spatial::{Child, ChildRef, LightTree, MappedLanes, SpatialSampler, TREE_WIDTH};

/// The share of the region's pixels the lights' dots cover together (before the radius cap).
pub const DOT_AREA_SHARE: f64 = 0.03;

/// The largest dot radius in pixels.
pub const MAX_DOT_RADIUS: f64 = 9.0;

/// The decades of probability the colouring spans (below `max q · 10^-4`: the darkest).
pub const PROBABILITY_DECADES: f64 = 4.0;

/// The octaves of a lane's map drawn ([`tree_view_plane`] at a node of spots): cells below
/// `2^-MAP_OCTAVES` of the map's largest value are the faintest.
pub const MAP_OCTAVES: f64 = 8.0;

/// Spot footprints are drawn for at most this many lights.
pub const FOOTPRINT_LIMIT: usize = 2000;

/// What the top view shows (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct TreeView<'a> {
    /// The scene: light positions, powers, emission profiles, image rectangle.
    pub scene: &'a Scene,
    /// The sampler built over it ([`SpatialSampler::for_scene`]).
    pub sampler: &'a SpatialSampler,
    /// The depth whose groups are outlined (0: one group of every light).
    pub depth: usize,
    /// A recorded pick to highlight.
    pub pick: Option<&'a TreePick>,
    /// A pick probability per light (scene index) to colour the lights by.
    pub probabilities: Option<&'a [f64]>,
    /// The plane region shown, `[min, max]`; `None`: the scene's image rectangle.
    pub region: Option<[DVec2; 2]>,
}

/// A group of lights at a depth of the tree: a subtree or a leaf cluster.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeGroup {
    /// Branch decisions from the root to it.
    pub depth: usize,
    /// Its lights, in the tree's leaf order ([`LightTree::lights`]; for the exact pick the
    /// order of [`crate::spatial::ExactSampler::lights`]).
    pub lights: Range<usize>,
    /// The box of their positions' `(x, y)`.
    pub box_on_plane: [DVec2; 2],
}

/// The groups `depth` branch decisions below the root: every internal node or leaf
/// cluster at exactly that depth, and every leaf cluster reached sooner (it splits no
/// further). The exact pick (few lights) is one group of all its lights at every depth.
pub fn tree_groups(sampler: &SpatialSampler, depth: usize) -> Vec<TreeGroup> {
    match sampler {
        SpatialSampler::Exact(exact) => {
            let lights: Vec<_> = exact.lights().iter().map(|&(_, l)| l).collect();
            plane_box(&lights, 0..lights.len())
                .map(|box_on_plane| TreeGroup {
                    depth: 0,
                    lights: 0..lights.len(),
                    box_on_plane,
                })
                .into_iter()
                .collect()
        }
        SpatialSampler::Tree(tree) => {
            let mut groups = Vec::new();
            collect_groups(tree, tree.root(), 0, depth, &mut groups);
            groups
        }
    }
}

/// The groups below `at` (at depth `at_depth`) down to `depth`, in lane order.
fn collect_groups(
    tree: &LightTree,
    at: ChildRef,
    at_depth: usize,
    depth: usize,
    out: &mut Vec<TreeGroup>,
) {
    match at.get() {
        Child::Node(k) if at_depth < depth => {
            for lane in 0..crate::spatial::TREE_WIDTH {
                collect_groups(tree, tree.nodes()[k].child(lane), at_depth + 1, depth, out);
            }
        }
        Child::Empty => {}
        _ => {
            let lights = tree.span(at).unwrap_or(0..0);
            if let Some(box_on_plane) = plane_box(tree.lights(), lights.clone()) {
                out.push(TreeGroup {
                    depth: at_depth,
                    lights,
                    box_on_plane,
                });
            }
        }
    }
}

/// The caption: `depth d: n groups · N lights`.
pub fn tree_view_caption(depth: usize, groups: usize, lights: usize) -> String {
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    format!(
        "depth {depth}: {} · {}",
        plural(groups, "group", "groups"),
        plural(lights, "light", "lights")
    )
}

/// The plane → pixel map of a top view's frame: equal scales, `+y` up, the region centred
/// (what a click on the picture needs to find the point of the plane under it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneToPixels {
    region_min: DVec2,
    region_max_y: f64,
    scale: f64,
    offset: (f64, f64),
}

impl PlaneToPixels {
    fn new([lo, hi]: [DVec2; 2], (left, top, width, height): (f64, f64, f64, f64)) -> Self {
        let extent = (hi - lo).max(DVec2::splat(1e-300));
        let scale = (width / extent.x).min(height / extent.y);
        let offset = (
            left + 0.5 * (width - extent.x * scale),
            top + 0.5 * (height - extent.y * scale),
        );
        Self {
            region_min: lo,
            region_max_y: hi.y,
            scale,
            offset,
        }
    }

    /// The pixel `(x, y)` of the plane point `p`.
    pub fn point(&self, p: DVec2) -> (f32, f32) {
        (
            (self.offset.0 + (p.x - self.region_min.x) * self.scale) as f32,
            (self.offset.1 + (self.region_max_y - p.y) * self.scale) as f32,
        )
    }

    /// The plane point under pixel `(x, y)`: the inverse of [`PlaneToPixels::point`].
    pub fn plane_point(&self, (x, y): (f32, f32)) -> DVec2 {
        DVec2::new(
            self.region_min.x + (f64::from(x) - self.offset.0) / self.scale,
            self.region_max_y - (f64::from(y) - self.offset.1) / self.scale,
        )
    }

    /// A box `[lo, hi]` as `(x, y, w, h)`, widened by `pad` pixels on each side.
    fn rect(&self, [lo, hi]: [DVec2; 2], pad: f32) -> (f32, f32, f32, f32) {
        let (x0, y1) = self.point(lo);
        let (x1, y0) = self.point(hi);
        (x0 - pad, y0 - pad, x1 - x0 + 2.0 * pad, y1 - y0 + 2.0 * pad)
    }
}

/// The colours of a node's four lanes while a stepped pick stands at it (none of them the
/// lights' own colour), for the picture and for whatever shows the lanes' bars beside it.
pub const LANE_COLORS: [Rgba8; TREE_WIDTH] = [
    palette::LIGHTS[1],
    palette::LIGHTS[2],
    palette::LIGHTS[4],
    palette::LIGHTS[5],
];

/// How far a recorded pick is shown ([`tree_view_plane`]), counting its stages: with a
/// tile's cut ([`TreePick::cut`]) stage 0 stands at the cut (the tile outlined, its entries'
/// boxes thin, the one drawn thick) and the rest shift by one; then stage `s < steps` stands
/// at node `steps[s]` (the path so far, and that node's four lanes in [`LANE_COLORS`]);
/// stage `steps` at the leaf cluster (the whole path, the cluster's lights ringed); stage
/// `steps + 1` and beyond: the picked light, as [`tree_view`] draws it.
pub fn pick_stages(pick: &TreePick) -> usize {
    usize::from(pick.cut.is_some()) + pick.steps.len() + 2
}

/// Draws the top view of `view` (see the module docs).
pub fn tree_view(view: &TreeView, style: &Style) -> Result<Pixmap, DrawError> {
    let n = check(view)?;
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let (w, h) = (f64::from(style.width), f64::from(style.height));
    let frame = (16.0, 64.0, (w - 32.0).max(1.0), (h - 88.0).max(1.0));
    let (groups, _) = draw_plane(&mut pixmap, view, frame, &colors, usize::MAX)?;
    canvas::title(
        &mut pixmap,
        "Light tree from above",
        Some(&tree_view_caption(view.depth, groups, n)),
        &colors,
    )?;
    let note = match view.probabilities {
        Some(_) => "dot area: power p_i · colour: pick probability (log, 4 decades)",
        None => "dot area: power p_i · boxes: the groups' lights",
    };
    text::draw_text(
        &mut pixmap,
        note,
        (16.0, (h - 8.0) as f32),
        (HAlign::Left, VAlign::Bottom),
        &TextStyle::new(canvas::TICK_SIZE, colors.muted),
    )?;
    Ok(pixmap)
}

/// [`tree_view_plane`]'s picture and what its caller writes and clicks by.
#[derive(Debug)]
pub struct PlaneView {
    /// The plane alone, filling the picture.
    pub pixmap: Pixmap,
    /// Its plane → pixel map, so that a click on the picture finds its point of the plane.
    pub map: PlaneToPixels,
    /// The groups outlined at the view's depth.
    pub groups: usize,
}

/// The plane of [`tree_view`] alone, filling the picture (no title, no notes: the app
/// writes those in its own text, at its own size), with the recorded pick shown up to
/// stage `stage` ([`pick_stages`]).
pub fn tree_view_plane(
    view: &TreeView,
    style: &Style,
    stage: usize,
) -> Result<PlaneView, DrawError> {
    check(view)?;
    let colors = style.theme.colors();
    let mut pixmap = canvas::blank(style)?;
    let (w, h) = (f64::from(style.width), f64::from(style.height));
    let frame = (6.0, 6.0, (w - 12.0).max(1.0), (h - 12.0).max(1.0));
    let (groups, map) = draw_plane(&mut pixmap, view, frame, &colors, stage)?;
    Ok(PlaneView {
        pixmap,
        map,
        groups,
    })
}

/// The number of lights, once the view is drawable (lights, probabilities of the right
/// length).
fn check(view: &TreeView) -> Result<usize, DrawError> {
    let n = view.scene.positions.len();
    if n == 0 {
        return Err(DrawError::Empty("no lights"));
    }
    if let Some(q) = view.probabilities
        && q.len() != n
    {
        return Err(DrawError::Length {
            what: "probabilities",
            expected: n,
            got: q.len(),
        });
    }
    Ok(n)
}

/// The plane in `frame` `(left, top, width, height)`: image rectangle, footprints, groups,
/// lights and the pick up to `stage`; the margins cleared. Returns the number of groups and
/// the frame's plane → pixel map.
fn draw_plane(
    pixmap: &mut Pixmap,
    view: &TreeView,
    frame: (f64, f64, f64, f64),
    colors: &palette::ThemeColors,
    stage: usize,
) -> Result<(usize, PlaneToPixels), DrawError> {
    let scene = view.scene;
    let n = scene.positions.len();
    let groups = tree_groups(view.sampler, view.depth);
    let region = view.region.unwrap_or_else(|| default_region(scene));
    let map = PlaneToPixels::new(region, frame);
    let image = [scene.plane.min, scene.plane.max];
    canvas::stroke_rect(pixmap, map.rect(image, 0.0), 1.0, colors.grid);

    if let Some(emission) = scene.emission.as_deref().filter(|_| n <= FOOTPRINT_LIMIT) {
        for (e, &p) in emission.iter().zip(scene.positions.iter()) {
            if let Some(footprint) = e
                .footprint(p)
                .filter(|f| f[0].is_finite() && f[1].is_finite())
            {
                canvas::stroke_rect(pixmap, map.rect(footprint, 0.0), 1.0, colors.grid);
            }
        }
    }
    for (g, group) in groups.iter().enumerate() {
        let color = palette::light_color(g).with_alpha(220);
        canvas::stroke_rect(pixmap, map.rect(group.box_on_plane, 3.0), 1.5, color);
    }
    draw_lights(pixmap, view, &map, (frame.2 * frame.3, colors.muted))?;
    if let Some(pick) = view.pick {
        draw_pick(pixmap, view, pick, &map, (colors.foreground, stage));
    }
    clear_margins(pixmap, frame, colors.background);
    Ok((groups.len(), map))
}

/// The scene's image rectangle widened to hold every light with power.
fn default_region(scene: &Scene) -> [DVec2; 2] {
    let mut region = [scene.plane.min, scene.plane.max];
    for (p, &phi) in scene.positions.iter().zip(scene.powers.as_slice()) {
        if phi > 0.0 {
            region = [region[0].min(p.truncate()), region[1].max(p.truncate())];
        }
    }
    region
}

/// Paints the background over everything outside the frame `(left, top, width, height)`
/// (what the plane's drawing spilled there), before the title and notes.
fn clear_margins(pixmap: &mut Pixmap, (left, top, width, height): (f64, f64, f64, f64), bg: Rgba8) {
    let (w, h) = (pixmap.width() as f32, pixmap.height() as f32);
    let (l, t) = (left as f32 - 8.0, top as f32 - 8.0);
    let (r, b) = ((left + width) as f32 + 8.0, (top + height) as f32 + 8.0);
    canvas::fill_rect(pixmap, 0.0, 0.0, w, t, bg);
    canvas::fill_rect(pixmap, 0.0, b, w, h - b, bg);
    canvas::fill_rect(pixmap, 0.0, t, l, b - t, bg);
    canvas::fill_rect(pixmap, r, t, w - r, b - t, bg);
}

/// The lights as dots of area `A·p_i` (module docs), coloured by `view.probabilities`.
fn draw_lights(
    pixmap: &mut Pixmap,
    view: &TreeView,
    map: &PlaneToPixels,
    (frame_area, unpicked): (f64, Rgba8),
) -> Result<(), DrawError> {
    let powers = view.scene.powers.as_slice();
    let total: f64 = powers.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(DrawError::Empty("no power"));
    }
    let area = DOT_AREA_SHARE * frame_area / total;
    let q_max = view
        .probabilities
        .map_or(0.0, |q| q.iter().fold(0.0f64, |m, &v| m.max(v)));
    for (i, (&p, &phi)) in view.scene.positions.iter().zip(powers).enumerate() {
        if phi <= 0.0 {
            continue;
        }
        let color = match view.probabilities {
            None => palette::LIGHTS[0],
            Some(q) if q[i] > 0.0 && q_max > 0.0 => {
                viridis(1.0 + (q[i] / q_max).log10() / PROBABILITY_DECADES)
            }
            Some(_) => unpicked,
        };
        let (x, y) = map.point(p.truncate());
        let a = area * phi;
        if a < 1.0 {
            text::blend(
                pixmap,
                x.floor() as i64,
                y.floor() as i64,
                color,
                a.max(0.15) as f32,
            );
        } else {
            let r = (a / std::f64::consts::PI)
                .sqrt()
                .clamp(0.56, MAX_DOT_RADIUS);
            canvas::disc(pixmap, (x, y), r as f32, color.with_alpha(230));
        }
    }
    Ok(())
}

/// The pick up to `stage` ([`pick_stages`]): the chosen lanes' boxes so far; at a node its
/// four lanes in [`LANE_COLORS`] (a culled one thin); at the leaf its lights ringed; at the
/// end the picked light circled and joined to the shading point (a cross, at every stage).
fn draw_pick(
    pixmap: &mut Pixmap,
    view: &TreeView,
    pick: &TreePick,
    map: &PlaneToPixels,
    (ink, stage): (Rgba8, usize),
) {
    let stage = match &pick.cut {
        Some(cut) if stage == 0 => {
            draw_cut(pixmap, view, cut, map, ink);
            draw_cross(pixmap, map.point(pick.x));
            return;
        }
        Some(cut) => {
            if let Some(b) = cut.entries[cut.entry].box_on_plane {
                canvas::stroke_rect(pixmap, map.rect(b, 5.0), 2.5, ink);
            }
            stage - 1
        }
        None => stage,
    };
    for step in pick.steps.iter().take(stage) {
        if let Some(b) = step.lanes[step.lane].box_on_plane {
            canvas::stroke_rect(pixmap, map.rect(b, 5.0), 2.5, ink);
        }
    }
    if let Some(step) = pick.steps.get(stage) {
        if let SpatialSampler::Tree(tree) = view.sampler
            && let Some(mapped) = tree.mapped(step.node)
        {
            draw_lane_map(pixmap, mapped, step.lane, map, LANE_COLORS[step.lane]);
        }
        for (lane, color) in step.lanes.iter().zip(LANE_COLORS) {
            if let Some(b) = lane.box_on_plane {
                let width = if lane.culled.is_some() { 1.0 } else { 3.0 };
                canvas::stroke_rect(pixmap, map.rect(b, 7.0), width, color);
            }
        }
    } else if stage == pick.steps.len() {
        for light in &pick.leaf.lights {
            let at = view.scene.positions[light.light as usize].truncate();
            ring(pixmap, map.point(at), 7.0, ink.with_alpha(200));
        }
    }
    let (x, y) = map.point(pick.x);
    draw_cross(pixmap, (x, y));
    if stage > pick.steps.len() {
        let at = view.scene.positions[pick.light as usize].truncate();
        let (cx, cy) = map.point(at);
        ring(pixmap, (cx, cy), 12.0, ink);
        canvas::line(pixmap, (x, y), (cx, cy), 1.0, ink.with_alpha(160));
    }
}

/// The shading point: a cross.
fn draw_cross(pixmap: &mut Pixmap, (x, y): (f32, f32)) {
    let arm = 7.0;
    for (dx, dy) in [(arm, arm), (arm, -arm)] {
        canvas::line(
            pixmap,
            (x - dx, y - dy),
            (x + dx, y + dy),
            2.5,
            palette::UNIFORM,
        );
    }
}

/// A tile's cut: the tile outlined, each entry's box thin in its lane colour's order, the
/// entry drawn thick.
fn draw_cut(pixmap: &mut Pixmap, view: &TreeView, cut: &CutStep, map: &PlaneToPixels, ink: Rgba8) {
    let at = |[px, py]: [u32; 2]| {
        view.scene
            .plane
            .point_at(DVec2::new(f64::from(px), f64::from(py)))
    };
    let [first, end] = cut.pixels;
    let (a, b) = (at(first), at(end));
    canvas::stroke_rect(
        pixmap,
        map.rect([a.min(b), a.max(b)], 2.0),
        2.0,
        palette::UNIFORM,
    );
    for (k, entry) in cut.entries.iter().enumerate() {
        if let Some(b) = entry.box_on_plane {
            let (width, color) = if k == cut.entry {
                (3.0, ink)
            } else {
                (1.0, LANE_COLORS[k % TREE_WIDTH].with_alpha(200))
            };
            canvas::stroke_rect(pixmap, map.rect(b, 5.0), width, color);
        }
    }
}

/// The map of what lane `lane`'s lights give the plane ([`MappedLanes`], a 16 × 16 raster
/// over their footprints, for spots and ranges), its cells filled in `color` with an opacity
/// that follows the cell's logarithmic code (brighter where the lane weighs more).
fn draw_lane_map(
    pixmap: &mut Pixmap,
    mapped: &MappedLanes,
    lane: usize,
    map: &PlaneToPixels,
    color: Rgba8,
) {
    let [lo_x, lo_y, per_x, per_y, scale] = mapped.map.map(|field| field[lane]);
    if !(per_x > 0.0 && per_y > 0.0 && scale > 0.0 && per_x.is_finite() && per_y.is_finite()) {
        return;
    }
    let (dx, dy) = (1.0 / per_x, 1.0 / per_y);
    for (cell, &code) in mapped.codes(lane).iter().enumerate() {
        if code == 0 {
            continue;
        }
        let (i, j) = ((cell % GRID_SIDE) as f64, (cell / GRID_SIDE) as f64);
        let lo = DVec2::new(lo_x + i * dx, lo_y + j * dy);
        let (x, y, w, h) = map.rect([lo, lo + DVec2::new(dx, dy)], 0.0);
        // The top MAP_OCTAVES octaves of the map, from faint to strong.
        let top = 255.0 - 8.0 * MAP_OCTAVES;
        let strength = ((f64::from(code) - top) / (255.0 - top)).clamp(0.0, 1.0);
        let alpha = 12.0 + 150.0 * strength;
        canvas::fill_rect(pixmap, x, y, w, h, color.with_alpha(alpha as u8));
    }
}

/// A circle of radius `r` around `(x, y)`.
fn ring(pixmap: &mut Pixmap, (x, y): (f32, f32), r: f32, color: Rgba8) {
    if let Some(path) = PathBuilder::from_circle(x, y, r) {
        let stroke = Stroke {
            width: 2.5,
            ..Stroke::default()
        };
        pixmap.stroke_path(
            &path,
            &canvas::paint(color),
            &stroke,
            Transform::identity(),
            None,
        );
    }
}
