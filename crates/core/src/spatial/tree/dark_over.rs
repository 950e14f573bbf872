//! Whether a light provably gives a rectangle of the plane nothing: its range ends before
//! the rectangle, or its spot's cone misses it. A tile's cut leaves such a light out
//! ([`super::cut_growth`]), so that it neither takes a share of the tile nor keeps its leaf
//! cluster whole.
//!
//! # The cone, exactly
//! A spot at `L` (`L_z > 0`) with unit axis `a` and outer angle `θo ≤ π/2` lights the points
//! `x` of the plane where `a·v ≥ c·|v|`, `v = x − L`, `c = cos θo ≥ 0`: a convex set `C`
//! (a cone cut by the plane). `C` meets the rectangle `R` either across one of `R`'s edges
//! or, missing all four, lies inside `R` whole; then `C` is bounded (an ellipse), so the
//! axis meets the plane, at `h = L + a·L_z/(−a_z)` inside `C`, and `h ∈ R`.
//!
//! On an edge `x(t) = p + t·d`, `t ∈ [0, 1]`, write `α + β·t = a·v(t)` and
//! `|v(t)|² = γ + 2δ·t + ε·t²`. The edge is lit where `α + β·t ≥ 0` and
//!
//! `g(t) = (α + β·t)² − c²·(γ + 2δ·t + ε·t²) ≥ 0`,
//!
//! a quadratic in `t` (`A = β² − c²ε`, `B = 2(αβ − c²δ)`, `g(0) = α² − c²γ`): its largest
//! value on an interval is at an end, or at the vertex `t_v = −B/(2A)` with the value
//! `g(0) − B²/(4A)` where `A < 0` and `t_v` lies inside. The edge is called dark where that
//! largest value over the part of `[0, 1]` in front of the light (`α + β·t ≥ 0`, widened by
//! `10^-9`) is below `−10^-9·M`, with `M = (|α| + |β|)² + c²(|v(0)| + |d|)²` bounding every
//! term of `g` on the edge: the few roundings of each term are `~10^-16·M`, and the vertex
//! misplaced by rounding loses at most that much again. So a lit edge is never called dark;
//! a dark one is, unless the cone passes within about `10^-9` (relative) of it.

use glam::{DVec2, DVec3};

use crate::scene::EmissionShape;

/// Relative slack of the tests: far above the roundings (`~10^-16`), far below what
/// separates a lit tile from a dark one.
const SLACK: f64 = 1e-9;

/// Whether the light at `light_in_world` with the profile `emission` gives no point of the
/// rectangle `[lo, hi]` of the plane anything (`S = 0` over all of it), by conservative
/// tests that may say `false` of a dark rectangle but never `true` of a lit one:
/// - its range `r` ends before the rectangle's nearest point (`d_min ≥ r`, where the
///   window `1 − (d/r)⁴` is 0), with `10^-9` of `r` to spare;
/// - its cone misses the rectangle ([`cone_misses`], the module docs).
pub(super) fn dark_over(
    emission: &EmissionShape,
    light_in_world: DVec3,
    [lo, hi]: [DVec2; 2],
) -> bool {
    if let Some(range) = emission.range() {
        let nearest = light_in_world.truncate().clamp(lo, hi);
        let d_min = (nearest.extend(0.0) - light_in_world).length();
        if d_min >= range * (1.0 + SLACK) {
            return true;
        }
    }
    emission.has_spot()
        && cone_misses(
            light_in_world,
            emission.axis(),
            emission.cos_outer(),
            [lo, hi],
        )
}

