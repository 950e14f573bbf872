//! A light `z` above a pixel centre, from `z = 1` down to `z = 10^-154` (where the
//! irradiance under it still fits `f64`), with every power scaled by `2^k`, `k ∈ [−1000,
//! 1000]`, on top: relMSE, the variance and efficiency ratios between schemes keep their
//! value, `V̂` and the efficiency follow `z` exactly as the geometry says (`z^-4` and `z^4`),
//! and no figure is 0, `inf` or NaN unless it truly is (the exact pick's zero variance).
//!
//! Two scenes of two lights over 4×4 pixels:
//! * `similar(z)`: one geometry scaled by `z` (plane `4z` a side, lights at `(1.5, 2.5, 1)·z`
//!   — above the centre of pixel (1, 1) — and `(3, 1, 1)·z`). Every `G_i(x)` is `z^-2` times
//!   that of `z = 1`, so every relative figure is the same at every `z`, up to the rounding of
//!   the scaled positions: each `G` moves by a few ulps, each relMSE term `(d/E)²` by at
//!   most `2|d/E|·(1 + 1/p_i)` times that, so `10^-10` relative is far above it.
//! * `under(z)`: the issue's scene, a 4×4 plane of side 4 with one light `z` above pixel
//!   (1, 1)'s centre and the other at `(3, 1, 1)`. Under the near light `G ≈ 1/(4πz²)`; the
//!   other light adds `(z/ρ)²/13`-relative there (`ρ ≈ 2.3` its distance), and the other
//!   pixels enter relMSE through `ε ∝ Ē² ∝ z^-4` and `V̂` through their `O(1)` variances:
//!   every relative figure is its `z → 0` limit up to `O(z²)`, below `10^-10` for
//!   `z ≤ 10^-6`.
//! * `beside(z)`: the same with the near light `0.3` beside the centre, down to `10^-300`:
//!   its share vanishes as `O(z)`, and the figures keep those of `z = 10^-16`.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use glam::{DVec3, dvec2, dvec3};
use lightpick_core::render::{
    CpuRenderer, Efficiency, ErrorMetrics, Reference, efficiency, error_metrics,
    is_zero_variance_scaled,
};
use lightpick_core::scene::{ReceiverPlane, Scene, pixel_center};
use lightpick_core::{Scaled, Scheme};
use proptest::prelude::*;

/// The schemes compared: three with a variance, and the exact spatial pick (zero variance
/// on two lights).
const SCHEMES: [Scheme; 4] = [Scheme::Uniform, Scheme::Alias, Scheme::Cdf, Scheme::Spatial];

/// Virtual render seconds, the same for every scheme and scene: the efficiency is then
/// `1/(V̂·T)` with one `T`, and its ratios are those of `1/V̂`.
const SECONDS: f64 = 1e-3;

/// Relative agreement of two relative figures (see the module docs for the bound).
const TOLERANCE: f64 = 1e-10;

/// Powers of the near and the other light (unequal, so that the schemes' pmfs differ),
/// times `2^k`.
fn powers(k: i32) -> Vec<f64> {
    [1.0, 3.0]
        .iter()
        .map(|&p| Scaled::new(p, k).to_f64())
        .collect()
}

fn scene(side: f64, lights: [DVec3; 2], powers: Vec<f64>) -> Scene {
    Scene::from_parts(
        "near",
        ReceiverPlane {
            min: dvec2(0.0, 0.0),
            max: dvec2(side, side),
            width: 4,
            height: 4,
        },
        lights.to_vec(),
        powers,
    )
    .unwrap()
}

/// A 4×4 plane of side 4 with the given lights.
fn scene_of(lights: Vec<DVec3>, powers: Vec<f64>) -> Scene {
    Scene::from_parts(
        "lights",
        ReceiverPlane {
            min: dvec2(0.0, 0.0),
            max: dvec2(4.0, 4.0),
            width: 4,
            height: 4,
        },
        lights,
        powers,
    )
    .unwrap()
}

fn similar(z: f64, k: i32) -> Scene {
    scene(
        4.0 * z,
        [dvec3(1.5, 2.5, 1.0) * z, dvec3(3.0, 1.0, 1.0) * z],
        powers(k),
    )
}

fn under(z: f64, powers: Vec<f64>) -> Scene {
    scene(4.0, [dvec3(1.5, 2.5, z), dvec3(3.0, 1.0, 1.0)], powers)
}

/// [`under`] with the near light `0.3` to the left of the centre of pixel (1, 1).
fn beside(z: f64, powers: Vec<f64>) -> Scene {
    scene(4.0, [dvec3(1.2, 2.5, z), dvec3(3.0, 1.0, 1.0)], powers)
}

