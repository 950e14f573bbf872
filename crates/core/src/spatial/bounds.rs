//! Bounds of what a tree lane's lights can light (pbrt-v4's `LightBounds`, with a box on
//! the plane): for lights with spot cones or ranges only. A lane whose bounds exclude a
//! point is culled there (probability 0): the bounds hold every point any of its lights
//! lights, so no light that gives the point anything is lost.

use glam::{DQuat, DVec2, DVec3};

use super::SpatialLight;
use crate::scene::EmissionShape;

/// What the lights of a tree lane can do at most, for lights with emission profiles
/// (pbrt-v4's `LightBounds`; the module docs), and where on the plane they can do it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneBounds {
    /// The box of the lane's light positions, its cones and ranges: what culls it where
    /// its footprint is unbounded.
    pub geometry: LaneReach,
    /// `Σ p_i·g_i`: the lane's normalized power weighted by each light's on-axis gain
    /// ([`EmissionShape::gain`]; 1 for a light without a spot).
    pub intensity: f64,
    /// The box on the plane outside which no light of the lane gives anything (the union of
    /// the lights' [`EmissionShape::footprint`]s); infinite when some light's is unbounded.
    pub footprint: [DVec2; 2],
}

impl LaneBounds {
    /// An empty lane's bounds (no light: no intensity, reaches nothing).
    pub const EMPTY: LaneBounds = LaneBounds {
        geometry: LaneReach {
            min: DVec3::INFINITY,
            max: DVec3::NEG_INFINITY,
            axis: DVec3::Z,
            cos_spread: 1.0,
            cos_emission: 1.0,
            range: 0.0,
        },
        intensity: 0.0,
        footprint: [DVec2::INFINITY, DVec2::NEG_INFINITY],
    };

    /// An unbounded footprint.
    const EVERYWHERE: [DVec2; 2] = [DVec2::NEG_INFINITY, DVec2::INFINITY];

    /// The bounds of one light.
    pub fn of_light(light: &SpatialLight, emission: &EmissionShape) -> Self {
        let (axis, cos_spread, cos_emission) = if emission.has_spot() {
            (emission.axis(), 1.0, emission.cos_outer())
        } else {
            (DVec3::Z, -1.0, -1.0)
        };
        LaneBounds {
            geometry: LaneReach {
                min: light.position_in_world,
                max: light.position_in_world,
                axis,
                cos_spread,
                cos_emission,
                range: emission.range().unwrap_or(f64::INFINITY),
            },
            intensity: light.power * emission.gain(),
            footprint: emission
                .footprint(light.position_in_world)
                .unwrap_or(Self::EVERYWHERE),
        }
    }

    /// The bounds of the lights of `a` and of `b` together.
    pub fn union(a: &LaneBounds, b: &LaneBounds) -> Self {
        let (ga, gb) = (&a.geometry, &b.geometry);
        if a.intensity == 0.0 && ga.min.x > ga.max.x {
            return *b;
        }
        if b.intensity == 0.0 && gb.min.x > gb.max.x {
            return *a;
        }
        let (axis, cos_spread) = cone_union((ga.axis, ga.cos_spread), (gb.axis, gb.cos_spread));
        LaneBounds {
            geometry: LaneReach {
                min: ga.min.min(gb.min),
                max: ga.max.max(gb.max),
                axis,
                cos_spread,
                cos_emission: ga.cos_emission.min(gb.cos_emission),
                range: ga.range.max(gb.range),
            },
            intensity: a.intensity + b.intensity,
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
        self.geometry.reach(point_on_plane)
    }
}

/// What culls a lane whose footprint on the plane is unbounded (some light's cone reaches
/// the horizon and it has no range): the box of its lights, the cone holding their axes,
/// the widest outer cone and the longest range, as in its [`LaneBounds`]. A lane with a
/// bounded footprint needs none of it: its footprint already holds every point it lights,
/// so the tree keeps these only for nodes with an unbounded lane
/// ([`crate::spatial::grid::MappedLanes::reaches`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneReach {
    /// The box of the lane's light positions, in the world.
    pub min: DVec3,
    /// See [`LaneReach::min`].
    pub max: DVec3,
    /// The axis of the cone that holds every light's spot axis.
    pub axis: DVec3,
    /// `cos θo` of that cone's half-angle; −1 (any direction) when some light is not a spot.
    pub cos_spread: f64,
    /// `cos θe` of the widest outer cone; −1 when some light is not a spot.
    pub cos_emission: f64,
    /// The longest range; `∞` when some light has none.
    pub range: f64,
}

impl LaneReach {
    /// A reach that culls nothing: no range, no cone (what the GPU reads for a lane whose
    /// footprint is bounded, where it never asks).
    pub const EVERYWHERE: LaneReach = LaneReach {
        min: DVec3::ZERO,
        max: DVec3::ZERO,
        axis: DVec3::Z,
        cos_spread: -1.0,
        cos_emission: -1.0,
        range: f64::INFINITY,
    };

