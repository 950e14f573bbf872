//! A leaf cluster's contributions `c_j = p_j·G_j(x)·S_j(x)` at one point, evaluated lane by
//! lane without a branch, so that the lanes' square roots and divisions run side by side
//! (packed) rather than one light after another, bit for bit what each light's own
//! evaluation ([`SpatialLight::contribution`], [`SpatialLight::contribution_culled`]) gives.
//!
//! **Measured.** Lights with profiles were evaluated one by one, each behind a cull test
//! without a square root; evaluating the whole formula light by light without that test was
//! slower (`crate::scene::light_term_culled`'s docs). Evaluated lane by lane, four lanes a
//! vector where the processor has AVX2 ([`shaped_contributions`]), a pixel sample took
//! 7–12 % less on `stage`, `random.json` and `arena.json` and 2 % less on `gallery` (the
//! `pass_order` example, samples in a row, the fastest of eight alternating runs: 61.8 →
//! 57.4, 90.9 → 80.0, 73.7 → 67.0 and 77.2 → 75.8 ns); compiled for AVX-512 it was slower
//! than the version before. Point lights were already evaluated lane by lane; compiling them
//! for AVX2 gained nothing measurable.
//!
//! Weighing a cluster of spots by its terms in `f32` instead (eight lanes a vector, the
//! picked light's own term then evaluated in `f64` for the estimate) was measured too: the
//! evaluation's share of a `stage` pick fell from 42 % to 20–24 %, but the picked light's
//! own term and the conversions of each light's twelve figures cost more than that saved
//! (the `pass_order` example, three runs alternating: 69–100 ns a sample on `stage` against
//! 54–60 in `f64`, slower on `gallery`, `random.json` and `arena.json` as well). Not kept.

use glam::DVec2;

use super::LEAF_SIZE;
use crate::avx2::avx2_dispatch;
use crate::scene::{
    EmissionShape, distance_squared, four_pi_r_cubed, four_pi_r2_times, range_window, spot_falloff,
};
use crate::spatial::SpatialLight;

avx2_dispatch! {
    /// `c_j = p_j·G_j(x)·S_j(x)` of lights with emission profiles `emission` (at most
    /// [`LEAF_SIZE`]) at `point_on_plane` into `c`, **bit for bit**
    /// [`SpatialLight::contribution_culled`], each light one lane
    /// ([`shaped_lane`]; the lanes where that is not the light's own
    /// value are then taken from it, one by one). Lanes beyond `lights.len()` give 0 (a light
    /// of no power).
    ///
    /// Compiled for AVX2 where the processor has it (checked at run time; four lanes a
    /// vector where the baseline packs two; the same bits, as every operation is an IEEE one
    /// rounded once and none is fused), else for the baseline.
    #[inline]
    pub(super) fn shaped_contributions(
        lights: &[SpatialLight],
        emission: &[EmissionShape],
        point_on_plane: DVec2,
        c: &mut [f64; LEAF_SIZE],
    ) => shaped_contributions_in;
}

/// [`shaped_contributions`]' body, inlined into each of its compilations.
#[allow(
    clippy::inline_always,
    reason = "compiled into the AVX2 instance too, where its loops widen"
)]
#[inline(always)]
fn shaped_contributions_in(
    lights: &[SpatialLight],
    emission: &[EmissionShape],
    point_on_plane: DVec2,
    c: &mut [f64; LEAF_SIZE],
) {
    debug_assert!(lights.len() <= LEAF_SIZE && emission.len() == lights.len());
    // Padding lanes: a point light straight above `x` with no power (finite, positive G).
    let mut lx = [point_on_plane.x; LEAF_SIZE];
    let mut ly = [point_on_plane.y; LEAF_SIZE];
    let mut lz = [1.0; LEAF_SIZE];
    let mut power = [0.0; LEAF_SIZE];
    let mut shape = [LaneShape::POINT; LEAF_SIZE];
    for (j, (light, e)) in lights.iter().zip(emission).enumerate() {
        let at = light.position_in_world;
        (lx[j], ly[j], lz[j], power[j]) = (at.x, at.y, at.z, light.power);
        shape[j] = LaneShape::of(e);
    }
    let mut own = [true; LEAF_SIZE];
    for j in 0..LEAF_SIZE {
        let (dx, dy) = (lx[j] - point_on_plane.x, ly[j] - point_on_plane.y);
        (c[j], own[j]) = shaped_lane(dx, dy, lz[j], shape[j], power[j]);
    }
    for (j, (light, e)) in lights.iter().zip(emission).enumerate() {
        if !own[j] {
            c[j] = light.contribution_culled(e, point_on_plane);
        }
    }
}