/// Every scheme's error and efficiency after 4 samples per pixel (seed 1).
fn measure(scene: &Scene) -> Vec<(Scheme, ErrorMetrics, Efficiency)> {
    let reference = Reference::compute(scene);
    assert_eq!(reference.overflow(), None);
    SCHEMES
        .iter()
        .map(|&scheme| {
            let mut renderer = CpuRenderer::new(scene, scheme, 1);
            renderer.accumulate(4);
            let acc = renderer.accumulator();
            (
                scheme,
                error_metrics(acc, &reference),
                efficiency(acc, SECONDS),
            )
        })
        .collect()
}

/// Whether the scheme's variance is the rounding of zero next to the largest measured.
fn exact(row: &Efficiency, rows: &[(Scheme, ErrorMetrics, Efficiency)]) -> bool {
    let largest = rows
        .iter()
        .map(|(_, _, e)| e.normalized_variance)
        .fold(Scaled::ZERO, |a, b| if b > a { b } else { a });
    is_zero_variance_scaled(row.normalized_variance, largest)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE * b.abs()
}

/// No figure is 0, `inf` or NaN, except what a zero-variance (exact) scheme truly has.
fn check_real(
    scheme: Scheme,
    m: &ErrorMetrics,
    e: &Efficiency,
    exact: bool,
) -> Result<(), TestCaseError> {
    prop_assert!(
        m.rel_mse.is_finite() && !m.rmse_log10.is_nan(),
        "{scheme}: {m:?}"
    );
    prop_assert!(e.seconds_per_sample > 0.0, "{scheme}: {e:?}");
    if exact {
        // Rounding of the exact pick (a relative error near 1e-16), or exactly 0.
        prop_assert!(
            m.rel_mse < 1e-20 && m.rmse_log10 < f64::INFINITY,
            "{scheme}: {m:?}"
        );
        prop_assert!(e.efficiency > Scaled::ZERO, "{scheme}: {e:?}");
        return Ok(());
    }
    prop_assert!(
        m.rel_mse > 0.0 && m.rmse_log10.is_finite(),
        "{scheme}: {m:?}"
    );
    for (name, x, log) in [
        (
            "normalized_variance",
            e.normalized_variance,
            e.normalized_variance_log10,
        ),
        ("efficiency", e.efficiency, e.efficiency_log10),
    ] {
        prop_assert!(
            x.is_finite() && x > Scaled::ZERO,
            "{scheme}: {name} {x:?} in {e:?}"
        );
        prop_assert!(
            log.is_finite() && (log - x.log10()).abs() < 1e-12,
            "{scheme}: {name}"
        );
    }
    prop_assert!(e.variance_log10.is_finite(), "{scheme}: {e:?}");
    Ok(())
}

