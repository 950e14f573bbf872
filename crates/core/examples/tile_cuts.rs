//! A measurement before a build: would a per-tile light cut make the spatial pick cheap
//! while keeping its variance? (Lightcuts / stochastic lightcuts cut the tree once per
//! region; the receiver here is one plane with a known pixel grid, so a region is a tile of
//! pixels.)
//!
//! The candidate: the image is split into tiles of `T × T` pixels. For each tile, the tree
//! is cut into at most `K` entries (subtrees or leaf clusters), refining from the root the
//! entry of largest importance at the tile (a representative light's `Φ·z/r³`, as the
//! descent weighs lanes); the tile keeps the entries' probabilities, the descent's mixture
//! `(1 − ε)·I/ΣI + ε·Φ/ΣΦ` on the same `2^24` grid. A pick at pixel `x` takes an entry by
//! the tile's probabilities (one table lookup, no evaluation), then descends from it at `x`
//! exactly as the tree does; its pdf is the entry's probability times the descent's below
//! it, so it stays exact and positive wherever a light contributes.
//!
//! Printed per scene: the exact variance of one sample (`Σ c_i²/q_i − E²`, mean over shading
//! points) of power picking, of today's tree and of each cut, as "× below power"; and the
//! time per pixel sample (pick and contribution, one thread, `ns`) of the alias table, of
//! today's tree and of each cut, picking the entry with an alias table over the tile's masses.
//!
//! ```text
//! cargo run --release -p lightpick-core --example tile_cuts -- heavy-tail grid equal million
//! ```
//!
//! Point-light scenes only: over spots the entries would be weighed by the lanes' maps.

use std::time::Instant;

use glam::{DVec2, DVec3};
use lightpick_core::scene::{Scene, pixel_center};
use lightpick_core::spatial::importance::{GRID, GRID_CELL, POWER_SHARE, pick_on_grid};
use lightpick_core::spatial::{Child, ChildRef, LightTree, SpatialSampler};
use lightpick_core::{AliasTable, LightPowers, Rng};

/// An entry of a cut: a subtree or leaf cluster with its representative light.
#[derive(Clone, Copy, Debug)]
struct Entry {
    at: ChildRef,
    centroid: DVec3,
    power: f64,
    /// A single light of a leaf cluster (its leaf-order index), picked with no evaluation.
    light: Option<usize>,
}

/// One tile's cut: entries, their masses on the `2^24` grid, and an alias table over them.
struct TileCut {
    entries: Vec<Entry>,
    masses: Vec<u32>,
    table: AliasTable,
}

/// `Φ·z/r³` of an entry seen from `x`.
fn importance(e: &Entry, x: DVec2) -> f64 {
    let d = e.centroid.truncate() - x;
    let r2 = d.length_squared() + e.centroid.z * e.centroid.z;
    e.power * e.centroid.z / (r2 * r2.sqrt())
}

/// The lanes of node `k` as entries.
fn lanes(tree: &LightTree, k: usize) -> impl Iterator<Item = Entry> + '_ {
    let node = &tree.nodes()[k];
    (0..4)
        .map(move |lane| Entry {
            at: node.child(lane),
            centroid: node.centroid(lane),
            power: node.power(lane),
            light: None,
        })
        .filter(|e| e.at.get() != Child::Empty)
}

/// The cut, its leaf clusters replaced by their lights (picked by their importance at the
/// tile, with no evaluation at `x` but the picked light's).
fn expand_leaves(tree: &LightTree, entries: Vec<Entry>) -> Vec<Entry> {
    let mut out = Vec::new();
    for e in entries {
        match e.at.get() {
            Child::Leaf { first, count } => {
                for j in first..first + count {
                    let l = tree.lights()[j];
                    if l.power > 0.0 {
                        out.push(Entry {
                            at: e.at,
                            centroid: l.position_in_world,
                            power: l.power,
                            light: Some(j),
                        });
                    }
                }
            }
            _ => out.push(e),
        }
    }
    out
}

/// The cut of at most `k_max` entries for a tile centred on `center`.
fn cut(tree: &LightTree, center: DVec2, k_max: usize) -> Vec<Entry> {
    let Child::Node(root) = tree.root().get() else {
        return Vec::new();
    };
    let mut entries: Vec<Entry> = lanes(tree, root).collect();
    loop {
        let best = entries
            .iter()
            .enumerate()
            .filter(|(_, e)| matches!(e.at.get(), Child::Node(_)))
            .max_by(|a, b| importance(a.1, center).total_cmp(&importance(b.1, center)));
        let Some((i, e)) = best.map(|(i, e)| (i, *e)) else {
            break;
        };
        let Child::Node(k) = e.at.get() else { break };
        let children: Vec<Entry> = lanes(tree, k).collect();
        if entries.len() - 1 + children.len() > k_max {
            break;
        }
        entries.swap_remove(i);
        entries.extend(children);
    }
    entries
}

