//! `lightpick plot tree`: the light tree seen from above ([`draw::tree_view`]), headless,
//! with one spatial pick recorded at a pixel ([`TreePick::record`]): its path drawn, its
//! steps printed as text or, with `--json`, as one JSON object.
//!
//! The pick at pixel `(px, py)` draws from stream `Rng::new(seed, py·width + px)` (the
//! variance map's layout, [`lightpick_core::stats::variance_map`]), so the same arguments
//! record the same pick.

use anyhow::bail;
use clap::{Args, ValueEnum};
use glam::DVec2;
use lightpick_core::Rng;
use lightpick_core::draw::{self, TreeView};
use lightpick_core::lesson::tree_pick::{Culled, TreePick};
use lightpick_core::scene::pixel_center;
use lightpick_core::spatial::SpatialSampler;
use serde_json::json;

use super::input::PositionedArgs;
use super::plot_output::{OutputArgs, scene_or_seed};
use crate::numbers;

/// The depth whose groups are outlined when `--depth` is not given (less on a shallower
/// tree).
pub const DEFAULT_DEPTH: usize = 2;

/// Arguments of `lightpick plot tree`.
#[derive(Debug, Args)]
pub struct TreeArgs {
    /// The scene (default: the worked example).
    #[command(flatten)]
    pub scene: PositionedArgs,
    /// The depth whose groups are outlined, 0 (one group of every light) to the tree's
    /// deepest node (default: 2, or the deepest when the tree is shallower).
    #[arg(long)]
    pub depth: Option<usize>,
    /// Record one spatial pick at this pixel's centre (column,row; row 0 at the top): its
    /// path is drawn and its steps printed.
    #[arg(long, value_name = "PX,PY")]
    pub pixel: Option<String>,
    /// Random seed of the recorded pick.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Colour the lights by their power share (power), by the spatial pick's probability at
    /// the pixel (spatial), or by their ideal share of the pixel's irradiance (ideal);
    /// spatial and ideal need --pixel.
    #[arg(long, value_enum, default_value_t = TreeColor::Power)]
    pub color: TreeColor,
    /// Print the recorded pick as one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// The output picture.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// What the lights' colours show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TreeColor {
    /// The power pmf `p_i = Φ_i/ΣΦ`.
    Power,
    /// The spatial pick's `P(i | x)` at the pixel.
    Spatial,
    /// The ideal share `s_i(x)/E(x)` of the pixel's irradiance.
    Ideal,
}

