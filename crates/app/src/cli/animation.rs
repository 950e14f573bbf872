//! `lightpick plot animation`: the uniform, alias (power) and spatial progressive images of a
//! scene converging side by side, as an animated GIF for slides, each frame captioned with
//! every panel's samples per pixel and RMSE against the exact reference (the figure
//! `lightpick render` prints). The app's File → "Export animation…" records the same
//! animation through [`record`].
//!
//! # What a frame is
//! Frame `k` of `F` shows the three [`CpuRenderer`] images (one per scheme, the same seed)
//! after `s_k` samples per pixel, with `s_0 = 1`, `s_{F−1} = M` (`--max-spp`) and the counts
//! between spaced geometrically ([`frame_spp`]). The renderers continue from one frame to the
//! next, so frame `k + 1` adds `s_{k+1} − s_k` samples to the same estimates. Every image of
//! every frame is tonemapped with one exposure (`--exposure`, by default `1 / mean` of the
//! reference), so what changes from frame to frame is the noise, not the brightness.
//!
//! # Determinism
//! The CPU renderer and the reference are the same bits whatever the thread count, the
//! drawing is pure, and the GIF palettes come from `image`'s deterministic `NeuQuant`
//! quantizer (one local palette per frame): the same arguments write the same bytes.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context as _, bail};
use clap::Args;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use indicatif::{ProgressBar, ProgressStyle};
use lightpick_core::Scheme;
use lightpick_core::draw::{
    self, AnimationFrame, AnimationPanel, Theme, animation_zoom, auto_exposure,
    palette::scheme_color,
};
use lightpick_core::render::{CpuRenderer, Reference, error_metrics};
use lightpick_core::scene::Scene;
use lightpick_core::spatial::EXACT_MAX_LIGHTS;
use serde_json::json;

use super::input::PositionedArgs;

/// Frames of an animation by default.
pub const DEFAULT_FRAMES: u32 = 24;
/// Samples per pixel of the last frame by default.
pub const DEFAULT_MAX_SPP: u32 = 256;
/// Milliseconds each frame is shown by default.
pub const DEFAULT_DELAY_MS: u32 = 250;
/// Milliseconds the last frame is shown by default (the converged images, before the loop
/// starts again).
pub const DEFAULT_HOLD_MS: u32 = 2000;
/// The image width by default (capped at the scene's own).
pub const DEFAULT_WIDTH: u32 = 96;

/// The most frames an animation may have.
pub const MAX_FRAMES: u32 = 240;
/// The largest `--max-spp`.
pub const MAX_SPP: u32 = 1 << 16;
/// Image sides (pixels) an animation accepts: from 8 to 512.
pub const SIDE_RANGE: std::ops::RangeInclusive<u32> = 8..=512;
/// Frame delays (milliseconds) an animation accepts: GIF counts in hundredths of a second,
/// and browsers show delays under 20 ms slower than asked.
pub const DELAY_RANGE: std::ops::RangeInclusive<u32> = 20..=60_000;

/// `NeuQuant`'s sampling factor for frames of more than 256 colours (1 = best, 30 =
/// fastest; 10 is the gif crate's suggested balance).
const QUANTIZER_SPEED: i32 = 10;

/// The schemes shown, left to right, with their captions.
pub const PANELS: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

/// Arguments of `lightpick plot animation`.
#[derive(Debug, Args)]
pub struct AnimationArgs {
    /// The scene (default: the seed preset).
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

/// What an animation records: the CLI's flags or the app's running state.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The scene, its plane already at the image size.
    pub scene: Scene,
    /// Seed of every pixel stream.
    pub seed: u64,
    /// Tonemap exposure; `None`: `1 / mean` of the reference ([`auto_exposure`]).
    pub exposure: Option<f64>,
    /// Frames.
    pub frames: u32,
    /// Samples per pixel of the last frame.
    pub max_spp: u32,
    /// Milliseconds each frame is shown.
    pub delay_ms: u32,
    /// Milliseconds the last frame is shown.
    pub hold_ms: u32,
    /// Light or dark surroundings.
    pub theme: Theme,
}