/// The constants of a light's emission factor `S = g·t²·w` as a lane reads them
/// ([`EmissionShape`]'s, without the range itself).
#[derive(Clone, Copy, Debug, PartialEq)]
struct LaneShape {
    /// The unit spot axis (zero without a spot).
    axis: [f64; 3],
    /// `cos θi` (1 without a spot).
    cos_inner: f64,
    /// `cos θo` (−1 without a spot).
    cos_outer: f64,
    /// `1/(cos θi − cos θo)` (0 without a spot).
    cone_scale: f64,
    /// `g = 4π/Ω` (1 without a spot).
    gain: f64,
    /// `1/r_max` (0 without a range).
    inv_range: f64,
}

impl LaneShape {
    /// A bare point light's: `S ≡ 1`.
    const POINT: LaneShape = LaneShape {
        axis: [0.0; 3],
        cos_inner: 1.0,
        cos_outer: -1.0,
        cone_scale: 0.0,
        gain: 1.0,
        inv_range: 0.0,
    };

    /// The lane constants of `e`.
    #[inline]
    fn of(e: &EmissionShape) -> LaneShape {
        LaneShape {
            axis: e.axis().to_array(),
            cos_inner: e.cos_inner(),
            cos_outer: e.cos_outer(),
            cone_scale: e.cone_scale(),
            gain: e.gain(),
            inv_range: e.inv_range(),
        }
    }
}

/// `c = p·G·S` of a light `(dx, dy, z)` from the point (`to_light`, as
/// [`crate::scene::light_term`] forms it) with power `power` and shape `s`, every factor a
/// selection rather than a branch, and whether that is the light's own value: `false` where
/// `light_term`'s own rule differs (a light on or below the plane, `4π r³` below the least
/// normal `f64`) or where the product is not finite (an `∞·0` the culled evaluation
/// avoids): there the caller takes [`SpatialLight::contribution_culled`] itself.
///
/// The factors are the shape's own, [`spot_falloff`] (`t² = 1` for a light without a spot)
/// and [`range_window`] (`w = 1` exactly for a light without a range); `light_term`
/// multiplies by one only where the light has it, and multiplying by an exact 1 changes no
/// bit, so the product is the one the branching evaluation forms, operation for operation
/// (none fused). A dark lane (a cone or range
/// that leaves the point unlit) gives `+0`, as the culled evaluation does.
#[allow(
    clippy::inline_always,
    reason = "inlined into the loops it is a lane of, which widen only then"
)]
#[inline(always)]
fn shaped_lane(dx: f64, dy: f64, z: f64, s: LaneShape, power: f64) -> (f64, bool) {
    let r2 = distance_squared(dx, dy, z);
    let r = r2.sqrt();
    let denominator = four_pi_r2_times(r2, r);
    let g = z / denominator;
    // `axis · to_point` with `to_point = −to_light`, summed as `DVec3::dot` sums it.
    let cos_alpha = ((s.axis[0] * -dx + s.axis[1] * -dy) + s.axis[2] * -z) / r;
    let falloff = spot_falloff(cos_alpha, s.cos_inner, s.cos_outer, s.cone_scale);
    let window = range_window(r, s.inv_range);
    let c = power * (g * ((s.gain * falloff) * window));
    (
        c,
        z > 0.0 && denominator >= f64::MIN_POSITIVE && c.is_finite(),
    )
}

