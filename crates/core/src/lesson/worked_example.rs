//! The worked example every lightpick user knows, as a fixture.

use crate::powers::LightPowers;

/// Three lights of power 2, 5 and 20 whose contributions at the shading point are 1, 2 and
/// 15, so the exact total is 18. The alias table is thresholds `6/27, 15/27, 1` with aliases
/// `2, 2, 2`, realizing `2/27, 5/27, 20/27`; uniform and power sampling both average 18,
/// with per-sample variances 366 and 14.85.
#[derive(Clone, Copy, Debug)]
pub struct WorkedExample;

impl WorkedExample {
    /// The powers `Φ = 2, 5, 20`.
    pub const POWERS: [f64; 3] = [2.0, 5.0, 20.0];
    /// The contributions `f = 1, 2, 15` at the shading point.
    pub const CONTRIBUTIONS: [f64; 3] = [1.0, 2.0, 15.0];
    /// The exact total `Σ f = 18`.
    pub const EXACT: f64 = 18.0;
    /// Per-sample variance of uniform picking: `3·(1 + 4 + 225) − 18² = 366`.
    pub const UNIFORM_VARIANCE: f64 = 366.0;
    /// Per-sample variance of power picking: `13.5 + 21.6 + 303.75 − 324 = 14.85`.
    pub const POWER_VARIANCE: f64 = 14.85;

    /// The powers, validated.
    pub fn powers() -> LightPowers {
        // The constant powers are finite, positive and few: validation cannot fail.
        LightPowers::new(Self::POWERS.to_vec()).unwrap_or_else(|_| unreachable!())
    }
}