/// Whether the cone `{v : a·v ≥ c·|v|}` from `light_in_world` (`L_z > 0`, `a = axis` of
/// unit length, `c = cos_outer ∈ [0, 1]`) misses the rectangle `[lo, hi]` of the plane
/// `z = 0`, with the module docs' slack: never `true` where the cone reaches a point of it.
fn cone_misses(light_in_world: DVec3, axis: DVec3, cos_outer: f64, [lo, hi]: [DVec2; 2]) -> bool {
    let c = cos_outer;
    if !(light_in_world.z > 0.0 && (0.0..=1.0).contains(&c) && lo.cmple(hi).all()) {
        return false;
    }
    // The axis's foot, where it meets the plane: lit, and inside C whenever C is bounded.
    if axis.z < 0.0 {
        let foot = (light_in_world + axis * (light_in_world.z / -axis.z)).truncate();
        let extent = (hi - lo).length() + (light_in_world.truncate() - lo).length();
        let slack = SLACK * (extent + light_in_world.z);
        if !(foot.cmplt(lo - slack).any() || foot.cmpgt(hi + slack).any()) {
            return false;
        }
    }
    let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
    (0..4).all(|k| {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        edge_misses(p.extend(0.0) - light_in_world, (q - p).extend(0.0), axis, c)
    })
}