/// One frame's figures.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FrameStats {
    /// Samples per pixel of every panel.
    pub spp: u32,
    /// RMSE of each panel against the reference, in [`PANELS`] order.
    pub rmse: [f64; 3],
}

/// A recorded animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Recorded {
    /// The GIF file's bytes.
    pub gif: Vec<u8>,
    /// Frame width and height in pixels.
    pub frame_size: (u32, u32),
    /// The exposure used.
    pub exposure: f64,
    /// Pixels the reference covers (all of them unless lights × pixels exceeds its budget).
    pub reference_pixels: usize,
    /// Every frame's samples per pixel and RMSEs.
    pub frames: Vec<FrameStats>,
}

/// The samples per pixel of each of `frames` frames ending at `max_spp`: strictly
/// increasing whole numbers from 1 (a single frame: `max_spp` alone), as close as possible to
/// the geometric sequence `max_spp^(k/(frames−1))`.
///
/// Rounding the geometric sequence repeats small counts (1, 1, 2, 2, …), so each count is
/// raised to one more than the one before (a forward pass) and then lowered to one less than
/// the one after (a backward pass from `max_spp`); with `frames ≤ max_spp` the result starts
/// at 1, ends at `max_spp` and increases strictly.
///
/// # Panics
/// If `frames == 0` or `frames > max_spp` (refused earlier by [`Recording::check`]).
pub fn frame_spp(frames: u32, max_spp: u32) -> Vec<u32> {
    assert!(
        frames >= 1 && frames <= max_spp,
        "frame_spp needs 1 ≤ frames ≤ max_spp"
    );
    if frames == 1 {
        return vec![max_spp];
    }
    let last = frames - 1;
    let mut spp: Vec<u32> = (0..frames)
        .map(|k| {
            (f64::from(max_spp)
                .powf(f64::from(k) / f64::from(last))
                .round() as u32)
                .clamp(1, max_spp)
        })
        .collect();
    for k in 1..spp.len() {
        spp[k] = spp[k].max(spp[k - 1] + 1);
    }
    spp[last as usize] = max_spp;
    for k in (0..last as usize).rev() {
        spp[k] = spp[k].min(spp[k + 1] - 1);
    }
    spp
}

/// The figures of a recording that need no scene.
#[derive(Clone, Copy, Debug)]
struct Timing {
    frames: u32,
    max_spp: u32,
    delay_ms: u32,
    hold_ms: u32,
    exposure: Option<f64>,
}

impl Timing {
    /// Refuses out-of-range figures, naming the CLI flag.
    fn check(self) -> anyhow::Result<()> {
        if !(1..=MAX_FRAMES).contains(&self.frames) {
            bail!(
                "--frames must be between 1 and {MAX_FRAMES} (got {})",
                self.frames
            );
        }
        if !(1..=MAX_SPP).contains(&self.max_spp) {
            bail!(
                "--max-spp must be between 1 and {MAX_SPP} (got {})",
                self.max_spp
            );
        }
        if self.frames > self.max_spp {
            bail!(
                "--frames {} needs --max-spp of at least {} (every frame adds samples)",
                self.frames,
                self.frames
            );
        }
        for (flag, ms) in [("--delay-ms", self.delay_ms), ("--hold-ms", self.hold_ms)] {
            if !DELAY_RANGE.contains(&ms) {
                bail!(
                    "{flag} must be between {} and {} (got {ms})",
                    DELAY_RANGE.start(),
                    DELAY_RANGE.end()
                );
            }
        }
        if let Some(e) = self.exposure
            && !(e.is_finite() && e > 0.0)
        {
            bail!("--exposure must be a positive finite number (got {e})");
        }
        Ok(())
    }
}

