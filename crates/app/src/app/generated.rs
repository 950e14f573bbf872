//! Scenes the Lights panel makes: random powers of a chosen [`PowerShape`] (Randomize,
//! Generate) and random positions above the plane (Generate, + Add), deterministic in a seed.

use glam::{DVec3, dvec3};
use lightpick_core::Rng;
use lightpick_core::scene::ReceiverPlane;

/// The shape of the random powers that the lights panel's Randomize and Generate draw: a
/// fixed unit-scale density, times a scale ([`random_powers`]). Not the core's
/// `lightpick_core::scene::PowerDistribution`, the parameterized recipe of a scene file's
/// generator (another density family, drawn from another stream).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PowerShape {
    /// Uniform on `[0, 1)` times the scale.
    Uniform,
    /// Exponential with mean 1, times the scale.
    Exponential,
    /// Pareto with shape `α = 1.5` (heavy tail), times the scale.
    Pareto,
    /// Log-normal `exp(2·Z)` (powers spanning decades), times the scale.
    LogNormal,
}

impl PowerShape {
    /// Every distribution, in menu order.
    pub const ALL: [PowerShape; 4] = [
        PowerShape::Uniform,
        PowerShape::Exponential,
        PowerShape::Pareto,
        PowerShape::LogNormal,
    ];

    /// The menu label.
    pub fn label(self) -> &'static str {
        match self {
            PowerShape::Uniform => "uniform [0, 1)",
            PowerShape::Exponential => "exponential (mean 1)",
            PowerShape::Pareto => "Pareto (α = 1.5)",
            PowerShape::LogNormal => "log-normal (σ = 2)",
        }
    }

    /// One power from two independent uniforms in `[0, 1)` (inverse-CDF and Box–Muller
    /// transforms, so the shared counter-based RNG drives everything).
    pub fn draw(self, u1: f64, u2: f64) -> f64 {
        match self {
            PowerShape::Uniform => u1,
            PowerShape::Exponential => -(1.0 - u1).ln(),
            PowerShape::Pareto => (1.0 - u1).powf(-1.0 / 1.5),
            PowerShape::LogNormal => {
                let r = (-2.0 * (1.0 - u1).ln()).sqrt();
                (2.0 * r * (std::f64::consts::TAU * u2).cos()).exp()
            }
        }
    }
}

/// `count` powers drawn from `dist` with generator `seed`, scaled by `scale`.
pub fn random_powers(count: usize, dist: PowerShape, scale: f64, seed: u64) -> Vec<f64> {
    (0..count)
        .map(|i| {
            let mut rng = Rng::new(seed, i as u64);
            scale * dist.draw(rng.next_unit(), rng.next_unit())
        })
        .collect()
}

/// `count` light positions scattered above `plane` (heights between 5% and 40% of the
/// plane's extent), deterministic in `seed`.
pub fn random_positions(count: usize, plane: &ReceiverPlane, seed: u64) -> Vec<DVec3> {
    let extent = (plane.max - plane.min).max_element();
    (0..count)
        .map(|i| {
            let mut rng = Rng::new(seed ^ 0x05ee_d0f1_1167, i as u64);
            let x = plane.min.x + rng.next_unit() * (plane.max.x - plane.min.x);
            let y = plane.min.y + rng.next_unit() * (plane.max.y - plane.min.y);
            let z = extent * (0.05 + 0.35 * rng.next_unit());
            dvec3(x, y, z)
        })
        .collect()
}
