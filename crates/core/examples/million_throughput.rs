//! Throughput on the `million` preset (10^6 lights over 512 × 512 pixels): how long the
//! preset takes to generate, its exact reference to compute (light-pixel evaluations a
//! second), and each table-driven scheme to build and render 16 samples a pixel, with the
//! render's error against the reference. A measurement, not a check: it prints.
//!
//! ```text
//! cargo run --release -p lightpick-core --example million_throughput
//! ```

use std::time::Instant;

use lightpick_core::Scheme;
use lightpick_core::render::{CpuRenderer, Reference, error_metrics};
use lightpick_core::scene::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let threads = rayon::current_num_threads();
    let start = Instant::now();
    let scene = Scene::preset("million")?;
    let generate = start.elapsed().as_secs_f64();
    println!("threads: {threads}");
    println!(
        "generate the million preset ({} lights): {generate:.3} s",
        scene.light_count()
    );

    let start = Instant::now();
    let reference = Reference::compute(&scene);
    let reference_s = start.elapsed().as_secs_f64();
    let evaluations = reference.pixels().len() as f64 * scene.light_count() as f64;
    println!(
        "reference: {} pixels in {reference_s:.3} s ({:.0} M light-pixel evaluations/s)",
        reference.pixels().len(),
        evaluations / reference_s / 1e6
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
            "{scheme}: build {build:.3} s, {spp} spp at {}×{} in {seconds:.3} s = {:.1} M samples/s; rmse {:.3e}, relMSE {:.3e}",
            scene.plane.width,
            scene.plane.height,
            samples / seconds / 1e6,
            m.rmse,
            m.rel_mse
        );
    }
    Ok(())
}
