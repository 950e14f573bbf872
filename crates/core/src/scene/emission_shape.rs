//! What the emission factor `S(x)` of a light is evaluated with ([`super::Emission`]'s
//! module docs): the unit spot axis, the cones' cosines, the gain and the range, derived once
//! from the profile as given. The light tree keeps only this for each of its lights (72
//! bytes, against the 120 of an [`Emission`], which also keeps the cone as given).

use glam::{DVec2, DVec3};

#[cfg(doc)]
use super::Emission;

/// The constants of one light's emission factor `S(x) = g·t(α)²·w(d)`: a spot's unit axis,
/// `cos θi`, `cos θo` and `1/(cos θi − cos θo)`, the gain `g`, and the range `r` and `1/r`.
/// A light has a spot exactly when `1/(cos θi − cos θo) ≠ 0` and a range exactly when
/// `r ≠ 0`, so the shape needs no flags.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionShape {
    /// The unit spot axis (zero without a spot).
    pub(super) axis: DVec3,
    /// `cos θi` (1 without a spot).
    pub(super) cos_inner: f64,
    /// `cos θo` (−1 without a spot).
    pub(super) cos_outer: f64,
    /// `1/(cos θi − cos θo)` (`> 0` for a spot, 0 without one).
    pub(super) cone_scale: f64,
    /// `g = 4π/Ω` (1 without a spot).
    pub(super) gain: f64,
    /// `1/r` (0 without a range).
    pub(super) inv_range: f64,
    /// The range `r` (0 without one).
    pub(super) range: f64,
}

impl EmissionShape {
    /// A bare point light's: `S ≡ 1`.
    pub const POINT: EmissionShape = EmissionShape {
        axis: DVec3::ZERO,
        cos_inner: 1.0,
        cos_outer: -1.0,
        cone_scale: 0.0,
        gain: 1.0,
        inv_range: 0.0,
        range: 0.0,
    };

    /// Whether the light has a spot cone.
    #[inline]
    pub fn has_spot(&self) -> bool {
        self.cone_scale != 0.0
    }

    /// Whether the light has a range.
    #[inline]
    pub fn has_range(&self) -> bool {
        self.range != 0.0
    }

    /// Whether this is a bare point light's (`S ≡ 1`).
    pub fn is_point(&self) -> bool {
        !self.has_spot() && !self.has_range()
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

    /// `cos θi` (1 without a spot).
    pub fn cos_inner(&self) -> f64 {
        self.cos_inner
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

    /// The range `r`, if the light has one.
    pub fn range(&self) -> Option<f64> {
        self.has_range().then_some(self.range)
    }

    /// The spot falloff `t²` for `cos α`: 1 from `cos θi` on, 0 up to `cos θo`,
    /// `((cos α − cos θo)/(cos θi − cos θo))²` between, 1 without a spot.
    #[inline]
    pub fn falloff(&self, cos_alpha: f64) -> f64 {
        spot_falloff(cos_alpha, self.cos_inner, self.cos_outer, self.cone_scale)
    }

    /// The range window `clamp(1 − (d/r)⁴, 0, 1)` at distance `d` (1 without a range).
    #[inline]
    pub fn window(&self, distance: f64) -> f64 {
        range_window(distance, self.inv_range)
    }

    /// `S(x) = g · t² · w` for the light at `light_in_world` and the point `point_on_plane`
    /// (module docs); the light must not be on the point (then `S` is not defined).
    #[inline]
    pub fn factor(&self, light_in_world: DVec3, point_on_plane: DVec2) -> f64 {
        let to_point = point_on_plane.extend(0.0) - light_in_world;
        self.factor_along(to_point, to_point.length())
    }

    /// [`EmissionShape::factor`] from the light's vector to the point, `to_point`, and its length
    /// `distance = |to_point|` (`> 0`), already at hand: [`super::light_term`] shares the
    /// distance with `G` instead of taking a second square root (the same bits).
    #[inline]
    pub(crate) fn factor_along(&self, to_point: DVec3, distance: f64) -> f64 {
        let mut s = self.gain;
        if self.has_spot() {
            s *= self.falloff(self.axis.dot(to_point) / distance);
        }
        if self.has_range() {
            s *= self.window(distance);
        }
        s
    }

    /// The spot's cone term `t²` toward `point_on_plane` for the light at `light_in_world`
    /// (module docs: 1 inside the inner cone, 0 beyond the outer), or `None` for a light
    /// without a spot. What power picking ignores and the light tree's cone bounds weigh.
    pub fn cone_term(&self, light_in_world: DVec3, point_on_plane: DVec2) -> Option<f64> {
        if !self.has_spot() {
            return None;
        }
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
        if self.has_spot() {
            floor *= self.falloff(least_cos);
        }
        if self.has_range() {
            floor *= self.window(farthest);
        }
        floor
    }

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
        if self.has_range() {
            let r = self.range;
            // The window lights up to `d·(1/r) < 1` as rounded, a few ulps past r: take
            // r·(1 + 8ε). Then (r − h)(r + h) rather than r² − h², which cancels where h nears
            // r, and the box widened past the rounding of the root and of at ± reach.
            let r = r * (1.0 + 8.0 * f64::EPSILON);
            let reach = ((r - h) * (r + h)).max(0.0).sqrt();
            let slack = 1e-9 * (at.abs() + reach) + DVec2::splat(f64::MIN_POSITIVE);
            bounds = Some([at - reach - slack, at + reach + slack]);
        }
        if self.has_spot() && -self.axis.z > (1.0 - self.cos_outer * self.cos_outer).sqrt() {
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

impl Default for EmissionShape {
    fn default() -> Self {
        EmissionShape::POINT
    }
}

/// A spot's falloff `t²` at `cos α` from its `cos θi`, `cos θo` and
/// `s = 1/(cos θi − cos θo)`: 1 from `cos θi` on, 0 up to `cos θo`, `((cos α − cos θo)·s)²`
/// between, and 1 for a light without a spot (`s = 0`). Written as selections rather than
/// branches, so that the light tree's leaves evaluate it lane by lane (the same values).
#[inline]
pub(crate) fn spot_falloff(cos_alpha: f64, cos_inner: f64, cos_outer: f64, cone_scale: f64) -> f64 {
    let t = (cos_alpha - cos_outer) * cone_scale;
    let below_inner = if cos_alpha <= cos_outer { 0.0 } else { t * t };
    let cone = if cos_alpha >= cos_inner {
        1.0
    } else {
        below_inner
    };
    if cone_scale == 0.0 { 1.0 } else { cone }
}

/// The range window `clamp(1 − (d·(1/r))⁴, 0, 1)` at distance `d` from `1/r`: exactly 1
/// for a light without a range (`1/r = 0`).
#[inline]
pub(crate) fn range_window(distance: f64, inv_range: f64) -> f64 {
    let q = distance * inv_range;
    let q2 = q * q;
    (1.0 - q2 * q2).clamp(0.0, 1.0)
}
