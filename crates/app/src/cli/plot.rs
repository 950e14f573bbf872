//! `lightpick plot`: the app's pictures drawn headless (tiny-skia → PNG), for handouts and
//! snapshot tests: the alias-table diagram, the pmf histogram, the convergence plot, the
//! image sheet, the convergence animation (GIF, [`super::animation`]), the light tree from
//! above ([`super::plot_tree`]) and the schemes' per-pixel variance maps.

use anyhow::bail;
use clap::{Args, Subcommand, ValueEnum};
use lightpick_core::draw::{
    self, ConvergenceAxis, ConvergenceSeries, HistogramData, SchemeCounts, SheetImages,
};
use lightpick_core::render::{CpuRenderer, Reference, cpu_convergence};
use lightpick_core::stats::variance_map::VarianceMap;
use lightpick_core::{AliasTable, PointFreeSampler as _, Sampler, Scheme};
use serde_json::json;

use super::input::{PositionedArgs, PowersArgs};
use super::plot_output::{OutputArgs, scene_or_seed};
use super::sample::{check_count, count_cpu};

/// Arguments of `lightpick plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// Which picture.
    #[command(subcommand)]
    pub kind: PlotKind,
}

/// The pictures `lightpick plot` draws.
#[derive(Debug, Subcommand)]
pub enum PlotKind {
    /// The alias-table diagram: unit columns split at their thresholds.
    Table {
        /// Where the powers come from.
        #[command(flatten)]
        powers: PowersArgs,
        /// The output picture.
        #[command(flatten)]
        output: OutputArgs,
    },
    /// Expected pmf beside observed frequencies of uniform and alias sampling.
    Histogram {
        /// Where the powers come from.
        #[command(flatten)]
        powers: PowersArgs,
        /// Samples per scheme.
        #[arg(long, default_value_t = 10_000)]
        count: u64,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The output picture.
        #[command(flatten)]
        output: OutputArgs,
    },
    /// Log-log RMSE against samples per pixel (or seconds) per scheme.
    ///
    /// The schemes default to uniform, alias, cdf and spatial. A zero-variance series (the
    /// exact spatial pick on ≤ 16 lights, whose RMSE is rounding) is left off the axes and
    /// named in the legend.
    Convergence {
        /// The scene (default: the worked example).
        #[command(flatten)]
        scene: PositionedArgs,
        /// The schemes plotted, comma separated: uniform, alias (or power),
        /// alias-one-random, cdf, spatial.
        #[arg(
            long,
            value_name = "LIST",
            value_delimiter = ',',
            default_values_t = [Scheme::Uniform, Scheme::Alias, Scheme::Cdf, Scheme::Spatial]
        )]
        schemes: Vec<Scheme>,
        /// Largest samples per pixel of the series.
        #[arg(long, default_value_t = 256)]
        spp: u32,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Horizontal axis: spp or seconds.
        #[arg(long, value_enum, default_value_t = Axis::Spp)]
        axis: Axis,
        /// The output picture.
        #[command(flatten)]
        output: OutputArgs,
    },
    /// Uniform | power | spatial | reference, with error maps, at equal samples per pixel.
    Sheet {
        /// The scene (default: the worked example).
        #[command(flatten)]
        scene: PositionedArgs,
        /// Samples per pixel of the three estimates.
        #[arg(long, default_value_t = 4)]
        spp: u32,
        /// Random seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Image width in pixels (default: the scene's, capped at 160).
        #[arg(long)]
        image_width: Option<u32>,
        /// The output picture.
        #[command(flatten)]
        output: OutputArgs,
    },
    /// An animated GIF of the uniform, alias and spatial images converging side by side,
    /// each frame captioned with every panel's spp and RMSE (for slides).
    ///
    /// Frames are spaced geometrically from 1 spp to --max-spp; the same arguments write the
    /// same bytes.
    Animation(super::animation::AnimationArgs),
    /// The light tree seen from above: lights by power, the groups at a depth, and one
    /// spatial pick recorded at a pixel (its path drawn, its steps printed).
    Tree(super::plot_tree::TreeArgs),
    /// Uniform, power and spatial per-pixel variance of one sample side by side, on one
    /// log colour scale: exact where lights × pixels fit the budget, else estimated.
    Variance {
        /// The scene (default: the worked example).
        #[command(flatten)]
        scene: PositionedArgs,
        /// Samples per pixel of an estimated map (used only beyond the exact budget).
        #[arg(long, default_value_t = 16)]
        spp: u32,
        /// Random seed of an estimated map.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Print the means and the method as one JSON object.
        #[arg(long)]
        json: bool,
        /// The output picture.
        #[command(flatten)]
        output: OutputArgs,
    },
}

