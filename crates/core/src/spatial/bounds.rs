//! Bounds of what a tree lane's lights can light (pbrt-v4's `LightBounds`, with a box on
//! the plane): for lights with spot cones or ranges only. A lane whose bounds exclude a
//! point is culled there (probability 0): the bounds hold every point any of its lights
//! lights, so no light that gives the point anything is lost.

use glam::{DQuat, DVec2, DVec3};

use super::SpatialLight;
use crate::scene::Emission;

/// What the lights of a tree lane can do at most, for lights with emission profiles
/// (pbrt-v4's `LightBounds`; the module docs), and where on the plane they can do it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneBounds {
    /// The box of the lane's light positions, in the world.
    pub min: DVec3,
    /// See [`LaneBounds::min`].
    pub max: DVec3,
    /// `Σ p_i·g_i`: the lane's normalized power weighted by each light's on-axis gain
    /// ([`Emission::gain`]; 1 for a light without a spot).
    pub intensity: f64,
    /// The axis of the cone that holds every light's spot axis.
    pub axis: DVec3,
    /// `cos θo` of that cone's half-angle; −1 (any direction) when some light is not a spot.
    pub cos_spread: f64,
    /// `cos θe` of the widest outer cone; −1 when some light is not a spot.
    pub cos_emission: f64,
    /// The longest range; `∞` when some light has none.
    pub range: f64,
    /// The box on the plane outside which no light of the lane gives anything (the union of
    /// the lights' [`Emission::footprint`]s); infinite when some light's is unbounded.
    pub footprint: [DVec2; 2],
}

impl LaneBounds {
    /// An empty lane's bounds (no light: no intensity, reaches nothing).
    pub const EMPTY: LaneBounds = LaneBounds {
        min: DVec3::INFINITY,
        max: DVec3::NEG_INFINITY,
        intensity: 0.0,
        axis: DVec3::Z,
        cos_spread: 1.0,
        cos_emission: 1.0,
        range: 0.0,
        footprint: [DVec2::INFINITY, DVec2::NEG_INFINITY],
    };

    /// An unbounded footprint.
    const EVERYWHERE: [DVec2; 2] = [DVec2::NEG_INFINITY, DVec2::INFINITY];

    /// The bounds of one light.
    pub fn of_light(light: &SpatialLight, emission: &Emission) -> Self {
        let (axis, cos_spread, cos_emission) = match emission.spot() {
            Some(_) => (emission.axis(), 1.0, emission.cos_outer()),
            None => (DVec3::Z, -1.0, -1.0),
        };
        LaneBounds {
            min: light.position_in_world,
            max: light.position_in_world,
            intensity: light.power * emission.gain(),
            axis,
            cos_spread,
            cos_emission,
            range: emission.range().unwrap_or(f64::INFINITY),
            footprint: emission
                .footprint(light.position_in_world)
                .unwrap_or(Self::EVERYWHERE),
        }
    }

    /// The bounds of the lights of `a` and of `b` together.
    pub fn union(a: &LaneBounds, b: &LaneBounds) -> Self {
        if a.intensity == 0.0 && a.min.x > a.max.x {
            return *b;
        }
        if b.intensity == 0.0 && b.min.x > b.max.x {
            return *a;
        }
        let (axis, cos_spread) = cone_union((a.axis, a.cos_spread), (b.axis, b.cos_spread));
        LaneBounds {
            min: a.min.min(b.min),
            max: a.max.max(b.max),
            intensity: a.intensity + b.intensity,
            axis,
            cos_spread,
            cos_emission: a.cos_emission.min(b.cos_emission),
            range: a.range.max(b.range),
            footprint: [
                a.footprint[0].min(b.footprint[0]),
                a.footprint[1].max(b.footprint[1]),
            ],
        }
    }