/// The mixture's masses over the entries at `center` (the descent's rule, any width).
fn masses(entries: &[Entry], center: DVec2) -> Vec<u32> {
    let importance: Vec<f64> = entries.iter().map(|e| importance(e, center)).collect();
    let (ti, tp): (f64, f64) = (
        importance.iter().sum(),
        entries.iter().map(|e| e.power).sum(),
    );
    let p: Vec<f64> = entries
        .iter()
        .zip(&importance)
        .map(|(e, i)| (1.0 - POWER_SHARE) * i / ti + POWER_SHARE * e.power / tp)
        .collect();
    let mut m: Vec<u32> = p
        .iter()
        .map(|&p| {
            if p > 0.0 {
                ((p * f64::from(GRID)) as u32).max(1)
            } else {
                0
            }
        })
        .collect();
    let sum: i64 = m.iter().map(|&v| i64::from(v)).sum();
    let largest = (0..m.len()).max_by_key(|&i| m[i]).unwrap_or(0);
    m[largest] = (i64::from(m[largest]) + i64::from(GRID) - sum) as u32;
    m
}

/// The tile cuts of the scene's pixel grid, tiles of `side` pixels.
fn tile_cuts(
    scene: &Scene,
    tree: &LightTree,
    (side, k_max, expand): (u32, usize, bool),
) -> (Vec<TileCut>, u32) {
    let plane = &scene.plane;
    let tiles_x = plane.width.div_ceil(side);
    let tiles_y = plane.height.div_ceil(side);
    let cuts = (0..tiles_y)
        .flat_map(|ty| (0..tiles_x).map(move |tx| (tx, ty)))
        .map(|(tx, ty)| {
            let px = (tx * side + side / 2).min(plane.width - 1);
            let py = (ty * side + side / 2).min(plane.height - 1);
            let center = pixel_center(plane, px, py);
            let mut entries = cut(tree, center, k_max);
            if expand {
                entries = expand_leaves(tree, entries);
            }
            let masses = masses(&entries, center);
            let powers = LightPowers::new(masses.iter().map(|&m| f64::from(m)).collect())
                .expect("positive masses");
            TileCut {
                entries,
                masses,
                table: AliasTable::build(&powers),
            }
        })
        .collect();
    (cuts, tiles_x)
}

/// `q_i` of every light of the subtree `at` times `pdf`, at `x`, into `q` (scene order).
fn subtree_pdfs(tree: &LightTree, at: ChildRef, x: DVec2, pdf: f64, q: &mut [f64]) {
    match at.get() {
        Child::Node(k) => {
            let masses = tree.node_masses_at(k, x);
            for (lane, m) in masses.into_iter().enumerate() {
                if m > 0 {
                    let child = tree.nodes()[k].child(lane);
                    subtree_pdfs(tree, child, x, pdf * f64::from(m) * GRID_CELL, q);
                }
            }
        }
        Child::Leaf { first, count } => {
            let (m, _) = tree.leaf_masses_at(first, count, x);
            for j in 0..count {
                q[tree.order()[first + j] as usize] = pdf * f64::from(m[j]) * GRID_CELL;
            }
        }
        Child::Empty => {}
    }
}

/// One pick below `at` at `x`: the estimate `c_i / q_i` given the entry's probability.
fn descend(tree: &LightTree, mut at: ChildRef, x: DVec2, rng: &mut Rng, mut pdf: f64) -> f64 {
    while let Child::Node(k) = at.get() {
        let m = tree.node_masses_at(k, x);
        let lane = pick_on_grid(&m, rng.next_u32() >> 8);
        pdf *= f64::from(m[lane]) * GRID_CELL;
        at = tree.nodes()[k].child(lane);
    }
    let Child::Leaf { first, count } = at.get() else {
        return 0.0;
    };
    let (m, c) = tree.leaf_masses_at(first, count, x);
    let j = pick_on_grid(&m[..count], rng.next_u32() >> 8);
    let pdf = pdf * f64::from(m[j]) * GRID_CELL;
    if pdf > 0.0 { c[j] / pdf } else { 0.0 }
}