/// The convergence plot's horizontal axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Axis {
    /// Samples per pixel.
    Spp,
    /// Rendering seconds.
    Seconds,
}

/// Draws the requested picture.
pub fn run(args: &PlotArgs) -> anyhow::Result<()> {
    match &args.kind {
        PlotKind::Table { powers, output } => table(powers, output),
        PlotKind::Histogram {
            powers,
            count,
            seed,
            output,
        } => histogram(powers, *count, *seed, output),
        PlotKind::Convergence {
            scene,
            schemes,
            spp,
            seed,
            axis,
            output,
        } => convergence(scene, schemes, *spp, *seed, *axis, output),
        PlotKind::Sheet {
            scene,
            spp,
            seed,
            image_width,
            output,
        } => sheet(scene, *spp, *seed, *image_width, output),
        PlotKind::Animation(args) => super::animation::run(args),
        PlotKind::Tree(args) => super::plot_tree::run(args),
        PlotKind::Variance {
            scene,
            spp,
            seed,
            json,
            output,
        } => variance(scene, *spp, *seed, *json, output),
    }
}

/// `plot table`: the exact construction's diagram of the given powers.
fn table(powers: &PowersArgs, output: &OutputArgs) -> anyhow::Result<()> {
    let style = output.style()?;
    let powers = powers.load()?;
    let table = AliasTable::build_exact(&powers);
    output.write(&draw::table_diagram(
        &table,
        draw::fraction_denominator(&powers),
        &style,
    )?)
}

/// `plot histogram`: `count` picks of uniform and alias sampling against the pmf.
fn histogram(
    powers: &PowersArgs,
    count: u64,
    seed: u64,
    output: &OutputArgs,
) -> anyhow::Result<()> {
    let style = output.style()?;
    check_count(count)?;
    let powers = powers.load()?;
    let mut schemes = Vec::new();
    for scheme in [Scheme::Uniform, Scheme::Alias] {
        let sampler = Sampler::build(scheme, &powers);
        let expected = (0..sampler.light_count())
            .map(|i| sampler.probability(i))
            .collect();
        let counts = count_cpu(&sampler, count, seed);
        schemes.push(SchemeCounts::new(scheme, counts, expected)?);
    }
    let data = HistogramData {
        pmf: powers.pmf(),
        schemes,
    };
    output.write(&draw::histogram(&data, &style)?)
}

/// `plot convergence`: each scheme's RMSE against the exact reference, up to `spp`.
fn convergence(
    scene: &PositionedArgs,
    schemes: &[Scheme],
    spp: u32,
    seed: u64,
    axis: Axis,
    output: &OutputArgs,
) -> anyhow::Result<()> {
    let style = output.style()?;
    check_spp(spp)?;
    check_schemes(schemes)?;
    let scene = scene_or_seed(scene, "plot convergence")?;
    let reference = Reference::compute(&scene);
    let series: Vec<ConvergenceSeries> = cpu_convergence(&scene, &reference, schemes, seed, spp)
        .into_iter()
        .map(|s| ConvergenceSeries::of_measured(s.scheme, &s.series))
        .collect();
    let axis = match axis {
        Axis::Spp => ConvergenceAxis::Spp,
        Axis::Seconds => ConvergenceAxis::Seconds,
    };
    output.write(&draw::convergence(&series, axis, &style)?)
}