    /// 0 when no light of the lane can light `point_on_plane`, else 1: outside the lane's
    /// footprint (which, when bounded, already holds every point its cones and ranges
    /// reach), or, for a lane whose footprint is unbounded, beyond the longest range from
    /// the box or outside every cone: with `θw` the angle between the cone's
    /// axis and the direction from the box's centre to the point, `θb` the half-angle the
    /// box's bounding sphere subtends there (π inside it), no light direction within `θo` of
    /// the axis comes within `θe` of the point's direction when `max(0, θw − θo − θb) ≥ θe`
    /// (pbrt-v4's `LightBounds::Importance`, its cosines composed without inverse
    /// trigonometry).
    #[inline]
    pub fn reach(&self, point_on_plane: DVec2) -> f64 {
        let [lo, hi] = self.footprint;
        if !(point_on_plane.cmpge(lo).all() && point_on_plane.cmple(hi).all()) {
            return 0.0;
        }
        // A bounded footprint holds every point the lane's cones and ranges reach.
        if lo.is_finite() && hi.is_finite() {
            return 1.0;
        }
        let p = point_on_plane.extend(0.0);
        let outside = (self.min - p).max(p - self.max).max(DVec3::ZERO);
        if outside.length_squared() >= self.range * self.range {
            return 0.0;
        }
        if self.cos_spread <= -1.0 || self.cos_emission <= -1.0 {
            return 1.0;
        }
        let centre = 0.5 * (self.min + self.max);
        let radius2 = 0.25 * (self.max - self.min).length_squared();
        let to_point = p - centre;
        let d2 = to_point.length_squared();
        if d2 <= radius2 {
            return 1.0;
        }
        let d = d2.sqrt();
        let cos_w = (self.axis.dot(to_point) / d).clamp(-1.0, 1.0);
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let sin_spread = (1.0 - self.cos_spread * self.cos_spread).max(0.0).sqrt();
        let sin2_b = radius2 / d2;
        let cos_b = (1.0 - sin2_b).max(0.0).sqrt();
        let sin_b = sin2_b.sqrt();
        // θx = max(0, θw − θo), then θp = max(0, θx − θb).
        let (cos_x, sin_x) = cos_sin_sub_clamped((cos_w, sin_w), (self.cos_spread, sin_spread));
        let (cos_p, _) = cos_sin_sub_clamped((cos_x, sin_x), (cos_b, sin_b));
        if cos_p <= self.cos_emission { 0.0 } else { 1.0 }
    }
}

/// `(cos, sin)` of `max(0, a − b)` from those of `a` and `b` (angles in `[0, π]`).
#[inline]
fn cos_sin_sub_clamped((cos_a, sin_a): (f64, f64), (cos_b, sin_b): (f64, f64)) -> (f64, f64) {
    if cos_a > cos_b {
        (1.0, 0.0)
    } else {
        (
            cos_a * cos_b + sin_a * sin_b,
            (sin_a * cos_b - cos_a * sin_b).max(0.0),
        )
    }
}

/// The smallest cone (axis, `cos` half-angle) found by pbrt-v4's `DirectionCone::Union`
/// that holds two cones; `cos = −1` is every direction.
fn cone_union((wa, cos_a): (DVec3, f64), (wb, cos_b): (DVec3, f64)) -> (DVec3, f64) {
    if cos_a <= -1.0 || cos_b <= -1.0 {
        return (DVec3::Z, -1.0);
    }
    let theta_a = cos_a.clamp(-1.0, 1.0).acos();
    let theta_b = cos_b.clamp(-1.0, 1.0).acos();
    let theta_d = wa.angle_between(wb);
    if (theta_d + theta_b).min(std::f64::consts::PI) <= theta_a {
        return (wa, cos_a);
    }
    if (theta_d + theta_a).min(std::f64::consts::PI) <= theta_b {
        return (wb, cos_b);
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b);
    if theta_o >= std::f64::consts::PI {
        return (DVec3::Z, -1.0);
    }
    let theta_r = theta_o - theta_a;
    let wr = wa.cross(wb);
    if wr.length_squared() == 0.0 {
        return (DVec3::Z, -1.0);
    }
    let w = DQuat::from_axis_angle(wr.normalize(), theta_r) * wa;
    // Rounding in the rotation: keep the cone a touch wider than computed.
    (
        w.normalize(),
        (theta_o + 1e-9).min(std::f64::consts::PI).cos(),
    )
}
