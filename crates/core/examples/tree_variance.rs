//! The exact variance of the spatial scheme against power sampling, per scene: how many times
//! fewer samples the light tree needs than power picking for the same noise.
//!
//! At each of `G × G` shading points `x` (pixel centres of a `G × G` raster over the scene's
//! plane) the exact per-sample variances are `Σ c_i²/P(i | x) − E²` for the spatial scheme
//! and `Σ c_i²/p_i − E²` for power sampling (`c_i = p_i·G_i(x)·S_i(x)`, `E = Σ c_i`); the
//! figure is the ratio of their means over the points. Also printed: the share of picks that
//! land on a light giving `x` nothing (`1 − Σ_{c_i > 0} P(i | x)`, mean over the points).
//!
//! ```text
//! cargo run --release -p lightpick-core --example tree_variance -- stage gallery random arena
//! ```
//!
//! Names are presets, or `random` (2000 spots at random heights aimed at random marks, a
//! third with ranges) and `arena` (1500 spots on a ring aimed into it, every fifth wide):
//! spot sets the tree was not tuned to; and three clustered sets of point lights near the
//! plane that no preset resembles ([`clustered`]): `clusters-low`, `chandeliers` and
//! `strips`. `--write DIR` also saves those five as lightpick JSON (`DIR/random.json`,
//! `DIR/arena.json`, `DIR/clusters-low.json`, …) for `lightpick bench --scene`.

use glam::{DVec2, DVec3, dvec2, dvec3};
use lightpick_core::scene::{Emission, ReceiverPlane, Scene, Spot, pixel_center};
use lightpick_core::spatial::SpatialSampler;

// `SplitMix64`, the integration tests' generator of test inputs: a fixed stream for the
// generated spot sets.
#[path = "../tests/integration/common/mix.rs"]
mod mix;
use mix::SplitMix;

#[path = "tree_variance/clustered.rs"]
mod clustered;

/// A spot at `from` aimed at `mark` on the plane.
fn aimed(from: DVec3, mark: DVec3, inner: f64, outer: f64) -> Spot {
    Spot {
        direction: mark - from,
        inner_cone: inner,
        outer_cone: outer,
    }
}

fn spot_scene(
    name: &str,
    side: f64,
    lights: &[(DVec3, f64, Spot, Option<f64>)],
) -> Result<Scene, Box<dyn std::error::Error>> {
    let plane = ReceiverPlane {
        min: dvec2(-side, -side),
        max: dvec2(side, side),
        width: 128,
        height: 128,
    };
    let scene = Scene::from_parts(
        name,
        plane,
        lights.iter().map(|l| l.0).collect(),
        lights.iter().map(|l| l.1).collect(),
    )?;
    let emission = lights
        .iter()
        .map(|l| Emission::new(Some(l.2), l.3))
        .collect::<Result<_, _>>()?;
    Ok(scene.with_emission(emission))
}

/// 2000 spots over a 20 m square, 2–8 m up, aimed at random marks, a third with ranges.
fn random_spots() -> Result<Scene, Box<dyn std::error::Error>> {
    let mut d = SplitMix(11);
    let lights: Vec<_> = (0..2000)
        .map(|_| {
            let from = dvec3(
                d.range(-10.0, 10.0),
                d.range(-10.0, 10.0),
                d.range(2.0, 8.0),
            );
            let mark = dvec3(d.range(-10.0, 10.0), d.range(-10.0, 10.0), 0.0);
            let outer = d.range(0.05, 0.8);
            let range = (d.next_f64() < 0.3).then(|| d.range(6.0, 20.0));
            let power = 10f64.powf(d.range(0.0, 2.0));
            let inner = outer * d.range(0.0, 0.9);
            (from, power, aimed(from, mark, inner, outer), range)
        })
        .collect();
    spot_scene("random", 10.0, &lights)
}

/// 1500 spots on a ring of radius 20 m, 12–15 m up, aimed at marks within 14 m of its
/// centre; every fifth is wide.
fn arena() -> Result<Scene, Box<dyn std::error::Error>> {
    let mut d = SplitMix(12);
    let lights: Vec<_> = (0..1500)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 1500.0;
            let from = dvec3(20.0 * a.cos(), 20.0 * a.sin(), 12.0 + d.range(0.0, 3.0));
            let r = 14.0 * d.next_f64().sqrt();
            let b = d.range(0.0, std::f64::consts::TAU);
            let mark = dvec3(r * b.cos(), r * b.sin(), 0.0);
            let outer = if i % 5 == 0 {
                d.range(0.3, 0.6)
            } else {
                d.range(0.03, 0.12)
            };
            let power = d.range(50.0, 500.0);
            (from, power, aimed(from, mark, 0.7 * outer, outer), None)
        })
        .collect();
    spot_scene("arena", 18.0, &lights)
}

/// `(Var_power / Var_spatial, wasted share of picks)` over `side × side` points.
fn measure(scene: &Scene, side: u32) -> (f64, f64) {
    let sampler = SpatialSampler::for_scene(scene);
    let pmf = scene.powers.pmf();
    let raster = ReceiverPlane {
        width: side,
        height: side,
        ..scene.plane.clone()
    };
    let (mut spatial, mut power, mut wasted) = (0.0, 0.0, 0.0);
    for k in 0..side * side {
        let x: DVec2 = pixel_center(&raster, k % side, k / side);
        let q = sampler.pdfs(x);
        let (mut e, mut s2, mut p2, mut useful) = (0.0, 0.0, 0.0, 0.0);
        for (i, &p) in pmf.iter().enumerate() {
            let c = p * scene.light_term(i, x);
            if c > 0.0 {
                e += c;
                s2 += c * c / q[i];
                p2 += c * c / p;
                useful += q[i];
            }
        }
        spatial += (s2 - e * e).max(0.0);
        power += (p2 - e * e).max(0.0);
        wasted += if e > 0.0 {
            (1.0 - useful).max(0.0)
        } else {
            0.0
        };
    }
    (power / spatial, wasted / f64::from(side * side))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut names: Vec<String> = std::env::args().skip(1).collect();
    // `--write DIR`: save `random` and `arena` as lightpick JSON (for `lightpick bench
    // --scene`).
    if let Some(at) = names.iter().position(|a| a == "--write") {
        let dir = std::path::PathBuf::from(names.get(at + 1).ok_or("--write DIR")?);
        std::fs::write(dir.join("random.json"), random_spots()?.to_json())?;
        std::fs::write(dir.join("arena.json"), arena()?.to_json())?;
        for scene in clustered::all()? {
            std::fs::write(dir.join(format!("{}.json", scene.name)), scene.to_json())?;
        }
        names.drain(at..=at + 1);
    }
    let names = if names.is_empty() {
        ["stage", "gallery", "random", "arena", "heavy-tail", "grid"]
            .map(String::from)
            .to_vec()
    } else {
        names
    };
    println!(
        "{:<12} {:>8} {:>24} {:>14}",
        "scene", "lights", "Var power / Var spatial", "wasted picks"
    );
    for name in names {
        let scene = match name.as_str() {
            "random" => random_spots()?,
            "arena" => arena()?,
            other => match clustered::by_name(other)? {
                Some(scene) => scene,
                None => Scene::preset(other)?,
            },
        };
        let side = if scene.light_count() > 100_000 {
            17
        } else {
            37
        };
        let (ratio, wasted) = measure(&scene, side);
        println!(
            "{name:<12} {:>8} {ratio:>23.1}× {:>13.1} %",
            scene.light_count(),
            100.0 * wasted
        );
    }
    Ok(())
}