/// Draws the tree, records the pick and prints it.
pub fn run(args: &TreeArgs) -> anyhow::Result<()> {
    let style = args.output.style()?;
    let pixel = args.pixel.as_deref().map(parse_pixel).transpose()?;
    if pixel.is_none() && args.color != TreeColor::Power {
        let name = if args.color == TreeColor::Spatial {
            "spatial"
        } else {
            "ideal"
        };
        bail!("--color {name} needs --pixel PX,PY: the probabilities are those at a point");
    }
    let scene = scene_or_seed(&args.scene, "plot tree")?;
    if let Some([px, py]) = pixel
        && (px >= scene.plane.width || py >= scene.plane.height)
    {
        bail!(
            "--pixel {px},{py} is outside the image ({}×{} pixels: columns 0 to {}, rows 0 \
             to {})",
            scene.plane.width,
            scene.plane.height,
            scene.plane.width.saturating_sub(1),
            scene.plane.height.saturating_sub(1)
        );
    }
    let sampler = SpatialSampler::for_scene(&scene);
    let deepest = deepest_depth(&sampler);
    let depth = match args.depth {
        Some(d) if d > deepest => bail!(
            "--depth {d} is beyond the tree: its deepest groups are at depth {deepest} \
             ({} lights)",
            scene.light_count()
        ),
        Some(d) => d,
        None => DEFAULT_DEPTH.min(deepest),
    };
    let at = pixel.map(|[px, py]| {
        let x = pixel_center(&scene.plane, px, py);
        let stream = u64::from(py) * u64::from(scene.plane.width) + u64::from(px);
        let pick = TreePick::record(&sampler, x, &mut Rng::new(args.seed, stream));
        ([px, py], x, pick)
    });
    let probabilities = match (args.color, &at) {
        (TreeColor::Spatial, Some((_, x, _))) => Some(sampler.pdfs(*x)),
        (TreeColor::Ideal, Some((_, x, _))) => Some(scene.irradiance_shares(*x)),
        _ => Some(scene.powers.pmf()),
    };
    let pick = at.as_ref().and_then(|(_, _, p)| p.as_ref());
    let view = TreeView {
        scene: &scene,
        sampler: &sampler,
        depth,
        pick,
        probabilities: probabilities.as_deref(),
        region: None,
    };
    args.output.write(&draw::tree_view(&view, &style)?)?;
    let groups = draw::tree_groups(&sampler, depth).len();
    if args.json {
        super::print_json(&json!({
            "lights": scene.light_count(),
            "depth": depth,
            "deepest_depth": deepest,
            "groups": groups,
            "color": format!("{:?}", args.color).to_lowercase(),
            "seed": args.seed,
            "pixel": at.as_ref().map(|(p, _, _)| p.to_vec()),
            "x": at.as_ref().map(|(_, x, _)| [x.x, x.y]),
            "pick": pick.map(pick_json),
        }))?;
    } else {
        println!(
            "{}; wrote {}",
            draw::tree_view_caption(depth, groups, scene.light_count()),
            args.output.out.display()
        );
        match &at {
            Some((p, x, Some(pick))) => print_pick(*p, *x, args.seed, pick),
            Some(([px, py], _, None)) => {
                println!("no light contributes at pixel ({px}, {py}): nothing to pick");
            }
            None => {}
        }
    }
    Ok(())
}

/// `PX,PY` as two pixel indices.
fn parse_pixel(text: &str) -> anyhow::Result<[u32; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let parsed: Vec<Option<u32>> = parts.iter().map(|p| p.parse().ok()).collect();
    match parsed.as_slice() {
        [Some(px), Some(py)] => Ok([*px, *py]),
        _ => bail!("--pixel '{text}': give a column and a row, e.g. --pixel 40,12"),
    }
}

/// The deepest depth whose groups differ: the internal levels of the tree (0 for the exact
/// pick, one group of every light).
fn deepest_depth(sampler: &SpatialSampler) -> usize {
    match sampler {
        SpatialSampler::Exact(_) => 0,
        SpatialSampler::Tree(tree) => (tree.depth() as usize).saturating_sub(1),
    }
}

/// A cull reason in words.
fn culled_words(c: Culled) -> &'static str {
    match c {
        Culled::Empty => "empty",
        Culled::OutsideFootprint => "outside footprint",
        Culled::BeyondRange => "beyond range",
        Culled::OutsideCone => "outside cone",
        Culled::NoPower => "no power",
    }
}

