//! Measures the light tree's per-tile cuts ([`lightpick_core::spatial::TileCuts`]) against the
//! tree descended from its root: the exact variance of one sample and the time per pixel
//! sample: the cuts as built, the cuts as first built (weighed by the tree's probabilities
//! alone), and the built ones with another cut size, spread limit, share of the weights
//! given by the tree's probabilities, or with every leaf cluster kept whole.
//!
//! Printed per scene (rendered at 128 × 128 pixels): the exact variance of one sample
//! (`Σ c_i²/q_i − E²`, mean over a grid of points off the pixel centres) of power picking, of the tree
//! without cuts and with each cut, as "× below power" (and over the tree's own); and the
//! time per pixel sample (pick and estimate, one thread, in pixel order, `ns`) of the alias
//! table and of each, as a multiple of the alias table's, with every tile cut beforehand;
//! how long cutting every tile took, the mean entries a tile and how much of a tile's mass
//! lies on single lights.
//!
//! ```text
//! cargo run --release -p lightpick-core --example tile_cuts -- equal heavy-tail grid stage
//! ```

use std::time::Instant;

use glam::DVec2;
use lightpick_core::scene::{Scene, pixel_center};
use lightpick_core::spatial::importance::GRID_CELL;
use lightpick_core::spatial::{Child, SpatialSampler, TileCuts};
use lightpick_core::{AliasTable, Rng};

/// `Σ c²/q − E²` at one point for the pmf `q`.
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

/// Cuts every tile of `sampler`'s tree (so that the times after are the picks' alone): the
/// milliseconds it took, the mean entries a tile and the mean mass of single lights.
fn cut_every_tile(sampler: &SpatialSampler) -> (f64, f64, f64) {
    let SpatialSampler::Tree(tree) = sampler else {
        return (0.0, 0.0, 0.0);
    };
    let Some(cuts) = tree.tile_cuts() else {
        return (0.0, 0.0, 0.0);
    };
    let start = Instant::now();
    cuts.cut_all(tree);
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let [tx, ty] = cuts.tiles();
    let tiles = (tx * ty) as usize;
    let (mut entries, mut singles) = (0usize, 0.0);
    for tile in 0..tiles {
        for (entry, mass) in cuts.entries(tree, tile) {
            entries += 1;
            if let Child::Leaf { count: 1, .. } = entry.get() {
                singles += f64::from(mass) * GRID_CELL;
            }
        }
    }
    (ms, entries as f64 / tiles as f64, singles / tiles as f64)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let names: Vec<String> = std::env::args().skip(1).collect();
    for name in &names {
        let mut scene = Scene::preset(name).or_else(|_| Scene::load(name))?;
        scene.plane.width = 128;
        scene.plane.height = 128;
        let SpatialSampler::Tree(tree) = SpatialSampler::for_scene(&scene) else {
            println!("{name}: exact pick (few lights), nothing to cut");
            continue;
        };
        let n = scene.light_count();
        let pmf = scene.powers.pmf();
        let table = AliasTable::build(&scene.powers);
        let built = TileCuts::build(&tree, &scene.plane).ok_or("a tree to cut")?;
        let (k, spread) = (built.max_entries(), built.max_spread());
        let sized = |tiles: u32, k: usize, spread: f64| {
            TileCuts::build_sized(&tree, &scene.plane, tiles, k, spread).expect("a tree to cut")
        };
        // Each row: its label and its cuts (`None`: the tree from its root).
        let rows: Vec<(String, Option<TileCuts>)> = vec![
            ("the tree from its root".into(), None),
            (
                "64 × 64 tiles, cut ≤ 64, spread ≤ 1.25, weighed by the tree's probabilities"
                    .into(),
                Some(sized(64, 64, 1.25).weighing_by_tree_probabilities()),
            ),
            (
                format!(
                    "built: cut ≤ {k}, spread ≤ {spread}, weighed by estimates, the tree's share {}",
                    lightpick_core::spatial::CUT_TREE_SHARE
                ),
                Some(built.clone()),
            ),
            (
                format!("cut ≤ {}, spread ≤ {spread}", k / 2),
                Some(sized(64, k / 2, spread)),
            ),
            (
                format!("cut ≤ {}, spread ≤ {spread}", 2 * k),
                Some(sized(64, 2 * k, spread)),
            ),
            (
                format!("cut ≤ {}, spread ≤ {spread}", 4 * k),
                Some(sized(64, 4 * k, spread)),
            ),
            (
                format!("cut ≤ {k}, spread ≤ 1.25"),
                Some(sized(64, k, 1.25)),
            ),
            (format!("cut ≤ {k}, spread ≤ 1.6"), Some(sized(64, k, 1.6))),
            (format!("cut ≤ {k}, spread ≤ 4"), Some(sized(64, k, 4.0))),
            (
                "built, the tree's share 0.1".into(),
                Some(built.clone().with_tree_share(0.1)),
            ),
            (
                "built, the tree's share 0.25".into(),
                Some(built.clone().with_tree_share(0.25)),
            ),
            (
                "built, the tree's share 0.5".into(),
                Some(built.clone().with_tree_share(0.5)),
            ),
            (
                format!("cut ≤ {k}, spread ≤ {spread}, clusters whole"),
                Some(built.clone().keeping_leaf_clusters()),
            ),
        ];
        let samplers: Vec<SpatialSampler> = rows
            .iter()
            .map(|(_, cuts)| SpatialSampler::Tree(tree.clone().with_cuts(cuts.clone())))
            .collect();
        // Shading points: a G × G raster of pixel centres.
        let g: u32 = if n > 100_000 { 6 } else { 24 };
        let (mut v_power, mut v) = (0.0, vec![0.0; samplers.len()]);
        for j in 0..g {
            for i in 0..g {
                // Off the pixel centres (where the cuts are weighed at 128 × 128 pixels).
                let (fx, fy) = (
                    (f64::from(i) + 0.37) / f64::from(g),
                    (f64::from(j) + 0.61) / f64::from(g),
                );
                let (lo, hi) = (scene.plane.min, scene.plane.max);
                let x = DVec2::new(lo.x + fx * (hi.x - lo.x), hi.y - fy * (hi.y - lo.y));
                let c: Vec<f64> = (0..n).map(|i| pmf[i] * scene.light_term(i, x)).collect();
                v_power += variance(&c, &pmf);
                for (v, s) in v.iter_mut().zip(&samplers) {
                    *v += variance(&c, &s.pdfs(x));
                }
            }
        }
        // Time per pixel sample, one thread: 128 × 128 pixels, 32 samples each.
        let spp = 32u64;
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
        println!("{name} ({n} lights): alias {t_alias:.1} ns per pixel sample");
        let v_tree = v[0];
        for (((label, _), s), v) in rows.iter().zip(&samplers).zip(&v) {
            let (cut_ms, entries, singles) = cut_every_tile(s);
            let t = time(&mut |x, rng| s.estimate(x, rng));
            println!(
                "  {label}: {:.0}× below power ({:.2}× the tree's variance); {t:.1} ns ({:.1}× \
                 alias); every tile cut in {cut_ms:.1} ms, {entries:.1} entries a tile, \
                 {singles:.2} of their mass on single lights",
                v_power / v,
                v / v_tree,
                t / t_alias
            );
        }
    }
    Ok(())
}
