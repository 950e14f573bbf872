//! What a light emits beyond a bare point light: a spot cone and a range, for the lights
//! (and only the scenes) that have them.
//!
//! A point light of power `Φ` has the intensity `I = Φ/4π` in every direction and gives the
//! plane the irradiance `Φ·G(x)` ([`super::geometry_term`]). A light with an
//! [`Emission`] gives `Φ·G(x)·S(x)`, with the emission factor
//!
//! `S(x) = g · t(α)² · w(d)`,
//!
//! * `t = clamp((cos α − cos θo)/(cos θi − cos θo), 0, 1)` for a spot (α the angle between
//!   the spot's axis and the direction from the light to `x`; 1 without a spot): glTF's
//!   `KHR_lights_punctual` falloff, full intensity inside the inner cone `θi`, none beyond
//!   the outer cone `θo`;
//! * `w = clamp(1 − (d/r)⁴, 0, 1)` for a light of range `r` at distance `d` (1 without one);
//! * `g = 4π/Ω`, `Ω = 2π·[(1 − cos θi) + (cos θi − cos θo)/3]` the solid angle that the
//!   falloff `t²` weights (`∫ t² dω`, exact: `t` is linear in `cos α`), and `g = 1` without a
//!   spot. So a spot of power `Φ` has the intensity `I = Φ/Ω` on its axis: the power is the
//!   light's emitted flux whatever its cone, and a spot's irradiance is a point light's of
//!   the same intensity times `t²`, as glTF defines it. The range window is an artist's
//!   cut-off and does not change `Φ`.
//!
//! Every scheme, the exact reference, the inspector, the estimator view, the light tree and
//! the GPU kernels evaluate this one definition ([`super::light_term`] and its WGSL twin).

use glam::{DVec2, DVec3};

/// A spot light's cone, as glTF's `KHR_lights_punctual` describes one.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spot {
    /// The axis the spot points along, in the world (any length; normalized for use).
    pub direction: DVec3,
    /// Half-angle `θi` (radians) of the cone of full intensity.
    pub inner_cone: f64,
    /// Half-angle `θo` (radians) beyond which the spot emits nothing;
    /// `0 ≤ θi < θo ≤ π/2`.
    pub outer_cone: f64,
}

/// Why an emission profile was refused; the message leaves the light and the field
/// ([`EmissionError::field`]) to the caller.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EmissionError {
    /// The spot's direction is zero, NaN or infinite.
    #[error("not a finite non-zero vector ({0:?})")]
    Direction([f64; 3]),
    /// The cone angles are not `0 ≤ inner < outer ≤ π/2`.
    #[error("cones must satisfy 0 ≤ inner_cone < outer_cone ≤ π/2 (got {inner}, {outer})")]
    Cones {
        /// The inner half-angle given.
        inner: f64,
        /// The outer half-angle given.
        outer: f64,
    },
    /// The range is not a finite positive length.
    #[error("must be finite and positive (got {0})")]
    Range(f64),
}

impl EmissionError {
    /// The field of the light the error is about (`spot.direction`, `spot`, `range`).
    pub fn field(&self) -> &'static str {
        match self {
            EmissionError::Direction(_) => "spot.direction",
            EmissionError::Cones { .. } => "spot",
            EmissionError::Range(_) => "range",
        }
    }
}

/// One light's emission profile (module docs): its spot cone and range as given, and the
/// constants the factor `S(x)` is evaluated with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    spot: Option<Spot>,
    range: Option<f64>,
    /// The unit spot axis (zero without a spot).
    axis: DVec3,
    cos_inner: f64,
    cos_outer: f64,
    /// `1/(cos θi − cos θo)` (0 without a spot).
    cone_scale: f64,
    /// `g = 4π/Ω` (1 without a spot).
    gain: f64,
    /// `1/r` (0 without a range).
    inv_range: f64,
}

impl Emission {
    /// A bare point light: `S ≡ 1`.
    pub const POINT: Emission = Emission {
        spot: None,
        range: None,
        axis: DVec3::ZERO,
        cos_inner: 1.0,
        cos_outer: -1.0,
        cone_scale: 0.0,
        gain: 1.0,
        inv_range: 0.0,
    };

