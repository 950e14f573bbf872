//! The light tree's per-tile cuts: each tile's entries partition the tree's lights that can
//! light the tile, their masses sum to `2^24`; the pdf of a pick through a cut equals a
//! reference recomputed from the entries and the tree's own branch masses, is positive
//! wherever a light contributes (at pixel centres, corners and tile edges, for points,
//! spots and ranges), and picks follow it.

use glam::{DVec2, dvec2, dvec3};
use lightpick_core::Rng;
use lightpick_core::scene::{Emission, ReceiverPlane, Scene, pixel_center};
use lightpick_core::spatial::importance::{GRID, GRID_CELL};
use lightpick_core::spatial::{Child, ChildRef, LightTree};

use crate::common::SplitMix;
use crate::common::cuts::{cut_and_root_variances, cut_tree};
use crate::common::fit::assert_picks_fit;
use crate::common::scenes::{
    preset_at, random_powers, scattered_positions, square_plane, tilted_spot,
};

/// Point lights over `[-1, 1]²` (a fifth of power 0, some below the plane) on a 40 × 24
/// pixel plane.
fn points_scene(n: usize, seed: u64) -> Scene {
    let mut d = SplitMix(seed);
    let positions = scattered_positions(&mut d, n, 1.0, 0.05..0.8, (7, 6));
    let powers = random_powers(&mut d, n, 3.0, 4);
    let plane = ReceiverPlane {
        min: dvec2(-1.0, -0.6),
        max: dvec2(1.0, 0.6),
        width: 40,
        height: 24,
    };
    Scene::from_parts("points", plane, positions, powers).expect("valid")
}

/// Narrow and wide spots, some ranged, over `[-2, 2]²` on a 30 × 30 pixel plane.
pub(crate) fn spots_scene(n: usize, seed: u64) -> Scene {
    let mut d = SplitMix(seed);
    let (mut positions, mut powers, mut emission) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        positions.push(dvec3(
            d.range(-2.0, 2.0),
            d.range(-2.0, 2.0),
            d.range(0.2, 1.5),
        ));
        powers.push(10f64.powf(d.range(-2.0, 2.0)));
        let spot = (i % 4 != 0).then(|| {
            let (outer, tilt) = (d.range(0.05, 1.0), d.range(0.0, 0.9));
            tilted_spot(&mut d, outer, tilt, 0.0..0.9)
        });
        let range = (i % 3 == 1).then(|| d.range(0.4, 3.0));
        emission.push(Emission::new(spot, range).expect("valid"));
    }
    Scene::from_parts("spots", square_plane(2.0, 30), positions, powers)
        .expect("valid")
        .with_emission(emission)
}

/// Points of the plane where a cut could go wrong: every pixel centre and corner (tile
/// edges among them), and points just inside the plane's edges.
fn probe_points(plane: &ReceiverPlane) -> Vec<DVec2> {
    let mut points = Vec::new();
    for py in 0..=plane.height {
        for px in 0..=plane.width {
            let corner = plane.point_at(dvec2(f64::from(px), f64::from(py)));
            points.push(corner.clamp(plane.min, plane.max));
            if px < plane.width && py < plane.height {
                points.push(pixel_center(plane, px, py));
            }
        }
    }
    points.push(plane.min);
    points.push(plane.max);
    points
}

/// `P(i | x)` recomputed from the tile's entries: the entry whose leaf-order range holds
/// the light, its mass, then the tree's branch masses below it (one product, as a pick
/// realizes it).
fn reference_pdf(tree: &LightTree, x: DVec2, j: usize) -> f64 {
    let cuts = tree.tile_cuts().expect("cuts");
    let Some(tile) = cuts.tile_at(x) else {
        return tree
            .clone()
            .with_cuts(None)
            .pdf(x, tree.order()[j] as usize);
    };
    let Some((entry, mass)) = cuts
        .entries(tree, tile)
        .find(|&(e, _)| tree.span(e).is_some_and(|s| s.contains(&j)))
    else {
        return 0.0;
    };
    let mut pdf = f64::from(mass) * GRID_CELL;
    let mut at: ChildRef = entry;
    loop {
        match at.get() {
            Child::Node(k) => {
                let masses = tree.node_masses_at(k, x);
                let node = &tree.nodes()[k];
                let lane = (0..4)
                    .find(|&l| tree.span(node.child(l)).is_some_and(|s| s.contains(&j)))
                    .expect("a lane holds the light");
                pdf *= f64::from(masses[lane]) * GRID_CELL;
                at = node.child(lane);
            }
            Child::Leaf { first, count } => {
                let (masses, _) = tree.leaf_masses_at(first, count, x);
                return pdf * (f64::from(masses[j - first]) * GRID_CELL);
            }
            Child::Empty => return 0.0,
        }
    }
}