/// Each node's lanes' masses by power alone (a static descent, nothing evaluated at `x`).
fn power_masses(tree: &LightTree) -> Vec<[u32; 4]> {
    tree.nodes()
        .iter()
        .map(|node| {
            let p: [f64; 4] = std::array::from_fn(|l| node.power(l));
            let total: f64 = p.iter().sum();
            lightpick_core::spatial::importance::grid_masses(p.map(|v| v / total))
        })
        .collect()
}

/// A pick below `at` by power alone, the picked light's estimate given the entry's `pdf`.
fn descend_by_power(
    tree: &LightTree,
    static_masses: &[[u32; 4]],
    mut at: ChildRef,
    x: DVec2,
    rng: &mut Rng,
    mut pdf: f64,
) -> f64 {
    while let Child::Node(k) = at.get() {
        let m = &static_masses[k];
        let lane = pick_on_grid(m, rng.next_u32() >> 8);
        pdf *= f64::from(m[lane]) * GRID_CELL;
        at = tree.nodes()[k].child(lane);
    }
    let Child::Leaf { first, count } = at.get() else {
        return 0.0;
    };
    let lights = &tree.lights()[first..first + count];
    let total: f64 = lights.iter().map(|l| l.power).sum();
    let mut p = [0.0; 8];
    for (pj, l) in p.iter_mut().zip(lights) {
        *pj = l.power / total;
    }
    let m = lightpick_core::spatial::importance::grid_masses(p);
    let j = pick_on_grid(&m[..count], rng.next_u32() >> 8);
    let pdf = pdf * f64::from(m[j]) * GRID_CELL;
    if pdf > 0.0 {
        lights[j].contribution(x) / pdf
    } else {
        0.0
    }
}

/// `q_i` below `at` by power alone (as [`descend_by_power`] picks), times `pdf`.
fn subtree_power_pdfs(
    tree: &LightTree,
    static_masses: &[[u32; 4]],
    at: ChildRef,
    pdf: f64,
    q: &mut [f64],
) {
    match at.get() {
        Child::Node(k) => {
            for lane in 0..4 {
                let m = static_masses[k][lane];
                if m > 0 {
                    let child = tree.nodes()[k].child(lane);
                    subtree_power_pdfs(
                        tree,
                        static_masses,
                        child,
                        pdf * f64::from(m) * GRID_CELL,
                        q,
                    );
                }
            }
        }
        Child::Leaf { first, count } => {
            let lights = &tree.lights()[first..first + count];
            let total: f64 = lights.iter().map(|l| l.power).sum();
            let mut p = [0.0; 8];
            for (pj, l) in p.iter_mut().zip(lights) {
                *pj = l.power / total;
            }
            let m = lightpick_core::spatial::importance::grid_masses(p);
            for j in 0..count {
                q[tree.order()[first + j] as usize] = pdf * f64::from(m[j]) * GRID_CELL;
            }
        }
        Child::Empty => {}
    }
}

