//! The pixel inspector's state: the selected pixel and the cached inspection of it (the
//! scene's spatial sampler comes shared with the scene, built once per generation).

use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::pixel_center;

use super::built::Built;

/// Which pixel is inspected, and its inspection for the current scene.
#[derive(Debug, Default)]
pub struct Inspector {
    /// The inspected pixel `(px, py)`, or `None` (the window is closed).
    pub pixel: Option<[u32; 2]>,
    /// Bring the window to the front on its next frame (a pixel was just clicked).
    pub raise: bool,
    cached: Option<Cached>,
}

#[derive(Debug)]
struct Cached {
    generation: u64,
    pixel: [u32; 2],
    inspection: PointInspection,
}

impl Inspector {
    /// The inspection of the selected pixel for `built`'s scene (with its spatial sampler),
    /// computed (`O(N)`) when the pixel or the scene changed. `None` when no pixel is
    /// selected or it lies outside the scene's image.
    pub fn inspection(&mut self, built: &Built) -> Option<&PointInspection> {
        let pixel = self.pixel?;
        let scene = &built.scene;
        if pixel[0] >= scene.plane.width || pixel[1] >= scene.plane.height {
            return None;
        }
        let fresh = self
            .cached
            .as_ref()
            .is_some_and(|c| c.generation == built.generation && c.pixel == pixel);
        if !fresh {
            let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
            let inspection = PointInspection::at_with_spatial(scene, x, built.samplers.spatial());
            self.cached = Some(Cached {
                generation: built.generation,
                pixel,
                inspection,
            });
        }
        self.cached.as_ref().map(|c| &c.inspection)
    }

    /// Heap bytes of the cached inspection: only the lights it lists (at most
    /// `2·LISTED_PER_RANKING`), whatever the scene's size.
    pub fn heap_bytes(&self) -> usize {
        self.cached.as_ref().map_or(0, |c| {
            c.inspection.lights.capacity()
                * std::mem::size_of::<lightpick_core::inspect::LightShare>()
        })
    }
}
