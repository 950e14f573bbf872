//! Writes the exact image of every preset but `million` as a PNG (exposure: 1 over the
//! image's mean irradiance) into a folder, for looking at by eye: the argument, or
//! `$TMPDIR/lightpick-presets/`.
//!
//! ```text
//! cargo run --release -p lightpick-core --example preset_previews -- previews/
//! ```

use lightpick_core::render::{Reference, tonemap_rgba8};
use lightpick_core::scene::{PRESET_NAMES, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args_os().nth(1).map_or_else(
        || std::env::temp_dir().join("lightpick-presets"),
        std::path::PathBuf::from,
    );
    std::fs::create_dir_all(&dir)?;
    for name in PRESET_NAMES {
        if name == "million" {
            continue;
        }
        let scene = Scene::preset(name)?;
        let reference = Reference::compute(&scene);
        let image = reference.image().ok_or("a reference image")?;
        let mean = image.iter().sum::<f64>() / image.len() as f64;
        let rgba = tonemap_rgba8(image, 1.0 / mean);
        let path = dir.join(format!("{name}.png"));
        image::save_buffer(
            &path,
            &rgba,
            scene.plane.width,
            scene.plane.height,
            image::ExtendedColorType::Rgba8,
        )?;
        println!("{}", path.display());
    }
    Ok(())
}
