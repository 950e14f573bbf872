//! The Light tree panel: a tab beside the images (key 6, View → Light tree), the tree from
//! above with its groups at a chosen depth, and one spatial pick stepped from its tile's cut
//! to a light (Next / Back, Page Down / Page Up) whose product of steps is the renderer's
//! pdf.

use egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::panels::layout::tabs_with;
use lightpick::app::{LightpickApp, PanelKind};
use lightpick::numbers::three_significant;
use lightpick_core::draw::{pick_stages, tree_groups, tree_view_caption};
use lightpick_core::lesson::tree_pick::TreePick;
use lightpick_core::scene::pixel_center;

use crate::common::painted::painted;
use crate::common::{click, panel, shows_containing, window};

/// The panel alone on `preset`, with the pick at `pixel`.
fn tree_panel(preset: &str, pixel: [u32; 2]) -> Harness<'static, LightpickApp> {
    let mut app = LightpickApp::for_tests();
    app.state.load_preset(preset);
    app.state.light_tree.select_pixel(pixel);
    let mut harness = panel(PanelKind::LightTree, app, [1000.0, 900.0]);
    harness.run();
    harness
}

#[test]
fn key_6_and_the_view_menu_show_the_light_tree_beside_the_images() {
    let mut harness = window(LightpickApp::for_tests(), [1024.0, 768.0]);
    harness.run();
    let place = tabs_with(PanelKind::Images);
    assert_eq!(harness.state().layout.shown(place), PanelKind::Images);
    assert!(!shows_containing(&harness, "Groups at depth"));
    harness.key_press(Key::Num6);
    harness.run();
    assert_eq!(harness.state().layout.shown(place), PanelKind::LightTree);
    assert!(shows_containing(&harness, "Groups at depth"));
    // Back to the images by their tab, then to the tree by the View menu.
    click(&mut harness, "Images");
    assert_eq!(harness.state().layout.shown(place), PanelKind::Images);
    click(&mut harness, "View");
    // The menu's item, drawn after the tab of the same name.
    harness
        .query_all_by_label("Light tree")
        .last()
        .expect("the View menu's item")
        .click();
    harness.run();
    assert_eq!(harness.state().layout.shown(place), PanelKind::LightTree);
}

#[test]
fn the_caption_counts_the_groups_at_the_chosen_depth() {
    let mut harness = tree_panel("grid", [72, 194]);
    for depth in [0, 1, 2, 3] {
        harness.state_mut().state.light_tree.depth = depth;
        harness.run();
        let state = &harness.state().state;
        let groups = tree_groups(state.built.samplers.spatial(), depth).len();
        assert_eq!(
            groups,
            4usize.pow(depth as u32),
            "1024 lights split in four"
        );
        let caption = tree_view_caption(depth, groups, 1024);
        assert!(shows_containing(&harness, &caption), "{caption}");
    }
}

