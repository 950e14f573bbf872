//! `lightpick scene`: what a scene file holds (its lights by kind, their powers, what was
//! skipped), as text or as the JSON contract scripts read; `--out` writes it as lightpick
//! JSON for editing.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::scene::{Loaded, Scene};
use serde_json::{Value, json};

use super::input::SceneArgs;
use crate::numbers::short;

/// Arguments of `lightpick scene`.
#[derive(Debug, Args)]
pub struct SceneCommandArgs {
    /// The scene file or preset (and `--floor`).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Write the scene as lightpick JSON (names, spots and ranges kept) to this file.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `lightpick scene`.
pub fn run(args: &SceneCommandArgs) -> anyhow::Result<()> {
    let Some(loaded) = args.scene.load_with_report()? else {
        bail!("no scene given: use --scene FILE or --preset NAME");
    };
    if let Some(out) = &args.out {
        lightpick_core::atomic_file::write_bytes_atomically(out, loaded.scene.to_json().as_bytes())
            .with_context(|| format!("--out {}", out.display()))?;
    }
    if args.json {
        super::print_json(&scene_json(&loaded))
    } else {
        print!("{}", scene_text(&loaded, args.out.as_deref()));
        Ok(())
    }
}

/// The JSON contract: `{"name", "plane", "lights": [{"name"?, "position", "power",
/// "spot"?: {"direction", "inner_cone", "outer_cone"}, "range"?}], "import": {"format",
/// "points", "spots", "skipped": [{"name", "reason"}]}}`, angles in radians, positions
/// after the floor.
pub fn scene_json(loaded: &Loaded) -> Value {
    let scene = &loaded.scene;
    let lights: Vec<Value> = (0..scene.light_count())
        .map(|i| {
            let p = scene.positions[i];
            let mut light = serde_json::Map::new();
            if let Some(name) = scene.name_of(i) {
                light.insert("name".into(), json!(name));
            }
            light.insert("position".into(), json!([p.x, p.y, p.z]));
            light.insert("power".into(), json!(scene.powers.as_slice()[i]));
            if let Some(e) = scene.emission_of(i) {
                if let Some(s) = e.spot() {
                    let d = s.direction;
                    light.insert(
                        "spot".into(),
                        json!({
                            "direction": [d.x, d.y, d.z],
                            "inner_cone": s.inner_cone,
                            "outer_cone": s.outer_cone,
                        }),
                    );
                }
                if let Some(r) = e.range() {
                    light.insert("range".into(), json!(r));
                }
            }
            Value::Object(light)
        })
        .collect();
    let plane = &scene.plane;
    json!({
        "name": scene.name,
        "plane": {
            "min": [plane.min.x, plane.min.y],
            "max": [plane.max.x, plane.max.y],
            "width": plane.width,
            "height": plane.height,
        },
        "lights": lights,
        "import": loaded.report,
    })
}

/// The text summary: format, counts, power range, plane, skipped lights.
fn scene_text(loaded: &Loaded, out: Option<&std::path::Path>) -> String {
    let scene: &Scene = &loaded.scene;
    let report = &loaded.report;
    let powers = scene.powers.as_slice();
    let positive = powers.iter().copied().filter(|&p| p > 0.0);
    let (min, max) = positive.fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    });
    let zeros = powers.iter().filter(|&&p| p == 0.0).count();
    let above = scene.positions.iter().filter(|p| p.z > 0.0).count();
    let plane = &scene.plane;
    let mut text = format!(
        "{}: {} ({})\n  powers: {} to {}{}, total {}\n  {} of {} lights above the receiver (z > 0)\n  plane: x {} to {}, y {} to {}, {} × {} pixels\n",
        scene.name,
        report.summary(),
        report.format.name(),
        short(min),
        short(max),
        if zeros > 0 {
            format!(" ({zeros} at 0)")
        } else {
            String::new()
        },
        short(scene.powers.total()),
        above,
        scene.light_count(),
        short(plane.min.x),
        short(plane.max.x),
        short(plane.min.y),
        short(plane.max.y),
        plane.width,
        plane.height,
    );
    for s in &report.skipped {
        let _ = writeln!(text, "  skipped '{}': {}", s.name, s.reason);
    }
    if let Some(out) = out {
        let _ = writeln!(text, "  written to {} (lightpick JSON)", out.display());
    }
    text
}
