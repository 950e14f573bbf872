//! Where powers and scenes come from: `--powers`, `--powers-file`, `--scene`, `--preset`.

use std::path::PathBuf;

use anyhow::{Context as _, bail};
use clap::Args;
use lightpick_core::LightPowers;
use lightpick_core::scene::{LoadOptions, Loaded, PRESET_NAMES, Scene};

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

/// Where a scene comes from: a file (lightpick JSON, glTF/GLB, CSV) or a built-in preset.
#[derive(Debug, Args, Clone, Default)]
pub struct SceneArgs {
    /// A scene file: lightpick JSON, glTF 2.0 (.gltf/.glb with `KHR_lights_punctual`) or a
    /// CSV / white-space list of x, y, z, power.
    #[arg(long, value_name = "FILE", conflicts_with = "preset")]
    pub scene: Option<PathBuf>,
    /// A built-in scene: worked-example (also `seed`), equal, dominant, zeros, heavy-tail,
    /// million, extreme-range, grid, stage, gallery.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// The receiver's height (lightpick's z, glTF's y): every light's z becomes z − H.
    /// Default: the file's ground, z = 0.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub floor: Option<f64>,
}

/// Reads a scene file of any format through the one loader (`lightpick_core::scene::load`),
/// the receiver at `floor`. Errors start with how the file was named: `--scene FILE: ` for
/// the flag (`door = Some("--scene")`), `FILE: ` (the path as typed) for `lightpick FILE`.
pub fn read_scene(
    path: &std::path::Path,
    floor: Option<f64>,
    door: Option<&str>,
) -> anyhow::Result<Loaded> {
    lightpick_core::scene::load(path, &LoadOptions { floor }).with_context(|| match door {
        Some(flag) => format!("{flag} {}", path.display()),
        None => path.display().to_string(),
    })
}

impl SceneArgs {
    /// The scene named, or `None` when neither `--scene` nor `--preset` was given.
    pub fn load(&self) -> anyhow::Result<Option<Scene>> {
        Ok(self.load_with_report()?.map(|l| l.scene))
    }

    /// [`SceneArgs::load`] with what the file held (a preset reports as JSON).
    pub fn load_with_report(&self) -> anyhow::Result<Option<Loaded>> {
        if let Some(path) = &self.scene {
            return Ok(Some(read_scene(path, self.floor, Some("--scene"))?));
        }
        if let Some(name) = &self.preset {
            // The core's names, the worked example's former name `seed` among them.
            let Some(text) = Scene::preset_source(name) else {
                bail!(
                    "--preset: unknown preset '{name}' (expected one of {})",
                    PRESET_NAMES.join(", ")
                );
            };
            let loaded = lightpick_core::scene::load_bytes(
                text.as_bytes(),
                name,
                Some("json"),
                &LoadOptions { floor: self.floor },
            )
            .with_context(|| format!("--preset {name}"))?;
            return Ok(Some(loaded));
        }
        if self.floor.is_some() {
            bail!("--floor: give a scene (--scene FILE or --preset NAME) to move its receiver");
        }
        Ok(None)
    }
}

/// The scene of a command that needs light positions (`render`, `plot convergence`,
/// `plot sheet`): `--scene FILE` or `--preset NAME`.
///
/// Bare powers (`--powers`, `--powers-file`) place no light anywhere, and no convention
/// here invents positions for them, so those flags are accepted (hidden from the help) only
/// to be refused with a message that says a scene or preset is needed, rather than clap's
/// "unexpected argument".
#[derive(Debug, Args, Clone, Default)]
pub struct PositionedArgs {
    /// The scene file or preset.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Refused: powers without positions (see the type's docs).
    #[arg(long, value_name = "LIST", allow_hyphen_values = true, hide = true)]
    pub powers: Option<String>,
    /// Refused: powers without positions (see the type's docs).
    #[arg(long, value_name = "FILE", hide = true)]
    pub powers_file: Option<PathBuf>,
}

impl PositionedArgs {
    /// The scene named, `None` when neither `--scene` nor `--preset` was given; refuses
    /// `--powers`/`--powers-file`, naming `command` (e.g. `plot convergence`).
    pub fn load(&self, command: &str) -> anyhow::Result<Option<Scene>> {
        let flag = if self.powers.is_some() {
            Some("--powers")
        } else if self.powers_file.is_some() {
            Some("--powers-file")
        } else {
            None
        };
        if let Some(flag) = flag {
            bail!(
                "{flag}: {command} needs light positions, which bare powers do not have; \
                 use --scene FILE or --preset NAME"
            );
        }
        self.scene.load()
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
            parse_numbers(list, false, "--powers")?
        } else if let Some(path) = &self.powers_file {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("--powers-file {}", path.display()))?;
            parse_numbers(&text, true, &path.display().to_string())?
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

/// Parses a list of numbers. Items are separated by commas and, when `whitespace` is set
/// (files), also by runs of white space. An item between two commas (or before a leading or
/// after a trailing comma) that holds nothing but white space is refused as empty, in
/// `--powers 2,,20` and in a file alike; the error names the item (0-based, matching light
/// indices) and the text found. A text with no item at all gives an empty list.
pub(crate) fn parse_numbers(
    text: &str,
    whitespace: bool,
    source: &str,
) -> anyhow::Result<Vec<f64>> {
    if text.trim().is_empty() {
        return Ok(Vec::new());
    }
    let mut items: Vec<&str> = Vec::new();
    for piece in text.split(',') {
        let before = items.len();
        if whitespace {
            items.extend(piece.split_whitespace());
        } else if !piece.trim().is_empty() {
            items.push(piece.trim());
        }
        if items.len() == before {
            bail!("{source}: item {before} is empty");
        }
    }
    items
        .iter()
        .enumerate()
        .map(|(i, item)| {
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
            parse_numbers("2, 5,20", false, "--powers").unwrap(),
            vec![2.0, 5.0, 20.0]
        );
        assert!(parse_numbers(" ", false, "--powers").unwrap().is_empty());
    }

    #[test]
    fn names_the_bad_item() {
        let err = parse_numbers("2,x,20", false, "--powers").unwrap_err();
        assert_eq!(err.to_string(), "--powers: item 1 ('x') is not a number");
        let err = parse_numbers("2,,20", false, "--powers").unwrap_err();
        assert_eq!(err.to_string(), "--powers: item 1 is empty");
        let err = parse_numbers("2 5", false, "--powers").unwrap_err();
        assert_eq!(err.to_string(), "--powers: item 0 ('2 5') is not a number");
    }

    #[test]
    fn files_accept_any_white_space() {
        assert_eq!(
            parse_numbers("1 2\n3,\t4\n", true, "f").unwrap(),
            vec![1.0, 2.0, 3.0, 4.0]
        );
        assert_eq!(
            parse_numbers("1\r\n2 ,3\n\n", true, "f").unwrap(),
            vec![1.0, 2.0, 3.0]
        );
    }

    #[test]
    fn files_refuse_empty_items_as_lists_do() {
        for (text, index) in [("2,,20", 1), ("1 2, ,3", 2), (",1", 0), ("1,2,\n", 2)] {
            let err = parse_numbers(text, true, "f").unwrap_err();
            assert_eq!(
                err.to_string(),
                format!("f: item {index} is empty"),
                "{text:?}"
            );
            let list = parse_numbers(text, false, "--powers").unwrap_err();
            assert!(list.to_string().ends_with("is empty"), "{text:?}: {list}");
        }
    }
}