/// Steps a pick to its end with Next and Page Down, back with Back and Page Up; at the end
/// the product of the steps is printed equal, bit for bit, to the renderer's pdf.
fn steps_to_the_renderers_pdf(preset: &str, pixel: [u32; 2]) {
    let mut harness = tree_panel(preset, pixel);
    let (record, renderer_pdf) = {
        let state = &mut harness.state_mut().state;
        let built = std::sync::Arc::clone(&state.built);
        let seed = state.settings.seed;
        // The first pick number whose light gives the pixel something (a pick may end on
        // a light whose cone misses x: then ê = 0 and there is no record).
        let record = (0..100)
            .find_map(|number| {
                state.light_tree.number = number;
                state.light_tree.pick(&built, seed)?.record.clone()
            })
            .expect("lights reach the pixel");
        let scene = &built.scene;
        let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
        let pdf = built.samplers.spatial().pdf(x, record.light as usize);
        (record, pdf)
    };
    harness.run();
    assert_eq!(record.pdf.to_bits(), renderer_pdf.to_bits(), "{preset}");
    let product = record
        .cut
        .iter()
        .map(|c| c.pdf_after)
        .chain(record.steps.iter().map(|s| s.lanes[s.lane].probability))
        .chain(std::iter::once(record.picked().probability))
        .fold(1.0, |p, f| p * f);
    assert_eq!(product.to_bits(), record.pdf.to_bits(), "{preset}");
    let stages = pick_stages(&record);
    assert!(shows_containing(&harness, &format!("stage 1 of {stages}")));
    // The first stage is the tile's cut: the groups and single lights fixed for the whole
    // tile, counted, and the one the draw takes, named as the panels name it.
    let cut = record.cut.as_ref().expect("the pixel's tile has a cut");
    let singles = cut.entries.iter().filter(|e| e.light.is_some()).count();
    let groups = cut.entries.len() - singles;
    let plural = |n: usize, word: &str| match n {
        1 => format!("1 {word}"),
        _ => format!("{n} {word}s"),
    };
    let held = match (groups, singles) {
        (_, 0) => plural(groups, "group"),
        (0, _) => plural(singles, "single light"),
        _ => format!(
            "{} and {}",
            plural(groups, "group"),
            plural(singles, "single light")
        ),
    };
    assert!(
        shows_containing(&harness, &format!("keeps a cut of the tree: {held} that")),
        "{preset}: {}",
        painted(&harness)
    );
    let taken = match cut.entries[cut.entry].light {
        Some(light) => format!("light {}", light + 1),
        None => format!("group {}", cut.entry + 1),
    };
    assert!(shows_containing(
        &harness,
        &format!("→ {taken}. P so far: {}", three_significant(cut.pdf_after))
    ));
    for stage in 1..stages {
        if stage % 2 == 1 {
            click(&mut harness, "Next");
        } else {
            harness.key_press(Key::PageDown);
            harness.run();
        }
        assert_eq!(harness.state().state.light_tree.stage, stage, "{preset}");
        assert!(shows_containing(
            &harness,
            &format!("stage {} of {stages}", stage + 1)
        ));
    }
    // The end: Next is disabled and the pdf is the renderer's.
    click(&mut harness, "Next");
    assert_eq!(harness.state().state.light_tree.stage, stages - 1);
    let text = painted(&harness);
    assert!(
        text.contains(&format!("= {}", three_significant(record.pdf))),
        "{preset}: {text}"
    );
    assert!(text.contains("the same, bit for bit"), "{preset}: {text}");
    assert!(
        text.contains(&format!(
            "Power picking would pick light {}",
            record.light + 1
        )),
        "{preset}"
    );
    click(&mut harness, "Back");
    harness.key_press(Key::PageUp);
    harness.run();
    assert_eq!(
        harness.state().state.light_tree.stage,
        stages - 3,
        "{preset}"
    );
}

#[test]
fn a_pick_steps_down_the_grids_tree_to_the_renderers_pdf() {
    steps_to_the_renderers_pdf("grid", [72, 194]);
}

#[test]
fn a_pick_steps_down_a_spot_tree_to_the_renderers_pdf() {
    // The stage: spots and ranged washes, whose groups are culled where they cannot reach.
    steps_to_the_renderers_pdf("stage", [60, 70]);
}

#[test]
fn culled_groups_say_why_and_take_no_probability() {
    let mut harness = tree_panel("stage", [60, 70]);
    // Below the tiles' cuts (which leave out what cannot reach a tile) a node's group is
    // culled where x alone is out of its lights' reach: at a pixel near a spot's edge.
    // The cuts take most of a tile's mass to single spots and leaf clusters: the pixels of
    // a coarse raster over the whole stage, until a pick goes through such a node.
    let pixels: Vec<[u32; 2]> = (0..640)
        .map(|k| [8 * (k % 32) + 3, 8 * (k / 32) + 5])
        .collect();
    let (pixel, number, stage, record) = find_pick(&mut harness, &pixels, |record| {
        record.steps.iter().position(|s| {
            s.lanes
                .iter()
                .any(|l| l.culled.is_some() && l.light_count() > 0)
        })
    })
    .expect("a culled group on the stage");
    show_stage(&mut harness, pixel, number, stage + 1);
    let step = &record.steps[stage];
    for lane in step.lanes.iter().filter(|l| l.culled.is_some()) {
        assert_eq!(lane.probability, 0.0);
        assert_eq!(lane.mass, 0);
    }
    assert!(
        shows_containing(&harness, "culled:"),
        "{}",
        painted(&harness)
    );
}

