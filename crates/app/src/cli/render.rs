//! `lightpick render`: a progressive rendering of a scene, its error against the exact
//! reference, and a convergence series at power-of-two samples per pixel.
//!
//! PNG mappings (`--map`):
//! * `tonemap` (default): irradiance `E` → `L = exposure·E` → Reinhard `L/(1+L)` → sRGB,
//!   grey ([`lightpick_core::render::tonemap_value`]); the exposure defaults to
//!   `1/mean(reference)`, so an average pixel maps to display value `srgb(0.5)`.
//! * `error`: the relative error `|Ê − E|/E` of each pixel on a log scale from 0.1 % to
//!   1000 %, in viridis (dark = accurate); magenta marks a non-finite value
//!   ([`lightpick_core::draw::error_color`]). Needs a reference over every pixel.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context as _, bail};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use lightpick_core::draw::{auto_exposure, error_color};
use lightpick_core::gpu::{GpuContext, GpuRenderer};
use lightpick_core::render::{
    Accumulator, CpuRenderer, Efficiency, ErrorMetrics, Reference, SeriesPoint, efficiency,
    error_metrics, rmse, series_spp, tonemap_rgba8,
};
use lightpick_core::scene::{MAX_PIXELS, MAX_PLANE_SIDE, Scene};
use lightpick_core::{Scaled, Scheme};
use serde_json::json;

use super::device::{Device, choose};
use super::input::PositionedArgs;

/// The largest `--spp` accepted.
const MAX_SPP: u32 = 1 << 20;

/// How the PNG shows the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Mapping {
    /// Reinhard tonemap of the irradiance, sRGB grey.
    Tonemap,
    /// Relative error against the reference, log scale, viridis.
    Error,
}

/// Arguments of `lightpick render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene to render.
    #[command(flatten)]
    pub scene: PositionedArgs,
    /// uniform, power (alias), alias-one-random, cdf (CPU only), spatial (by contribution
    /// at each pixel: exact for ≤ 16 lights, a light tree beyond).
    #[arg(long, default_value = "power")]
    pub scheme: Scheme,
    /// Samples per pixel.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// cpu or gpu; by default the GPU when an adapter exists, else the CPU (with a notice).
    #[arg(long, value_enum)]
    pub device: Option<Device>,
    /// Override the scene's image width.
    #[arg(long)]
    pub width: Option<u32>,
    /// Override the scene's image height.
    #[arg(long)]
    pub height: Option<u32>,
    /// PNG output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// How the PNG maps the image: tonemap (default) or error.
    #[arg(long, value_enum, default_value_t = Mapping::Tonemap)]
    pub map: Mapping,
    /// Exposure of the tonemap (default: 1 / mean reference irradiance).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f64>,
    /// HDR output (an .exr file of 32-bit float irradiance).
    #[arg(long, value_name = "FILE")]
    pub hdr: Option<PathBuf>,
    /// Write the statistics (JSON) to this file.
    #[arg(long, value_name = "FILE")]
    pub stats: Option<PathBuf>,
    /// Print the statistics as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Renders and writes the requested outputs.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    check_numbers(args)?;
    let Some(mut scene) = args.scene.load("render")? else {
        bail!("no scene given: use --scene FILE or --preset NAME");
    };
    resize(&mut scene, args.width, args.height)?;
    let ctx = open_device(args, &scene)?;

    let started = Instant::now();
    let reference = Reference::compute(&scene);
    let reference_seconds = started.elapsed().as_secs_f64();
    if let Some(overflow) = reference.overflow() {
        anyhow::bail!("{overflow}");
    }

    let mut renderer = match &ctx {
        Some(ctx) => Progressive::Gpu(Box::new(GpuRenderer::new(
            ctx,
            &scene,
            args.scheme,
            args.seed,
        )?)),
        None => Progressive::Cpu(Box::new(CpuRenderer::new(&scene, args.scheme, args.seed))),
    };
    let (series, acc) = render_series(&mut renderer, &reference, args.spp)?;
    let exposure = args
        .exposure
        .unwrap_or_else(|| auto_exposure(reference.values()));
    if let Some(path) = &args.out {
        write_png(path, &acc, &reference, args.map, exposure)?;
    }
    if let Some(path) = &args.hdr {
        write_exr(path, &acc)?;
    }
    let seconds = series.last().map_or(0.0, |p| p.seconds);
    let rendered = Rendered {
        scene: &scene,
        ctx: ctx.as_ref(),
        reference: &reference,
        reference_seconds,
        acc: &acc,
        metrics: error_metrics(&acc, &reference),
        efficiency: efficiency(&acc, seconds),
        seconds,
        series,
        exposure,
    };
    rendered.report(args)
}