/// `c_j = p_j·G_j(x)` of point lights `lights` (at most [`LEAF_SIZE`]) into `c`, bit for bit
/// [`crate::spatial::SpatialLight::contribution`]: `G`'s own `r²` and `4π r³`, laid out over
/// all [`LEAF_SIZE`] lanes without a branch (so that they evaluate together),
/// the rare lanes where `G`'s own rule differs (a light on or below the plane, `r³`
/// underflowing) then taken from it.
#[inline]
pub(super) fn point_contributions(lights: &[SpatialLight], x: DVec2, c: &mut [f64; LEAF_SIZE]) {
    let (mut lx, mut ly, mut lz, mut power) = (
        [0.0; LEAF_SIZE],
        [0.0; LEAF_SIZE],
        [1.0; LEAF_SIZE],
        [0.0; LEAF_SIZE],
    );
    for (j, light) in lights.iter().enumerate() {
        let at = light.position_in_world;
        (lx[j], ly[j], lz[j], power[j]) = (at.x, at.y, at.z, light.power);
    }
    let mut denominator = [0.0; LEAF_SIZE];
    for j in 0..LEAF_SIZE {
        let r2 = distance_squared(lx[j] - x.x, ly[j] - x.y, lz[j]);
        denominator[j] = four_pi_r_cubed(r2);
        c[j] = power[j] * (lz[j] / denominator[j]);
    }
    for (j, light) in lights.iter().enumerate() {
        if !(lz[j] > 0.0 && denominator[j] >= f64::MIN_POSITIVE) {
            c[j] = light.contribution(x);
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::scene::{Emission, Spot};
    use crate::{Rng, unit_f64};

    /// A uniform draw in `[lo, hi)`.
    fn uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * unit_f64(rng.next_u32())
    }

    /// A light of a leaf: mostly spots a little above the plane, aimed anywhere from
    /// straight down to past the horizon, with cones from narrow to a hemisphere; some
    /// ranged, some bare, some on or below the plane or `10^-120` above it.
    fn random_light(rng: &mut Rng) -> (SpatialLight, Emission) {
        let height = match rng.next_u32() % 16 {
            0 => -uniform(rng, 0.0, 1.0),
            1 => 0.0,
            2 => 1e-120,
            _ => uniform(rng, 0.05, 2.0),
        };
        let light = SpatialLight {
            position_in_world: DVec3::new(uniform(rng, -2.0, 2.0), uniform(rng, -2.0, 2.0), height),
            power: uniform(rng, 0.001, 1.0),
        };
        let spot = (!rng.next_u32().is_multiple_of(4)).then(|| {
            let outer = uniform(rng, 0.01, std::f64::consts::FRAC_PI_2);
            Spot {
                direction: DVec3::new(
                    uniform(rng, -1.0, 1.0),
                    uniform(rng, -1.0, 1.0),
                    uniform(rng, -1.0, 0.3),
                ),
                inner_cone: outer * uniform(rng, 0.0, 0.99),
                outer_cone: outer,
            }
        });
        let range = (rng.next_u32().is_multiple_of(3)).then(|| uniform(rng, 0.05, 3.0));
        let emission = match Emission::new(spot, range) {
            Ok(e) => e,
            // A direction drawn as zero: a bare light instead.
            Err(_) => Emission::POINT,
        };
        (light, emission)
    }

    #[test]
    fn every_lane_gives_its_lights_own_bits() {
        let mut rng = Rng::new(41, 0);
        let (mut lit, mut in_falloff, mut dark, mut own_rule, mut windowed) = (0, 0, 0, 0, 0);
        for leaf in 0..20_000 {
            let count = 1 + leaf % LEAF_SIZE;
            let (lights, emission): (Vec<SpatialLight>, Vec<Emission>) =
                (0..count).map(|_| random_light(&mut rng)).unzip();
            let shapes: Vec<EmissionShape> = emission.iter().map(|e| *e.shape()).collect();
            // A point under a light now and then, else anywhere around the leaf.
            let x = if leaf.is_multiple_of(7) {
                lights[0].position_in_world.truncate()
            } else {
                DVec2::new(uniform(&mut rng, -3.0, 3.0), uniform(&mut rng, -3.0, 3.0))
            };
            let (mut dispatched, mut baseline) = ([f64::NAN; LEAF_SIZE], [f64::NAN; LEAF_SIZE]);
            shaped_contributions(&lights, &shapes, x, &mut dispatched);
            shaped_contributions_in(&lights, &shapes, x, &mut baseline);
            for j in 0..LEAF_SIZE {
                let own = lights
                    .get(j)
                    .map_or(0.0, |l| l.contribution_culled(&shapes[j], x));
                assert_eq!(
                    dispatched[j].to_bits(),
                    own.to_bits(),
                    "leaf {leaf} lane {j}"
                );
                assert_eq!(baseline[j].to_bits(), own.to_bits(), "leaf {leaf} lane {j}");
                let Some(light) = lights.get(j) else { continue };
                let e = &shapes[j];
                let at = light.position_in_world;
                if at.z < 1e-100 {
                    own_rule += 1;
                } else if own > 0.0 {
                    lit += 1;
                    let t2 = e.cone_term(at, x).unwrap_or(1.0);
                    in_falloff += usize::from(t2 > 0.0 && t2 < 1.0);
                    windowed += usize::from(e.window(at.distance(x.extend(0.0))) < 1.0);
                } else {
                    dark += 1;
                }
            }
        }
        // The lanes took every path: lit, inside a cone's falloff and a range's window,
        // dark, and the rule of `light_term` itself.
        for (what, n) in [
            ("lit", lit),
            ("in a falloff", in_falloff),
            ("in a window", windowed),
            ("dark", dark),
            ("by G's own rule", own_rule),
        ] {
            assert!(n > 1000, "{n} lanes {what}");
        }
    }
}