/// Refuses an image side outside [`SIDE_RANGE`], naming `flag`.
fn check_side(flag: &str, side: u32) -> anyhow::Result<()> {
    if !SIDE_RANGE.contains(&side) {
        bail!(
            "{flag} must be between {} and {} (got {side})",
            SIDE_RANGE.start(),
            SIDE_RANGE.end()
        );
    }
    Ok(())
}

impl Recording {
    /// Refuses what cannot be recorded, naming the CLI flag.
    pub fn check(&self) -> anyhow::Result<()> {
        Timing {
            frames: self.frames,
            max_spp: self.max_spp,
            delay_ms: self.delay_ms,
            hold_ms: self.hold_ms,
            exposure: self.exposure,
        }
        .check()?;
        check_side("--width", self.scene.plane.width)?;
        check_side("--height", self.scene.plane.height)
    }
}

/// Sets the scene's image size: `width` (default: the scene's, capped at
/// [`DEFAULT_WIDTH`]) and `height` (default: the scene's aspect at that width).
pub fn size_scene(scene: &mut Scene, width: Option<u32>, height: Option<u32>) {
    let (w0, h0) = (scene.plane.width.max(1), scene.plane.height.max(1));
    let w = width.unwrap_or(w0.min(DEFAULT_WIDTH));
    let h = height
        .unwrap_or_else(|| ((f64::from(w) * f64::from(h0) / f64::from(w0)).round() as u32).max(1));
    scene.plane.width = w;
    scene.plane.height = h;
}

/// A panel's caption: label and what it picks lights by.
fn caption(scheme: Scheme, lights: usize) -> (&'static str, &'static str) {
    match scheme {
        Scheme::Uniform => ("uniform", "1/N each"),
        Scheme::Alias | Scheme::AliasOneRandom | Scheme::Cdf => ("alias", "∝ power"),
        Scheme::Spatial if lights <= EXACT_MAX_LIGHTS => ("spatial", "∝ contribution"),
        Scheme::Spatial => ("spatial", "∝ contribution (tree)"),
    }
}

