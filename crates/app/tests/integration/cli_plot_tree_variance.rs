//! `lightpick plot tree` and `lightpick plot variance`: the tree's top view on the `grid`
//! preset and the worked example's variance maps against goldens in `tests/snapshots/`
//! (update with `UPDATE_SNAPSHOTS=1`), the recorded pick's JSON against the core's
//! `SpatialSampler::pdf`, the captions' means against `VarianceMap`, and the one-line errors.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use lightpick_core::Scheme;
use lightpick_core::scene::{Scene, pixel_center};
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::stats::variance_map::VarianceMap;

use crate::common::{assert_error, json, num, run_ok, scratch, snapshot_options};

fn snapshot(path: &std::path::Path, name: &str) {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    assert_eq!(image.dimensions(), (800, 500));
    egui_kittest::image_snapshot_options(&image, name, &snapshot_options());
}

#[test]
fn the_grid_trees_top_view_with_a_pick_matches_its_golden() {
    let dir = scratch("plot-tree");
    let png = dir.join("tree.png");
    let out = run_ok(&[
        "plot",
        "tree",
        "--preset",
        "grid",
        "--depth",
        "2",
        "--pixel",
        "100,60",
        "--seed",
        "3",
        "--color",
        "spatial",
        "--out",
        png.to_str().unwrap(),
    ]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("depth 2: 16 groups · 1024 lights"), "{text}");
    assert!(text.contains("spatial pick at pixel (100, 60)"), "{text}");
    assert!(
        text.contains("tile 985 (pixels 100..104 × 60..64): cut of "),
        "{text}"
    );
    assert!(text.contains("picked light "), "{text}");
    snapshot(&png, "plot_tree_grid");
}

/// The recorded pick's JSON at `pixel` of `preset`, with its scene.
fn pick_at(preset: &str, pixel: [u32; 2], seed: &str) -> (serde_json::Value, Scene) {
    let dir = scratch("plot-tree-json");
    let png = dir.join("t.png");
    let v = json(&[
        "plot",
        "tree",
        "--preset",
        preset,
        "--pixel",
        &format!("{},{}", pixel[0], pixel[1]),
        "--seed",
        seed,
        "--json",
        "--out",
        png.to_str().unwrap(),
    ]);
    (v, Scene::preset(preset).unwrap())
}

#[test]
fn the_picks_pdf_is_the_product_of_its_steps_and_the_samplers_pdf() {
    for (preset, pixel, seed) in [
        ("grid", [100, 60], "3"),
        ("grid", [3, 250], "11"),
        ("grid", [128, 128], "1"),
        ("worked-example", [128, 100], "5"),
    ] {
        let (v, scene) = pick_at(preset, pixel, seed);
        let what = format!("{preset} at {pixel:?}");
        let pick = &v["pick"];
        let steps = pick["steps"].as_array().unwrap();
        let cut = &pick["cut"];
        let mut product = 1.0;
        if preset == "grid" {
            // The tile's cut first: the entry the scene's cuts give the draw, its
            // probability its mass on the 2^24 grid.
            let entries = cut["entries"].as_array().expect("a tile's cut");
            let entry = cut["entry"].as_u64().unwrap() as usize;
            let masses: Vec<u64> = entries
                .iter()
                .map(|e| e["mass"].as_u64().unwrap())
                .collect();
            assert_eq!(masses.iter().sum::<u64>(), 1 << 24, "{what}");
            let SpatialSampler::Tree(tree) = SpatialSampler::for_scene(&scene) else {
                panic!("{what}: a tree");
            };
            let cuts = tree.tile_cuts().expect("cuts");
            let tile = cut["tile"].as_u64().unwrap() as usize;
            let u = cut["random24"].as_u64().unwrap() as u32;
            let (_, mass) = cuts.pick(&tree, tile, u).expect("power");
            assert_eq!(u64::from(mass), masses[entry], "{what}");
            product = num(&entries[entry]["probability"]);
            assert_eq!(
                product,
                masses[entry] as f64 / f64::from(1u32 << 24),
                "{what}"
            );
            assert_eq!(num(&cut["pdf_after"]), product, "{what}");
        } else {
            assert!(
                cut.is_null() && steps.is_empty(),
                "{what}: the exact pick has no node"
            );
        }
        for step in steps {
            let lane = step["lane"].as_u64().unwrap() as usize;
            let lanes = step["lanes"].as_array().unwrap();
            assert_eq!(lanes.len(), 4);
            let chosen = &lanes[lane];
            assert!(
                chosen["culled"].is_null(),
                "{what}: a chosen lane is never culled"
            );
            assert!(chosen["light_count"].as_u64().unwrap() > 0);
            for l in lanes {
                assert_eq!(
                    l["culled"].is_null(),
                    num(&l["probability"]) > 0.0,
                    "{what}"
                );
            }
            product *= num(&chosen["probability"]);
            assert_eq!(num(&step["pdf_after"]), product, "{what}");
            let u = num(&step["random"]);
            assert!((0.0..1.0).contains(&u));
        }
        let leaf = &pick["leaf"];
        let picked = leaf["picked"].as_u64().unwrap() as usize;
        product *= num(&leaf["lights"][picked]["probability"]);
        let pdf = num(&pick["pdf"]);
        assert_eq!(pdf, product, "{what}: the pdf is the product of the steps");
        let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
        assert_eq!(v["x"], serde_json::json!([x.x, x.y]));
        let light = pick["light"].as_u64().unwrap() as usize;
        assert_eq!(
            leaf["lights"][picked]["light"].as_u64().unwrap() as usize,
            light
        );
        let sampler = SpatialSampler::for_scene(&scene);
        assert_eq!(pdf, sampler.pdf(x, light), "{what}: SpatialSampler::pdf");
        assert!(pdf > 0.0);
        let exact = num(&pick["irradiance"]);
        let expected = scene.exact_irradiance(x) / scene.powers.as_slice().iter().sum::<f64>();
        assert!(
            (exact - expected).abs() <= 1e-12 * expected,
            "{what}: {exact} vs {expected}"
        );
        assert_eq!(num(&pick["power_pmf"]), scene.powers.pmf()[light], "{what}");
    }
}