#[test]
fn each_tile_partitions_the_lights_that_can_light_it_with_masses_summing_to_the_grid() {
    for scene in [points_scene(500, 1), spots_scene(400, 2)] {
        let tree = cut_tree(&scene);
        let cuts = tree.tile_cuts().expect("cuts");
        let [tx, ty] = cuts.tiles();
        for tile in 0..(tx * ty) as usize {
            let entries: Vec<_> = cuts.entries(&tree, tile).collect();
            assert!(entries.len() <= cuts.max_entries());
            let total: u64 = entries.iter().map(|&(_, m)| u64::from(m)).sum();
            assert!(
                total == u64::from(GRID) || total == 0,
                "tile {tile}: Σ m = {total}"
            );
            // Disjoint leaf-order ranges, in order.
            let mut end = 0;
            for &(e, _) in &entries {
                let span = tree.span(e).expect("no empty entry");
                assert!(span.start >= end, "tile {tile}: entries overlap");
                end = span.end;
            }
        }
    }
}

#[test]
fn the_pdf_through_a_cut_equals_the_reference_and_is_positive_wherever_a_light_contributes() {
    for scene in [points_scene(300, 3), spots_scene(300, 4)] {
        let tree = cut_tree(&scene);
        let pmf = scene.powers.pmf();
        let mut away = 0;
        for x in probe_points(&scene.plane) {
            let pdfs = tree.pdfs(x);
            let total: f64 = pdfs.iter().sum();
            assert!(
                total <= 1.0 + 16.0 * f64::from(tree.draws()) * f64::EPSILON,
                "Σ pdf = {total} at {x}"
            );
            for (j, &i) in tree.order().iter().enumerate() {
                let i = i as usize;
                assert_eq!(pdfs[i], reference_pdf(&tree, x, j), "light {i} at {x}");
                let c = pmf[i] * scene.light_term(i, x);
                assert!(
                    pdfs[i] > 0.0 || c == 0.0,
                    "light {i} gives {c} at {x} but has pdf 0"
                );
                away += usize::from(c == 0.0 && pdfs[i] == 0.0);
            }
        }
        // The spots' tiles leave out lanes that cannot reach them.
        if scene.emission.is_some() {
            assert!(away > 0, "some light culled somewhere");
        }
    }
}

#[test]
fn picks_through_a_cut_follow_their_pdf() {
    for scene in [points_scene(200, 5), spots_scene(200, 6)] {
        let tree = cut_tree(&scene);
        for x in [
            pixel_center(&scene.plane, 3, 4),
            pixel_center(&scene.plane, 17, 11),
        ] {
            let pdfs = tree.pdfs(x);
            let draws = 200_000u64;
            let mut counts = vec![0u64; scene.light_count()];
            let mut none = 0u64;
            for s in 0..draws {
                match tree.sample(x, &mut Rng::new(11, s)) {
                    Some(pick) => {
                        assert_eq!(pick.pdf, pdfs[pick.light as usize]);
                        counts[pick.light as usize] += 1;
                    }
                    None => none += 1,
                }
            }
            let picked = draws - none;
            let total: f64 = pdfs.iter().sum();
            assert_picks_fit(&counts, picked, |i| pdfs[i] / total);
        }
    }
}

#[test]
fn presets_are_cut_with_fewer_draws_than_the_tree_needs_from_its_root() {
    // The cut decides the top of the descent once per tile: on average over the plane a
    // pick takes fewer node steps than from the root (the reason the cuts exist).
    for name in ["heavy-tail", "grid", "stage"] {
        let scene = preset_at(name, 64, 64);
        let tree = cut_tree(&scene);
        let cuts = tree.tile_cuts().expect("cuts");
        let [tx, ty] = cuts.tiles();
        let mut deeper = 0usize;
        for tile in 0..(tx * ty) as usize {
            deeper += usize::from(cuts.entries(&tree, tile).any(|(e, _)| e != tree.root()));
        }
        assert!(
            deeper * 2 > (tx * ty) as usize,
            "{name}: {deeper} of {} tiles start below the root",
            tx * ty
        );
    }
}