/// `plot sheet`: uniform, power and spatial images beside the reference, at `spp`.
fn sheet(
    scene: &PositionedArgs,
    spp: u32,
    seed: u64,
    image_width: Option<u32>,
    output: &OutputArgs,
) -> anyhow::Result<()> {
    let style = output.style()?;
    check_spp(spp)?;
    let mut scene = scene_or_seed(scene, "plot sheet")?;
    let width = image_width.unwrap_or(scene.plane.width.min(160));
    if !(8..=1024).contains(&width) {
        bail!("--image-width must be between 8 and 1024 (got {width})");
    }
    let aspect = f64::from(scene.plane.height) / f64::from(scene.plane.width);
    scene.plane.height = ((f64::from(width) * aspect).round() as u32).max(1);
    scene.plane.width = width;
    let reference = Reference::compute(&scene);
    let Some(exact) = reference.image() else {
        bail!(
            "the image sheet needs a reference over every pixel; {} lights × {} pixels \
             exceed its budget (lower --image-width)",
            scene.light_count(),
            scene.plane.pixel_count()
        );
    };
    let render = |scheme| {
        let mut r = CpuRenderer::new(&scene, scheme, seed);
        r.accumulate(spp);
        r.accumulator().image()
    };
    let uniform = render(Scheme::Uniform);
    let importance = render(Scheme::Alias);
    let spatial = render(Scheme::Spatial);
    let images = SheetImages {
        width: scene.plane.width as usize,
        height: scene.plane.height as usize,
        uniform: &uniform,
        importance: &importance,
        spatial: &spatial,
        reference: exact,
        spp: u64::from(spp),
        exposure: None,
    };
    output.write(&draw::image_sheet(&images, &style)?)
}

/// The schemes `plot variance` compares, left to right.
pub const VARIANCE_SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

/// `plot variance`: each scheme's [`VarianceMap`] on one shared log scale.
fn variance(
    scene: &PositionedArgs,
    spp: u32,
    seed: u64,
    print_json: bool,
    output: &OutputArgs,
) -> anyhow::Result<()> {
    let style = output.style()?;
    check_spp(spp)?;
    if spp < 2 {
        bail!("--spp must be at least 2 to estimate a variance (got {spp})");
    }
    let scene = scene_or_seed(scene, "plot variance")?;
    let maps = VARIANCE_SCHEMES.map(|scheme| VarianceMap::compute(&scene, scheme, spp, seed));
    let panels: Vec<(Scheme, &[f64])> = VARIANCE_SCHEMES
        .iter()
        .zip(&maps)
        .map(|(&s, m)| (s, m.values.as_slice()))
        .collect();
    let (exact, k) = (maps[0].exact, maps[0].samples_per_pixel);
    let sheet = draw::VarianceSheet {
        width: scene.plane.width as usize,
        height: scene.plane.height as usize,
        maps: &panels,
        exact,
        samples_per_pixel: k,
        lights: scene.light_count(),
    };
    output.write(&draw::variance_sheet(&sheet, &style)?)?;
    let method = draw::variance_method_line(exact, k);
    let rows: Vec<_> = panels
        .iter()
        .map(|&(scheme, values)| {
            let mean = draw::variance_mean(values);
            (scheme, mean, draw::variance_caption(scheme, mean))
        })
        .collect();
    if print_json {
        let schemes: Vec<_> = rows
            .iter()
            .map(|(scheme, mean, caption)| {
                json!({ "scheme": scheme.name(), "mean": mean, "caption": caption })
            })
            .collect();
        super::print_json(&json!({
            "width": scene.plane.width,
            "height": scene.plane.height,
            "lights": scene.light_count(),
            "exact": exact,
            "samples_per_pixel": k,
            "method": method,
            "schemes": schemes,
        }))?;
    } else {
        for (_, _, caption) in &rows {
            println!("{caption}");
        }
        println!("{method}; wrote {}", output.out.display());
    }
    Ok(())
}

fn check_spp(spp: u32) -> anyhow::Result<()> {
    if spp == 0 || spp > 1 << 16 {
        bail!("--spp must be between 1 and 65536 (got {spp})");
    }
    Ok(())
}

/// Refuses an empty `--schemes` list and a scheme named twice (`alias` and `power` are one).
fn check_schemes(schemes: &[Scheme]) -> anyhow::Result<()> {
    if schemes.is_empty() {
        bail!("--schemes: give at least one scheme");
    }
    for (i, s) in schemes.iter().enumerate() {
        if schemes[..i].contains(s) {
            bail!("--schemes: item {i} ('{s}') is already in the list");
        }
    }
    Ok(())
}