    /// 0 when no light of the lane can light `point_on_plane`, else 1, for a lane whose
    /// footprint holds the point but is unbounded ([`LaneBounds::reach`] past its
    /// footprint): beyond the longest range from the box, or outside every cone (the
    /// angles of [`LaneBounds::reach`]).
    #[inline]
    pub fn reach(&self, point_on_plane: DVec2) -> f64 {
        if self.beyond_range(point_on_plane) {
            return 0.0;
        }
        let p = point_on_plane.extend(0.0);
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
        if cos_p < self.cos_emission - REACH_SLACK {
            0.0
        } else {
            1.0
        }
    }
}

impl LaneReach {
    /// Whether `point_on_plane` lies farther from the box of the lane's lights than their
    /// longest range: [`LaneReach::reach`]'s first test, culling only beyond the rounding
    /// of both sides (a few ulps), by a relative margin.
    #[inline]
    pub fn beyond_range(&self, point_on_plane: DVec2) -> bool {
        let p = point_on_plane.extend(0.0);
        let outside = (self.min - p).max(p - self.max).max(DVec3::ZERO);
        outside.length_squared() > self.range * self.range * (1.0 + REACH_SLACK)
    }
}

/// The margin beyond which [`LaneBounds::reach`] culls: relative for the squared range,
/// absolute for the cosines; far above their rounding (a few ulps), far below any scene's
/// scale.
pub(crate) const REACH_SLACK: f64 = 1e-12;

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
/// that holds two cones; `cos = −1` is every direction. The angle between the axes is
/// `2·asin(|wb − wa|/2)` (pbrt-v4's `AngleBetween`: accurate for nearly parallel axes, where
/// `acos` of their dot product gives 0 below about `10^-8`), and every cone returned is
/// widened against rounding ([`padded_cos`]), so it holds both cones' axes even when they
/// are `5·10^-9` apart.
fn cone_union((wa, cos_a): (DVec3, f64), (wb, cos_b): (DVec3, f64)) -> (DVec3, f64) {
    use std::f64::consts::PI;
    if cos_a <= -1.0 || cos_b <= -1.0 {
        return (DVec3::Z, -1.0);
    }
    let theta_a = cos_a.clamp(-1.0, 1.0).acos();
    let theta_b = cos_b.clamp(-1.0, 1.0).acos();
    let theta_d = angle_between(wa, wb);
    if (theta_d + theta_b).min(PI) <= theta_a {
        return (wa, padded_cos(theta_a));
    }
    if (theta_d + theta_a).min(PI) <= theta_b {
        return (wb, padded_cos(theta_b));
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b);
    if theta_o >= PI {
        return (DVec3::Z, -1.0);
    }
    let theta_r = theta_o - theta_a;
    let wr = wa.cross(wb);
    if wr.length_squared() == 0.0 {
        return (DVec3::Z, -1.0);
    }
    let w = DQuat::from_axis_angle(wr.normalize(), theta_r) * wa;
    (w.normalize(), padded_cos(theta_o))
}

/// The angle between two directions, `2·asin(|v2 − v1|/2)` of the unit vectors (or
/// `π − 2·asin(|v2 + v1|/2)` beyond a right angle): accurate to a few ulps at every angle.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    let (a, b) = (a.normalize(), b.normalize());
    if a.dot(b) < 0.0 {
        std::f64::consts::PI - 2.0 * ((a + b).length() / 2.0).min(1.0).asin()
    } else {
        2.0 * ((b - a).length() / 2.0).min(1.0).asin()
    }
}

