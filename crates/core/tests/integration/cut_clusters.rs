//! Which lights a tile's cut takes out of their leaf clusters, and which it leaves out of a
//! cluster it keeps whole: a spot enters alone only where it lights its whole tile, or as
//! the core of a cluster whose other lights lighting the tile did (lit at a weighing point
//! at least), and a cluster kept whole is narrowed only past lights that give the tile
//! nothing (checked by brute force over rasters of the tiles).

use glam::dvec2;
use lightpick_core::spatial::{Child, ChildRef, LightTree};

use crate::common::cuts::cut_tree;
use crate::common::scenes::preset_at;
use crate::tile_cuts::spots_scene;

/// Every leaf cluster of `tree`, as its nodes' lanes hold it (the root too when it is one).
fn leaf_clusters(tree: &LightTree) -> std::collections::HashSet<ChildRef> {
    let lanes = tree.nodes().iter().flat_map(|n| (0..4).map(|l| n.child(l)));
    std::iter::once(tree.root())
        .chain(lanes)
        .filter(|c| matches!(c.get(), Child::Leaf { .. }))
        .collect()
}

/// The single lights that `tree`'s cuts took out of their leaf clusters, with their tiles
/// and their clusters' ranges: each one sits one level below its cluster.
fn single_lights(tree: &LightTree) -> Vec<(usize, usize, std::ops::Range<usize>)> {
    let (cuts, clusters) = (tree.tile_cuts().expect("cuts"), leaf_clusters(tree));
    let [tx, ty] = cuts.tiles();
    let mut singles = Vec::new();
    for tile in 0..(tx * ty) as usize {
        for (entry, _) in cuts.entries(tree, tile) {
            if let Child::Leaf { first, count: 1 } = entry.get()
                && !clusters.contains(&entry)
            {
                let cluster = clusters
                    .iter()
                    .find(|c| tree.span(**c).is_some_and(|s| s.contains(&first)))
                    .expect("a cluster holds the light");
                assert_eq!(tree.depth_of(entry), tree.depth_of(*cluster).map(|d| d + 1));
                singles.push((
                    tile,
                    first,
                    tree.span(*cluster).expect("a cluster's lights"),
                ));
            }
        }
    }
    singles
}

