//! The light tree's top view (`draw::tree_view`): its groups at each depth are the tree's
//! subtrees there, counted independently from the nodes; the drawing of a recorded pick on
//! a fixed scene matches its golden PNG (`tests/snapshots/`, with the workspace's snapshot
//! tolerance and `UPDATE_SNAPSHOTS=1` switch); wrong inputs are refused.

use glam::{DVec2, dvec2};
use lightpick_core::Rng;
use lightpick_core::draw::{self, DrawError, Style, TreeView};
use lightpick_core::lesson::tree_pick::TreePick;
use lightpick_core::scene::Scene;
use lightpick_core::spatial::{Child, ChildRef, LightTree, SpatialSampler};

use crate::common::scenes::scattered_random;
use crate::common::snapshot_support::assert_snapshot;

/// Subtrees and leaf clusters exactly `depth` decisions below `at` (at `at_depth`), plus
/// leaf clusters reached sooner: counted from the nodes' child words.
fn count_at_depth(tree: &LightTree, at: ChildRef, at_depth: usize, depth: usize) -> usize {
    match at.get() {
        Child::Empty => 0,
        Child::Leaf { .. } => usize::from(at_depth <= depth),
        Child::Node(k) if at_depth < depth => (0..4)
            .map(|lane| count_at_depth(tree, tree.nodes()[k].child(lane), at_depth + 1, depth))
            .sum(),
        Child::Node(_) => 1,
    }
}

#[test]
fn groups_at_a_depth_are_the_trees_subtrees_there() {
    let scene = scattered_random(1000, 41, 1.0, 2.0);
    let sampler = SpatialSampler::for_scene(&scene);
    let SpatialSampler::Tree(tree) = &sampler else {
        panic!("1000 lights make a tree");
    };
    let mut previous = 0;
    for depth in 0..=tree.depth() as usize + 1 {
        let groups = draw::tree_groups(&sampler, depth);
        assert_eq!(
            groups.len(),
            count_at_depth(tree, tree.root(), 0, depth),
            "depth {depth}"
        );
        assert!(groups.len() >= previous, "groups only split");
        previous = groups.len();
        // The groups partition the lights, in leaf order, and each box holds its lights.
        let mut next = 0;
        for g in &groups {
            assert_eq!(g.lights.start, next);
            next = g.lights.end;
            for l in &tree.lights()[g.lights.clone()] {
                let p = l.position_in_world.truncate();
                assert!(p.cmpge(g.box_on_plane[0]).all() && p.cmple(g.box_on_plane[1]).all());
            }
        }
        assert_eq!(next, tree.lights().len());
    }
    assert_eq!(draw::tree_groups(&sampler, 0).len(), 1);
    assert_eq!(draw::tree_groups(&sampler, 1).len(), 4);
    assert_eq!(draw::tree_groups(&sampler, 2).len(), 16);
    assert_eq!(
        draw::tree_view_caption(2, 16, 1000),
        "depth 2: 16 groups · 1000 lights"
    );
}

/// The snapshot scene: 300 random lights over a 2 × 1.5 rectangle, a pick at a fixed point.
fn snapshot_scene() -> (Scene, SpatialSampler, TreePick) {
    let scene = scattered_random(300, 21, 1.0, 1.5);
    let sampler = SpatialSampler::for_scene(&scene);
    let pick = TreePick::record(&sampler, dvec2(0.3, -0.2), &mut Rng::new(7, 0))
        .expect("lights shine there");
    (scene, sampler, pick)
}

#[test]
fn tree_view_with_a_pick_matches_its_golden() {
    let (scene, sampler, pick) = snapshot_scene();
    assert!(pick.cut.is_some(), "a pick from its tile's cut");
    let view = TreeView {
        scene: &scene,
        sampler: &sampler,
        depth: 2,
        pick: Some(&pick),
        probabilities: None,
        region: None,
    };
    let pixmap = draw::tree_view(&view, &Style::default()).expect("draws");
    assert_snapshot("tree_view_pick", 800, 500, &draw::to_rgba8(&pixmap));
}

#[test]
fn tree_view_coloured_by_the_spatial_pdf_matches_its_golden() {
    let (scene, sampler, _) = snapshot_scene();
    let x = DVec2::new(-0.5, 0.4);
    let pdfs = sampler.pdfs(x);
    let view = TreeView {
        scene: &scene,
        sampler: &sampler,
        depth: 1,
        pick: None,
        probabilities: Some(&pdfs),
        region: Some([dvec2(-2.0, -2.0), dvec2(2.0, 2.0)]),
    };
    let pixmap = draw::tree_view(&view, &Style::default()).expect("draws");
    assert_snapshot("tree_view_spatial_pdf", 800, 500, &draw::to_rgba8(&pixmap));
}

#[test]
fn tree_view_refuses_wrong_inputs_and_draws_many_lights() {
    let (scene, sampler, _) = snapshot_scene();
    let short = vec![0.5; 3];
    let view = TreeView {
        scene: &scene,
        sampler: &sampler,
        depth: 1,
        pick: None,
        probabilities: Some(&short),
        region: None,
    };
    assert!(matches!(
        draw::tree_view(&view, &Style::default()),
        Err(DrawError::Length {
            expected: 300,
            got: 3,
            ..
        })
    ));
    // 200 000 lights: mostly sub-pixel dots, drawn without a path each.
    let big = scattered_random(200_000, 5, 1.0, 1.0);
    let sampler = SpatialSampler::for_scene(&big);
    let view = TreeView {
        scene: &big,
        sampler: &sampler,
        depth: 3,
        pick: None,
        probabilities: None,
        region: None,
    };
    let small = Style {
        width: 200,
        height: 150,
        ..Style::default()
    };
    let pixmap = draw::tree_view(&view, &small).expect("draws");
    assert_eq!((pixmap.width(), pixmap.height()), (200, 150));
    // The exact pick (few lights) is one group.
    let few = scattered_random(10, 6, 1.0, 1.0);
    let exact = SpatialSampler::for_scene(&few);
    assert_eq!(draw::tree_groups(&exact, 3).len(), 1);
}