/// `Σ c²/q − E²` at `x` for the pmf `q`.
fn variance(c: &[f64], q: &[f64]) -> f64 {
    let e: f64 = c.iter().sum();
    let second: f64 = c
        .iter()
        .zip(q)
        .filter(|(_, q)| **q > 0.0)
        .map(|(c, q)| c * c / q)
        .sum();
    second - e * e
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let names: Vec<String> = std::env::args().skip(1).collect();
    // (tile side, cut size, leaves as lights, below the cut by power alone)
    let configs = [
        (4u32, 64usize, false, false),
        (8, 64, true, false),
        (4, 64, true, false),
        (8, 64, true, true),
        (4, 64, true, true),
        (4, 256, true, true),
        (2, 256, true, true),
    ];
    for name in &names {
        let mut scene = Scene::preset(name)?;
        scene.plane.width = 128;
        scene.plane.height = 128;
        let SpatialSampler::Tree(tree) = SpatialSampler::for_scene(&scene) else {
            println!("{name}: exact pick (few lights), nothing to cut");
            continue;
        };
        let n = scene.light_count();
        let pmf = scene.powers.pmf();
        let table = AliasTable::build(&scene.powers);
        let spatial = SpatialSampler::Tree(tree.clone());
        // Shading points: a G × G raster of pixel centres.
        let g: u32 = if n > 100_000 { 6 } else { 24 };
        let points: Vec<(u32, u32)> = (0..g)
            .flat_map(|j| (0..g).map(move |i| (i, j)))
            .map(|(i, j)| ((2 * i + 1) * 128 / (2 * g), (2 * j + 1) * 128 / (2 * g)))
            .collect();
        let cuts: Vec<_> = configs
            .iter()
            .map(|&(side, k, expand, by_power)| {
                (
                    side,
                    k,
                    (expand, by_power),
                    tile_cuts(&scene, &tree, (side, k, expand)),
                )
            })
            .collect();
        let static_masses = power_masses(&tree);
        let (mut v_power, mut v_tree) = (0.0, 0.0);
        let mut v_cut = vec![0.0; cuts.len()];
        for &(px, py) in &points {
            let x = pixel_center(&scene.plane, px, py);
            let c: Vec<f64> = (0..n).map(|i| pmf[i] * scene.light_term(i, x)).collect();
            v_power += variance(&c, &pmf);
            v_tree += variance(&c, &spatial.pdfs(x));
            for (v, (side, _, (_, by_power), (tiles, tiles_x))) in v_cut.iter_mut().zip(&cuts) {
                let tile = &tiles[((py / side) * tiles_x + px / side) as usize];
                let mut q = vec![0.0; n];
                for (e, &m) in tile.entries.iter().zip(&tile.masses) {
                    let p = f64::from(m) * GRID_CELL;
                    match e.light {
                        Some(j) => q[tree.order()[j] as usize] = p,
                        None if *by_power => {
                            subtree_power_pdfs(&tree, &static_masses, e.at, p, &mut q);
                        }
                        None => subtree_pdfs(&tree, e.at, x, p, &mut q),
                    }
                }
                *v += variance(&c, &q);
            }
        }
        // Time per pixel sample, one thread: 128 × 128 pixels, 8 samples each.
        let spp = 8u64;
        let time = |f: &mut dyn FnMut(DVec2, &mut Rng) -> f64| {
            let start = Instant::now();
            let mut sum = 0.0;
            for py in 0..128 {
                for px in 0..128 {
                    let x = pixel_center(&scene.plane, px, py);
                    for k in 0..spp {
                        let mut rng = Rng::new(7, (k << 32) | u64::from(py * 128 + px));
                        sum += f(x, &mut rng);
                    }
                }
            }
            std::hint::black_box(sum);
            start.elapsed().as_secs_f64() * 1e9 / (128.0 * 128.0 * spp as f64)
        };
        let t_alias = time(&mut |x, rng| {
            let i = table.sample(rng) as usize;
            scene.light_term(i, x) / table.pmf(i) * pmf[i]
        });
        let t_tree = time(&mut |x, rng| spatial.estimate(x, rng));
        println!(
            "{name} ({n} lights): power 1×, tree {:.0}× below power; T alias {t_alias:.1} ns, tree {t_tree:.1} ns ({:.1}×)",
            v_power / v_tree,
            t_tree / t_alias
        );
        for ((side, k, (expand, by_power), (tiles, tiles_x)), v) in cuts.iter().zip(&v_cut) {
            let t_cut = time(&mut |x, rng| {
                let (px, py) = (
                    ((x.x - scene.plane.min.x) / (scene.plane.max.x - scene.plane.min.x) * 128.0)
                        as u32,
                    ((scene.plane.max.y - x.y) / (scene.plane.max.y - scene.plane.min.y) * 128.0)
                        as u32,
                );
                let tile = &tiles[((py.min(127) / side) * tiles_x + px.min(127) / side) as usize];
                let e = tile.table.sample(rng) as usize;
                let p = f64::from(tile.masses[e]) * GRID_CELL;
                match tile.entries[e].light {
                    Some(j) => tree.lights()[j].contribution(x) / p,
                    None if *by_power => {
                        descend_by_power(&tree, &static_masses, tile.entries[e].at, x, rng, p)
                    }
                    None => descend(&tree, tile.entries[e].at, x, rng, p),
                }
            });
            println!(
                "  tiles {side}×{side} px, cut ≤ {k}{}: {:.0}× below power ({:.2}× the tree's variance); T {t_cut:.1} ns ({:.1}× alias)",
                match (*expand, *by_power) {
                    (true, true) => ", leaves as lights, below by power",
                    (true, false) => ", leaves as lights",
                    _ => "",
                },
                v_power / v,
                v / v_tree,
                t_cut / t_alias
            );
        }
    }
    Ok(())
}
