//! The spatial sampler is unbiased point by point on spot rigs no preset resembles: at every
//! pixel centre and at points on and just inside every cone's rim and every range's edge,
//! each light that gives the point light has a positive pick probability. The estimate
//! `f_i/P(i | x)` then averages to `Σ_{P > 0} f_i = E(x)` exactly, at that point, so a
//! render's error keeps falling as `1/spp` (a light culled where it shines would leave a
//! bias no sample count removes).

use glam::{DVec2, DVec3, dvec2, dvec3};
use lightpick_core::scene::{Emission, ReceiverPlane, Scene, Spot};
use lightpick_core::spatial::SpatialSampler;

use crate::common::SplitMix;
use crate::common::scenes::tilted_spot;

/// A spot rig: `n` lights over `[-3, 3]²` at heights 0.05–2, every one a spot (cones from
/// 0.002 rad to near π/2, tilted up to grazing), some in coincident pairs with axes a few
/// nanoradians apart, about half with ranges (some barely reaching the plane).
fn rig(n: usize, seed: u64) -> Scene {
    let mut d = SplitMix(seed);
    let mut positions: Vec<DVec3> = Vec::new();
    let mut powers = Vec::new();
    let mut emission = Vec::new();
    while positions.len() < n {
        let position = dvec3(d.range(-3.0, 3.0), d.range(-3.0, 3.0), d.range(0.05, 2.0));
        let outer = 10f64
            .powf(d.range(-2.7, 0.19))
            .min(std::f64::consts::FRAC_PI_2);
        let tilt = d.range(0.0, 1.5);
        let spot = tilted_spot(&mut d, outer, tilt, 0.0..0.95);
        let range = (d.next_f64() < 0.5).then(|| position.z * d.range(1.0001, 4.0));
        positions.push(position);
        powers.push(10f64.powf(d.range(-3.0, 3.0)));
        emission.push(Emission::new(Some(spot), range).expect("valid"));
        // Every fourth: a twin at the same place, its axis a few nanoradians off.
        if positions.len().is_multiple_of(4) && positions.len() < n {
            let turn = 5e-9 * d.range(0.5, 2.0);
            let twin = Spot {
                direction: spot.direction.normalize() + dvec3(turn, -turn, 0.0),
                ..spot
            };
            positions.push(position);
            powers.push(10f64.powf(d.range(-3.0, 3.0)));
            emission.push(Emission::new(Some(twin), range).expect("valid"));
        }
    }
    Scene::from_parts(
        "rig",
        ReceiverPlane {
            min: dvec2(-3.0, -3.0),
            max: dvec2(3.0, 3.0),
            width: 48,
            height: 48,
        },
        positions,
        powers,
    )
    .expect("valid")
    .with_emission(emission)
}

/// Points of the plane on the rim of light `i`'s cone (just inside it) and of its range.
fn rim_points(scene: &Scene, i: usize, d: &mut SplitMix) -> Vec<DVec2> {
    let p = scene.positions[i];
    let emission = scene.emission.as_ref().expect("a rig")[i];
    let mut points = Vec::new();
    if let Some(spot) = emission.spot() {
        let axis = spot.direction.normalize();
        // A basis around the axis, and rays at the outer angle less a hair.
        let helper = if axis.z.abs() < 0.9 {
            DVec3::Z
        } else {
            DVec3::X
        };
        let u = axis.cross(helper).normalize();
        let v = axis.cross(u);
        for shrink in [1e-6, 1e-9, 1e-12] {
            let angle = spot.outer_cone * (1.0 - shrink);
            for _ in 0..6 {
                let turn = d.range(0.0, std::f64::consts::TAU);
                let ray = axis * angle.cos() + (u * turn.cos() + v * turn.sin()) * angle.sin();
                if ray.z < -1e-9 {
                    let t = -p.z / ray.z;
                    let hit = p + ray * t;
                    points.push(dvec2(hit.x, hit.y));
                }
            }
        }
    }
    if let Some(range) = emission.range() {
        for shrink in [1e-6, 1e-9, 1e-12] {
            let reach = range * (1.0 - shrink);
            if reach > p.z {
                let across = (reach * reach - p.z * p.z).sqrt();
                let turn = d.range(0.0, std::f64::consts::TAU);
                points.push(dvec2(p.x + across * turn.cos(), p.y + across * turn.sin()));
            }
        }
    }
    points
}

/// At `x`: every light with a positive contribution has a positive pick probability, and the
/// probabilities sum to at most one.
fn assert_unbiased_at(scene: &Scene, sampler: &SpatialSampler, x: DVec2, what: &str) {
    let pdfs = sampler.pdfs(x);
    let total: f64 = pdfs.iter().sum();
    assert!(total <= 1.0 + 1e-9, "{what} at {x}: Σ P = {total}");
    for (i, &pdf) in pdfs.iter().enumerate() {
        let f = scene.powers.as_slice()[i] * scene.light_term(i, x);
        assert!(
            !(f > 0.0 && pdf <= 0.0),
            "{what}: light {i} gives {f:e} at {x} but is never picked there (bias)"
        );
    }
}

