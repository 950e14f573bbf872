//! The pixel inspector's state: the selected pixel, the scene's spatial sampler (built once
//! per scene generation on a worker thread) and the cached inspection of the pixel.

use std::sync::Arc;

use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::{Scene, pixel_center};
use lightpick_core::spatial::SpatialSampler;

use crate::app::background::Background;

/// Which pixel is inspected, and its inspection for the current scene.
#[derive(Debug, Default)]
pub struct Inspector {
    /// The inspected pixel `(px, py)`, or `None` (the window is closed).
    pub pixel: Option<[u32; 2]>,
    /// The spatial sampler of a scene generation, built on a worker thread (inline in tests).
    pub spatial: Background<(u64, Arc<SpatialSampler>)>,
    cached: Option<Cached>,
}

#[derive(Debug)]
struct Cached {
    generation: u64,
    pixel: [u32; 2],
    with_spatial: bool,
    inspection: PointInspection,
}

impl Inspector {
    /// The spatial sampler of the scene of `generation`, once built; the first call for a
    /// generation starts building it (`O(N log N)`, on a worker thread in the app).
    pub fn spatial_sampler(
        &mut self,
        generation: u64,
        scene: &Arc<Scene>,
    ) -> Option<Arc<SpatialSampler>> {
        self.spatial.poll();
        let spatial = self
            .spatial
            .result
            .as_ref()
            .filter(|(g, _)| *g == generation)
            .map(|(_, sampler)| Arc::clone(sampler));
        if spatial.is_none() {
            let for_build = Arc::clone(scene);
            self.spatial
                .start(generation, "lightpick-inspector-spatial", move |_| {
                    let sampler = SpatialSampler::build(&for_build.positions, &for_build.powers);
                    (generation, Arc::new(sampler))
                });
            // Inline (tests): built at once.
            self.spatial.poll();
            return self
                .spatial
                .result
                .as_ref()
                .filter(|(g, _)| *g == generation)
                .map(|(_, sampler)| Arc::clone(sampler));
        }
        spatial
    }

    /// The inspection of the selected pixel for the scene of `generation`, computed (`O(N)`)
    /// when the pixel or the scene changed, and again once the scene's spatial sampler is
    /// ready. `None` when no pixel is selected or it lies outside the scene's image.
    pub fn inspection(&mut self, generation: u64, scene: &Arc<Scene>) -> Option<&PointInspection> {
        let pixel = self.pixel?;
        if pixel[0] >= scene.plane.width || pixel[1] >= scene.plane.height {
            return None;
        }
        let spatial = self.spatial_sampler(generation, scene);
        let fresh = self.cached.as_ref().is_some_and(|c| {
            c.generation == generation && c.pixel == pixel && c.with_spatial == spatial.is_some()
        });
        if !fresh {
            let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
            let inspection = match &spatial {
                Some(sampler) => PointInspection::at_with_spatial(scene, x, sampler),
                None => PointInspection::at(scene, x),
            };
            self.cached = Some(Cached {
                generation,
                pixel,
                with_spatial: spatial.is_some(),
                inspection,
            });
        }
        self.cached.as_ref().map(|c| &c.inspection)
    }
}
