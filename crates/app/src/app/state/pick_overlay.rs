//! Where each scheme picks at the inspected pixel: every light's probability under power
//! picking (`p_i`), spatial picking (`P(i | x)`) and the ideal pick (`s_i`, its share of the
//! irradiance there), with the lights' places on the plane, for the inspector's top views.
//! The numbers are the inspector's own ([`lightpick_core::inspect::PointInspection`]
//! computes the same three for the lights it lists).

use glam::DVec2;
use lightpick_core::{LightSampler as _, SceneSamplers, Scheme, ShadingContext};

/// The most lights the overlay draws (beyond, it says the scene is too large to draw light
/// by light and the inspector's table stands).
pub const OVERLAY_MAX_LIGHTS: usize = 50_000;

/// The three probabilities of every light at one shading point.
#[derive(Clone, Debug, PartialEq)]
pub struct PickOverlay {
    /// The shading point.
    pub x: DVec2,
    /// Each light's place on the plane (its position seen from above).
    pub lights: Vec<DVec2>,
    /// `p_i = Φ_i/ΣΦ`: power picking.
    pub power: Vec<f64>,
    /// `P(i | x)`: spatial picking at `x`.
    pub spatial: Vec<f64>,
    /// `s_i = p_i·G_i(x) / Σ_j p_j·G_j(x)`: the ideal pick (0 everywhere when no light
    /// reaches `x`).
    pub ideal: Vec<f64>,
}

impl PickOverlay {
    /// The overlay at `x` of the scene `samplers` hold; `None` beyond
    /// [`OVERLAY_MAX_LIGHTS`] lights.
    pub fn at(samplers: &SceneSamplers, x: DVec2) -> Option<Self> {
        let scene = samplers.scene();
        let n = scene.light_count();
        if n > OVERLAY_MAX_LIGHTS {
            return None;
        }
        let power = scene.powers.pmf();
        let ideal = scene.irradiance_shares(x);
        Some(Self {
            x,
            lights: scene.positions.iter().map(|p| p.truncate()).collect(),
            power,
            spatial: samplers
                .sampler(Scheme::Spatial)
                .pmfs_at(&ShadingContext::at(x)),
            ideal,
        })
    }
}