/// Renders and encodes the animation, calling `progress(done, total)` after the reference
/// (`done = 0`) and after each frame (`done = 1 ..= total`, `total` = frames).
pub fn record(
    recording: &Recording,
    progress: &mut dyn FnMut(u32, u32),
) -> anyhow::Result<Recorded> {
    recording.check()?;
    let scene = &recording.scene;
    let total = recording.frames;
    let reference = Reference::compute(scene);
    if let Some(overflow) = reference.overflow() {
        bail!("{overflow}");
    }
    let exposure = recording
        .exposure
        .unwrap_or_else(|| auto_exposure(reference.values()));
    progress(0, total);

    let (width, height) = (scene.plane.width as usize, scene.plane.height as usize);
    let zoom = animation_zoom(width);
    let lights = scene.light_count();
    let mut renderers: Vec<CpuRenderer> = PANELS
        .iter()
        .map(|&scheme| CpuRenderer::new(scene, scheme, recording.seed))
        .collect();
    let spps = frame_spp(recording.frames, recording.max_spp);
    let mut bytes = Vec::new();
    let mut frames = Vec::with_capacity(spps.len());
    let mut frame_size = (0, 0);
    {
        let mut encoder = GifEncoder::new_with_speed(&mut bytes, QUANTIZER_SPEED);
        encoder.set_repeat(Repeat::Infinite)?;
        for (k, &spp) in spps.iter().enumerate() {
            let mut images = Vec::with_capacity(PANELS.len());
            let mut rmse = [0.0; 3];
            for (r, slot) in renderers.iter_mut().zip(&mut rmse) {
                r.accumulate(spp - r.samples_per_pixel());
                *slot = error_metrics(r.accumulator(), &reference).rmse;
                images.push(r.accumulator().image());
            }
            let panels: Vec<AnimationPanel<'_>> = PANELS
                .iter()
                .zip(&images)
                .zip(rmse)
                .map(|((&scheme, image), rmse)| {
                    let (label, detail) = caption(scheme, lights);
                    AnimationPanel {
                        label,
                        detail,
                        color: scheme_color(scheme),
                        image,
                        spp: u64::from(spp),
                        rmse,
                    }
                })
                .collect();
            let title = format!(
                "{}: {spp} sample{} per pixel",
                scene.name,
                if spp == 1 { "" } else { "s" }
            );
            let subtitle = format!(
                "{lights} light{} · {width}×{height} px · same seed and exposure · RMSE against the exact image",
                if lights == 1 { "" } else { "s" }
            );
            let pixmap = draw::animation_frame(
                &AnimationFrame {
                    width,
                    height,
                    zoom,
                    panels: &panels,
                    exposure,
                    title: &title,
                    subtitle: &subtitle,
                    progress: (k, spps.len()),
                },
                recording.theme,
            )?;
            frame_size = (pixmap.width(), pixmap.height());
            let rgba =
                RgbaImage::from_raw(pixmap.width(), pixmap.height(), draw::to_rgba8(&pixmap))
                    .context("frame buffer size")?;
            let ms = if k + 1 == spps.len() {
                recording.hold_ms
            } else {
                recording.delay_ms
            };
            encoder.encode_frame(Frame::from_parts(
                rgba,
                0,
                0,
                Delay::from_numer_denom_ms(ms, 1),
            ))?;
            frames.push(FrameStats { spp, rmse });
            progress(k as u32 + 1, total);
        }
    }
    Ok(Recorded {
        gif: bytes,
        frame_size,
        exposure,
        reference_pixels: reference.pixels().len(),
        frames,
    })
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
        None => Scene::preset("seed")?,
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
    std::fs::write(&args.out, &recorded.gif)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_spaced_geometrically_and_strictly() {
        assert_eq!(frame_spp(1, 64), vec![64]);
        assert_eq!(frame_spp(7, 64), vec![1, 2, 4, 8, 16, 32, 64]);
        assert_eq!(frame_spp(4, 4), vec![1, 2, 3, 4]);
        for (frames, max) in [(24, 256), (24, 24), (2, 1 << 16), (240, 300), (5, 7)] {
            let s = frame_spp(frames, max);
            assert_eq!(s.len(), frames as usize);
            assert_eq!(s[0], 1, "{frames} {max}");
            assert_eq!(*s.last().expect("frames"), max);
            assert!(s.windows(2).all(|w| w[0] < w[1]), "{s:?}");
        }
    }

    #[test]
    fn recordings_are_checked() {
        let mut scene = Scene::preset("seed").expect("preset");
        size_scene(&mut scene, Some(16), None);
        assert_eq!((scene.plane.width, scene.plane.height), (16, 16));
        let ok = Recording {
            scene,
            seed: 1,
            exposure: None,
            frames: 4,
            max_spp: 8,
            delay_ms: 100,
            hold_ms: 100,
            theme: Theme::Light,
        };
        ok.check().expect("valid");
        let err = |r: Recording| r.check().expect_err("refused").to_string();
        assert!(
            err(Recording {
                frames: 0,
                ..ok.clone()
            })
            .starts_with("--frames must be")
        );
        assert!(
            err(Recording {
                frames: 9,
                ..ok.clone()
            })
            .contains("--max-spp of at least 9")
        );
        assert!(
            err(Recording {
                delay_ms: 5,
                ..ok.clone()
            })
            .starts_with("--delay-ms")
        );
        assert!(
            err(Recording {
                exposure: Some(f64::NAN),
                ..ok.clone()
            })
            .starts_with("--exposure")
        );
        let mut wide = ok.clone();
        wide.scene.plane.width = 4096;
        assert!(err(wide).starts_with("--width must be between 8 and 512"));
    }
}
