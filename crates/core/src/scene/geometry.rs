//! The one place the point-light irradiance formula and the pixel layout live.

use glam::{DVec2, DVec3};

use super::EmissionShape;

/// `G(x) = max(0, z)/(4π r³)`: the irradiance at `x = (x, y, 0)` per unit power of a point
/// light at `light_in_world`, for the receiver normal `+z` (`cos θ = z/r`). Zero for a light
/// on or below the plane.
#[inline]
pub fn geometry_term(light_in_world: DVec3, point_on_plane: DVec2) -> f64 {
    let z = light_in_world.z;
    if z <= 0.0 {
        return 0.0;
    }
    let to_light = light_in_world.truncate() - point_on_plane;
    let r2 = distance_squared(to_light.x, to_light.y, z);
    geometry_term_at(z, r2, r2.sqrt())
}

/// `G = z/(4π r³)` from the light's height `z > 0`, `r²` ([`distance_squared`]) and
/// `r = √r²`.
#[inline]
fn geometry_term_at(z: f64, r2: f64, r: f64) -> f64 {
    let denominator = four_pi_r2_times(r2, r);
    if denominator >= f64::MIN_POSITIVE {
        z / denominator
    } else {
        // r³ underflows for r < 10^-102.7: (z/r)/(4π r²) keeps G finite while it fits f64
        // (a light 10^-150 above the point gives 8·10^298).
        (z / r) / (4.0 * std::f64::consts::PI * r2)
    }
}

/// `r² = dx² + dy² + z²`, summed in this order (x, then y, then z): the squared distance
/// from a point of the plane to a light `(dx, dy)` across and `z` above it, as [`geometry_term`]
/// takes it (the light tree's leaves take it too, lane by lane, bit for bit).
#[inline]
pub(crate) fn distance_squared(dx: f64, dy: f64, z: f64) -> f64 {
    (dx * dx + dy * dy) + z * z
}

/// `4π r³` from `r²`, the denominator of [`geometry_term`] (`G = z/(4π r³)` wherever it does
/// not underflow).
#[inline]
pub(crate) fn four_pi_r_cubed(r2: f64) -> f64 {
    four_pi_r2_times(r2, r2.sqrt())
}

/// `4π r² · r` from `r²` and `r = √r²`: [`four_pi_r_cubed`] with its square root given.
#[inline]
pub(crate) fn four_pi_r2_times(r2: f64, r: f64) -> f64 {
    4.0 * std::f64::consts::PI * r2 * r
}

/// `G(x)·S(x)`: the irradiance at `point_on_plane` per unit power of the light at
/// `light_in_world` with the emission profile `emission` (`None`: a point light, `S ≡ 1`).
/// The one definition of a light's contribution (`Φ_i` times this): every scheme, the
/// reference, the inspector, the light tree and the GPU kernels evaluate it or its WGSL
/// twin. Zero wherever `G` is (a light on or below the plane).
// Always inlined: the light tree's single-light pick called it (8 % of a `stage` render).
#[allow(
    clippy::inline_always,
    reason = "measured: inlined, a spatial sample on `stage` takes 34.5 ns, not 34.7"
)]
#[inline(always)]
pub fn light_term(
    light_in_world: DVec3,
    emission: Option<&EmissionShape>,
    point_on_plane: DVec2,
) -> f64 {
    let Some(e) = emission else {
        return geometry_term(light_in_world, point_on_plane);
    };
    let z = light_in_world.z;
    if z <= 0.0 {
        return 0.0;
    }
    // G's distance serves S too: `to_point = −to_light` and `|to_point|² = r²` to the bit
    // (negation is exact and the squares are summed in the same order), so this is
    // `G · e.factor(light, x)` with one square root instead of two.
    let to_light = light_in_world.truncate() - point_on_plane;
    let r2 = distance_squared(to_light.x, to_light.y, z);
    let r = r2.sqrt();
    let g = geometry_term_at(z, r2, r);
    if g > 0.0 {
        g * e.factor_along(DVec3::new(-to_light.x, -to_light.y, -z), r)
    } else {
        0.0
    }
}

