//! `lightpick plot animation`: its flags, checked before a scene is loaded, turned into a
//! [`Recording`] of [`crate::recording`] and written as a GIF, with a progress bar and a
//! summary (text or `--json`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context as _;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use lightpick_core::draw::Theme;
use lightpick_core::scene::Scene;
use serde_json::json;

use super::input::PositionedArgs;
use crate::recording::{
    DEFAULT_DELAY_MS, DEFAULT_FRAMES, DEFAULT_HOLD_MS, DEFAULT_MAX_SPP, PANELS, Recording, Timing,
    check_side, record, size_scene,
};

/// Arguments of `lightpick plot animation`.
#[derive(Debug, Args)]
pub struct AnimationArgs {
    /// The scene (default: the worked example).
    #[command(flatten)]
    pub scene: PositionedArgs,
    /// Frames of the animation (1 to 240).
    #[arg(long, default_value_t = DEFAULT_FRAMES)]
    pub frames: u32,
    /// Samples per pixel of the last frame; frames are spaced geometrically from 1 spp (at
    /// least one frame per sample count, so at least --frames).
    #[arg(long, default_value_t = DEFAULT_MAX_SPP)]
    pub max_spp: u32,
    /// Milliseconds each frame is shown (20 to 60000, rounded down to hundredths of a
    /// second).
    #[arg(long, default_value_t = DEFAULT_DELAY_MS)]
    pub delay_ms: u32,
    /// Milliseconds the last frame is shown before the loop restarts (20 to 60000).
    #[arg(long, default_value_t = DEFAULT_HOLD_MS)]
    pub hold_ms: u32,
    /// Image width in pixels, 8 to 512 (default: the scene's, capped at 96); the frame
    /// enlarges small images by a whole factor.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels, 8 to 512 (default: the scene's aspect at --width).
    #[arg(long)]
    pub height: Option<u32>,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Tonemap exposure (default: 1 / mean reference irradiance).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f64>,
    /// Light text on a dark background.
    #[arg(long)]
    pub dark: bool,
    /// The GIF to write.
    #[arg(long, value_name = "FILE.gif")]
    pub out: PathBuf,
    /// Print a summary (sizes and every frame's RMSE per scheme) as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Records the animation and writes it.
pub fn run(args: &AnimationArgs) -> anyhow::Result<()> {
    // Flags that need no scene are checked before loading one (a large preset takes time).
    Timing {
        frames: args.frames,
        max_spp: args.max_spp,
        delay_ms: args.delay_ms,
        hold_ms: args.hold_ms,
        exposure: args.exposure,
    }
    .check()?;
    for (flag, side) in [("--width", args.width), ("--height", args.height)] {
        if let Some(side) = side {
            check_side(flag, side)?;
        }
    }
    let mut scene = match args.scene.load("plot animation")? {
        Some(scene) => scene,
        None => Scene::preset("worked-example")?,
    };
    size_scene(&mut scene, args.width, args.height);
    let recording = Recording {
        scene,
        seed: args.seed,
        exposure: args.exposure,
        frames: args.frames,
        max_spp: args.max_spp,
        delay_ms: args.delay_ms,
        hold_ms: args.hold_ms,
        theme: if args.dark { Theme::Dark } else { Theme::Light },
    };
    recording.check()?;
    let bar = ProgressBar::new(u64::from(args.frames));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let started = Instant::now();
    let recorded = record(&recording, &mut |done, _| bar.set_position(u64::from(done)))?;
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    lightpick_core::atomic_file::write_bytes_atomically(&args.out, &recorded.gif)
        .with_context(|| format!("--out {}", args.out.display()))?;
    let scene = &recording.scene;
    if args.json {
        let frames: Vec<serde_json::Value> = recorded
            .frames
            .iter()
            .map(|f| {
                let rmse: serde_json::Map<String, serde_json::Value> = PANELS
                    .iter()
                    .zip(f.rmse)
                    .map(|(s, r)| (s.name().to_owned(), json!(r)))
                    .collect();
                json!({ "spp": f.spp, "rmse": rmse })
            })
            .collect();
        super::print_json(&json!({
            "out": args.out.display().to_string(),
            "scene": scene.name,
            "lights": scene.light_count(),
            "seed": recording.seed,
            "schemes": PANELS.iter().map(|s| s.name()).collect::<Vec<_>>(),
            "width": scene.plane.width,
            "height": scene.plane.height,
            "frame_width": recorded.frame_size.0,
            "frame_height": recorded.frame_size.1,
            "exposure": recorded.exposure,
            "delay_ms": recording.delay_ms,
            "hold_ms": recording.hold_ms,
            "bytes": recorded.gif.len(),
            "seconds": seconds,
            "reference": {
                "pixels": recorded.reference_pixels,
                "complete": recorded.reference_pixels == scene.plane.pixel_count(),
            },
            "frames": frames,
        }))?;
    } else {
        let last = recorded.frames.last().map_or([0.0; 3], |f| f.rmse);
        println!(
            "wrote {} ({} frame{}, {}×{} px, {} kB) in {seconds:.1} s; RMSE at {} spp: uniform \
             {:.3e}, alias {:.3e}, spatial {:.3e}",
            args.out.display(),
            recorded.frames.len(),
            if recorded.frames.len() == 1 { "" } else { "s" },
            recorded.frame_size.0,
            recorded.frame_size.1,
            recorded.gif.len().div_ceil(1000),
            recording.max_spp,
            last[0],
            last[1],
            last[2]
        );
    }
    Ok(())
}
