//! The convergence animation: the uniform, alias (power) and spatial progressive images of a
//! scene converging side by side, as an animated GIF for slides, each frame captioned with
//! every panel's samples per pixel and RMSE against the exact reference (the figure
//! `lightpick render` prints). `lightpick plot animation` (`crate::cli`) and the app's
//! File → "Export animation…" both record it through [`record`]; it sits below both, so
//! neither imports the other.
//!
//! # What a frame is
//! Frame `k` of `F` shows the three [`CpuRenderer`] images (one per scheme, the same seed)
//! after `s_k` samples per pixel, with `s_0 = 1`, `s_{F−1} = M` (`max_spp`) and the counts
//! between spaced geometrically ([`frame_spp`]). The renderers continue from one frame to the
//! next, so frame `k + 1` adds `s_{k+1} − s_k` samples to the same estimates. Every image of
//! every frame is tonemapped with one exposure (`exposure`, by default `1 / mean` of the
//! reference), so what changes from frame to frame is the noise, not the brightness.
//!
//! # Determinism
//! The CPU renderer and the reference are the same bits whatever the thread count, the
//! drawing is pure, and the GIF palettes come from `image`'s deterministic `NeuQuant`
//! quantizer (one local palette per frame): the same recording writes the same bytes.

mod limits;

use anyhow::{Context as _, bail};
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use lightpick_core::Scheme;
use lightpick_core::draw::{
    self, AnimationFrame, AnimationPanel, Theme, animation_zoom, auto_exposure,
    palette::scheme_color,
};
use lightpick_core::render::{CpuRenderer, Reference, error_metrics};
use lightpick_core::scene::Scene;
use lightpick_core::spatial::EXACT_MAX_LIGHTS;

pub use limits::{DELAY_RANGE, MAX_FRAMES, MAX_SPP, SIDE_RANGE, Timing, check_side, frame_spp};

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

/// `NeuQuant`'s sampling factor for frames of more than 256 colours (1 = best, 30 =
/// fastest; 10 is the gif crate's suggested balance).
const QUANTIZER_SPEED: i32 = 10;

/// The schemes shown, left to right, with their captions.
pub const PANELS: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

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
            let stats = FrameStats { spp, rmse };
            let rgba = draw_frame(recording, &images, stats, exposure, (k, spps.len()))?;
            frame_size = rgba.dimensions();
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
            frames.push(stats);
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

/// Frame `progress.0` of `progress.1`: the three panels' `images` (in [`PANELS`] order)
/// captioned with `stats`, titled with the scene, as RGBA pixels.
fn draw_frame(
    recording: &Recording,
    images: &[Vec<f64>],
    FrameStats { spp, rmse }: FrameStats,
    exposure: f64,
    progress: (usize, usize),
) -> anyhow::Result<RgbaImage> {
    let scene = &recording.scene;
    let (width, height) = (scene.plane.width as usize, scene.plane.height as usize);
    let lights = scene.light_count();
    let panels: Vec<AnimationPanel<'_>> = PANELS
        .iter()
        .zip(images)
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
            zoom: animation_zoom(width),
            panels: &panels,
            exposure,
            title: &title,
            subtitle: &subtitle,
            progress,
        },
        recording.theme,
    )?;
    RgbaImage::from_raw(pixmap.width(), pixmap.height(), draw::to_rgba8(&pixmap))
        .context("frame buffer size")
}