/// [`light_term`] behind a test without a square root or a division: 0 where the spot's
/// cone or the range provably leaves `point_on_plane` dark, [`light_term`] itself elsewhere.
/// Equal to [`light_term`] wherever that is finite (a light far enough above the plane that
/// `G` does not overflow, where `∞·0` would give NaN).
///
/// With `d = x − light` (`d_z = −z`), `D = a·d` the dot product [`light_term`] forms and
/// `r² = |d|²`, the cone is dark where `D ≤ 0` or `D² < cos²θo·r²·(1 − 2^-40)`: then
/// `D/√r² < cos θo·(1 − 2^-41)` in exact arithmetic and, each of the few roundings on either
/// side within `2^-53`, the computed `D/r` is below `cos θo` too, so the falloff is 0. The
/// range is dark where `r²/r_max² > 1 + 2^-40`, so that the computed `r/r_max ≥ 1` and the
/// window is 0. Anything else (NaN, an overflowing or underflowing square) takes the full
/// evaluation. Evaluating both the tests and the term in every case and letting the tests
/// pick (no branch), light by light, was measured slower: `stage`, `gallery` and
/// `random.json` 67, 84 and 95 → 76, 94 and 102 ns a pixel sample (the `pass_order` example,
/// samples in a row). A leaf cluster evaluates its lights lane by lane instead, packed, the
/// same bits (`spatial::tree::leaf_terms`), and takes this for its rare lanes; the maps'
/// integration takes it at every point.
#[inline]
pub(crate) fn light_term_culled(
    light_in_world: DVec3,
    emission: &EmissionShape,
    point_on_plane: DVec2,
) -> f64 {
    const MARGIN: f64 = 1.0 / (1u64 << 40) as f64;
    let z = light_in_world.z;
    let to_light = light_in_world.truncate() - point_on_plane;
    let r2 = distance_squared(to_light.x, to_light.y, z);
    let cos_outer = emission.cos_outer();
    if emission.cone_scale() != 0.0 && cos_outer >= 0.0 {
        let dot = emission
            .axis()
            .dot(DVec3::new(-to_light.x, -to_light.y, -z));
        if dot <= 0.0 || dot * dot < cos_outer * cos_outer * r2 * (1.0 - MARGIN) {
            return 0.0;
        }
    }
    let inv_range = emission.inv_range();
    if r2 * (inv_range * inv_range) > 1.0 + MARGIN {
        return 0.0;
    }
    light_term(light_in_world, Some(emission), point_on_plane)
}

