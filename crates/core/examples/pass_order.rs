//! Times the spatial scheme's lockstep picks (`SpatialSampler::estimate_many`, eight
//! pixels of a row at a time) in the two orders a render takes them: every sample of a
//! pixel in a row (`lightpick bench`'s main table, 32 here), or passes of one sample a
//! pixel over the whole image (the app's images), each with the picks that ask for their
//! tiles' cuts ahead (`estimate_many_cold`) and without. One thread, the receiver at
//! `256 × 256` pixels (the app's size for the presets; tiles of 4 pixels), every tile cut
//! beforehand; each figure the fastest of three runs, in ns per pixel sample.
//!
//! ```text
//! cargo run --release -p lightpick-core --example pass_order -- heavy-tail grid million
//! ```

use std::time::Instant;

use glam::DVec2;
use lightpick_core::Rng;
use lightpick_core::scene::{Scene, pixel_center};
use lightpick_core::spatial::SpatialSampler;

/// Pixels along each side of the receiver.
const SIDE: u32 = 256;
/// Samples a pixel.
const SPP: u32 = 32;
/// Pixels of a lockstep batch.
const BATCH: usize = 8;

/// The fastest of three renders' ns per pixel sample: in passes of one sample a pixel when
/// `passes`, with the cold picks when `cold`.
fn time(scene: &Scene, sampler: &SpatialSampler, passes: bool, cold: bool) -> f64 {
    let (outer, inner) = if passes { (SPP, 1) } else { (1, SPP) };
    let mut fastest = f64::INFINITY;
    for _ in 0..3 {
        let start = Instant::now();
        let mut sum = 0.0;
        for pass in 0..outer {
            for py in 0..SIDE {
                for px0 in (0..SIDE).step_by(BATCH) {
                    let points: [DVec2; BATCH] =
                        std::array::from_fn(|j| pixel_center(&scene.plane, px0 + j as u32, py));
                    for sample in 0..inner {
                        let k = u64::from(pass * inner + sample);
                        let mut rngs: [Rng; BATCH] = std::array::from_fn(|j| {
                            Rng::new(7, (k << 32) | u64::from(py * SIDE + px0 + j as u32))
                        });
                        let estimates = if cold {
                            sampler.estimate_many_cold(&points, &mut rngs)
                        } else {
                            sampler.estimate_many(&points, &mut rngs)
                        };
                        sum += estimates.iter().sum::<f64>();
                    }
                }
            }
        }
        std::hint::black_box(sum);
        let samples = f64::from(SIDE) * f64::from(SIDE) * f64::from(SPP);
        fastest = fastest.min(start.elapsed().as_secs_f64() * 1e9 / samples);
    }
    fastest
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for name in std::env::args().skip(1) {
        let mut scene = Scene::preset(&name).or_else(|_| Scene::load(&name))?;
        scene.plane.width = SIDE;
        scene.plane.height = SIDE;
        let sampler = SpatialSampler::for_scene(&scene);
        if let SpatialSampler::Tree(tree) = &sampler
            && let Some(cuts) = tree.tile_cuts()
        {
            cuts.cut_all(tree);
        }
        let [in_row, in_row_cold, passes, passes_cold] =
            [(false, false), (false, true), (true, false), (true, true)]
                .map(|(p, c)| time(&scene, &sampler, p, c));
        println!(
            "{name} ({} lights): samples in a row {in_row:.1} ns, cold {in_row_cold:.1} ns; \
             passes of one sample {passes:.1} ns, cold {passes_cold:.1} ns ({:.2}×)",
            scene.light_count(),
            passes / passes_cold
        );
    }
    Ok(())
}
