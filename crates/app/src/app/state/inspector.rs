//! The pixel inspector's state: the selected pixel and the cached inspection of it (the
//! scene's spatial sampler comes shared with the scene, built once per generation).

use lightpick_core::Scheme;
use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::pixel_center;

use super::built::Built;
use super::pick_overlay::PickOverlay;

/// Which pixel is inspected, and its inspection for the current scene.
#[derive(Debug, Default)]
pub struct Inspector {
    /// The inspected pixel `(px, py)`, or `None` (the window is closed).
    pub pixel: Option<[u32; 2]>,
    /// Bring the window to the front on its next frame (a pixel was just clicked).
    pub raise: bool,
    cached: Option<Cached>,
    overlay: Option<(u64, [u32; 2], Option<PickOverlay>)>,
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
            let inspection = PointInspection::at_with_spatial(
                scene,
                x,
                &built.samplers.sampler(Scheme::Spatial),
            );
            self.cached = Some(Cached {
                generation: built.generation,
                pixel,
                inspection,
            });
        }
        self.cached.as_ref().map(|c| &c.inspection)
    }

    /// Every light's pick probability under power, spatial and ideal picking at the selected
    /// pixel ([`PickOverlay`]), computed when the pixel or the scene changed; `None` without a
    /// pixel or beyond the overlay's light count.
    pub fn overlay(&mut self, built: &Built) -> Option<&PickOverlay> {
        let pixel = self.pixel?;
        let scene = &built.scene;
        if pixel[0] >= scene.plane.width || pixel[1] >= scene.plane.height {
            return None;
        }
        if !self
            .overlay
            .as_ref()
            .is_some_and(|(g, p, _)| *g == built.generation && *p == pixel)
        {
            let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
            self.overlay = Some((built.generation, pixel, PickOverlay::at(&built.samplers, x)));
        }
        self.overlay.as_ref().and_then(|(_, _, o)| o.as_ref())
    }

    /// Heap bytes of the cached inspection (only the lights it lists, at most
    /// `2·LISTED_PER_RANKING`) and of the top views' overlay (40 bytes a light, only up to
    /// [`super::pick_overlay::OVERLAY_MAX_LIGHTS`] lights).
    pub fn heap_bytes(&self) -> usize {
        let overlay = self
            .overlay
            .as_ref()
            .and_then(|(_, _, o)| o.as_ref())
            .map_or(0, |o| {
                o.lights.capacity() * 16
                    + (o.power.capacity() + o.spatial.capacity() + o.ideal.capacity()) * 8
            });
        overlay
            + self.cached.as_ref().map_or(0, |c| {
                c.inspection.lights.capacity()
                    * std::mem::size_of::<lightpick_core::inspect::LightShare>()
            })
    }
}