#[test]
fn the_guide_ends_on_this_scenes_variances() {
    let mut harness = tree_panel("grid", [72, 194]);
    harness.state_mut().state.light_tree.guide_step = 4;
    // The sentence's variances are computed inline in tests.
    for _ in 0..3 {
        harness.run();
    }
    let variances = harness
        .state()
        .state
        .current_scene_sentence()
        .map(|s| s.variances)
        .expect("the scene's variances");
    let text = painted(&harness);
    assert!(
        text.contains(&lightpick::numbers::short(variances[2])),
        "{text}"
    );
    assert!(text.contains("lower than power's"), "{text}");
}

#[test]
fn each_group_shows_where_power_picking_would_go() {
    // The grid's nodes split equal lights in four equal groups: a quarter each by power,
    // wherever the point; the spatial probabilities are not a quarter.
    let mut harness = tree_panel("grid", [72, 194]);
    let pixels: Vec<[u32; 2]> = (0..8).map(|k| [72 + 17 * k, 194 - 13 * k]).collect();
    let (pixel, number, stage, _) = find_pick(&mut harness, &pixels, |record| {
        record.steps.iter().position(|s| {
            s.lanes
                .iter()
                .all(|l| l.light_count() == s.lanes[0].light_count())
        })
    })
    .expect("a pick through a node of four equal groups");
    show_stage(&mut harness, pixel, number, stage + 1);
    let text = painted(&harness);
    assert_eq!(text.matches("by power: 0.250").count(), 4, "{text}");
    assert!(!text.contains("P = 0.250"), "{text}");
}

/// The first of the picks at `pixels` (each pixel's picks in turn, as New pick numbers them)
/// whose record `stage_of` finds a step in: the pixel, the pick's number, that step, and the
/// record.
fn find_pick(
    harness: &mut Harness<'static, LightpickApp>,
    pixels: &[[u32; 2]],
    stage_of: impl Fn(&TreePick) -> Option<usize>,
) -> Option<([u32; 2], u64, usize, TreePick)> {
    let state = &mut harness.state_mut().state;
    let built = std::sync::Arc::clone(&state.built);
    let seed = state.settings.seed;
    pixels.iter().find_map(|&pixel| {
        (0..100).find_map(|number| {
            state.light_tree.select_pixel(pixel);
            state.light_tree.number = number;
            let record = state.light_tree.pick(&built, seed)?.record.clone()?;
            Some((pixel, number, stage_of(&record)?, record))
        })
    })
}

/// Shows stage `stage` of pick `number` at `pixel` (stage 0 is the tile's cut).
fn show_stage(
    harness: &mut Harness<'static, LightpickApp>,
    pixel: [u32; 2],
    number: u64,
    stage: usize,
) {
    let state = &mut harness.state_mut().state;
    state.light_tree.select_pixel(pixel);
    state.light_tree.number = number;
    state.light_tree.stage = stage;
    harness.run();
}

#[test]
fn a_cut_that_takes_a_single_light_names_it_and_picks_it_alone() {
    // Far from its lights a tile of the grid takes some of them one by one: the cut stage
    // names the light the draw takes, and the leaf holds that light alone.
    let mut harness = tree_panel("grid", [10, 10]);
    let pixels: Vec<[u32; 2]> = (0..8).map(|k| [10 + 29 * k, 240 - 27 * k]).collect();
    let (pixel, number, _, record) = find_pick(&mut harness, &pixels, |record| {
        let cut = record.cut.as_ref()?;
        cut.entries[cut.entry].light.map(|_| 0)
    })
    .expect("a pick that takes a single light");
    let cut = record.cut.as_ref().expect("a cut");
    let light = cut.entries[cut.entry].light.expect("a single light");
    assert_eq!(record.light, light);
    assert_eq!(record.leaf.lights.len(), 1);
    assert!(record.steps.is_empty(), "no node below a single light");
    show_stage(&mut harness, pixel, number, 0);
    assert!(shows_containing(
        &harness,
        &format!(
            "→ light {}. P so far: {}. The pick is that light",
            light + 1,
            three_significant(cut.pdf_after)
        )
    ));
    show_stage(&mut harness, pixel, number, 1);
    assert!(shows_containing(&harness, "the one light the cut took"));
}
