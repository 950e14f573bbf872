//! The arguments of `lightpick bench` and what they resolve to: the table sizes to time and
//! the scenes to render (presets, then `--scene` files), with their defaults.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::scene::Scene;

/// `N` of a full run: 3 to `1.6·10^7`.
const FULL_SIZES: [usize; 8] = [
    3, 64, 1000, 10_000, 100_000, 1_000_000, 4_000_000, 16_000_000,
];
/// `N` of a `--quick` run.
const QUICK_SIZES: [usize; 4] = [3, 1000, 100_000, 1_000_000];
/// The largest `N` accepted by `--sizes`.
const MAX_SIZE: usize = 1 << 26;
/// Presets of a `--quick` run (`million` is left out: its reference dominates the run; the
/// two spot scenes stay, for the spatial scheme's figures where power picking fails).
const QUICK_PRESETS: [&str; 8] = [
    "worked-example",
    "equal",
    "dominant",
    "zeros",
    "heavy-tail",
    "extreme-range",
    "stage",
    "gallery",
];

/// Arguments of `lightpick bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// A short run (under a minute in release on two cores): fewer sizes, smaller renders.
    #[arg(long)]
    pub quick: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write a PNG of RMSE against rendering time per scheme (the heavy-tail preset, or
    /// the first one rendered).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Table sizes to time instead of the defaults, comma separated (e.g. `3,1000`).
    #[arg(long, value_name = "LIST")]
    pub sizes: Option<String>,
    /// Presets to render instead of the defaults, comma separated, or `none`.
    #[arg(long, value_name = "LIST")]
    pub presets: Option<String>,
    /// A scene file to render too (lightpick JSON, glTF/GLB, CSV; repeatable), after the
    /// presets; named by its file name.
    #[arg(long, value_name = "FILE")]
    pub scene: Vec<PathBuf>,
    /// The receiver's height for `--scene` files (glTF's y), instead of the file's ground.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub floor: Option<f64>,
    /// Samples per pixel of each render (default 1024, `--quick` 256).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Skip the GPU measurement.
    #[arg(long)]
    pub no_gpu: bool,
    /// Seed of the powers, the samples and the renders.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// A scene to render, with the name its rows carry (the preset's, or the file's stem).
pub(super) struct NamedScene {
    /// The preset's name or the file's name.
    pub(super) name: String,
    /// The scene as loaded (at its own resolution).
    pub(super) scene: Arc<Scene>,
}

impl BenchArgs {
    /// The table sizes to time: `--sizes`, or the defaults of a full or `--quick` run.
    pub(super) fn sizes(&self) -> anyhow::Result<Vec<usize>> {
        let Some(list) = &self.sizes else {
            return Ok(if self.quick {
                QUICK_SIZES.to_vec()
            } else {
                FULL_SIZES.to_vec()
            });
        };
        list.split(',')
            .map(|s| {
                let n: usize = s
                    .trim()
                    .parse()
                    .with_context(|| format!("--sizes: '{}' is not a count", s.trim()))?;
                if n == 0 || n > MAX_SIZE {
                    bail!("--sizes: each size must be between 1 and {MAX_SIZE} (got {n})");
                }
                Ok(n)
            })
            .collect()
    }

    /// The presets to render (`--presets`, or the defaults) and then the `--scene` files.
    pub(super) fn scenes(&self) -> anyhow::Result<Vec<NamedScene>> {
        let names: Vec<String> = match &self.presets {
            None if self.quick => QUICK_PRESETS.iter().map(|s| (*s).to_owned()).collect(),
            None if !self.scene.is_empty() => Vec::new(),
            None => lightpick_core::scene::PRESET_NAMES
                .iter()
                .map(|s| (*s).to_owned())
                .collect(),
            Some(list) if list.trim() == "none" => Vec::new(),
            Some(list) => list.split(',').map(|s| s.trim().to_owned()).collect(),
        };
        let mut out = Vec::new();
        for name in names {
            let scene = Scene::preset(&name).with_context(|| format!("--presets '{name}'"))?;
            out.push(NamedScene {
                name,
                scene: Arc::new(scene),
            });
        }
        for path in &self.scene {
            let scene = super::super::input::read_scene(path, self.floor, Some("--scene"))?.scene;
            out.push(NamedScene {
                name: path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                ),
                scene: Arc::new(scene),
            });
        }
        Ok(out)
    }

    /// Samples per pixel of each render: `--spp`, or 1024 (`--quick`: 256); at least 1.
    pub(super) fn spp(&self) -> anyhow::Result<u32> {
        let spp = self.spp.unwrap_or(if self.quick { 256 } else { 1024 });
        if spp == 0 {
            bail!("--spp must be at least 1");
        }
        Ok(spp)
    }
}
