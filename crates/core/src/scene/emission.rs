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

use glam::DVec3;

use super::EmissionShape;

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

/// One light's emission profile (module docs): its spot cone as given, and the constants
/// the factor `S(x)` is evaluated with ([`EmissionShape`], which it dereferences to: every
/// evaluation of `S` is the shape's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    spot: Option<Spot>,
    shape: EmissionShape,
}

impl Emission {
    /// A bare point light: `S ≡ 1`.
    pub const POINT: Emission = Emission {
        spot: None,
        shape: EmissionShape::POINT,
    };

    /// The profile of a light with an optional spot cone and an optional range, validated:
    /// a finite non-zero direction, `0 ≤ θi < θo ≤ π/2`, a finite `r > 0`.
    pub fn new(spot: Option<Spot>, range: Option<f64>) -> Result<Emission, EmissionError> {
        let mut e = Emission::POINT;
        if let Some(r) = range {
            if !(r.is_finite() && r > 0.0) {
                return Err(EmissionError::Range(r));
            }
            e.shape.range = r;
            e.shape.inv_range = 1.0 / r;
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
            let shape = &mut e.shape;
            shape.axis = s.direction / length;
            shape.cos_inner = inner.cos();
            shape.cos_outer = outer.cos();
            // 1 − cos θi and cos θi − cos θo without cancellation (narrow cones). The width
            // is positive (θi < θo), so a spot's `cone_scale` is never 0.
            let one_minus_inner = 2.0 * (0.5 * inner).sin().powi(2);
            let width = 2.0 * (0.5 * (outer + inner)).sin() * (0.5 * (outer - inner)).sin();
            shape.cone_scale = 1.0 / width;
            shape.gain = 2.0 / (one_minus_inner + width / 3.0);
            e.spot = Some(s);
        }
        Ok(e)
    }

    /// The spot cone as given, if the light is a spot ([`EmissionShape::axis`] is its
    /// direction normalized).
    pub fn spot(&self) -> Option<Spot> {
        self.spot
    }

    /// What `S(x)` is evaluated with.
    pub fn shape(&self) -> &EmissionShape {
        &self.shape
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
        let cone = self
            .spot
            .is_none_or(|s| self.shape.axis.z < s.outer_cone.sin());
        let range = self.shape.range().is_none_or(|r| r > z);
        cone && range
    }
}

impl std::ops::Deref for Emission {
    type Target = EmissionShape;

    fn deref(&self) -> &EmissionShape {
        &self.shape
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
    use glam::DVec2;
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

    /// The shape tells a spot and a range from their own constants (`1/(cos θi − cos θo)`
    /// and `r`, never 0 for a spot or a range), so it must say what was given: at ordinary
    /// cones, at cones so narrow or so close that `cos θi − cos θo` rounds to 0 or below the
    /// smallest normal, and at ranges from the least subnormal to the largest finite.
    #[test]
    fn the_shape_says_what_was_given() {
        let tiny = f64::from_bits(1);
        let cones = [
            (0.2, 0.7),
            (0.0, FRAC_PI_2),
            (0.0, tiny),
            (0.0, f64::MIN_POSITIVE),
            (1.0, 1.0 + f64::EPSILON),
            (FRAC_PI_2 - 1e-15, FRAC_PI_2),
            (1e-300, 2e-300),
        ];
        let ranges = [None, Some(tiny), Some(1e-300), Some(2.5), Some(f64::MAX)];
        for &(inner, outer) in &cones {
            for spot in [
                None,
                Some(Spot {
                    direction: DVec3::new(0.3, -0.2, -1.0),
                    inner_cone: inner,
                    outer_cone: outer,
                }),
            ] {
                for range in ranges {
                    let e = Emission::new(spot, range).expect("valid");
                    let shape = e.shape();
                    assert_eq!(shape.has_spot(), spot.is_some(), "{spot:?} {range:?}");
                    assert_eq!(shape.range(), range, "{spot:?}");
                    assert_eq!(shape.is_point(), spot.is_none() && range.is_none());
                    assert_eq!(e.spot(), spot);
                }
            }
        }
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
