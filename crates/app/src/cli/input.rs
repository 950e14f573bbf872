//! Where powers and scenes come from: `--powers`, `--powers-file`, `--scene`, `--preset`.

use std::path::PathBuf;

use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::LightPowers;
use lightpick_core::scene::{PRESET_NAMES, Scene};

/// The sources of light powers shared by every subcommand; exactly one is used.
#[derive(Debug, Args, Clone, Default)]
pub struct PowersArgs {
    /// Light powers, comma separated, e.g. `2,5,20`.
    #[arg(long, value_name = "LIST", allow_hyphen_values = true)]
    pub powers: Option<String>,
    /// A file of powers separated by commas or white space.
    #[arg(long, value_name = "FILE", conflicts_with = "powers")]
    pub powers_file: Option<PathBuf>,
    /// The powers of a scene file's lights.
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// Where a scene comes from: a JSON file or a built-in preset.
#[derive(Debug, Args, Clone, Default)]
pub struct SceneArgs {
    /// A JSON scene file.
    #[arg(long, value_name = "FILE", conflicts_with = "preset")]
    pub scene: Option<PathBuf>,
    /// A built-in scene: seed, equal, dominant, zeros, heavy-tail, million, extreme-range.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
}

impl SceneArgs {
    /// The scene named, or `None` when neither `--scene` nor `--preset` was given.
    pub fn load(&self) -> anyhow::Result<Option<Scene>> {
        if let Some(path) = &self.scene {
            let scene = Scene::load(path).with_context(|| format!("--scene {}", path.display()))?;
            return Ok(Some(scene));
        }
        if let Some(name) = &self.preset {
            if !PRESET_NAMES.contains(&name.as_str()) {
                bail!(
                    "--preset: unknown preset '{name}' (expected one of {})",
                    PRESET_NAMES.join(", ")
                );
            }
            return Ok(Some(Scene::preset(name)?));
        }
        Ok(None)
    }
}

impl PowersArgs {
    /// Reads and validates the powers from whichever source was given.
    pub fn load(&self) -> anyhow::Result<LightPowers> {
        let given = [
            self.powers.is_some(),
            self.powers_file.is_some(),
            self.scene.scene.is_some() || self.scene.preset.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() > 1 {
            bail!("give the powers once: --powers, --powers-file, or --scene/--preset");
        }
        let values = if let Some(list) = &self.powers {
            parse_numbers(list, &[','], "--powers")?
        } else if let Some(path) = &self.powers_file {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("--powers-file {}", path.display()))?;
            parse_numbers(
                &text,
                &[',', ' ', '\t', '\n', '\r'],
                &path.display().to_string(),
            )?
        } else if let Some(scene) = self.scene.load()? {
            return Ok(scene.powers);
        } else {
            bail!(
                "no powers given: use --powers 2,5,20, --powers-file FILE, --scene FILE or \
                 --preset NAME"
            );
        };
        LightPowers::new(values).map_err(Into::into)
    }
}

/// Parses numbers separated by any of `separators`; the error names the item (0-based,
/// matching light indices) and the text found.
pub(crate) fn parse_numbers(
    text: &str,
    separators: &[char],
    source: &str,
) -> anyhow::Result<Vec<f64>> {
    let items: Vec<&str> = if separators.len() == 1 {
        text.split(separators[0]).map(str::trim).collect()
    } else {
        text.split(|c| separators.contains(&c))
            .filter(|s| !s.trim().is_empty())
            .map(str::trim)
            .collect()
    };
    if items.len() == 1 && items[0].is_empty() {
        return Ok(Vec::new());
    }
    items
        .iter()
        .enumerate()
        .map(|(i, item)| {
            if item.is_empty() {
                bail!("{source}: item {i} is empty");
            }
            item.parse::<f64>()
                .map_err(|_| anyhow::anyhow!("{source}: item {i} ('{item}') is not a number"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_comma_lists_with_spaces() {
        assert_eq!(
            parse_numbers("2, 5,20", &[','], "--powers").unwrap(),
            vec![2.0, 5.0, 20.0]
        );
    }

    #[test]
    fn names_the_bad_item() {
        let err = parse_numbers("2,x,20", &[','], "--powers").unwrap_err();
        assert_eq!(err.to_string(), "--powers: item 1 ('x') is not a number");
        let err = parse_numbers("2,,20", &[','], "--powers").unwrap_err();
        assert_eq!(err.to_string(), "--powers: item 1 is empty");
    }

    #[test]
    fn files_accept_any_white_space() {
        assert_eq!(
            parse_numbers("1 2\n3,\t4\n", &[',', ' ', '\t', '\n'], "f").unwrap(),
            vec![1.0, 2.0, 3.0, 4.0]
        );
    }
}
