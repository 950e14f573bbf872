//! The estimator view's state: which shading point it estimates (the worked example's, or a clicked
//! pixel's), whether it runs, and the running [`PointEstimator`] of the current scene
//! generation (rebuilt, from sample 0, whenever the powers, the point or the seed change).

use std::sync::Arc;

use glam::DVec2;
use lightpick_core::point_estimate::PointEstimator;
use lightpick_core::scene::{Scene, pixel_center};
use lightpick_core::walkthrough::{CLASSIC_GEOMETRY, CLASSIC_POWERS};
use lightpick_core::{
    AliasTable, LightPowers, Sampler, Scheme, SchemeSampler, ShadingContext, Uniform,
};

use super::built::Built;

/// The run stops by itself after this many samples per scheme.
pub const ESTIMATOR_MAX_SAMPLES: u64 = 10_000_000;
/// At most this many samples per scheme per frame while running (10^6 lights: a few ms).
const MAX_SAMPLES_PER_FRAME: u64 = 20_000;

/// Which shading point the view estimates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EstimatorPoint {
    /// The worked example's shading point: three lights whose geometry factors `g = 1/2, 2/5, 3/4`
    /// turn powers `2, 5, 20` into contributions `1, 2, 15` (`f_i = Φ_i·g_i`, so the
    /// contributions follow the powers live). On a scene without three lights, the classic
    /// powers.
    WorkedExample,
    /// The point at the centre of pixel `(px, py)` of the images: every light's
    /// `f_i = Φ_i·G_i(x)`, and the spatial scheme too.
    Pixel([u32; 2]),
}

/// What the estimator was built from: a new key starts it over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BuiltFor {
    generation: u64,
    point: EstimatorPoint,
    seed: u64,
}

/// The estimator view's state (in `AppState::estimator`).
#[derive(Debug)]
pub struct EstimatorState {
    /// Whether the window is shown.
    pub open: bool,
    /// The shading point estimated.
    pub point: EstimatorPoint,
    /// Whether samples are added every frame.
    pub running: bool,
    /// Why the point cannot be estimated (no light reaches it), when it cannot.
    pub problem: Option<String>,
    /// Bring the window to the front on its next frame (it was just opened by a click).
    pub raise: bool,
    estimator: Option<(BuiltFor, PointEstimator)>,
}

impl Default for EstimatorState {
    fn default() -> Self {
        Self {
            open: false,
            point: EstimatorPoint::WorkedExample,
            raise: false,
            running: false,
            problem: None,
            estimator: None,
        }
    }
}

/// Whether the worked example's point uses the scene's own three lights (else the classic powers).
pub fn worked_example_uses_scene(built: &Built) -> bool {
    built.len() == CLASSIC_POWERS.len()
}

impl EstimatorState {
    /// Opens the view on `point`, paused at sample 0, in front of the other windows.
    pub fn open_at(&mut self, point: EstimatorPoint) {
        self.open = true;
        self.raise = true;
        self.running = false;
        if self.point != point {
            self.point = point;
            self.estimator = None;
        }
    }

    /// The running estimator for `built`, rebuilt from sample 0 when the scene generation,
    /// the point or the seed changed. `None` when the point cannot be estimated
    /// ([`EstimatorState::problem`]).
    pub fn sync(&mut self, built: &Built, seed: u64) -> Option<&mut PointEstimator> {
        let key = BuiltFor {
            generation: built.generation,
            point: self.point,
            seed,
        };
        if self.estimator.as_ref().is_none_or(|(k, _)| *k != key) {
            match build(built, self.point, seed) {
                Ok(estimator) => {
                    self.problem = None;
                    self.estimator = Some((key, estimator));
                }
                Err(problem) => {
                    self.problem = Some(problem);
                    self.estimator = None;
                    self.running = false;
                }
            }
        }
        self.estimator.as_mut().map(|(_, e)| e)
    }

    /// The estimator as last built (for drawing), if any.
    pub fn estimator(&self) -> Option<&PointEstimator> {
        self.estimator.as_ref().map(|(_, e)| e)
    }

    /// Heap bytes of the estimator as last built ([`PointEstimator::heap_bytes`]: 16 per
    /// light on a pixel's point), 0 when none is.
    pub fn heap_bytes(&self) -> usize {
        self.estimator().map_or(0, PointEstimator::heap_bytes)
    }