#[test]
fn the_tree_plot_refuses_bad_input() {
    let dir = scratch("plot-tree-bad");
    let png = dir.join("t.png");
    let out = png.to_str().unwrap();
    assert_error(
        &[
            "plot", "tree", "--preset", "grid", "--pixel", "256,3", "--out", out,
        ],
        "--pixel 256,3 is outside the image (256×256 pixels",
    );
    assert_error(
        &[
            "plot", "tree", "--preset", "grid", "--pixel", "4", "--out", out,
        ],
        "--pixel '4': give a column and a row",
    );
    assert_error(
        &[
            "plot", "tree", "--preset", "grid", "--depth", "40", "--out", out,
        ],
        "--depth 40 is beyond the tree",
    );
    assert_error(
        &["plot", "tree", "--depth", "1", "--out", out],
        "--depth 1 is beyond the tree: its deepest groups are at depth 0",
    );
    assert_error(
        &[
            "plot", "tree", "--preset", "grid", "--color", "spatial", "--out", out,
        ],
        "--color spatial needs --pixel",
    );
    assert_error(
        &["plot", "tree", "--color", "ideal", "--out", out],
        "--color ideal needs --pixel",
    );
    assert_error(
        &["plot", "tree", "--powers", "1,2", "--out", out],
        "--powers: plot tree needs light positions",
    );
    // The default scene and depth draw (the worked example's exact pick: depth 0).
    let v = json(&["plot", "tree", "--json", "--out", out]);
    assert_eq!(v["depth"], 0);
    assert!(v["pick"].is_null());
    run_ok(&[
        "plot", "tree", "--pixel", "10,20", "--color", "ideal", "--out", out,
    ]);
}

#[test]
fn the_worked_examples_variance_maps_match_their_golden_and_the_core_means() {
    let dir = scratch("plot-variance");
    let png = dir.join("v.png");
    let v = json(&[
        "plot",
        "variance",
        "--preset",
        "worked-example",
        "--json",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(v["exact"], true);
    assert_eq!(v["samples_per_pixel"], 0);
    assert!(v["method"].as_str().unwrap().starts_with("exact"));
    let scene = Scene::preset("worked-example").unwrap();
    let schemes = v["schemes"].as_array().unwrap();
    for (row, scheme) in schemes
        .iter()
        .zip([Scheme::Uniform, Scheme::Alias, Scheme::Spatial])
    {
        let map = VarianceMap::compute(&scene, scheme, 2, 1);
        assert!(map.exact);
        let mean = map.values.iter().sum::<f64>() / map.values.len() as f64;
        assert_eq!(num(&row["mean"]), mean, "{scheme}");
        // The caption drawn shows the same mean, to four significant digits.
        let caption = row["caption"].as_str().unwrap();
        let shown: f64 = caption.rsplit(' ').next().unwrap().parse().unwrap();
        assert!(
            (shown - mean).abs() <= 5e-4 * mean.abs() + 1e-300,
            "{caption} vs {mean}"
        );
    }
    // The worked example's exact spatial pick: zero variance up to rounding, far below power's.
    assert!(num(&schemes[2]["mean"]).abs() < 1e-9 * num(&schemes[1]["mean"]));
    assert!(num(&schemes[1]["mean"]) < num(&schemes[0]["mean"]));
    snapshot(&png, "plot_variance_worked_example");
}

#[test]
fn estimated_variance_maps_say_so_and_bad_input_is_refused() {
    let dir = scratch("plot-variance-est");
    let png = dir.join("v.png");
    let out = png.to_str().unwrap();
    // 1024 lights × 256² pixels exceed the exact budget: estimated from --spp samples.
    let v = json(&[
        "plot", "variance", "--preset", "grid", "--spp", "4", "--seed", "2", "--json", "--out", out,
    ]);
    assert_eq!(v["exact"], false);
    assert_eq!(v["samples_per_pixel"], 4);
    assert_eq!(v["method"], "estimated from 4 samples per pixel");
    let scene = Scene::preset("grid").unwrap();
    let map = VarianceMap::compute(&scene, Scheme::Spatial, 4, 2);
    let mean = map.values.iter().sum::<f64>() / map.values.len() as f64;
    assert_eq!(num(&v["schemes"][2]["mean"]), mean);
    assert!(num(&v["schemes"][2]["mean"]) < num(&v["schemes"][1]["mean"]));
    assert_error(
        &["plot", "variance", "--spp", "1", "--out", out],
        "--spp must be at least 2",
    );
    assert_error(
        &["plot", "variance", "--spp", "0", "--out", out],
        "--spp must be between 1 and 65536",
    );
}