#[test]
fn the_alias_columns_give_each_entry_exactly_its_mass_over_every_draw() {
    // Every 24-bit draw counted (brute force): each entry is taken for exactly `m_e` of the
    // `2^24` draws, on cuts of a power-of-two count and of counts with empty columns.
    for scene in [
        preset_at("equal", 64, 64),
        points_scene(500, 1),
        spots_scene(400, 2),
    ] {
        let tree = cut_tree(&scene);
        let cuts = tree.tile_cuts().expect("cuts");
        let [tx, ty] = cuts.tiles();
        let sizes: Vec<usize> = (0..(tx * ty) as usize)
            .map(|tile| cuts.entries(&tree, tile).count())
            .collect();
        let largest = (0..sizes.len()).max_by_key(|&t| sizes[t]).expect("tiles");
        let uneven = (0..sizes.len()).find(|&t| sizes[t] > 2 && !sizes[t].is_power_of_two());
        for tile in std::iter::once(largest).chain(uneven) {
            let entries: Vec<(ChildRef, u32)> = cuts.entries(&tree, tile).collect();
            let index: std::collections::HashMap<ChildRef, usize> = entries
                .iter()
                .enumerate()
                .map(|(k, &(e, _))| (e, k))
                .collect();
            let mut counts = vec![0u32; entries.len()];
            for u in 0..GRID {
                let (entry, mass) = cuts.pick(&tree, tile, u).expect("power");
                let k = index[&entry];
                assert_eq!(mass, entries[k].1);
                counts[k] += 1;
            }
            let masses: Vec<u32> = entries.iter().map(|&(_, m)| m).collect();
            assert_eq!(counts, masses, "tile {tile} of {} entries", entries.len());
        }
    }
}

/// Where a cut reaches single lights, each is weighed by its shares of the irradiance at
/// the tile's nine weighing points, `s_i(x_k) = c_i(x_k)/Σ_j c_j(x_k)`, and by its
/// probabilities under the tree from its root there, `t_i(x_k) = P_tree(i | x_k)`: with
/// `q̃(v) = √(max_k v(x_k) · rms_k v(x_k))` and `β` the tree's share,
/// `w_i = (1 − ε)·((1 − β)·q̃(s_i)/Σ q̃(s) + β·q̃(t_i)/Σ q̃(t)) + ε·p_i/Σ p`, on the `2^24`
/// grid (each mass `⌊w_i·2^24⌋` or 1, the remainder to the largest). Recomputed here from
/// the scene and the uncut tree's pdf, the weighing points from the tile's pixels (the
/// centres of its ninths), on `equal`, whose every tile is cut into its 64 lights: the cuts
/// as built (`β =` [`lightpick_core::spatial::CUT_TREE_SHARE`]) and with `β = ¼`.
#[test]
fn a_cut_of_single_lights_weighs_each_by_its_shares_at_the_weighing_points() {
    use lightpick_core::spatial::{CUT_TREE_SHARE, TileCuts};
    let scene = preset_at("equal", 128, 128);
    let built = cut_tree(&scene);
    // The cuts as built, and with a quarter of the weights by the tree's probabilities.
    let quarter = TileCuts::build(&built, &scene.plane)
        .expect("cuts")
        .with_tree_share(0.25);
    for (tree, share) in [
        (built.clone(), CUT_TREE_SHARE),
        (built.clone().with_cuts(Some(quarter)), 0.25),
    ] {
        weighs_each_by_its_shares(&scene, &tree, share);
    }
}