    /// Adds one frame's samples while running: about 5 % more each frame (evenly spread on
    /// the plot's log axis), at most 20 000, stopping at [`ESTIMATOR_MAX_SAMPLES`].
    pub fn run_frame(&mut self) {
        let Some((_, e)) = self.estimator.as_mut() else {
            return;
        };
        if !self.running {
            return;
        }
        let n = e.samples();
        if n >= ESTIMATOR_MAX_SAMPLES {
            self.running = false;
            return;
        }
        let add = (n / 20)
            .clamp(1, MAX_SAMPLES_PER_FRAME)
            .min(ESTIMATOR_MAX_SAMPLES - n);
        e.advance(add);
    }

    /// Adds `count` samples at once (the Step buttons).
    pub fn step(&mut self, count: u64) {
        if let Some((_, e)) = self.estimator.as_mut() {
            let room = ESTIMATOR_MAX_SAMPLES.saturating_sub(e.samples());
            e.advance(count.min(room));
        }
    }

    /// Forgets every sample (the streams start over).
    pub fn reset(&mut self) {
        if let Some((_, e)) = self.estimator.as_mut() {
            e.reset();
        }
    }
}

/// The estimator of `point` on `built`'s scene (see [`EstimatorPoint`]): uniform and power
/// picking everywhere, spatial picking too at a pixel, each the scene's own sampler through
/// the one interface ([`lightpick_core::LightSampler`]).
fn build(built: &Built, point: EstimatorPoint, seed: u64) -> Result<PointEstimator, String> {
    let scene = &built.scene;
    let schemes = |schemes: &[(&'static str, Scheme)]| -> Vec<(&'static str, SchemeSampler)> {
        schemes
            .iter()
            .map(|&(name, scheme)| (name, built.samplers.sampler(scheme)))
            .collect()
    };
    let point_free = [("uniform", Scheme::Uniform), ("power", Scheme::Alias)];
    let (contributions, at, runs) = match point {
        EstimatorPoint::WorkedExample if worked_example_uses_scene(built) => (
            scene
                .powers
                .as_slice()
                .iter()
                .zip(CLASSIC_GEOMETRY)
                .map(|(power, g)| power * g)
                .collect(),
            ShadingContext::default(),
            schemes(&point_free),
        ),
        EstimatorPoint::WorkedExample => {
            let powers = LightPowers::new(CLASSIC_POWERS.to_vec()).map_err(|e| e.to_string())?;
            let table = Arc::new(AliasTable::build_exact(&powers));
            let contributions = CLASSIC_POWERS
                .iter()
                .zip(CLASSIC_GEOMETRY)
                .map(|(power, g)| power * g)
                .collect();
            let runs = vec![
                ("uniform", Sampler::Uniform(Uniform::new(3)).into()),
                ("power", Sampler::Alias(table).into()),
            ];
            (contributions, ShadingContext::default(), runs)
        }
        EstimatorPoint::Pixel(pixel) => {
            if pixel[0] >= scene.plane.width || pixel[1] >= scene.plane.height {
                return Err(format!(
                    "pixel ({}, {}) is outside the {}×{} image",
                    pixel[0], pixel[1], scene.plane.width, scene.plane.height
                ));
            }
            let point_on_plane = pixel_center(&scene.plane, pixel[0], pixel[1]);
            let contributions = pixel_contributions(scene, point_on_plane)?;
            let runs = schemes(&[
                ("uniform", Scheme::Uniform),
                ("power", Scheme::Alias),
                ("spatial", Scheme::Spatial),
            ]);
            (contributions, ShadingContext::at(point_on_plane), runs)
        }
    };
    PointEstimator::new(contributions, at, runs, seed).map_err(|e| e.to_string())
}

/// `f_i = Φ_i·G_i(x)·S_i(x)` of every light at `point_on_plane`, refused when no light
/// reaches it or when the irradiance leaves `f64`.
fn pixel_contributions(scene: &Scene, point_on_plane: DVec2) -> Result<Vec<f64>, String> {
    let contributions = scene.weighted_terms(scene.powers.as_slice(), point_on_plane);
    let total: f64 = contributions.iter().sum();
    if !total.is_finite() {
        return Err("the irradiance at this point exceeds f64".to_owned());
    }
    if total <= 0.0 {
        return Err(
            "no light reaches this point: every estimate is 0, with no variance".to_owned(),
        );
    }
    Ok(contributions)
}