    /// The profile of a light with an optional spot cone and an optional range, validated:
    /// a finite non-zero direction, `0 ≤ θi < θo ≤ π/2`, a finite `r > 0`.
    pub fn new(spot: Option<Spot>, range: Option<f64>) -> Result<Emission, EmissionError> {
        let mut e = Emission::POINT;
        if let Some(r) = range {
            if !(r.is_finite() && r > 0.0) {
                return Err(EmissionError::Range(r));
            }
            e.range = Some(r);
            e.inv_range = 1.0 / r;
        }
        if let Some(s) = spot {
            let length = s.direction.length();
            if !(length.is_finite() && length > 0.0) {
                return Err(EmissionError::Direction(s.direction.to_array()));
            }
            let (inner, outer) = (s.inner_cone, s.outer_cone);
            if !(inner >= 0.0 && inner < outer && outer <= std::f64::consts::FRAC_PI_2) {
                return Err(EmissionError::Cones { inner, outer });
            }
            let axis = s.direction / length;
            e.spot = Some(s);
            e.axis = axis;
            e.cos_inner = inner.cos();
            e.cos_outer = outer.cos();
            // 1 − cos θi and cos θi − cos θo without cancellation (narrow cones).
            let one_minus_inner = 2.0 * (0.5 * inner).sin().powi(2);
            let width = 2.0 * (0.5 * (outer + inner)).sin() * (0.5 * (outer - inner)).sin();
            e.cone_scale = 1.0 / width;
            e.gain = 2.0 / (one_minus_inner + width / 3.0);
        }
        Ok(e)
    }

    /// The spot cone as given, if the light is a spot ([`Emission::axis`] is its direction
    /// normalized).
    pub fn spot(&self) -> Option<Spot> {
        self.spot
    }

    /// The range `r`, if the light has one.
    pub fn range(&self) -> Option<f64> {
        self.range
    }

    /// Whether the profile is a bare point light's (`S ≡ 1`).
    pub fn is_point(&self) -> bool {
        self.spot.is_none() && self.range.is_none()
    }

    /// `g = 4π/Ω`: a spot's on-axis intensity over a point light's of the same power (1
    /// without a spot).
    pub fn gain(&self) -> f64 {
        self.gain
    }

    /// The unit spot axis (zero without a spot).
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// `cos θo` (−1 without a spot).
    pub fn cos_outer(&self) -> f64 {
        self.cos_outer
    }

    /// `1/(cos θi − cos θo)` (0 without a spot).
    pub fn cone_scale(&self) -> f64 {
        self.cone_scale
    }

    /// `1/r` (0 without a range).
    pub fn inv_range(&self) -> f64 {
        self.inv_range
    }

    /// The spot falloff `t²` for `cos α` (1 without a spot).
    #[inline]
    pub fn falloff(&self, cos_alpha: f64) -> f64 {
        if self.spot.is_none() || cos_alpha >= self.cos_inner {
            1.0
        } else if cos_alpha <= self.cos_outer {
            0.0
        } else {
            let t = (cos_alpha - self.cos_outer) * self.cone_scale;
            t * t
        }
    }

    /// The range window `clamp(1 − (d/r)⁴, 0, 1)` at distance `d` (1 without a range).
    #[inline]
    pub fn window(&self, distance: f64) -> f64 {
        let q = distance * self.inv_range;
        let q2 = q * q;
        (1.0 - q2 * q2).clamp(0.0, 1.0)
    }

    /// `S(x) = g · t² · w` for the light at `light_in_world` and the point `point_on_plane`
    /// (module docs); the light must not be on the point (then `S` is not defined).
    #[inline]
    pub fn factor(&self, light_in_world: DVec3, point_on_plane: DVec2) -> f64 {
        let to_point = point_on_plane.extend(0.0) - light_in_world;
        self.factor_along(to_point, to_point.length())
    }

    /// [`Emission::factor`] from the light's vector to the point, `to_point`, and its length
    /// `distance = |to_point|` (`> 0`), already at hand: [`super::light_term`] shares the
    /// distance with `G` instead of taking a second square root (the same bits).
    #[inline]
    pub(crate) fn factor_along(&self, to_point: DVec3, distance: f64) -> f64 {
        let mut s = self.gain;
        if self.spot.is_some() {
            s *= self.falloff(self.axis.dot(to_point) / distance);
        }
        if self.range.is_some() {
            s *= self.window(distance);
        }
        s
    }