/// Whether the edge `v(t) = v0 + t·d`, `t ∈ [0, 1]` (from the light, in world space) has no
/// point with `a·v ≥ 0` and `g(t) = (a·v)² − c²|v|² ≥ 0`, with the module docs' slack.
fn edge_misses(v0: DVec3, d: DVec3, axis: DVec3, c: f64) -> bool {
    let (alpha, beta) = (axis.dot(v0), axis.dot(d));
    let c2 = c * c;
    let scale = (alpha.abs() + beta.abs()).powi(2) + c2 * (v0.length() + d.length()).powi(2);
    // The part of [0, 1] in front of the light (`α + β·t ≥ 0`), widened by the slack.
    let (mut from, mut to) = (0.0f64, 1.0f64);
    if beta > 0.0 {
        from = (-alpha / beta - SLACK).max(0.0);
    } else if beta < 0.0 {
        to = (-alpha / beta + SLACK).min(1.0);
    } else if alpha < 0.0 {
        from = 2.0;
    }
    if from > to {
        // Wholly behind the light (`max`, `min` take 0 and 1 over NaN: no NaN here).
        return alpha.is_finite() && beta.is_finite();
    }
    let g = |t: f64| {
        let v = v0 + d * t;
        let along = axis.dot(v);
        along * along - c2 * v.length_squared()
    };
    let a = beta * beta - c2 * d.length_squared();
    let b = 2.0 * (alpha * beta - c2 * v0.dot(d));
    let mut largest = g(from).max(g(to));
    if a < 0.0 {
        let vertex = -b / (2.0 * a);
        if vertex > from && vertex < to {
            largest = largest.max(g(0.0) - b * b / (4.0 * a));
        }
    }
    largest < -SLACK * scale
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3, dvec2, dvec3};

    use super::{cone_misses, dark_over};
    use crate::scene::{Emission, Spot};

    /// A fixed-seed uniform stream on `[0, 1)` (an LCG's top 53 bits).
    fn stream(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The largest `cos` of the angle to `axis` over a `steps × steps` raster of the
    /// rectangle and `64·steps` points along each of its edges: a brute-force reference,
    /// written apart from the quadratics under test.
    fn largest_cos(light: DVec3, axis: DVec3, [lo, hi]: [DVec2; 2], steps: u32) -> f64 {
        let cos_at = |x: DVec2| axis.dot((x.extend(0.0) - light).normalize());
        let mut largest = f64::NEG_INFINITY;
        for a in 0..=steps {
            for b in 0..=steps {
                let f = dvec2(f64::from(a), f64::from(b)) / f64::from(steps);
                largest = largest.max(cos_at(lo + (hi - lo) * f));
            }
        }
        let corners = [lo, dvec2(hi.x, lo.y), hi, dvec2(lo.x, hi.y)];
        for k in 0..4 {
            let (p, q) = (corners[k], corners[(k + 1) % 4]);
            for s in 0..=64 * steps {
                largest = largest.max(cos_at(p.lerp(q, f64::from(s) / f64::from(64 * steps))));
            }
        }
        largest
    }

    /// Spots and ranges at random, over random rectangles of the plane: wherever
    /// [`dark_over`] calls a rectangle dark, every point of a 33 × 33 raster over it (its
    /// edges and corners included) gets `S = 0`; and the test is not vacuous: it calls many
    /// rectangles dark, and none that the spot's axis meets.
    #[test]
    fn a_rectangle_called_dark_gets_nothing_from_the_light_anywhere() {
        let mut uniform = stream(0x2545_f491_4f6c_dd1d);
        let (mut dark, mut cases) = (0, 0);
        for _ in 0..4000 {
            let light = dvec3(
                4.0 * uniform() - 2.0,
                4.0 * uniform() - 2.0,
                0.05 + 2.0 * uniform(),
            );
            let outer = 0.05 + 1.4 * uniform();
            let spot = (uniform() < 0.8).then(|| Spot {
                direction: dvec3(uniform() - 0.5, uniform() - 0.5, -uniform()),
                inner_cone: outer * uniform(),
                outer_cone: outer,
            });
            let range = (uniform() < 0.4).then(|| light.z + 3.0 * uniform());
            let Ok(emission) = Emission::new(spot, range) else {
                continue;
            };
            let lo = dvec2(4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0);
            let hi = lo + dvec2(0.01 + uniform(), 0.01 + uniform());
            cases += 1;
            if !dark_over(&emission, light, [lo, hi]) {
                continue;
            }
            dark += 1;
            for a in 0..=32 {
                for b in 0..=32 {
                    let x = lo + (hi - lo) * dvec2(f64::from(a), f64::from(b)) / 32.0;
                    assert_eq!(
                        emission.factor(light, x),
                        0.0,
                        "{emission:?} at {light} lights {x} of [{lo}, {hi}]"
                    );
                }
            }
            // The axis's foot on the plane, where it reaches the plane inside the rectangle.
            let axis = emission.axis();
            if axis.z < 0.0 {
                let foot: DVec2 = (light + axis * (light.z / -axis.z)).truncate();
                assert!(
                    foot.cmplt(lo).any() || foot.cmpgt(hi).any(),
                    "the axis of {emission:?} at {light} meets [{lo}, {hi}], called dark"
                );
            }
        }
        assert!(dark * 5 > cases, "{dark} of {cases} rectangles called dark");
    }

    /// The cone test against the brute-force largest cosine, over cones from narrow
    /// (0.001 rad) to flat (π/2), axes pointing down, sideways and up, and rectangles from a
    /// thousandth to a few times the light's height: where the reference finds a point
    /// within the cone the test never calls the rectangle dark, and where the reference's
    /// largest cosine falls short of `cos θo` by more than its raster can hide (the
    /// cosine's slope times half a raster step, plus `10^-6`), the test calls it dark:
    /// exact, up to its slack, where the old angular bound was not.
    #[test]
    fn the_cone_test_is_exact_against_a_brute_force_maximum() {
        let mut uniform = stream(0x9e37_79b9_7f4a_7c15);
        let (mut lit, mut dark, mut cases) = (0, 0, 0);
        for case in 0..3000 {
            let light = dvec3(
                2.0 * uniform() - 1.0,
                2.0 * uniform() - 1.0,
                0.02 + 2.0 * uniform(),
            );
            let outer = match case % 4 {
                0 => 0.001 + 0.05 * uniform(),
                3 => std::f64::consts::FRAC_PI_2 * (1.0 - 0.01 * uniform()),
                _ => 0.05 + 1.5 * uniform(),
            };
            let axis = dvec3(
                uniform() - 0.5,
                uniform() - 0.5,
                if case % 5 == 0 {
                    uniform() - 0.3
                } else {
                    -uniform()
                },
            )
            .normalize();
            let size = light.z * 10f64.powf(-3.0 + 3.5 * uniform());
            let lo = light.truncate() + dvec2(4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0);
            let hi = lo + dvec2(size * (0.2 + uniform()), size * (0.2 + uniform()));
            let c = outer.cos();
            let steps = 64;
            let reference = largest_cos(light, axis, [lo, hi], steps);
            // |∇ cos| ≤ 1/|v| ≤ 1/L_z on the plane; a raster point lies within half a
            // step's diagonal of every point.
            let hidden = ((hi - lo).length() / f64::from(steps)) / light.z + 1e-6;
            let called_dark = cone_misses(light, axis, c, [lo, hi]);
            cases += 1;
            if reference >= c {
                lit += 1;
                assert!(
                    !called_dark,
                    "case {case}: cos {reference} ≥ {c} in [{lo}, {hi}], called dark"
                );
            } else if reference < c - hidden {
                dark += 1;
                assert!(
                    called_dark,
                    "case {case}: cos ≤ {reference} < {c} over [{lo}, {hi}], not called dark"
                );
            }
        }
        assert!(
            lit * 10 > cases && dark * 3 > cases,
            "{lit} lit, {dark} dark of {cases}"
        );
    }

    /// Rectangles that the cone's edge on the plane just grazes: a point of the conic is
    /// found by bisection along a ray from the axis's foot, and a rectangle that reaches
    /// away from the foot gets its corner on the ray a hair (`10^-12` of the distance)
    /// inside the conic, below the test's slack: a sliver of light that no raster would
    /// find, never called dark. Moved `10^-4` of the distance outside, where the brute-force
    /// reference finds it dark, it is called dark.
    #[test]
    fn a_rectangle_the_cone_grazes_is_lit_and_one_it_misses_by_a_hair_is_dark() {
        let mut uniform = stream(0x0123_4567_89ab_cdef);
        let (mut missed_cases, mut cases) = (0, 0);
        for case in 0..500 {
            let light = dvec3(0.0, 0.0, 0.5 + uniform());
            let outer = 0.05 + 1.2 * uniform();
            let axis = dvec3(uniform() - 0.5, uniform() - 0.5, -1.0).normalize();
            let c = outer.cos();
            let foot = (light + axis * (light.z / -axis.z)).truncate();
            let cos_at = |x: DVec2| axis.dot((x.extend(0.0) - light).normalize());
            let angle = std::f64::consts::TAU * uniform();
            let direction = dvec2(angle.cos(), angle.sin());
            // The conic along the ray, if it is bounded that way.
            let (mut inside, mut outside) = (0.0, 1.0);
            while cos_at(foot + direction * outside) >= c {
                outside *= 2.0;
                if outside > 1e6 {
                    break;
                }
            }
            if outside > 1e6 {
                continue;
            }
            cases += 1;
            for _ in 0..200 {
                let mid = 0.5 * (inside + outside);
                if cos_at(foot + direction * mid) >= c {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            // A rectangle away from the axis's foot, its corner on the ray at `reach`.
            let away = dvec2(direction.x.signum(), direction.y.signum()) * 0.5;
            let rect_at = |reach: f64| {
                let corner = foot + direction * reach;
                [corner.min(corner + away), corner.max(corner + away)]
            };
            let hair = 1e-12 * (inside + light.z);
            let grazed = rect_at(inside - hair);
            assert!(
                !cone_misses(light, axis, c, grazed),
                "case {case}: the cone reaches into {grazed:?}, called dark"
            );
            let missed = rect_at(inside + 1e8 * hair);
            if largest_cos(light, axis, missed, 16) < c - 1e-4 * (1.0 - c).max(1e-3) {
                missed_cases += 1;
                assert!(
                    cone_misses(light, axis, c, missed),
                    "case {case}: {missed:?} lies beyond the cone"
                );
            }
        }
        assert!(
            cases > 400 && missed_cases * 2 > cases,
            "{missed_cases} of {cases} missed rectangles checked"
        );
    }
}
