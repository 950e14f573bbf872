//! Scenes and their parts as several test modules build them: presets at a test size,
//! planes, lights scattered from a [`SplitMix`] stream, random powers and spots.

use std::ops::Range;

use glam::{DVec3, dvec2, dvec3};
use lightpick_core::LightPowers;
use lightpick_core::scene::{ReceiverPlane, Scene, Spot};

use super::SplitMix;

/// The preset `name` with a `width × height` pixel grid (its lights and rectangle
/// unchanged), to keep tests fast.
pub fn preset_at(name: &str, width: u32, height: u32) -> Scene {
    let mut scene = Scene::preset(name).expect("preset");
    scene.plane.width = width;
    scene.plane.height = height;
    scene
}

/// The square `[-half, half]²` of `pixels × pixels`.
pub fn square_plane(half: f64, pixels: u32) -> ReceiverPlane {
    ReceiverPlane {
        min: dvec2(-half, -half),
        max: dvec2(half, half),
        width: pixels,
        height: pixels,
    }
}

/// The plane `[-s, s] × [-0.75 s, 0.75 s]` of 40 × 30 pixels (`s = scale`).
pub fn scaled_plane(scale: f64) -> ReceiverPlane {
    ReceiverPlane {
        min: dvec2(-scale, -0.75 * scale),
        max: dvec2(scale, 0.75 * scale),
        width: 40,
        height: 30,
    }
}

/// `n` positions drawn from `d`, light by light: a height `z` from `heights`, then `x` and
/// `y` from `[-2, 2]`, all times `scale`; light `i` with `i % below_every == below_at`
/// hangs at `−z` instead (below the plane: it contributes nothing).
pub fn scattered_positions(
    d: &mut SplitMix,
    n: usize,
    scale: f64,
    heights: Range<f64>,
    (below_every, below_at): (usize, usize),
) -> Vec<DVec3> {
    (0..n)
        .map(|i| {
            let z = d.range(heights.start, heights.end);
            let z = if i % below_every == below_at { -z } else { z };
            dvec3(
                d.range(-2.0, 2.0) * scale,
                d.range(-2.0, 2.0) * scale,
                z * scale,
            )
        })
        .collect()
}

/// `n` powers drawn from `d`: `10^u` with `u` uniform in `[-decades, decades]`, but 0 for
/// every light `i` with `i % 5 == zero_at`, and light 0 at power 1 (never all zero).
pub fn random_powers(d: &mut SplitMix, n: usize, decades: f64, zero_at: usize) -> Vec<f64> {
    let mut powers: Vec<f64> = (0..n)
        .map(|i| {
            if i % 5 == zero_at {
                0.0
            } else {
                10f64.powf(d.range(-decades, decades))
            }
        })
        .collect();
    powers[0] = 1.0;
    powers
}

/// `n` lights over [`scaled_plane`]`(scale)`, named `test-{n}`, at `|x|, |y| ≤ 2s` and
/// `z ∈ [0.5 s, 2 s]` (every 17th below the plane) drawn from `SplitMix(seed)`, with
/// `powers`.
pub fn scattered(n: usize, seed: u64, scale: f64, powers: Vec<f64>) -> Scene {
    let positions = scattered_positions(&mut SplitMix(seed), n, scale, 0.5..2.0, (17, 16));
    Scene::new(
        format!("test-{n}"),
        scaled_plane(scale),
        positions,
        LightPowers::new(powers).expect("valid powers"),
    )
}

/// [`scattered`] with [`random_powers`] over `decades` (every fifth from the fourth at
/// power 0) drawn from the same stream after the positions.
pub fn scattered_random(n: usize, seed: u64, scale: f64, decades: f64) -> Scene {
    let mut d = SplitMix(seed);
    let positions = scattered_positions(&mut d, n, scale, 0.5..2.0, (17, 16));
    let powers = random_powers(&mut d, n, decades, 3);
    Scene::new(
        format!("test-{n}"),
        scaled_plane(scale),
        positions,
        LightPowers::new(powers).expect("valid"),
    )
}

/// A spot with half-angle `outer`, its axis `tilt` from straight down and turned about the
/// vertical by an angle drawn from `d`, then its inner cone a fraction of `outer` drawn
/// from `inner`.
pub fn tilted_spot(d: &mut SplitMix, outer: f64, tilt: f64, inner: Range<f64>) -> Spot {
    let turn = d.range(0.0, std::f64::consts::TAU);
    Spot {
        direction: dvec3(
            tilt.sin() * turn.cos(),
            tilt.sin() * turn.sin(),
            -tilt.cos(),
        ),
        inner_cone: outer * d.range(inner.start, inner.end),
        outer_cone: outer,
    }
}