    /// The spot's cone term `t²` toward `point_on_plane` for the light at `light_in_world`
    /// (module docs: 1 inside the inner cone, 0 beyond the outer), or `None` for a light
    /// without a spot. What power picking ignores and the light tree's cone bounds weigh.
    pub fn cone_term(&self, light_in_world: DVec3, point_on_plane: DVec2) -> Option<f64> {
        self.spot?;
        let to_point = point_on_plane.extend(0.0) - light_in_world;
        let distance = to_point.length();
        Some(if distance > 0.0 {
            self.falloff(self.axis.dot(to_point) / distance)
        } else {
            0.0
        })
    }

    /// A lower bound of `S(x)/g = t(α)²·w(d)` over the rectangle `[lo, hi]` of the plane for
    /// the light at `light_in_world` (`z > 0`): `t(min_c cos α_c)² · w(max_c d_c)` over the
    /// rectangle's four corners `c`. It holds because both factors take their least at a
    /// corner: `w` falls with `d`, a convex function of `x`, so `d` is largest at a corner;
    /// and `t` rises with `cos α`, whose superlevel sets `{x : cos α(x) ≥ k}` are, for
    /// `k ≥ 0`, a convex cone cut by the plane, hence convex, so `cos α` is least at a corner
    /// wherever that least is `≥ 0` (below 0 the bound is `t = 0` anyway, `θo ≤ π/2`).
    /// Since `S ≤ g`, a bound near 1 says the factor hardly changes over the rectangle (a
    /// cone's edge does not cross it). 1 for a bare point light.
    pub fn factor_floor_over(&self, light_in_world: DVec3, [lo, hi]: [DVec2; 2]) -> f64 {
        if self.is_point() {
            return 1.0;
        }
        let corners = [lo, DVec2::new(hi.x, lo.y), DVec2::new(lo.x, hi.y), hi];
        let (mut least_cos, mut farthest) = (f64::INFINITY, 0.0f64);
        for corner in corners {
            let to_corner = corner.extend(0.0) - light_in_world;
            let distance = to_corner.length();
            farthest = farthest.max(distance);
            least_cos = least_cos.min(self.axis.dot(to_corner) / distance);
        }
        let mut floor = 1.0;
        if self.spot.is_some() {
            floor *= self.falloff(least_cos);
        }
        if self.range.is_some() {
            floor *= self.window(farthest);
        }
        floor
    }

    /// Whether the light at `light_in_world` can light some point of the plane `z = 0`
    /// (strictly: `S > 0` somewhere below it): above the plane, a cone that reaches below
    /// the horizontal (`axis_z < sin θo`, the cone's open angle being `< θo` where `t > 0`),
    /// and a range beyond its height.
    pub fn reaches_plane(&self, light_in_world: DVec3) -> bool {
        let z = light_in_world.z;
        if z <= 0.0 {
            return false;
        }
        let cone = self.spot.is_none_or(|s| self.axis.z < s.outer_cone.sin());
        let range = self.range.is_none_or(|r| r > z);
        cone && range
    }
}

