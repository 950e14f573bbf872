//! The Light tree panel's state: the depth whose groups are outlined, how the lights are
//! coloured, the shading pixel of the stepped pick, which pick (its random stream) and how
//! far it is stepped, and the step of the guide.
//!
//! The pick is [`TreePick::record`] of the scene's own spatial sampler (the one the images
//! render with) at the pixel's centre, from the stream `Rng::new(seed ^ PICK_SALT, k)` of
//! pick number `k`: the same draws as `SpatialSampler::sample`, so its pdf is the
//! renderer's. It is recorded once per (generation, pixel, pick, seed) and kept.

use std::sync::Arc;

use lightpick_core::Rng;
use lightpick_core::draw::pick_stages;
use lightpick_core::lesson::tree_pick::TreePick;
use lightpick_core::scene::{ReceiverPlane, pixel_center};

use super::built::Built;
use super::pick_overlay::PickOverlay;

/// Salt of the stepped picks' streams (apart from the images' and the estimator's).
const PICK_SALT: u64 = 0x7E3A_11C5_D00D_F00D;

/// The steps of the guide ([`super::super::panels::light_tree_ui`] writes their text).
pub const GUIDE_STEPS: usize = 5;

/// How the top view colours the lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TreeColoring {
    /// One colour; the dots' area is the power.
    #[default]
    Power,
    /// By the spatial pick probability `P(i | x)` at the pick's pixel.
    Spatial,
    /// By the ideal pick probability `s_i = c_i(x)/Σ c` at the pick's pixel.
    Ideal,
}

impl TreeColoring {
    /// The probabilities of `overlay` this colouring shows (none for [`TreeColoring::Power`]).
    pub fn probabilities(self, overlay: &PickOverlay) -> Option<&[f64]> {
        match self {
            TreeColoring::Power => None,
            TreeColoring::Spatial => Some(&overlay.spatial),
            TreeColoring::Ideal => Some(&overlay.ideal),
        }
    }
}

/// A recorded pick with what the panel prints beside it.
#[derive(Clone, Debug)]
pub struct SteppedPick {
    /// The pixel whose centre `x` it was picked at.
    pub pixel: [u32; 2],
    /// Which pick at that pixel (its stream).
    pub number: u64,
    /// The record, `None` when no light reaches `x` (no pick, the estimate is 0).
    pub record: Option<TreePick>,
    /// The renderer's own `P(i | x)` of the picked light (`SpatialSampler::pdf`), to show
    /// it equals the product of the steps.
    pub renderer_pdf: Option<f64>,
    /// `Φ_total`: the record's normalized figures times it are irradiances.
    pub total_power: f64,
}

/// What a recorded pick is for: a new key records it again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PickKey {
    generation: u64,
    pixel: [u32; 2],
    number: u64,
    seed: u64,
}

/// A scene generation and a pixel: what the colouring's probabilities were computed for.
type OverlayKey = (u64, [u32; 2]);

/// The panel's state (in `AppState::light_tree`).
#[derive(Debug, Default)]
pub struct LightTreeState {
    /// The depth whose groups are outlined (0: one group of every light).
    pub depth: usize,
    /// How the lights are coloured.
    pub coloring: TreeColoring,
    /// The pixel of the stepped pick (the last clicked on the tree or the images).
    pub pixel: Option<[u32; 2]>,
    /// Which pick at that pixel: New pick counts up.
    pub number: u64,
    /// How far the pick is stepped ([`pick_stages`]: a node, the leaf, the end).
    pub stage: usize,
    /// The guide's step (0 to [`GUIDE_STEPS`] − 1).
    pub guide_step: usize,
    /// The inspector's pixel last adopted (a click on the images moves the pick there).
    adopted: Option<[u32; 2]>,
    recorded: Option<(PickKey, Arc<SteppedPick>)>,
    overlay: Option<(OverlayKey, Option<Arc<PickOverlay>>)>,
}

impl LightTreeState {
    /// Moves the pick to `pixel`, at its first pick, before its first step.
    pub fn select_pixel(&mut self, pixel: [u32; 2]) {
        if self.pixel != Some(pixel) {
            self.pixel = Some(pixel);
            self.number = 0;
            self.stage = 0;
        }
    }

    /// Follows a pixel newly clicked in the images (the inspector's), once per click.
    pub fn adopt_inspected(&mut self, inspected: Option<[u32; 2]>) {
        if inspected.is_some() && inspected != self.adopted {
            self.adopted = inspected;
            if let Some(pixel) = inspected {
                self.select_pixel(pixel);
            }
        }
    }

    /// The next pick at the same pixel, before its first step.
    pub fn new_pick(&mut self) {
        self.number += 1;
        self.stage = 0;
    }

    /// The pick's pixel, when it lies on `plane`'s image (a smaller scene may not hold it).
    fn pixel_on(&self, plane: &ReceiverPlane) -> Option<[u32; 2]> {
        self.pixel
            .filter(|p| p[0] < plane.width && p[1] < plane.height)
    }

    /// One stage on (up to the end of `pick`).
    pub fn next(&mut self, pick: &SteppedPick) {
        let last = pick.record.as_ref().map_or(0, |r| pick_stages(r) - 1);
        self.stage = (self.stage + 1).min(last);
    }

    /// One stage back.
    pub fn back(&mut self) {
        self.stage = self.stage.saturating_sub(1);
    }

    /// The pick at the current pixel on `built`'s scene with `seed`, recorded once.
    pub fn pick(&mut self, built: &Built, seed: u64) -> Option<Arc<SteppedPick>> {
        let scene = &built.scene;
        let pixel = self.pixel_on(&scene.plane)?;
        let key = PickKey {
            generation: built.generation,
            pixel,
            number: self.number,
            seed,
        };
        if let Some((k, pick)) = &self.recorded
            && *k == key
        {
            return Some(Arc::clone(pick));
        }
        let spatial = built.samplers.spatial();
        let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
        let mut rng = Rng::new(seed ^ PICK_SALT, self.number);
        let record = TreePick::record(spatial, x, &mut rng);
        let renderer_pdf = record.as_ref().map(|r| spatial.pdf(x, r.light as usize));
        let pick = Arc::new(SteppedPick {
            pixel,
            number: self.number,
            record,
            renderer_pdf,
            total_power: scene.powers.total(),
        });
        self.recorded = Some((key, Arc::clone(&pick)));
        Some(pick)
    }

    /// The probabilities at the pick's pixel when the colouring shows some ([`Self::overlay`];
    /// `None` for the power colouring).
    pub fn coloring_overlay(&mut self, built: &Built) -> Option<Arc<PickOverlay>> {
        match self.coloring {
            TreeColoring::Power => None,
            TreeColoring::Spatial | TreeColoring::Ideal => self.overlay(built),
        }
    }

    /// The three pick probabilities of every light at the pick's pixel (the inspector's
    /// [`PickOverlay`]), computed once per generation and pixel; `None` without a pixel or
    /// beyond the overlay's light count.
    pub fn overlay(&mut self, built: &Built) -> Option<Arc<PickOverlay>> {
        let scene = &built.scene;
        let pixel = self.pixel_on(&scene.plane)?;
        let key = (built.generation, pixel);
        if let Some((k, overlay)) = &self.overlay
            && *k == key
        {
            return overlay.clone();
        }
        let x = pixel_center(&scene.plane, pixel[0], pixel[1]);
        let overlay = PickOverlay::at(&built.samplers, x).map(Arc::new);
        self.overlay = Some((key, overlay.clone()));
        overlay
    }
}
