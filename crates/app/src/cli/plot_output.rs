//! What every `lightpick plot` picture shares: where and how it is written (`--out`, size,
//! theme) and the scene it draws when none is named (the worked example). Apart from
//! [`super::plot`] so that the pictures with their own file ([`super::plot_tree`]) take them
//! without importing the dispatcher that imports them.

use std::path::PathBuf;

use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::draw::{self, Style, Theme};
use lightpick_core::scene::Scene;

use super::input::PositionedArgs;

/// Where and how the picture is written.
#[derive(Debug, Args)]
pub struct OutputArgs {
    /// The PNG to write.
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
    /// Picture width in pixels.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Picture height in pixels.
    #[arg(long, default_value_t = 500)]
    pub height: u32,
    /// Light text on a dark background.
    #[arg(long)]
    pub dark: bool,
}

impl OutputArgs {
    /// The drawing's size and theme; refuses a size outside 64 to 8192.
    pub fn style(&self) -> anyhow::Result<Style> {
        for (flag, v) in [("--width", self.width), ("--height", self.height)] {
            if !(64..=8192).contains(&v) {
                bail!("{flag} must be between 64 and 8192 (got {v})");
            }
        }
        Ok(Style {
            width: self.width,
            height: self.height,
            theme: if self.dark { Theme::Dark } else { Theme::Light },
        })
    }

    /// Writes the picture to `--out`.
    pub fn write(&self, pixmap: &draw::Pixmap) -> anyhow::Result<()> {
        draw::write_png(pixmap, &self.out).with_context(|| format!("--out {}", self.out.display()))
    }
}

/// The scene named by `args`, or the worked example when none is.
pub fn scene_or_seed(args: &PositionedArgs, command: &str) -> anyhow::Result<Scene> {
    match args.load(command)? {
        Some(scene) => Ok(scene),
        None => Ok(Scene::preset("worked-example")?),
    }
}