impl Emission {
    /// The box on the plane `z = 0` outside which the light at `light_in_world` gives
    /// nothing, `[min, max]`, or `None` when its light reaches arbitrarily far (a point light
    /// without a range, a spot whose cone reaches the horizon).
    ///
    /// A spot's lit region is the conic `(d·a)² ≥ cos²θo·|d|²` of the offsets
    /// `d = (u, v, −h)` from the light (height `h`) to the plane; when the cone lies below
    /// the horizon (`−a_z > sin θo`) it is an ellipse `wᵀ(−M)w ≤ Q₀` about its centre, whose
    /// box has the half-extents `√(Q₀·(−C)/det)` and `√(Q₀·(−A)/det)` (`M = [[A, B], [B, C]]`
    /// the quadratic part); a range `r` bounds the region by the disc of radius `√(r² − h²)`.
    /// The box is widened by `10^-9` of its size against rounding, and the ellipse's by the
    /// error bound of its cancellation where the cone grazes the horizon (its determinant's
    /// condition number times `8ε`); past `κ·8ε = 1/4` the ellipse is not used.
    pub fn footprint(&self, light_in_world: DVec3) -> Option<[DVec2; 2]> {
        let h = light_in_world.z;
        let at = light_in_world.truncate();
        let mut bounds: Option<[DVec2; 2]> = None;
        if let Some(r) = self.range {
            // The window lights up to `d·(1/r) < 1` as rounded, a few ulps past r: take
            // r·(1 + 8ε). Then (r − h)(r + h) rather than r² − h², which cancels where h nears
            // r, and the box widened past the rounding of the root and of at ± reach.
            let r = r * (1.0 + 8.0 * f64::EPSILON);
            let reach = ((r - h) * (r + h)).max(0.0).sqrt();
            let slack = 1e-9 * (at.abs() + reach) + DVec2::splat(f64::MIN_POSITIVE);
            bounds = Some([at - reach - slack, at + reach + slack]);
        }
        if self.spot.is_some() && -self.axis.z > (1.0 - self.cos_outer * self.cos_outer).sqrt() {
            let (ax, ay, az) = (self.axis.x, self.axis.y, self.axis.z);
            let c2 = self.cos_outer * self.cos_outer;
            let a = ax * ax - c2;
            let b = ax * ay;
            let c = ay * ay - c2;
            let d = -ax * az * h;
            let e = -ay * az * h;
            let f = (az * az - c2) * h * h;
            let det = a * c - b * b;
            // Where the cone grazes the horizon `det` cancels: `κ` its condition number, so
            // that `8εκ` bounds its relative error and the centre's and extents' through it.
            let kappa = ((a * c).abs() + b * b) / det;
            let rel = 8.0 * f64::EPSILON * kappa;
            if det > 0.0 && a < 0.0 && c < 0.0 && rel < 0.25 {
                let u0 = (-d * c + e * b) / det;
                let v0 = (-e * a + d * b) / det;
                let centre_error = DVec2::new(
                    4.0 * f64::EPSILON * ((d * c).abs() + (e * b).abs()) / det + rel * u0.abs(),
                    4.0 * f64::EPSILON * ((e * a).abs() + (d * b).abs()) / det + rel * v0.abs(),
                );
                // q0's own cancellation, raised by its bound; det lowered by its bound.
                let q0_error = 8.0
                    * f64::EPSILON
                    * (1.0 + kappa)
                    * (f.abs() + (d * u0).abs() + (e * v0).abs());
                let q0 = (f + d * u0 + e * v0 + q0_error).max(0.0);
                let det_low = det * (1.0 - rel);
                let half = DVec2::new((q0 * -c / det_low).sqrt(), (q0 * -a / det_low).sqrt());
                let centre = at + DVec2::new(u0, v0);
                let slack =
                    1e-9 * (centre.abs() + half) + centre_error + DVec2::splat(f64::MIN_POSITIVE);
                let ellipse = [centre - half - slack, centre + half + slack];
                bounds = Some(match bounds {
                    Some([lo, hi]) => [lo.max(ellipse[0]), hi.min(ellipse[1])],
                    None => ellipse,
                });
            }
        }
        bounds
    }
}