/// Refuses a `--spp` or `--exposure` the renderer cannot use.
fn check_numbers(args: &RenderArgs) -> anyhow::Result<()> {
    if args.spp == 0 || args.spp > MAX_SPP {
        bail!("--spp must be between 1 and {MAX_SPP} (got {})", args.spp);
    }
    if let Some(e) = args.exposure
        && !(e.is_finite() && e > 0.0)
    {
        bail!("--exposure must be a positive finite number (got {e})");
    }
    Ok(())
}

/// The GPU to render on, or `None` for the CPU. What keeps the GPU from rendering `scene`
/// is known before opening it: the default device then takes the CPU with a notice; an
/// explicit `--device gpu` opens the GPU and gets the renderer's refusal as its error.
fn open_device(args: &RenderArgs, scene: &Scene) -> anyhow::Result<Option<GpuContext>> {
    let gpu_refusal = if args.scheme == Scheme::Cdf {
        Some("the cdf scheme renders on the CPU".to_owned())
    } else {
        GpuRenderer::check_scene(scene)
            .err()
            .map(|e| format!("{e}; using the CPU"))
    };
    let ctx = choose(args.device, gpu_refusal.is_none())?;
    if args.device.is_none()
        && let Some(refusal) = &gpu_refusal
    {
        eprintln!("notice: {refusal}");
    }
    Ok(ctx)
}

/// A finished render and what it was measured against, for the report.
struct Rendered<'a> {
    scene: &'a Scene,
    ctx: Option<&'a GpuContext>,
    reference: &'a Reference,
    reference_seconds: f64,
    acc: &'a Accumulator,
    metrics: ErrorMetrics,
    efficiency: Efficiency,
    /// Seconds of rendering (the last series point's).
    seconds: f64,
    series: Vec<SeriesPoint>,
    exposure: f64,
}

impl Rendered<'_> {
    /// Writes `--stats`, then prints the JSON (`--json`) or the text report.
    fn report(&self, args: &RenderArgs) -> anyhow::Result<()> {
        let stats = self.stats_json(args);
        if let Some(path) = &args.stats {
            let text = serde_json::to_string_pretty(&stats)?;
            lightpick_core::atomic_file::write_bytes_atomically(path, text.as_bytes())
                .with_context(|| format!("--stats {}", path.display()))?;
        }
        if args.json {
            super::print_json(&stats)?;
        } else {
            self.print_text(args);
        }
        Ok(())
    }

    /// Pixel samples taken: spp × pixels.
    fn samples(&self) -> f64 {
        f64::from(self.acc.samples_per_pixel) * self.scene.plane.pixel_count() as f64
    }

    /// The statistics object of `--json` and `--stats`.
    fn stats_json(&self, args: &RenderArgs) -> serde_json::Value {
        let (scene, acc, reference) = (self.scene, self.acc, self.reference);
        let (metrics, eff, seconds) = (&self.metrics, &self.efficiency, self.seconds);
        json!({
            "scene": scene.name,
            "lights": scene.light_count(),
            "scheme": args.scheme.name(),
            "device": if self.ctx.is_some() { "gpu" } else { "cpu" },
            "adapter": self.ctx.map(GpuContext::description),
            "seed": args.seed,
            "spp": acc.samples_per_pixel,
            "width": acc.width,
            "height": acc.height,
            "rmse": metrics.rmse,
            "rmse_log10": metrics.rmse_log10,
            "rel_mse": metrics.rel_mse,
            "seconds": seconds,
            "samples_per_second": self.samples() / seconds,
            "variance_per_sample": eff.variance_per_sample,
            "variance_log10": eff.variance_log10,
            "normalized_variance": eff.normalized_variance,
            "normalized_variance_log10": eff.normalized_variance_log10,
            "seconds_per_sample": eff.seconds_per_sample,
            "efficiency": eff.efficiency,
            "efficiency_log10": eff.efficiency_log10,
            "exposure": self.exposure,
            "reference": {
                "pixels": reference.pixels().len(),
                "complete": reference.is_complete(),
                "seconds": self.reference_seconds,
            },
            "series": self.series,
        })
    }

    /// The text report: what was rendered, its error, speed and efficiency.
    fn print_text(&self, args: &RenderArgs) {
        let (scene, acc, reference) = (self.scene, self.acc, self.reference);
        let (metrics, eff, seconds) = (&self.metrics, &self.efficiency, self.seconds);
        println!(
            "{} ({} lights), {}×{}, {} spp, scheme {}, {}",
            scene.name,
            scene.light_count(),
            acc.width,
            acc.height,
            acc.samples_per_pixel,
            args.scheme,
            self.ctx
                .map_or_else(|| "CPU".to_owned(), |c| format!("GPU {}", c.description()))
        );
        println!(
            "RMSE {:.4}  relMSE {:.4e}  {:.3} s  {:.3e} samples/s  efficiency {:.3}",
            rmse_scaled(metrics),
            metrics.rel_mse,
            seconds,
            self.samples() / seconds,
            eff.efficiency
        );
        if !reference.is_complete() {
            println!(
                "(the reference covers {} fixed pixels: lights × pixels exceeds its budget)",
                reference.pixels().len()
            );
        }
    }
}

