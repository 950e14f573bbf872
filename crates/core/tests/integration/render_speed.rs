//! Throughput measurements on the `million` preset, ignored by default (they assert nothing about
//! time). Run with `cargo test --release -p lightpick-core --test integration render_speed --
//! --ignored --nocapture`.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use std::time::Instant;

use lightpick_core::Scheme;
use lightpick_core::render::{CpuRenderer, Reference, error_metrics};
use lightpick_core::scene::Scene;

#[test]
#[ignore = "measurement, run by hand in release"]
fn million_preset_throughput() {
    let threads = rayon::current_num_threads();
    let start = Instant::now();
    let scene = Scene::preset("million").unwrap();
    let generate = start.elapsed().as_secs_f64();
    assert_eq!(scene.light_count(), 1_000_000);
    println!("threads: {threads}");
    println!("generate million preset: {generate:.3} s");

    let start = Instant::now();
    let reference = Reference::compute(&scene);
    let reference_s = start.elapsed().as_secs_f64();
    let evals = reference.pixels().len() as f64 * 1e6;
    println!(
        "reference: {} pixels in {reference_s:.3} s ({:.0} M light-pixel evaluations/s)",
        reference.pixels().len(),
        evals / reference_s / 1e6
    );

    for scheme in [Scheme::Alias, Scheme::Cdf, Scheme::Uniform] {
        let start = Instant::now();
        let mut renderer = CpuRenderer::new(&scene, scheme, 1);
        let build = start.elapsed().as_secs_f64();
        renderer.accumulate(1); // warm the caches and the thread pool
        let spp = 16;
        let start = Instant::now();
        renderer.accumulate(spp);
        let seconds = start.elapsed().as_secs_f64();
        let samples = f64::from(spp) * scene.plane.pixel_count() as f64;
        let m = error_metrics(renderer.accumulator(), &reference);
        println!(
            "{scheme}: build {build:.3} s, {spp} spp at 512x512 in {seconds:.3} s = {:.1} M samples/s; rmse {:.3e}, relMSE {:.3e}",
            samples / seconds / 1e6,
            m.rmse,
            m.rel_mse
        );
    }
}

#[cfg(feature = "draw")]
/// Writes the exact image of every preset but `million` as a PNG (exposure: 1 over the
/// image's mean irradiance) to `$TMPDIR/lightpick-presets/`, for looking at by eye.
#[test]
#[ignore = "writes preview images, run by hand"]
fn preset_previews() {
    let dir = std::env::temp_dir().join("lightpick-presets");
    std::fs::create_dir_all(&dir).unwrap();
    for name in lightpick_core::scene::PRESET_NAMES {
        if name == "million" {
            continue;
        }
        let scene = Scene::preset(name).unwrap();
        let reference = Reference::compute(&scene);
        let image = reference.image().unwrap();
        let mean = image.iter().sum::<f64>() / image.len() as f64;
        let rgba = lightpick_core::render::tonemap_rgba8(image, 1.0 / mean);
        let path = dir.join(format!("{name}.png"));
        image::save_buffer(
            &path,
            &rgba,
            scene.plane.width,
            scene.plane.height,
            image::ExtendedColorType::Rgba8,
        )
        .unwrap();
        println!("{}", path.display());
    }
}