impl Default for Emission {
    fn default() -> Self {
        Emission::POINT
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn spot(direction: DVec3, inner: f64, outer: f64) -> Emission {
        Emission::new(
            Some(Spot {
                direction,
                inner_cone: inner,
                outer_cone: outer,
            }),
            None,
        )
        .expect("valid spot")
    }

    #[test]
    fn the_falloff_is_the_written_formula() {
        let e = spot(DVec3::NEG_Z * 3.0, 0.2, 0.7);
        let (ci, co) = (0.2f64.cos(), 0.7f64.cos());
        for alpha in [0.0, 0.1, 0.2, 0.3, 0.45, 0.6, 0.69, 0.7, 0.9, 2.0] {
            let c = f64::cos(alpha);
            let t = ((c - co) / (ci - co)).clamp(0.0, 1.0);
            let got = e.falloff(c);
            assert!(
                (got - t * t).abs() <= 1e-14,
                "α {alpha}: {got} vs {}",
                t * t
            );
        }
        // Through the factor: a light at height 1 over the origin, points at angle α.
        let light = DVec3::Z;
        for alpha in [0.0, 0.35, 0.5, 0.65, 0.8] {
            let x = DVec2::new(f64::tan(alpha), 0.0);
            let t = ((alpha.cos() - co) / (ci - co)).clamp(0.0, 1.0);
            let want = e.gain() * t * t;
            assert!((e.factor(light, x) - want).abs() <= 1e-13 * e.gain());
        }
    }

    #[test]
    fn the_gain_conserves_the_power() {
        // ∫ S dω = 2π·g·∫ t² d(cos α) = 4π, by the midpoint rule in cos α over [cos θo, 1]
        // (t = 0 below). t² is monotone in cos α, so on each cell of width h the midpoint value
        // and the cell's mean both lie between the cell's end values: the rule's error is at
        // most h·(t²(1) − t²(cos θo)) = h. Relative to 4π that is g·h/2 = g·(1 − cos θo)/(2n),
        // and g·(1 − cos θo) ≤ 6 (the band's t² integrates to at least a third of its width).
        for (inner, outer) in [(0.0, 0.01), (0.0, FRAC_PI_2), (0.3, 0.5), (0.5, 0.50001)] {
            let e = spot(DVec3::X, inner, outer);
            let steps = 200_000;
            let low = outer.cos();
            let h = (1.0 - low) / f64::from(steps);
            let integral: f64 = (0..steps)
                .map(|k| e.falloff(low + (f64::from(k) + 0.5) * h) * h)
                .sum();
            let relative = 2.0 * PI * e.gain() * integral / (4.0 * PI) - 1.0;
            let bound = e.gain() * h / 2.0 + 1e-12;
            // (up to the rounding of 1 − cos θo, equality holding for θi = 0)
            assert!(bound <= 3.0 / f64::from(steps) * (1.0 + 1e-6));
            assert!(
                relative.abs() <= bound,
                "({inner}, {outer}): {relative} > {bound}"
            );
        }
        assert_eq!(Emission::POINT.gain(), 1.0);
    }

    #[test]
    fn the_range_window_is_the_written_formula() {
        let e = Emission::new(None, Some(2.0)).expect("valid");
        for d in [0.0, 0.5, 1.0, 1.9, 2.0, 3.0] {
            let want = (1.0 - (d / 2.0f64).powi(4)).clamp(0.0, 1.0);
            assert!((e.window(d) - want).abs() <= 1e-15);
        }
        assert_eq!(
            e.factor(DVec3::new(0.0, 0.0, 1.0), DVec2::new(3.0, 0.0)),
            0.0
        );
        assert!(e.reaches_plane(DVec3::new(0.0, 0.0, 1.9)));
        assert!(!e.reaches_plane(DVec3::new(0.0, 0.0, 2.0)));
    }

    #[test]
    fn spots_that_point_away_never_reach_the_plane() {
        let up = spot(DVec3::Z, 0.0, 0.5);
        assert!(!up.reaches_plane(DVec3::Z));
        // Horizontal axis: half the cone is below the horizontal.
        assert!(spot(DVec3::X, 0.0, 0.5).reaches_plane(DVec3::Z));
        // Tilted up by less than θo: its lower rim still dips below.
        let tilt = 0.4f64;
        let slightly_up = spot(DVec3::new(tilt.cos(), 0.0, tilt.sin()), 0.0, 0.5);
        assert!(slightly_up.reaches_plane(DVec3::Z));
        let above = spot(DVec3::new(0.5f64.cos(), 0.0, 0.5f64.sin() + 1e-9), 0.0, 0.5);
        assert!(!above.reaches_plane(DVec3::Z));
    }

    #[test]
    fn every_lit_point_lies_in_the_footprint() {
        let cases = [
            (DVec3::new(0.3, -0.2, -1.0), 0.2, 0.5, None),
            (DVec3::new(1.0, 0.4, -0.8), 0.1, 0.3, Some(6.0)),
            (DVec3::new(0.0, 0.0, -1.0), 0.0, 0.05, None),
            (DVec3::new(-0.5, 0.7, -2.0), 0.6, 0.9, None),
        ];
        let light = DVec3::new(0.5, -1.0, 2.0);
        for (direction, inner, outer, range) in cases {
            let e = Emission::new(
                Some(Spot {
                    direction,
                    inner_cone: inner,
                    outer_cone: outer,
                }),
                range,
            )
            .expect("valid");
            let [lo, hi] = e.footprint(light).expect("a bounded footprint");
            let (mut lit, mut tight) = (0, DVec2::splat(f64::INFINITY));
            for i in 0..400 {
                for j in 0..400 {
                    let x = DVec2::new(-20.0 + 0.1 * f64::from(i), -20.0 + 0.1 * f64::from(j));
                    if e.factor(light, x) > 0.0 {
                        lit += 1;
                        assert!(
                            x.cmpge(lo).all() && x.cmple(hi).all(),
                            "{x} outside {lo}..{hi}"
                        );
                        tight = tight.min((x - lo).min(hi - x));
                    }
                }
            }
            assert!(lit > 0);
            // The box is tight: lit points come within two grid steps of every side.
            assert!(tight.max_element() < 0.2, "{direction}: slack {tight}");
        }
        // Reaching the horizon: unbounded; a point light with a range: its disc's box.
        let wide = spot(DVec3::new(1.0, 0.0, -0.5), 0.0, 1.2);
        assert!(wide.footprint(light).is_none());
        let ranged = Emission::new(None, Some(2.5)).expect("valid");
        let [lo, hi] = ranged.footprint(light).expect("bounded by the range");
        // Width 3 (h = 2, r = 2.5), widened against rounding by about 10^-9 of its size.
        let width = hi.x - lo.x;
        assert!((3.0..3.0 + 1e-8).contains(&width), "width {width}");
        assert!(Emission::POINT.footprint(light).is_none());
    }

    #[test]
    fn the_factor_floor_bounds_the_factor_over_the_whole_rectangle_and_is_tight() {
        let light = DVec3::new(0.5, -1.0, 2.0);
        let profiles = [
            spot(DVec3::new(0.3, -0.2, -1.0), 0.2, 0.5),
            spot(DVec3::new(1.0, 0.4, -0.8), 0.1, 0.3),
            // Reaching past the horizon: the lit region is unbounded, still convex.
            spot(DVec3::new(1.0, 0.0, -0.5), 0.9, 1.5),
            Emission::new(None, Some(4.0)).expect("valid"),
            Emission::new(
                Some(Spot {
                    direction: DVec3::new(-0.5, 0.7, -2.0),
                    inner_cone: 0.6,
                    outer_cone: 0.9,
                }),
                Some(5.0),
            )
            .expect("valid"),
        ];
        // Rectangles inside, across and beyond the cones' edges, small and large.
        let rects = (0..12).flat_map(|i| {
            (0..12).flat_map(move |j| {
                [0.05, 0.7, 3.0].map(|side| {
                    let lo = DVec2::new(-6.0 + f64::from(i), -7.0 + f64::from(j));
                    [lo, lo + DVec2::new(side, 0.6 * side)]
                })
            })
        });
        let mut tight = 0;
        for rect in rects {
            for e in &profiles {
                let floor = e.factor_floor_over(light, rect);
                // The least of S/g over a 41 × 41 raster of the rectangle, edges included.
                let mut least = f64::INFINITY;
                for a in 0..=40 {
                    for b in 0..=40 {
                        let f = DVec2::new(f64::from(a), f64::from(b)) / 40.0;
                        let x = rect[0] + f * (rect[1] - rect[0]);
                        least = least.min(e.factor(light, x) / e.gain());
                    }
                }
                assert!(
                    floor <= least * (1.0 + 1e-12),
                    "{rect:?}: {floor} > {least}"
                );
                // At a corner the raster meets the bound: it is attained, not loose.
                tight += usize::from(floor > 0.0 && floor >= least * (1.0 - 1e-12));
            }
        }
        assert!(tight > 100, "only {tight} bounds attained");
        assert_eq!(
            Emission::POINT.factor_floor_over(light, [DVec2::ZERO; 2]),
            1.0
        );
    }

    #[test]
    fn bad_profiles_are_refused_by_field() {
        let cone = |i, o| {
            Emission::new(
                Some(Spot {
                    direction: DVec3::NEG_Z,
                    inner_cone: i,
                    outer_cone: o,
                }),
                None,
            )
        };
        for (i, o) in [
            (0.5, 0.5),
            (0.6, 0.5),
            (-0.1, 0.5),
            (0.0, 1.6),
            (f64::NAN, 0.5),
        ] {
            assert_eq!(cone(i, o).map_err(|e| e.field()), Err("spot"), "{i} {o}");
        }
        let dir = Emission::new(
            Some(Spot {
                direction: DVec3::ZERO,
                inner_cone: 0.0,
                outer_cone: 0.5,
            }),
            None,
        );
        assert_eq!(dir.map_err(|e| e.field()), Err("spot.direction"));
        for r in [0.0, -1.0, f64::INFINITY, f64::NAN] {
            assert_eq!(
                Emission::new(None, Some(r)).map_err(|e| e.field()),
                Err("range")
            );
        }
    }
}