/// The figures of `near` against those of `base`: the same relMSE and ratios, `V̂` larger by
/// `10^shift` and the efficiency smaller by it.
fn compare(
    base: &[(Scheme, ErrorMetrics, Efficiency)],
    near: &[(Scheme, ErrorMetrics, Efficiency)],
    shift: f64,
) -> Result<(), TestCaseError> {
    let (_, _, uniform_base) = &base[0];
    let (_, _, uniform_near) = &near[0];
    for ((scheme, mb, eb), (_, mn, en)) in base.iter().zip(near) {
        let is_exact = exact(eb, base);
        prop_assert_eq!(is_exact, exact(en, near), "{}", scheme);
        check_real(*scheme, mn, en, is_exact)?;
        if is_exact {
            continue;
        }
        prop_assert!(
            close(mn.rel_mse, mb.rel_mse),
            "{scheme}: relMSE {} vs {}",
            mn.rel_mse,
            mb.rel_mse
        );
        // log10 agreement to TOLERANCE·log10(e) ≈ 4.3e-11 is TOLERANCE relative.
        let log_tolerance = TOLERANCE * std::f64::consts::LOG10_E + 1e-12;
        prop_assert!(
            (en.normalized_variance_log10 - eb.normalized_variance_log10 - shift).abs()
                <= log_tolerance,
            "{scheme}: V̂ {en:?} vs {eb:?}"
        );
        prop_assert!(
            (en.efficiency_log10 - eb.efficiency_log10 + shift).abs() <= log_tolerance,
            "{scheme}: efficiency {en:?} vs {eb:?}"
        );
        // Ratios between schemes, computed as Scaled quotients: the same at every scale.
        let variance_ratio = |e: &Efficiency, u: &Efficiency| {
            (e.normalized_variance / u.normalized_variance).to_f64()
        };
        let efficiency_ratio =
            |e: &Efficiency, u: &Efficiency| (e.efficiency / u.efficiency).to_f64();
        prop_assert!(close(
            variance_ratio(en, uniform_near),
            variance_ratio(eb, uniform_base)
        ));
        prop_assert!(close(
            efficiency_ratio(en, uniform_near),
            efficiency_ratio(eb, uniform_base)
        ));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// The similar scenes from `z = 1` down to `10^-154`, powers times `2^k`.
    #[test]
    fn relative_figures_keep_their_value_at_every_height(
        decades in 0.0f64..=154.0,
        k in -1000i32..=1000,
    ) {
        let z = 10f64.powf(-decades);
        let base = measure(&similar(1.0, 0));
        let near = measure(&similar(z, k));
        // The geometry z times smaller: V̂ times z^-4.
        compare(&base, &near, -4.0 * z.log10())?;
    }

    /// The issue's scene, the near light from `10^-6` down to `10^-154` (where the figures
    /// are their `z → 0` limits), powers times `2^k`: relMSE and the ratios as at
    /// `z = 10^-6`, `V̂·z⁴` and the efficiency`/z⁴` too.
    #[test]
    fn a_light_next_to_a_pixel_keeps_every_relative_figure(
        decades in 6.0f64..=154.0,
        k in -1000i32..=1000,
    ) {
        let z = 10f64.powf(-decades);
        let z0 = 1e-6;
        let base = measure(&under(z0, powers(0)));
        let near = measure(&under(z, powers(k)));
        compare(&base, &near, -4.0 * (z / z0).log10())?;
    }

    /// The near light `0.3` beside pixel (1, 1)'s centre, from `10^-16` down to `10^-300`:
    /// its irradiance at every centre is `O(z)` and vanishes, so every figure (`V̂` too)
    /// tends to that of the other light alone, `O(z)` away (`≈ 500z` relative at pixel
    /// (1, 1)). The accumulation unit follows the largest irradiance at a pixel centre, not
    /// `1/(4πz²)`, so the sums of squares keep a variance (no scheme turns "exact").
    #[test]
    fn a_light_between_pixel_centres_keeps_every_figure(
        decades in 16.0f64..=300.0,
        k in -1000i32..=1000,
    ) {
        let z = 10f64.powf(-decades);
        let base = measure(&beside(1e-16, powers(0)));
        let near = measure(&beside(z, powers(k)));
        compare(&base, &near, 0.0)?;
    }

    /// The accumulation unit's exponent is that of the largest irradiance per unit power
    /// at any pixel centre, from any light, at any height down to `10^-150`.
    #[test]
    fn the_unit_follows_the_largest_irradiance_at_a_centre(
        lights in prop::collection::vec(
            (-2.0f64..6.0, -2.0f64..6.0, 0.0f64..150.0, -1.0f64..1.0),
            1..12,
        ),
    ) {
        let positions: Vec<DVec3> = lights
            .iter()
            .map(|&(x, y, decades, sign)| dvec3(x, y, sign.signum() * 10f64.powf(-decades)))
            .collect();
        let n = positions.len();
        let s = scene_of(positions.clone(), vec![1.0; n]);
        let largest = positions
            .iter()
            .flat_map(|&p| {
                let plane = &s.plane;
                (0..plane.width).flat_map(move |px| {
                    (0..plane.height).map(move |py| {
                        lightpick_core::scene::geometry_term(p, pixel_center(plane, px, py))
                    })
                })
            })
            .filter(|g| g.is_finite())
            .fold(0.0f64, f64::max);
        let expected = if largest > 0.0 {
            Scaled::from_f64(largest).exponent().clamp(-1000, 1000)
        } else {
            0
        };
        prop_assert_eq!(s.irradiance_shift(), expected);
    }

    /// The nearest pixel centre is the nearest of all the centres, inside the plane and out.
    #[test]
    fn the_nearest_pixel_centre_is_nearest(x in -3.0f64..7.0, y in -3.0f64..7.0) {
        let plane = ReceiverPlane {
            min: dvec2(-1.0, 0.5),
            max: dvec2(4.0, 3.5),
            width: 5,
            height: 4,
        };
        let at = dvec2(x, y);
        let nearest = plane.nearest_pixel_center(at);
        let best = (0..plane.width)
            .flat_map(|px| (0..plane.height).map(move |py| (px, py)))
            .map(|(px, py)| pixel_center(&plane, px, py).distance(at))
            .fold(f64::INFINITY, f64::min);
        prop_assert!(nearest.distance(at) <= best + 1e-12, "{at} → {nearest}: {best}");
    }
}

/// The issue's table: powers `1, 1`, the alias scheme at 4 samples per pixel. relMSE is the
/// same in every row from `z = 10^-3` (up to its `O(z²)` share of the other light, `10^-5`
/// relative at most there) down to `10^-154`, and the efficiency is a number in every row
/// (its `log10` falling by 4 per decade of `z`), never 0.
#[test]
fn the_issue_table_reads_one_rel_mse_and_an_efficiency_in_every_row() {
    let alias = |z: f64| {
        let scene = under(z, vec![1.0, 1.0]);
        let reference = Reference::compute(&scene);
        let mut renderer = CpuRenderer::new(&scene, Scheme::Alias, 1);
        renderer.accumulate(4);
        let acc = renderer.accumulator();
        (error_metrics(acc, &reference), efficiency(acc, SECONDS))
    };
    let (first, first_e) = alias(1e-3);
    for z in [1e-50, 1e-100, 1e-130, 1e-140, 1e-150, 1e-154] {
        let (m, e) = alias(z);
        assert!(
            (m.rel_mse - first.rel_mse).abs() <= 1e-5 * first.rel_mse,
            "z = {z:e}: relMSE {} vs {}",
            m.rel_mse,
            first.rel_mse
        );
        assert!(m.rmse_log10.is_finite() && m.rmse > 0.0, "{m:?}");
        assert!(
            e.efficiency > Scaled::ZERO && e.efficiency.is_finite(),
            "{e:?}"
        );
        let decades = (z / 1e-3).log10();
        assert!(
            (e.efficiency_log10 - first_e.efficiency_log10 - 4.0 * decades).abs() < 1e-4,
            "z = {z:e}: {e:?} vs {first_e:?}"
        );
    }
}

/// The reference under a light `10^-130 … 10^-154` above a pixel: `p·G` in the unit, not
/// the `0` that `p·z·2^-s ≈ 10^-390` would leave, and equal to the direct sum.
#[test]
fn the_reference_under_a_low_light_is_the_direct_sum() {
    for z in [1e-100, 1e-130, 1e-150, 1e-154] {
        let scene = under(z, vec![1.0, 3.0]);
        let reference = Reference::compute(&scene);
        // Pixel (1, 1), right under the near light.
        let at = 4 + 1;
        let position = reference.pixels().iter().position(|&p| p == at).unwrap();
        let in_unit = reference.in_unit()[position];
        let direct = pixel_center(&scene.plane, 1, 1);
        let g = scene.light_term(0, direct) * 0.25 + scene.light_term(1, direct) * 0.75;
        let expected = Scaled::from_f64(g) * Scaled::pow2(-scene.irradiance_shift());
        assert!(
            ((Scaled::from_f64(in_unit) / expected).to_f64() - 1.0).abs() < 1e-14,
            "z = {z:e}: {in_unit:e} vs {expected}"
        );
        assert!(in_unit > 0.01, "z = {z:e}: {in_unit:e}");
    }
}

/// A dim light (`p ≈ 10^-300`) `10^-100` above a pixel centre sets the accumulation unit
/// (`2^s ≈ 10^199`), so the bright light's irradiance is `≈ 10^-201` in it and its square
/// is not an `f64`: RMSE and relMSE are still those of the same scene with the dim light at
/// height 1, which differs by the dim light's share, `10^-99` relative at most (and the
/// dim light is never picked by power: its table column keeps it with probability 0).
#[test]
fn metrics_hold_where_the_image_is_far_below_the_unit() {
    // Two bright lights, so that every scheme has a variance.
    let with_dim_at = |z: f64| {
        Scene::from_parts(
            "dim",
            ReceiverPlane {
                min: dvec2(0.0, 0.0),
                max: dvec2(4.0, 4.0),
                width: 4,
                height: 4,
            },
            vec![
                dvec3(1.5, 2.5, z),
                dvec3(3.0, 1.0, 1.0),
                dvec3(0.5, 0.5, 0.7),
            ],
            vec![1e-300, 1.0, 3.0],
        )
        .unwrap()
    };
    let (low, high) = (with_dim_at(1e-100), with_dim_at(1.0));
    assert!(low.irradiance_shift() > 600, "{}", low.irradiance_shift());
    let metrics = |scene: &Scene, scheme: Scheme| {
        let reference = Reference::compute(scene);
        let mut renderer = CpuRenderer::new(scene, scheme, 1);
        renderer.accumulate(4);
        error_metrics(renderer.accumulator(), &reference)
    };
    for scheme in [Scheme::Uniform, Scheme::Alias] {
        let (a, b) = (metrics(&low, scheme), metrics(&high, scheme));
        assert!(a.rel_mse > 0.0 && a.rmse > 0.0, "{scheme}: {a:?}");
        assert!(
            (a.rel_mse - b.rel_mse).abs() <= 1e-12 * b.rel_mse,
            "{scheme}: {a:?} vs {b:?}"
        );
        assert!(
            (a.rmse - b.rmse).abs() <= 1e-12 * b.rmse,
            "{scheme}: {a:?} vs {b:?}"
        );
    }
}
