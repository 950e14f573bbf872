//! Times the images panel's variance maps (`variance_maps`): exact ones near the exact
//! budget (`equal`: 64 lights × 256² pixels), and at `10^6` lights (the `million` preset,
//! its tree built first, as the app's samplers are when the maps are asked for), three
//! times. A measurement, not a check: it prints.
//!
//! ```text
//! cargo run --release -p lightpick --example variance_map_timing
//! ```

use std::sync::Arc;

use lightpick::app::state::variance_maps::variance_maps;
use lightpick_core::scene::Scene;
use lightpick_core::{Construction, SceneSamplers};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let equal = Arc::new(Scene::preset("equal")?);
    let samplers = SceneSamplers::new(equal, Construction::Integer);
    let m = variance_maps(1, &samplers);
    println!(
        "equal: {:?} px, exact {}: {:.3} s",
        m.size(),
        m.exact(),
        m.seconds
    );
    let million = Arc::new(Scene::preset("million")?);
    let samplers = SceneSamplers::new(million, Construction::Integer);
    let _ = samplers.spatial();
    for _ in 0..3 {
        let m = variance_maps(1, &samplers);
        println!(
            "million: {:?} px, exact {}, {} spp: {:.3} s",
            m.size(),
            m.exact(),
            m.samples_per_pixel(),
            m.seconds
        );
    }
    Ok(())
}
