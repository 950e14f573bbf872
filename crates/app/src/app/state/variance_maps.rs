//! The images panel's variance maps: each scheme's per-pixel variance of one sample
//! ([`VarianceMap::of_sampler`]) over the scene's shared samplers
//! ([`SceneSamplers::sampler`]), computed once per scene generation on a background job
//! ([`crate::app::background::Background`]) and inline in tests.
//!
//! # Exact or estimated
//! Where `N × pixels ≤` [`APP_EXACT_BUDGET`] the maps are exact at the images' resolution.
//! Beyond, they are estimated from [`ESTIMATE_SPP`] samples per pixel on a grid of at most
//! [`ESTIMATE_MAX_SIDE`] pixels a side over the same plane (exact on that grid when it fits
//! the budget), so that `10^6` lights cost a fraction of a second on two cores. The
//! estimate's random streams use [`VARIANCE_SEED`], so a generation's maps are the same
//! bits every time.

use lightpick_core::stats::variance_map::VarianceMap;
use lightpick_core::{SceneSamplers, Scheme};

/// The most `N × pixels` light evaluations for which the app's maps are exact (`grid`'s
/// 1024 lights are exact on the 128² grid).
pub const APP_EXACT_BUDGET: u64 = 1 << 25;

/// Samples per pixel of an estimated map.
pub const ESTIMATE_SPP: u32 = 8;

/// The longest side, in pixels, of an estimated map's grid.
pub const ESTIMATE_MAX_SIDE: u32 = 128;

/// The seed of an estimated map's random streams.
pub const VARIANCE_SEED: u64 = 1;

/// The schemes of the three maps, left to right as the images.
pub const VARIANCE_SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

/// The three maps of one scene generation.
#[derive(Clone, Debug, PartialEq)]
pub struct VarianceMaps {
    /// The scene generation they describe.
    pub generation: u64,
    /// Uniform, power (alias) and spatial ([`VARIANCE_SCHEMES`]).
    pub maps: [VarianceMap; 3],
    /// Seconds the three took (wall clock, on the worker).
    pub seconds: f64,
}

impl crate::app::background::OfGeneration for VarianceMaps {
    fn generation(&self) -> u64 {
        self.generation
    }
}

impl VarianceMaps {
    /// The mean of each map over its pixels ([`lightpick_core::draw::variance_mean`]).
    pub fn means(&self) -> [f64; 3] {
        std::array::from_fn(|k| lightpick_core::draw::variance_mean(&self.maps[k].values))
    }

    /// Whether the maps are exact (else estimated).
    pub fn exact(&self) -> bool {
        self.maps[0].exact
    }

    /// Samples per pixel behind estimated maps (0 when exact).
    pub fn samples_per_pixel(&self) -> u32 {
        self.maps[0].samples_per_pixel
    }

    /// The maps' pixel grid `[width, height]`.
    pub fn size(&self) -> [u32; 2] {
        [self.maps[0].width, self.maps[0].height]
    }
}

/// The maps of the scene `samplers` hold, for `generation` (see the module docs).
pub fn variance_maps(generation: u64, samplers: &SceneSamplers) -> VarianceMaps {
    let start = std::time::Instant::now();
    let scene = samplers.scene();
    let n = scene.light_count() as u64;
    let fits = n.saturating_mul(scene.plane.pixel_count() as u64) <= APP_EXACT_BUDGET;
    let grid = if fits {
        None
    } else {
        let mut small = (**scene).clone();
        let (w, h) = (scene.plane.width.max(1), scene.plane.height.max(1));
        let scale = (f64::from(ESTIMATE_MAX_SIDE) / f64::from(w.max(h))).min(1.0);
        small.plane.width = ((f64::from(w) * scale).round() as u32).max(1);
        small.plane.height = ((f64::from(h) * scale).round() as u32).max(1);
        Some(small)
    };
    let on = grid.as_ref().unwrap_or(scene);
    let maps = VARIANCE_SCHEMES.map(|scheme| {
        VarianceMap::of_sampler(
            on,
            &samplers.sampler(scheme),
            APP_EXACT_BUDGET,
            ESTIMATE_SPP,
            VARIANCE_SEED,
        )
    });
    VarianceMaps {
        generation,
        maps,
        seconds: start.elapsed().as_secs_f64(),
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use lightpick_core::Construction;
    use lightpick_core::scene::Scene;

    use super::*;

    #[test]
    fn small_scenes_are_exact_at_the_images_resolution_large_ones_estimated_on_a_grid() {
        let scene = Arc::new(Scene::preset("worked-example").expect("a preset"));
        let samplers = SceneSamplers::new(Arc::clone(&scene), Construction::Exact);
        let m = variance_maps(3, &samplers);
        assert!(m.exact());
        assert_eq!(m.size(), [scene.plane.width, scene.plane.height]);
        let uniform = VarianceMap::compute(&scene, Scheme::Uniform, 2, 9);
        assert_eq!(m.maps[0], uniform, "the core's exact map, bit for bit");
        let power = VarianceMap::compute(&scene, Scheme::Alias, 2, 9);
        // Apart from the shared table's quantization of p_i (2^-32 relative, amplified by
        // the difference Σ s²/q − E²).
        let (a, b) = (
            m.means()[1],
            lightpick_core::draw::variance_mean(&power.values),
        );
        assert!((a - b).abs() <= 1e-9 * b, "{a} vs {b}");
        let grid = Arc::new(Scene::preset("grid").expect("a preset"));
        let samplers = SceneSamplers::new(Arc::clone(&grid), Construction::Exact);
        let m = variance_maps(4, &samplers);
        // 1024 lights × 256² pixels exceed the budget, 1024 × 128² fit it: exact there.
        assert_eq!(m.size(), [128, 128]);
        assert!(m.exact());
        assert!(
            m.means()[2] < m.means()[1],
            "spatial beats power on the grid"
        );
        // 10^4 lights × 128² exceed it: estimated on the grid.
        let heavy = Arc::new(Scene::preset("heavy-tail").expect("a preset"));
        let samplers = SceneSamplers::new(Arc::clone(&heavy), Construction::Exact);
        let m = variance_maps(5, &samplers);
        assert_eq!(m.size(), [128, 128]);
        assert!(!m.exact());
        assert_eq!(m.samples_per_pixel(), ESTIMATE_SPP);
    }
}