#[test]
fn every_light_that_shines_on_a_point_can_be_picked_there() {
    for (n, seed) in [(60, 11), (300, 12), (1200, 13)] {
        let scene = rig(n, seed);
        let sampler = SpatialSampler::for_scene(&scene);
        let plane = &scene.plane;
        for py in 0..plane.height {
            for px in 0..plane.width {
                let x = lightpick_core::scene::pixel_center(plane, px, py);
                assert_unbiased_at(&scene, &sampler, x, "pixel centre");
            }
        }
        let mut d = SplitMix(seed ^ 0xA5);
        let mut rims = 0;
        for i in 0..scene.light_count() {
            for x in rim_points(&scene, i, &mut d) {
                assert_unbiased_at(&scene, &sampler, x, "rim point");
                rims += 1;
            }
        }
        assert!(rims > 10 * n, "{rims} rim points for {n} lights");
    }
}

#[test]
fn the_rig_has_what_it_claims() {
    // The rims probed are really lit (else the test above could pass on points no light
    // reaches), and the twins really are nanoradians apart.
    let scene = rig(300, 12);
    let mut d = SplitMix(7);
    let mut lit = 0;
    let mut probed = 0;
    for i in 0..scene.light_count() {
        for x in rim_points(&scene, i, &mut d) {
            probed += 1;
            if scene.light_term(i, x) > 0.0 {
                lit += 1;
            }
        }
    }
    assert!(
        lit * 2 > probed,
        "{lit} of {probed} rim points lit by their light"
    );
    let emission = scene.emission.as_ref().expect("spots");
    let twins = (1..scene.light_count())
        .filter(|&i| scene.positions[i] == scene.positions[i - 1])
        .filter(|&i| {
            let (a, b) = (emission[i].spot(), emission[i - 1].spot());
            let (a, b) = (
                a.expect("spot").direction.normalize(),
                b.expect("spot").direction.normalize(),
            );
            // The stable angle (acos of a dot product near 1 loses it).
            let angle = 2.0 * (0.5 * (a - b).length()).asin();
            angle > 0.0 && angle < 1e-7
        })
        .count();
    assert!(twins > 30, "{twins} coincident twins");
}

/// Pixel by pixel, sampled: at pixels of a rig (lit and unlit, near rims), the mean of
/// many spatial estimates lies within 5σ of the exact value there, `σ² = Var/n` with the
/// exact variance of one sample `Σ_{q>0} c_i²/q_i − E²` (`c_i = p_i·G_i(x)`). A local bias
/// larger than a few σ would show at some pixel; a whole-image mean could hide it.
#[test]
fn estimates_average_to_the_exact_value_pixel_by_pixel() {
    let scene = rig(300, 21);
    let sampler = SpatialSampler::for_scene(&scene);
    let pmf = scene.powers.pmf();
    let plane = &scene.plane;
    let draws = 4000u64;
    let (mut checked, mut lit) = (0, 0);
    for (py, px) in (0..plane.height)
        .step_by(5)
        .flat_map(|y| (0..plane.width).step_by(5).map(move |x| (y, x)))
    {
        let x = lightpick_core::scene::pixel_center(plane, px, py);
        let pdfs = sampler.pdfs(x);
        let c: Vec<f64> = (0..scene.light_count())
            .map(|i| pmf[i] * scene.light_term(i, x))
            .collect();
        let exact: f64 = c.iter().sum();
        let second: f64 = c
            .iter()
            .zip(&pdfs)
            .filter(|(_, q)| **q > 0.0)
            .map(|(c, q)| c * c / q)
            .sum();
        let variance = (second - exact * exact).max(0.0);
        let mean = (0..draws)
            .map(|k| {
                sampler.estimate(
                    x,
                    &mut lightpick_core::Rng::new(9, (k << 16) | u64::from(py * 64 + px)),
                )
            })
            .sum::<f64>()
            / draws as f64;
        let sigma = (variance / draws as f64).sqrt();
        // 5σ, and the rounding of the sums where the variance is (near) zero.
        let bound = 5.0 * sigma + 1e-12 * exact.abs() + f64::MIN_POSITIVE;
        assert!(
            (mean - exact).abs() <= bound,
            "pixel ({px}, {py}): mean {mean:e} vs exact {exact:e}, σ {sigma:e}"
        );
        checked += 1;
        lit += usize::from(exact > 0.0 && variance > 0.0);
    }
    assert!(checked >= 80, "{checked} pixels checked");
    assert!(
        lit * 2 >= checked,
        "only {lit} of {checked} pixels lit with some noise"
    );
}