/// [`a_cut_of_single_lights_weighs_each_by_its_shares_at_the_weighing_points`] on `tree`,
/// whose cuts give the tree's probabilities the share `share` of the weights.
fn weighs_each_by_its_shares(scene: &Scene, tree: &LightTree, share: f64) {
    use lightpick_core::spatial::importance::POWER_SHARE;
    let cuts = tree.tile_cuts().expect("cuts");
    let pmf = scene.powers.pmf();
    let [tiles_x, tiles_y] = cuts.tiles();
    let tiles = (tiles_x * tiles_y) as usize;
    for tile in [0, 1, tiles_x as usize + 5, tiles / 2 + 17, tiles - 1] {
        let entries: Vec<(ChildRef, u32)> = cuts.entries(tree, tile).collect();
        let lights: Vec<usize> = entries
            .iter()
            .map(|&(e, _)| match e.get() {
                Child::Leaf { first, count: 1 } => tree.order()[first] as usize,
                other => panic!("tile {tile}: an entry {other:?} that is not one light"),
            })
            .collect();
        assert_eq!(
            lights.len(),
            scene.light_count(),
            "tile {tile}: every light"
        );
        let [first, end] = cuts
            .tile_pixels(tile)
            .map(|[px, py]| dvec2(f64::from(px), f64::from(py)));
        let points: Vec<DVec2> = (0..9)
            .map(|k| {
                let f = dvec2(f64::from(k % 3) + 0.5, f64::from(k / 3) + 0.5) / 3.0;
                scene.plane.point_at(first + f * (end - first))
            })
            .collect();
        let uncut = tree.clone().with_cuts(None);
        let normalized = |of: &dyn Fn(usize, DVec2) -> f64| -> Vec<Vec<f64>> {
            points
                .iter()
                .map(|&x| {
                    let v: Vec<f64> = lights.iter().map(|&i| of(i, x)).collect();
                    let total: f64 = v.iter().sum();
                    v.iter().map(|v| v / total).collect()
                })
                .collect()
        };
        let q_of = |shares: &[Vec<f64>]| -> Vec<f64> {
            (0..lights.len())
                .map(|e| {
                    let s: Vec<f64> = shares.iter().map(|at| at[e]).collect();
                    let largest = s.iter().fold(0.0f64, |m, &v| m.max(v));
                    let rms = (s.iter().map(|v| v * v).sum::<f64>() / 9.0).sqrt();
                    (largest * rms).sqrt()
                })
                .collect()
        };
        let q = q_of(&normalized(&|i, x| pmf[i] * scene.light_term(i, x)));
        let t = q_of(&normalized(&|i, x| uncut.pdf(x, i)));
        let (q_sum, t_sum) = (q.iter().sum::<f64>(), t.iter().sum::<f64>());
        let p_sum: f64 = lights.iter().map(|&i| pmf[i]).sum();
        let largest = entries.iter().map(|&(_, m)| m).max().expect("entries");
        for (e, &(_, mass)) in entries.iter().enumerate() {
            let blended = (1.0 - share) * q[e] / q_sum + share * t[e] / t_sum;
            let w = (1.0 - POWER_SHARE) * blended + POWER_SHARE * pmf[lights[e]] / p_sum;
            let cells = w * f64::from(GRID);
            // Flooring costs under a cell; the largest takes the remainder (under a cell
            // per entry).
            let slack = if mass == largest {
                1.0 + entries.len() as f64
            } else {
                1.0
            };
            assert!(
                (f64::from(mass) - cells).abs() <= slack,
                "tile {tile}, light {}: mass {mass} against {cells:.2} cells",
                lights[e]
            );
        }
    }
}

/// A `grid × grid` raster of pixel centres of `plane`.
fn pixel_raster(plane: &ReceiverPlane, grid: u32) -> Vec<DVec2> {
    (0..grid * grid)
        .map(|k| {
            let (i, j) = (k % grid, k / grid);
            pixel_center(
                plane,
                i * plane.width / grid + 1,
                j * plane.height / grid + 2,
            )
        })
        .collect()
}

/// Weighing a cut's entries by their estimates replaces the tree's top levels, whose
/// errors compound level by level: on point lights the cut's exact variance is well below
/// the tree's from its root (measured 0.07× on `equal`, 0.16× on `heavy-tail`; with a
/// quarter of the weights by the tree's probabilities, 0.14× and 0.21×).
#[test]
fn cuts_weighed_by_estimates_have_well_below_the_trees_variance_on_point_lights() {
    for name in ["equal", "heavy-tail"] {
        let scene = preset_at(name, 128, 128);
        let points = pixel_raster(&scene.plane, 12);
        let (cut, whole) = cut_and_root_variances(&scene, &points);
        assert!(
            cut < 0.3 * whole,
            "{name}: {cut:e} against the tree's {whole:e}"
        );
    }
}