/// The RMSE at any magnitude: its `f64` value, or the value of its `log10` beyond `f64`.
fn rmse_scaled(metrics: &ErrorMetrics) -> Scaled {
    if metrics.rmse.is_finite() {
        Scaled::from_f64(metrics.rmse)
    } else {
        Scaled::from_log10(metrics.rmse_log10)
    }
}

/// Applies `--width/--height`, refusing absurd sizes.
fn resize(scene: &mut Scene, width: Option<u32>, height: Option<u32>) -> anyhow::Result<()> {
    for (flag, value) in [("--width", width), ("--height", height)] {
        if let Some(v) = value
            && !(1..=MAX_PLANE_SIDE).contains(&v)
        {
            bail!("{flag} must be between 1 and {MAX_PLANE_SIDE} (got {v})");
        }
    }
    let w = width.unwrap_or(scene.plane.width);
    let h = height.unwrap_or(scene.plane.height);
    if w as usize * h as usize > MAX_PIXELS {
        bail!("{w}×{h} pixels exceed the limit of {MAX_PIXELS}");
    }
    scene.plane.width = w;
    scene.plane.height = h;
    Ok(())
}

/// The CPU or GPU renderer behind one progressive interface.
enum Progressive {
    Cpu(Box<CpuRenderer>),
    Gpu(Box<GpuRenderer>),
}

impl Progressive {
    /// Adds samples and waits for them (the GPU is synchronized by reading back).
    fn accumulate(&mut self, spp: u32) -> anyhow::Result<Accumulator> {
        Ok(match self {
            Progressive::Cpu(r) => {
                r.accumulate(spp);
                r.accumulator().clone()
            }
            Progressive::Gpu(r) => {
                r.accumulate(spp)?;
                r.readback()?
            }
        })
    }
}

/// Renders to each count of [`series_spp`], timing only the rendering (for the GPU the
/// readback that waits for it is included), with a progress bar on a terminal.
fn render_series(
    renderer: &mut Progressive,
    reference: &Reference,
    spp: u32,
) -> anyhow::Result<(Vec<SeriesPoint>, Accumulator)> {
    let bar = ProgressBar::new(u64::from(spp));
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} spp  {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut seconds = 0.0;
    let mut have = 0;
    let mut series = Vec::new();
    let mut last = None;
    for target in series_spp(spp) {
        let started = Instant::now();
        let acc = renderer.accumulate(target - have)?;
        seconds += started.elapsed().as_secs_f64();
        have = target;
        bar.set_position(u64::from(target));
        series.push(SeriesPoint {
            spp: target,
            rmse: rmse(&acc, reference),
            seconds,
        });
        last = Some(acc);
    }
    bar.finish_and_clear();
    let acc = last.ok_or_else(|| anyhow::anyhow!("nothing was rendered"))?;
    Ok((series, acc))
}

fn write_png(
    path: &Path,
    acc: &Accumulator,
    reference: &Reference,
    map: Mapping,
    exposure: f64,
) -> anyhow::Result<()> {
    let image = acc.image();
    let rgba = match map {
        Mapping::Tonemap => tonemap_rgba8(&image, exposure),
        Mapping::Error => {
            let Some(exact) = reference.image() else {
                bail!(
                    "--map error needs a reference over every pixel; this scene's covers {} \
                     (lower --width/--height)",
                    reference.pixels().len()
                );
            };
            image
                .iter()
                .zip(exact)
                .flat_map(|(&e, &r)| error_color(e, r).0)
                .collect()
        }
    };
    let buffer = image::RgbaImage::from_raw(acc.width, acc.height, rgba)
        .ok_or_else(|| anyhow::anyhow!("image buffer size mismatch"))?;
    let mut png = std::io::Cursor::new(Vec::new());
    buffer
        .write_to(&mut png, image::ImageFormat::Png)
        .with_context(|| format!("--out {}", path.display()))?;
    lightpick_core::atomic_file::write_bytes_atomically(path, png.get_ref())
        .with_context(|| format!("--out {}", path.display()))
}

fn write_exr(path: &Path, acc: &Accumulator) -> anyhow::Result<()> {
    let data: Vec<f32> = acc
        .image()
        .iter()
        .flat_map(|&e| {
            let v = e as f32;
            [v, v, v]
        })
        .collect();
    let buffer = image::Rgb32FImage::from_raw(acc.width, acc.height, data)
        .ok_or_else(|| anyhow::anyhow!("image buffer size mismatch"))?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    buffer
        .write_to(&mut bytes, image::ImageFormat::OpenExr)
        .with_context(|| format!("--hdr {}", path.display()))?;
    lightpick_core::atomic_file::write_bytes_atomically(path, bytes.get_ref())
        .with_context(|| format!("--hdr {}", path.display()))
}