/// The pick as JSON: per node the lanes and the draw, then the leaf and the figures.
fn pick_json(pick: &TreePick) -> serde_json::Value {
    let steps: Vec<_> = pick
        .steps
        .iter()
        .map(|s| {
            let lanes: Vec<_> = s
                .lanes
                .iter()
                .map(|l| {
                    json!({
                        "light_count": l.light_count(),
                        "importance": l.importance,
                        "share": l.share,
                        "branch_probability": l.branch_probability,
                        "mass": l.mass,
                        "probability": l.probability,
                        "culled": l.culled.map(culled_words),
                    })
                })
                .collect();
            json!({
                "node": s.node,
                "depth": s.depth,
                "lanes": lanes,
                "random24": s.random24,
                "random": f64::from(s.random24) / f64::from(1u32 << 24),
                "lane": s.lane,
                "pdf_after": s.pdf_after,
            })
        })
        .collect();
    let leaf_lights: Vec<_> = pick
        .leaf
        .lights
        .iter()
        .map(|l| {
            json!({
                "light": l.light,
                "contribution": l.contribution,
                "mass": l.mass,
                "probability": l.probability,
            })
        })
        .collect();
    let cut = pick.cut.as_ref().map(|c| {
        let entries: Vec<_> = c
            .entries
            .iter()
            .map(|e| {
                json!({
                    "depth": e.depth,
                    "light_count": e.lights.len(),
                    "light": e.light,
                    "mass": e.mass,
                    "probability": e.probability,
                })
            })
            .collect();
        json!({
            "tile": c.tile,
            "pixels": c.pixels,
            "entries": entries,
            "random24": c.random24,
            "random": f64::from(c.random24) / f64::from(1u32 << 24),
            "entry": c.entry,
            "pdf_after": c.pdf_after,
        })
    });
    json!({
        "cut": cut,
        "steps": steps,
        "leaf": {
            "lights": leaf_lights,
            "random24": pick.leaf.random24,
            "random": f64::from(pick.leaf.random24) / f64::from(1u32 << 24),
            "picked": pick.leaf.picked,
            "pdf_after": pick.leaf.pdf_after,
        },
        "light": pick.light,
        "pdf": pick.pdf,
        "contribution": pick.contribution,
        "estimate": pick.estimate,
        "irradiance": pick.irradiance,
        "power_pmf": pick.power_pmf,
    })
}

/// The pick as text, node by node.
fn print_pick([px, py]: [u32; 2], x: DVec2, seed: u64, pick: &TreePick) {
    let n = numbers::short;
    println!(
        "spatial pick at pixel ({px}, {py}), x = ({}, {}), seed {seed}:",
        n(x.x),
        n(x.y)
    );
    if let Some(c) = &pick.cut {
        let [[x0, y0], [x1, y1]] = c.pixels;
        let e = &c.entries[c.entry];
        println!(
            "tile {} (pixels {x0}..{x1} × {y0}..{y1}): cut of {}; u = {} (24-bit {}) → \
             entry {} (depth {}, {}), P = {}",
            c.tile,
            numbers::count(c.entries.len(), "entry", "entries"),
            n(f64::from(c.random24) / f64::from(1u32 << 24)),
            c.random24,
            c.entry,
            e.depth,
            match e.light {
                Some(light) => format!("light {light}"),
                None => numbers::count(e.lights.len(), "light", "lights"),
            },
            n(c.pdf_after)
        );
    }
    for s in &pick.steps {
        println!(
            "node {} (depth {}): u = {} (24-bit {}) → lane {}",
            s.node,
            s.depth,
            n(f64::from(s.random24) / f64::from(1u32 << 24)),
            s.random24,
            s.lane
        );
        for (l, lane) in s.lanes.iter().enumerate() {
            let mark = if l == s.lane { "→" } else { " " };
            let tail = lane
                .culled
                .map_or_else(String::new, |c| format!(", culled: {}", culled_words(c)));
            println!(
                "  {mark} lane {l}: {} lights, P = {}{tail}",
                lane.light_count(),
                n(lane.probability)
            );
        }
    }
    println!(
        "leaf: {}, u = {} (24-bit {})",
        numbers::count(pick.leaf.lights.len(), "light", "lights"),
        n(f64::from(pick.leaf.random24) / f64::from(1u32 << 24)),
        pick.leaf.random24
    );
    for (k, l) in pick.leaf.lights.iter().enumerate() {
        let mark = if k == pick.leaf.picked { "→" } else { " " };
        println!(
            "  {mark} light {}: c = {}, P = {}",
            l.light,
            n(l.contribution),
            n(l.probability)
        );
    }
    println!(
        "picked light {}: P(i|x) = {}, estimate c_i/P = {}, exact irradiance {}, power pmf \
         p_i = {}",
        pick.light,
        n(pick.pdf),
        n(pick.estimate),
        n(pick.irradiance),
        n(pick.power_pmf)
    );
}