#[test]
fn cuts_take_single_spots_only_where_each_is_lit_across_its_tile() {
    // Point lights: a tile far from its lights takes them one by one (a pick then
    // evaluates only the light it takes).
    let scene = preset_at("equal", 64, 64);
    let tree = cut_tree(&scene);
    let [tx, ty] = tree.tile_cuts().expect("cuts").tiles();
    let singles = single_lights(&tree).len();
    assert!(
        singles > (tx * ty) as usize,
        "equal: {singles} single lights over {} tiles",
        tx * ty
    );
    // Spots: a light enters a cut alone only where it lights each centre of the tile's
    // 3 × 3 ninths with at least a tenth of the most it gives any of them. A cone's lit
    // region on the plane and a range's disc are convex, so such a spot lights the whole
    // square those nine points span: checked by brute force over a raster of it, and the
    // nine points' rule over the tile's own pixel frame. (Or it is a cluster kept whole
    // and narrowed to the one light that can light the tile: every other light of the
    // cluster gives the tile's raster nothing. Or it is the core of its cluster: lit at
    // one of the nine points at least, beside lights of its cluster that entered alone
    // by the rule above, which the loop checks as it meets them.)
    let scene = spots_scene(400, 2);
    let tree = cut_tree(&scene);
    let cuts = tree.tile_cuts().expect("cuts");
    let singles = single_lights(&tree);
    assert!(singles.len() > 50, "{} single spots", singles.len());
    let single_at: std::collections::HashSet<(usize, usize)> = singles
        .iter()
        .map(|(tile, first, _)| (*tile, *first))
        .collect();
    let (mut alone, mut cores) = (0, 0);
    for (tile, first, cluster) in singles {
        let light = tree.order()[first] as usize;
        let [[x0, y0], [x1, y1]] = cuts.tile_pixels(tile);
        let term_at = |j: usize, fx: f64, fy: f64| {
            let pixel = dvec2(
                f64::from(x0) + fx * f64::from(x1 - x0),
                f64::from(y0) + fy * f64::from(y1 - y0),
            );
            scene.light_term(tree.order()[j] as usize, scene.plane.point_at(pixel))
        };
        let at = |fx: f64, fy: f64| term_at(first, fx, fy);
        let others_dark = cluster.clone().filter(|&j| j != first).all(|j| {
            (0..=16).all(|a| {
                (0..=16).all(|b| term_at(j, f64::from(a) / 16.0, f64::from(b) / 16.0) == 0.0)
            })
        });
        if others_dark {
            continue;
        }
        alone += 1;
        let ninths: Vec<f64> = (0..9)
            .map(|k| {
                at(
                    (f64::from(k % 3) + 0.5) / 3.0,
                    (f64::from(k / 3) + 0.5) / 3.0,
                )
            })
            .collect();
        let most = ninths.iter().fold(0.0f64, |m, &g| m.max(g));
        if !ninths.iter().all(|&g| g >= 0.1 * most) {
            // A core: lit at a weighing point, and some other light of its cluster entered
            // this tile's cut alone.
            assert!(
                most > 0.0,
                "tile {tile}: the core spot {light} is dark at all its ninths"
            );
            assert!(
                cluster
                    .clone()
                    .any(|j| j != first && single_at.contains(&(tile, j))),
                "tile {tile}: spot {light} taken alone without a peeled light beside it, \
                 its ninths {ninths:?}"
            );
            cores += 1;
            continue;
        }
        assert!(
            most > 0.0,
            "tile {tile}: spot {light} taken alone is dark at its ninths"
        );
        for a in 0..=8 {
            for b in 0..=8 {
                let (fx, fy) = (
                    (1.0 + 4.0 * f64::from(a) / 8.0) / 6.0,
                    (1.0 + 4.0 * f64::from(b) / 8.0) / 6.0,
                );
                assert!(
                    at(fx, fy) > 0.0,
                    "tile {tile}: spot {light} taken alone is dark at ({fx}, {fy}) of it"
                );
            }
        }
    }
    assert!(alone > 50, "{alone} spots taken out of their clusters");
    assert!(cores > 0, "no cluster's core of one spot");
}

/// Every light of the tree that no entry of a tile's cut holds (a cluster kept whole is
/// narrowed to its lights from the first that can light the tile to the last) gives every
/// point of a 17 × 17 raster over the tile, edges and corners included, nothing; and the
/// cuts of spots do narrow clusters.
#[test]
fn a_cluster_kept_whole_leaves_out_only_lights_dark_on_its_tile() {
    for scene in [spots_scene(400, 2), preset_at("stage", 96, 64)] {
        let tree = cut_tree(&scene);
        let cuts = tree.tile_cuts().expect("cuts");
        let clusters = leaf_clusters(&tree);
        let [tx, ty] = cuts.tiles();
        let mut narrowed = 0;
        for tile in 0..(tx * ty) as usize {
            let entries: Vec<_> = cuts.entries(&tree, tile).map(|(e, _)| e).collect();
            let held = |j: usize| {
                entries
                    .iter()
                    .any(|&e| tree.span(e).is_some_and(|s| s.contains(&j)))
            };
            narrowed += entries
                .iter()
                .filter(|e| {
                    matches!(e.get(), Child::Leaf { count, .. } if count > 1)
                        && !clusters.contains(e)
                })
                .count();
            let [[x0, y0], [x1, y1]] = cuts.tile_pixels(tile);
            for j in (0..tree.order().len()).filter(|&j| !held(j)) {
                for a in 0..=16 {
                    for b in 0..=16 {
                        let pixel = dvec2(
                            f64::from(x0) + f64::from(a) / 16.0 * f64::from(x1 - x0),
                            f64::from(y0) + f64::from(b) / 16.0 * f64::from(y1 - y0),
                        );
                        let x = scene.plane.point_at(pixel);
                        assert_eq!(
                            scene.light_term(tree.order()[j] as usize, x),
                            0.0,
                            "{}: tile {tile} leaves out light {j}, lit at {x}",
                            scene.name
                        );
                    }
                }
            }
        }
        assert!(
            narrowed > 20,
            "{}: {narrowed} clusters narrowed",
            scene.name
        );
    }
}