/// The centre of pixel `(px, py)` of `plane` on `z = 0` (row 0 at the top, `y = max.y`).
#[inline]
pub fn pixel_center(plane: &super::ReceiverPlane, px: u32, py: u32) -> DVec2 {
    plane.point_at(DVec2::new(f64::from(px) + 0.5, f64::from(py) + 0.5))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Emission;

    #[test]
    fn light_straight_above_follows_inverse_square() {
        let g1 = geometry_term(DVec3::new(0.0, 0.0, 1.0), DVec2::ZERO);
        let g2 = geometry_term(DVec3::new(0.0, 0.0, 2.0), DVec2::ZERO);
        assert!((g1 - 1.0 / (4.0 * std::f64::consts::PI)).abs() < 1e-15);
        assert!((g1 / g2 - 4.0).abs() < 1e-12);
    }

    #[test]
    fn light_below_the_plane_contributes_nothing() {
        assert_eq!(geometry_term(DVec3::new(0.0, 0.0, -1.0), DVec2::ZERO), 0.0);
        assert_eq!(geometry_term(DVec3::new(1.0, 0.0, 0.0), DVec2::ZERO), 0.0);
    }

    #[test]
    fn the_formula_is_the_written_one_bit_for_bit() {
        // dx² + dy² + z², then z / (4π r² √r²): the sum order the GPU twin follows too.
        let (light, x) = (DVec3::new(0.3, -1.7, 0.45), DVec2::new(1.1, 0.25));
        let (dx, dy, z) = (light.x - x.x, light.y - x.y, light.z);
        let r2 = dx * dx + dy * dy + z * z;
        let written = z / (4.0 * std::f64::consts::PI * r2 * r2.sqrt());
        assert_eq!(geometry_term(light, x).to_bits(), written.to_bits());
    }

    #[test]
    fn a_light_next_to_the_plane_stays_finite_while_it_fits() {
        // 10^-150 above the point: r³ = 10^-450 underflows, G = 1/(4π·10^-300) does not.
        let g = geometry_term(DVec3::new(0.0, 0.0, 1e-150), DVec2::ZERO);
        assert!(
            (g * 4.0 * std::f64::consts::PI / 1e300 - 1.0).abs() < 1e-14,
            "{g:e}"
        );
        // 10^-160: G ≈ 8·10^318 does not fit f64.
        assert_eq!(
            geometry_term(DVec3::new(0.0, 0.0, 1e-160), DVec2::ZERO),
            f64::INFINITY
        );
    }

    /// `light_term` takes `G`'s square root for `S` too: it must equal `G · S` computed
    /// apart (two square roots, [`EmissionShape::factor`]) bit for bit, for spots, ranges and
    /// both, inside, on and beyond the cones, straight under the light, and where `r³`
    /// underflows.
    #[test]
    fn a_lights_term_is_g_times_its_factor_bit_for_bit() {
        use crate::scene::Spot;
        let spot = |direction: DVec3, inner: f64, outer: f64| Spot {
            direction,
            inner_cone: inner,
            outer_cone: outer,
        };
        let profiles = [
            Emission::new(Some(spot(DVec3::NEG_Z, 0.2, 0.5)), None),
            Emission::new(Some(spot(DVec3::new(0.3, -0.2, -1.0), 0.0, 1.2)), Some(2.5)),
            Emission::new(None, Some(0.7)),
            Emission::new(Some(spot(DVec3::new(1.0, 0.0, -0.1), 0.4, 1.5)), None),
        ]
        .map(Result::unwrap);
        let lights = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.31, -0.77, 0.45),
            DVec3::new(-1.3, 2.1, 3.0),
            DVec3::new(0.25, 0.5, 1e-150),
        ];
        let mut checked = 0;
        for e in &profiles {
            for &light in &lights {
                for j in 0..41 {
                    for i in 0..41 {
                        let x = DVec2::new(-2.0 + 0.1 * i as f64, -2.0 + 0.1 * j as f64);
                        let x = if i == 20 && j == 20 {
                            light.truncate()
                        } else {
                            x
                        };
                        let g = geometry_term(light, x);
                        let apart = if g > 0.0 { g * e.factor(light, x) } else { 0.0 };
                        let fused = light_term(light, Some(e), x);
                        assert_eq!(fused.to_bits(), apart.to_bits(), "{light} {x} {e:?}");
                        checked += usize::from(fused > 0.0 && fused < g * e.gain());
                    }
                }
            }
        }
        // Points inside a cone's falloff or a range's window, not only on or off.
        assert!(checked > 200, "{checked}");
        assert_eq!(
            light_term(DVec3::new(0.0, 0.0, -1.0), Some(&profiles[0]), DVec2::ZERO),
            0.0
        );
    }

    /// The leaves' shortcut: `light_term_culled` equals `light_term` bit for bit, for spots
    /// narrow to flat, with and without ranges, at random points and at points placed on the
    /// outer cone's edge (where the margin is all that keeps the shortcut from ruling a lit
    /// point dark) and on the range's sphere; and the shortcut is taken (the cases where
    /// either is 0 are many).
    #[test]
    fn the_culled_term_is_the_full_term_bit_for_bit() {
        use crate::scene::Spot;
        let mut rng = crate::Rng::new(7, 0);
        let mut u = move || f64::from(rng.next_u32()) / 4_294_967_296.0;
        let (mut dark, mut cases) = (0, 0);
        for case in 0..300_000 {
            let light = DVec3::new(u() - 0.5, u() - 0.5, 1e-3 + u());
            let (tilt, turn) = (1.6 * u(), std::f64::consts::TAU * u());
            let axis = DVec3::new(
                tilt.sin() * turn.cos(),
                tilt.sin() * turn.sin(),
                -tilt.cos(),
            );
            let outer = 1e-3 + (std::f64::consts::FRAC_PI_2 - 1e-3) * u();
            let range = (case % 3 == 0).then(|| 0.05 + 2.0 * u());
            let spot = (case % 5 != 0).then_some(Spot {
                direction: axis,
                inner_cone: outer * u(),
                outer_cone: outer,
            });
            let e = Emission::new(spot, range).expect("valid");
            let x = match case % 4 {
                // On the outer cone's edge: the axis turned by θo about a perpendicular.
                0 | 1 if spot.is_some() => {
                    let side = axis.any_orthonormal_vector();
                    let (s, c) = (outer.sin(), outer.cos());
                    let normal = axis.cross(side);
                    let phi = std::f64::consts::TAU * u();
                    let edge = c * axis + s * (phi.cos() * side + phi.sin() * normal);
                    if edge.z >= -1e-9 {
                        continue;
                    }
                    (light - edge * (light.z / edge.z)).truncate()
                }
                // On the range's sphere.
                2 if range.is_some_and(|r| r > light.z) => {
                    let r = range.unwrap_or(0.0);
                    let across = (r * r - light.z * light.z).sqrt();
                    let phi = std::f64::consts::TAU * u();
                    light.truncate() + across * DVec2::new(phi.cos(), phi.sin())
                }
                _ => DVec2::new(4.0 * u() - 2.0, 4.0 * u() - 2.0),
            };
            let full = light_term(light, Some(&e), x);
            let culled = light_term_culled(light, &e, x);
            assert_eq!(
                culled.to_bits(),
                full.to_bits(),
                "light {light}, {e:?}, point {x}: {culled:e} against {full:e}"
            );
            cases += 1;
            dark += usize::from(full == 0.0);
        }
        assert!(
            cases > 250_000 && dark > cases / 5,
            "{dark} dark of {cases}"
        );
    }
}