/// Tiles are square in pixels and about `64²` whatever the receiver's aspect: the side
/// chosen is the integer whose tile count `w·h/s²` lies nearest `64²` on a log scale, checked
/// against every side from 1 up (a scan written apart from the rule's floor/ceil choice), on
/// square, wide, tall, one-pixel-thin and huge receivers; and a receiver's cuts use it.
#[test]
fn tiles_number_about_64_squared_whatever_the_aspect() {
    use lightpick_core::spatial::{CUT_TILES_PER_SIDE, tile_side_for};
    let target = f64::from(CUT_TILES_PER_SIDE).powi(2);
    // How far a side's tile count lies from the target, as a log ratio.
    let off = |w: u32, h: u32, s: u32| {
        (f64::from(w) * f64::from(h) / f64::from(s).powi(2) / target)
            .ln()
            .abs()
    };
    let sizes = [
        (1, 1),
        (64, 64),
        (128, 128),
        (256, 256),
        (512, 512),
        (256, 160),
        (160, 256),
        (1024, 768),
        (1000, 1),
        (1, 100_000),
        (95, 95),
        (97, 101),
        (4095, 4097),
        (65_535, 65_535),
        (u32::MAX, 3),
    ];
    for (w, h) in sizes {
        let side = tile_side_for(w, h, CUT_TILES_PER_SIDE);
        assert!(side >= 1);
        if f64::from(w) * f64::from(h) <= target {
            assert_eq!(side, 1, "{w} × {h}: fewer pixels than tiles");
            continue;
        }
        // The best side by scanning: the count falls as the side grows, so stop past it.
        let best = (1..=u32::MAX)
            .take_while(|&s| f64::from(s).powi(2) <= 4.0 * f64::from(w) * f64::from(h) / target)
            .min_by(|&a, &b| off(w, h, a).total_cmp(&off(w, h, b)))
            .expect("a side");
        assert!(
            (off(w, h, side) - off(w, h, best)).abs() <= 1e-12,
            "{w} × {h}: side {side} against {best}"
        );
        // So the count lies within a factor 2 of 64² (before the edges' partial tiles).
        assert!(
            off(w, h, side) <= std::f64::consts::LN_2 + 1e-12,
            "{w} × {h}"
        );
    }
    // Square receivers of 64·k pixels a side keep tiles of k pixels: 64 × 64 tiles.
    for k in [1, 2, 4, 8] {
        assert_eq!(tile_side_for(64 * k, 64 * k, CUT_TILES_PER_SIDE), k);
    }
    // A 256 × 160 receiver: 3-pixel tiles, 86 × 54 of them (not 64 along its longer side).
    let mut scene = points_scene(200, 5);
    scene.plane.width = 256;
    scene.plane.height = 160;
    let tree = cut_tree(&scene);
    let cuts = tree.tile_cuts().expect("cuts");
    assert_eq!(cuts.tile_side(), 3);
    assert_eq!(cuts.tiles(), [86, 54]);
}

/// A pick finds its tile without a division ([`TileCuts::tile_at`] from scales computed
/// once); at every pixel centre that is the pixel's own tile, `(px / s, py / s)` in
/// integers (what the GPU takes from the pixel's index), on receivers whose sides are not
/// multiples of the tile side, off-centre rectangles, thin, wide and tall ones.
///
/// [`TileCuts::tile_at`]: lightpick_core::spatial::TileCuts::tile_at
#[test]
fn every_pixel_centre_falls_in_its_pixels_tile() {
    let planes = [
        (dvec2(-1.0, -0.6), dvec2(1.0, 0.6), 40, 24),
        (dvec2(-3.7, 0.1), dvec2(12.3, 0.35), 1001, 7),
        (dvec2(1e6, -1e-3), dvec2(1e6 + 3.0, 1e-3), 97, 131),
        (dvec2(-0.3, -0.3), dvec2(0.3, 0.3), 256, 160),
        (dvec2(0.0, 0.0), dvec2(1.0, 1.0), 4099, 3),
    ];
    for (min, max, width, height) in planes {
        let mut scene = points_scene(300, 11);
        scene.plane = ReceiverPlane {
            min,
            max,
            width,
            height,
        };
        let tree = cut_tree(&scene);
        let cuts = tree.tile_cuts().expect("cuts");
        let side = cuts.tile_side();
        for py in 0..height {
            for px in 0..width {
                let x = pixel_center(&scene.plane, px, py);
                assert_eq!(
                    cuts.tile_at(x),
                    Some(cuts.tile_of_pixel(px, py)),
                    "{width} × {height} over {min}–{max}, tiles of {side}: pixel ({px}, {py})"
                );
            }
        }
        // The rectangle's corners fall in the corner tiles, and a point off it in none.
        let [tx, ty] = cuts.tiles();
        assert_eq!(cuts.tile_at(dvec2(min.x, max.y)), Some(0));
        assert_eq!(
            cuts.tile_at(dvec2(max.x, min.y)),
            Some((tx * ty - 1) as usize)
        );
        assert_eq!(cuts.tile_at(dvec2(max.x + (max.x - min.x), min.y)), None);
    }
}