/// `cos(θ)` of a cone's half-angle widened against rounding: by `10^-9` rad and then by
/// four ulps of the cosine, which is what widens a cone narrower than `10^-8` (whose cosine
/// rounds to 1); `−1` from `π` on.
fn padded_cos(theta: f64) -> f64 {
    let widened = theta + 1e-9;
    if widened >= std::f64::consts::PI {
        return -1.0;
    }
    (widened.cos() - 4.0 * f64::EPSILON).max(-1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Emission, Spot};

    fn spot(direction: DVec3, outer: f64, range: Option<f64>) -> Emission {
        Emission::new(
            Some(Spot {
                direction,
                inner_cone: 0.5 * outer,
                outer_cone: outer,
            }),
            range,
        )
        .expect("a valid spot")
    }

    fn light(at: DVec3) -> SpatialLight {
        SpatialLight {
            position_in_world: at,
            power: 0.5,
        }
    }

    /// The last `f64` step `t` in `[0, t_max]` along `from + t·dir` on the plane where
    /// `lit(t)` holds (it holds at 0 and not at `t_max`, once across), by bisection.
    fn rim(lit: impl Fn(f64) -> bool, t_max: f64) -> f64 {
        let (mut inside, mut outside) = (0.0f64, t_max);
        while inside.next_up() < outside {
            let mid = 0.5 * (inside + outside);
            let mid = if mid <= inside { inside.next_up() } else { mid };
            if lit(mid) {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        inside
    }

    #[test]
    fn coincident_spots_with_nearly_parallel_axes_light_their_rims() {
        // Two spots at one position whose cones reach the horizon (unbounded footprints, so
        // the lane's cone is what culls), axes 5e-9 rad apart: a point just inside b's cone
        // lies just outside a's, and the union cone must hold it.
        let at = DVec3::new(0.2, -0.1, 1.0);
        let wa = DVec3::new(1.0, 0.0, -0.2).normalize();
        let down = wa.cross(DVec3::NEG_Z).normalize();
        for apart in [5e-9, 1e-12, 3e-8, 1e-4] {
            let wb = DQuat::from_axis_angle(down, apart) * wa;
            let (a, b) = (spot(wa, 0.8, None), spot(wb, 0.8, None));
            let union = LaneBounds::union(
                &LaneBounds::of_light(&light(at), &a),
                &LaneBounds::of_light(&light(at), &b),
            );
            assert!(union.footprint[0].x.is_infinite(), "an unbounded footprint");
            // Along the plane, away from a's axis, out to b's rim.
            let ray = |t: f64| {
                let dir = DQuat::from_axis_angle(down, apart + t) * wa;
                at.truncate() + dir.truncate() * (at.z / -dir.z)
            };
            let last = rim(|t| b.factor(at, ray(t)) > 0.0, 1.0);
            let point = ray(last);
            assert!(b.factor(at, point) > 0.0, "lit by b");
            assert_eq!(a.factor(at, point), 0.0, "{apart} apart: not lit by a");
            assert_eq!(union.reach(point), 1.0, "{apart} apart: b's rim culled");
        }
    }

    /// A reproducible stream of uniforms in `[0, 1)` (a 64-bit LCG's top bits).
    fn uniforms(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn points_just_inside_a_range_are_kept() {
        // The last point along a ray where a light of range r still gives something lies in
        // its footprint box, for heights from 10^-3 to 10^-14 below r (where r² − h²
        // cancels; without the widening about one light in eight lost its rim), near the
        // origin and far from it.
        let mut unit = uniforms(12_345);
        for _ in 0..2000 {
            let r = 0.5 + 10.0 * unit();
            let h = r * (1.0 - 10f64.powf(-3.0 - 11.0 * unit()));
            let scale = 10f64.powf(-3.0 * unit());
            let at = DVec2::new(2000.0 * unit() - 1000.0, 2000.0 * unit() - 1000.0) * scale;
            let light_at = at.extend(h);
            let emission = Emission::new(None, Some(r)).expect("a valid range");
            let bounds = LaneBounds::of_light(&light(light_at), &emission);
            let angle = std::f64::consts::TAU * unit();
            let dir = DVec2::new(angle.cos(), angle.sin());
            let point = |t: f64| at + dir * t;
            assert!(emission.factor(light_at, point(0.0)) > 0.0);
            let last = point(rim(|t| emission.factor(light_at, point(t)) > 0.0, 2.0 * r));
            assert!(emission.factor(light_at, last) > 0.0);
            assert_eq!(
                bounds.reach(last),
                1.0,
                "light at {light_at}, range {r}: its rim culled"
            );
        }
    }

    #[test]
    fn grazing_spots_keep_their_rims() {
        // Cones just below the horizon: the footprint ellipse is long and its determinant
        // cancels; the last lit point along rays from below the light stays in its box.
        let at = DVec3::new(-0.4, 0.25, 1.0);
        for tilt in [1e-3, 1e-6, 1e-9, 1e-12] {
            let outer: f64 = 0.6;
            // −axis.z just above sin θo: the cone's upper edge dips `tilt` below the horizon.
            let elevation = -(outer + tilt);
            let axis = DVec3::new(elevation.cos(), 0.0, elevation.sin());
            let emission = spot(axis, outer, None);
            let bounds = LaneBounds::of_light(&light(at), &emission);
            for angle in [0.0f64, 0.3, -0.3, 1.2, -1.2, 3.0] {
                let dir = DVec2::new(angle.cos(), angle.sin());
                // From under the axis' foot outwards.
                let start = at.truncate() + axis.truncate() * (at.z / -axis.z);
                let from = |t: f64| start + dir * t;
                if emission.factor(at, from(0.0)) == 0.0 {
                    continue;
                }
                let last = from(rim(|t| emission.factor(at, from(t)) > 0.0, 1e13));
                assert!(emission.factor(at, last) > 0.0);
                assert_eq!(bounds.reach(last), 1.0, "tilt {tilt}, ray {angle}: culled");
            }
        }
    }
}
