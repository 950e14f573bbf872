//! Spots and ranges on the GPU (`emission.wgsl`, the node bounds of `spatial_bounds.wgsl`)
//! against the CPU with the same seeds.
//!
//! # The agreement criterion
//! The power schemes pick the same light for every (pixel, sample) on both sides (integer
//! arithmetic), so each pixel's difference is bounded by the sum of its samples' bounds.
//! One sample is `ê = w·G·g·t²·ω` (weight, geometry term, gain, spot falloff, range window);
//! with `u = 2^-24`, `B` the largest coordinate and `z` the light's height:
//!
//! * `G` carries the relative error `(57 B/z + 26)·u` (derived in `gpu_render.rs`), and
//!   `w`, `g` and the products add `4u`;
//! * the offset `d` from the light to the pixel carries an absolute error `19 u B` per
//!   component, so its direction `d/|d|` is off by at most `2·19 u B/|d| ≤ 38 u B/z`; the
//!   octahedral axis by `8u` (its test in `emission.rs`), and the scaling, length, division
//!   and dot product add `≤ 12u`: `|Δ cos α| ≤ (38 B/z + 20)·u`; `cos θo` and the scale
//!   `1/(cos θi − cos θo)` are rounded once each, so
//!   `Δt ≤ scale·((38 B/z + 21)·u) + 2u` and `|Δ t²| ≤ 2Δt + Δt²` (t is clamped to [0, 1]);
//! * `q = d/r` carries `(19 B/z + 8)·u` relative, and `|Δ(1 − q⁴)| ≤ 4q⁴·that + 2u` with
//!   `q ≤ 1` where the window is not clamped: `|Δω| ≤ (76 B/z + 34)·u`;
//!
//! so `|Δê| ≤ |ê|·(57 B/z + 30)·u + w·G·g·(|Δ t²| + |Δω|)`, summed over the pixel's
//! samples, plus `(spp − 1)·u` of the f32 running sum. The bound is computed sample by
//! sample from the CPU's own evaluation of the same picks.
//!
//! The exact spatial pick (≤ 16 lights) estimates the total `Σ c_j` whichever light it
//! picks: its bound is the sum of the per-light bounds. The light tree's decisions may flip
//! where an `f32` probability rounds across a draw (see `gpu_spatial.rs`), more often at a
//! penumbra than elsewhere: its per-pixel criterion counts those flips
//! (`the_light_tree_over_spots_and_ranges_matches_the_cpu_per_pixel`), and its image mean
//! is checked against the exact reference within 5 standard errors.

use crate::common::scenes::tilted_spot;
use crate::common::{self, SplitMix};
use glam::{DVec3, dvec2, dvec3};
use lightpick_core::gpu::GpuRenderer;
use lightpick_core::render::{CpuRenderer, Reference};
use lightpick_core::scene::{
    Emission, ReceiverPlane, Scene, geometry_term, light_term, pixel_center,
};
use lightpick_core::spatial::{Child, LightTree, SpatialSampler, TREE_WIDTH};
use lightpick_core::{LightPowers, Rng, Sampler, Scheme};

const U: f64 = 1.0 / (1u64 << 24) as f64;
const SPP: u32 = 16;

/// `n` lights over the plane `[-1, 1] × [-0.75, 0.75]`: every other a spot (mostly aimed
/// down, some grazing, cones from 0.2 to 1.2 rad), every third with a range of 1–3.
fn shaped_scene(n: usize, seed: u64) -> Scene {
    let mut d = SplitMix(seed);
    let mut positions = Vec::with_capacity(n);
    let mut powers = Vec::with_capacity(n);
    let mut emission = Vec::with_capacity(n);
    for i in 0..n {
        positions.push(dvec3(
            d.range(-1.5, 1.5),
            d.range(-1.2, 1.2),
            d.range(0.3, 1.5),
        ));
        powers.push(10f64.powf(d.range(-1.0, 1.0)));
        let spot = (i % 2 == 0).then(|| {
            let outer = d.range(0.2, 1.2);
            let tilt = if i % 10 == 0 {
                d.range(1.2, 1.6)
            } else {
                d.range(0.0, 0.8)
            };
            tilted_spot(&mut d, outer, tilt, 0.0..0.8)
        });
        let range = (i % 3 == 0).then(|| d.range(1.0, 3.0));
        emission.push(Emission::new(spot, range).expect("valid"));
    }
    Scene::from_parts(
        format!("shaped-{n}"),
        ReceiverPlane {
            min: dvec2(-1.0, -0.75),
            max: dvec2(1.0, 0.75),
            width: 40,
            height: 30,
        },
        positions,
        powers,
    )
    .expect("valid")
    .with_emission(emission)
}

/// Largest coordinate `B` of the scene (plane and lights).
fn largest_coordinate(scene: &Scene) -> f64 {
    let p = &scene.plane;
    let mut b = p.min.abs().max_element().max(p.max.abs().max_element());
    for l in scene.positions.iter() {
        b = b.max(l.abs().max_element());
    }
    b
}

/// `(|ê|, bound on |Δê|)` of one sample of light `i` with weight `w` at `x` (module docs).
fn sample_bound(scene: &Scene, i: usize, w: f64, x: glam::DVec2, b: f64) -> (f64, f64) {
    let light = scene.positions[i];
    let e = w * light_term(
        light,
        scene
            .emission_of(i)
            .map(lightpick_core::scene::Emission::shape),
        x,
    );
    let g = geometry_term(light, x);
    if g == 0.0 {
        return (0.0, 0.0);
    }
    let emission = scene.emission_of(i).expect("shaped");
    let z = light.z;
    let mut envelope = 0.0;
    if let Some(_spot) = emission.spot() {
        let dt = emission.cone_scale() * (38.0 * b / z + 21.0) * U + 2.0 * U;
        envelope += 2.0 * dt + dt * dt;
    }
    if emission.range().is_some() {
        envelope += (76.0 * b / z + 34.0) * U;
    }
    let bound = e.abs() * (57.0 * b / z + 30.0) * U + w * g * emission.gain() * envelope;
    (e, bound)
}

#[test]
fn power_schemes_with_spots_and_ranges_match_the_cpu_sample_by_sample() {
    let Some(ctx) = common::context() else {
        return;
    };
    let scene = shaped_scene(300, 21);
    let b = largest_coordinate(&scene);
    let pmf = scene.powers.pmf();
    let n = scene.light_count() as f64;
    let total = scene.powers.total();
    let plane = &scene.plane;
    for scheme in [Scheme::Uniform, Scheme::Alias] {
        let seed = 77;
        let mut gpu = GpuRenderer::new(ctx, &scene, scheme, seed).expect("renderer");
        assert_eq!(
            gpu.gpu_bytes_per_light(),
            48,
            "24 B of light and table, 24 B of shape"
        );
        gpu.accumulate(SPP).expect("accumulate");
        let image = gpu.readback().expect("readback").image();
        let mut cpu = CpuRenderer::new(&scene, scheme, seed);
        cpu.accumulate(SPP);
        let cpu_image = cpu.accumulator().image();
        let sampler = Sampler::build(scheme, &scene.powers);
        let (mut worst, mut lit) = (0.0f64, 0);
        for py in 0..plane.height {
            for px in 0..plane.width {
                let p = py * plane.width + px;
                let x = pixel_center(plane, px, py);
                let (mut sum, mut bound) = (0.0, 0.0);
                for k in 0..u64::from(SPP) {
                    let mut rng = Rng::new(seed, (k << 32) | u64::from(p));
                    let i = sampler.pick_light(&mut rng) as usize;
                    let w = if scheme == Scheme::Uniform {
                        n * pmf[i]
                    } else {
                        1.0
                    };
                    let (e, db) = sample_bound(&scene, i, w, x, b);
                    sum += e;
                    bound += db;
                }
                bound += f64::from(SPP - 1) * U * sum;
                let (c, g) = (cpu_image[p as usize], image[p as usize]);
                // The test's own sum is the CPU renderer's (same contract, f64).
                assert!((total * sum / f64::from(SPP) - c).abs() <= 1e-12 * c.max(1e-300));
                let allowed = total * bound / f64::from(SPP);
                assert!(
                    (g - c).abs() <= allowed,
                    "{scheme}: pixel {p}: GPU {g:e} vs CPU {c:e}, bound {allowed:e}"
                );
                if c > 0.0 {
                    lit += 1;
                    worst = worst.max((g - c).abs() / c);
                }
            }
        }
        assert!(lit > 600, "{scheme}: the scene lights most pixels ({lit})");
        eprintln!("{scheme}: worst relative difference {worst:.2e} over {lit} lit pixels");
    }
}

#[test]
fn the_exact_spatial_pick_with_spots_matches_the_cpu_per_pixel() {
    let Some(ctx) = common::context() else {
        return;
    };
    let scene = shaped_scene(12, 5);
    let b = largest_coordinate(&scene);
    let pmf = scene.powers.pmf();
    let total = scene.powers.total();
    let mut gpu = GpuRenderer::new(ctx, &scene, Scheme::Spatial, 3).expect("renderer");
    gpu.accumulate(SPP).expect("accumulate");
    let image = gpu.readback().expect("readback").image();
    let plane = &scene.plane;
    for py in 0..plane.height {
        for px in 0..plane.width {
            let p = (py * plane.width + px) as usize;
            let x = pixel_center(plane, px, py);
            // Every sample estimates S = Σ_j p_j·G_j·S_j: the bound is the sum of the lights'.
            let (mut s, mut bound) = (0.0, 0.0);
            for (j, &pj) in pmf.iter().enumerate() {
                let (e, db) = sample_bound(&scene, j, pj, x, b);
                s += e;
                bound += db;
            }
            // The exact pick's sum of ≤ 16 terms and the running sum over 16 samples.
            let allowed = total * (bound + (16.0 + f64::from(SPP)) * U * s);
            let (g, c) = (image[p], total * s);
            assert!(
                (g - c).abs() <= allowed,
                "pixel {p}: GPU {g:e} vs exact {c:e} (bound {allowed:e})"
            );
        }
    }
}

#[test]
fn the_light_tree_over_spots_and_ranges_is_unbiased_on_the_gpu() {
    let Some(ctx) = common::context() else {
        return;
    };
    let scene = shaped_scene(2000, 8);
    let reference = Reference::compute(&scene);
    let exact_mean: f64 = reference.values().iter().sum::<f64>() / reference.values().len() as f64;
    for device in ["cpu", "gpu"] {
        let acc = if device == "gpu" {
            let mut gpu = GpuRenderer::new(ctx, &scene, Scheme::Spatial, 9).expect("renderer");
            gpu.accumulate(64).expect("accumulate");
            gpu.readback().expect("readback")
        } else {
            let mut cpu = CpuRenderer::new(&scene, Scheme::Spatial, 9);
            cpu.accumulate(64);
            cpu.accumulator().clone()
        };
        let pixels = acc.sum.len() as f64;
        let image = acc.image();
        let mean = image.iter().sum::<f64>() / pixels;
        // Pixels are independent estimates: the mean's variance is Σ Var_p / spp / P².
        let var: f64 = (0..acc.sum.len())
            .map(|p| acc.variance_per_sample(p))
            .sum::<f64>()
            / 64.0
            / (pixels * pixels);
        let z = (mean - exact_mean) / var.sqrt();
        eprintln!("{device}: mean {mean:.6e}, exact {exact_mean:.6e}, z = {z:.2}");
        assert!(
            z.abs() < 5.0,
            "{device}: mean {mean} vs exact {exact_mean} (z = {z})"
        );
    }
}

#[test]
fn point_scenes_keep_24_bytes_per_light() {
    let Some(ctx) = common::context() else {
        return;
    };
    let mut scene = shaped_scene(50, 3);
    scene.emission = None;
    let r = GpuRenderer::new(ctx, &scene, Scheme::Alias, 1).expect("renderer");
    assert_eq!(r.gpu_bytes_per_light(), 24);
    let _ = (DVec3::ZERO, LightPowers::new(vec![1.0]));
}

/// The leaf cluster (its lights in leaf order) of every light of `tree`, by scene index.
fn leaves_by_light(tree: &LightTree, n: usize) -> Vec<std::ops::Range<usize>> {
    let mut leaf = vec![0..0; n];
    let mut stack = vec![tree.root()];
    while let Some(at) = stack.pop() {
        match at.get() {
            Child::Node(k) => stack.extend((0..TREE_WIDTH).map(|l| tree.nodes()[k].child(l))),
            Child::Leaf { first, count } => {
                for &i in &tree.order()[first..first + count] {
                    leaf[i as usize] = first..first + count;
                }
            }
            Child::Empty => {}
        }
    }
    leaf
}

/// The internal nodes above every light of `tree` (the nodes whose decisions lead to it), by
/// scene index.
fn ancestors_by_light(tree: &LightTree, n: usize) -> Vec<Vec<usize>> {
    let mut above = vec![Vec::new(); n];
    let mut stack = vec![(tree.root(), Vec::new())];
    while let Some((at, path)) = stack.pop() {
        match at.get() {
            Child::Node(k) => {
                let mut path = path;
                path.push(k);
                for l in 0..TREE_WIDTH {
                    stack.push((tree.nodes()[k].child(l), path.clone()));
                }
            }
            Child::Leaf { first, count } => {
                for &i in &tree.order()[first..first + count] {
                    above[i as usize].clone_from(&path);
                }
            }
            Child::Empty => {}
        }
    }
    above
}

/// Whether `x` lies within `eta` of an edge the descent reads (a lane's footprint, a cell of
/// a lane's map) in one of `nodes`: there the GPU's `f32` view of the plane may put `x` on
/// the other side, for every sample of the pixel.
fn near_an_edge(tree: &LightTree, nodes: &[usize], x: glam::DVec2, eta: f64) -> bool {
    let side = lightpick_core::spatial::grid::GRID_SIDE as f64;
    nodes.iter().any(|&k| {
        let Some(mapped) = tree.mapped(k) else {
            return false;
        };
        (0..TREE_WIDTH).any(|lane| {
            let [lo, hi] = mapped.footprint_of(lane);
            let near_box = (0..2).any(|a| (x[a] - lo[a]).abs() < eta || (x[a] - hi[a]).abs() < eta);
            let per = [mapped.map[2][lane], mapped.map[3][lane]];
            let near_cell = (0..2).any(|a| {
                let c = (x[a] - mapped.map[a][lane]) * per[a];
                (-1.0..=side + 1.0).contains(&c) && (c - c.round()).abs() < eta * per[a]
            });
            near_box || near_cell
        })
    })
}

/// The light tree over spots and ranges on the GPU against the CPU, pixel by pixel.
///
/// Where the GPU takes the CPU's decisions, a sample `ê = c_j / P` differs by what its
/// factors carry in `f32`: `c_j` by [`sample_bound`]; each of the `d` branch factors by
/// `2E + 3u` (a lane's importance is its map's value, a scale times a decoded code, rounded
/// `2u`, plus for unbounded lanes a geometry term, `E = (57 B/z + 26)·u`, see
/// `gpu_spatial.rs`); the leaf's factor `m_j/2^24`, `m_j = ⌊c_j/Σc·2^24⌋`, by the relative
/// errors of `c_j` and of `Σc` plus `1/m_j` for the floor. A decision flips with probability
/// at most `2E + 4u` a level and `2·ΣΔc/Σc` in the leaf (its masses' uncertainty), and a whole
/// pixel may take other branches where its centre lies within `η = 16·u·B` of a footprint's
/// or a map cell's edge (the `f32` pixel centre, corners and cell sizes). The pixels beyond
/// the summed bound are allowed to be twice the expected flips plus the pixels near an edge,
/// plus 3; the image means agree within 5 standard errors.
#[test]
fn the_light_tree_over_spots_and_ranges_matches_the_cpu_per_pixel() {
    let Some(ctx) = common::context() else {
        return;
    };
    // Fewer samples on `stage`: its narrow spots' penumbras make each sample's leaf
    // decision uncertain (see above), so the allowance grows with the samples.
    for (scene, seed, spp) in [
        (shaped_scene(600, 31), 5, SPP),
        (Scene::preset("stage").expect("preset"), 6, 4),
    ] {
        let what = scene.name.clone();
        let b = largest_coordinate(&scene);
        let pmf = scene.powers.pmf();
        let total = scene.powers.total();
        let sampler = SpatialSampler::for_scene(&scene);
        let SpatialSampler::Tree(tree) = &sampler else {
            panic!("{what}: a tree");
        };
        let leaf = leaves_by_light(tree, scene.light_count());
        let above = ancestors_by_light(tree, scene.light_count());
        let depth = f64::from(tree.draws());
        let z_min = scene
            .positions
            .iter()
            .filter(|p| p.z > 0.0)
            .fold(f64::INFINITY, |m, p| m.min(p.z));
        let e = (57.0 * b / z_min + 26.0) * U;
        let eta = 16.0 * U * b;
        let mut gpu = GpuRenderer::new(ctx, &scene, Scheme::Spatial, seed).expect("renderer");
        gpu.accumulate(spp).expect("accumulate");
        let image = gpu.readback().expect("readback").image();
        let mut cpu = CpuRenderer::new(&scene, Scheme::Spatial, seed);
        cpu.accumulate(spp);
        let acc = cpu.accumulator();
        let cpu_image = acc.image();
        let plane = &scene.plane;
        let (mut beyond, mut expected, mut fragile) = (0usize, 0.0f64, 0usize);
        let (mut mean_g, mut mean_c, mut var) = (0.0, 0.0, 0.0);
        let pixels = plane.pixel_count() as f64;
        for py in 0..plane.height {
            for px in 0..plane.width {
                let p = py * plane.width + px;
                let x = pixel_center(plane, px, py);
                let (mut sum, mut bound, mut flips, mut near) = (0.0, 0.0, 0.0, false);
                for k in 0..u64::from(spp) {
                    let mut rng = Rng::new(seed, (k << 32) | u64::from(p));
                    let Some(pick) = sampler.sample(x, &mut rng) else {
                        flips += depth * (2.0 * e + 4.0 * U);
                        continue;
                    };
                    let j = pick.light as usize;
                    near |= near_an_edge(tree, &above[j], x, eta);
                    let (c, dc) = sample_bound(&scene, j, pmf[j], x, b);
                    let (mut leaf_c, mut leaf_dc) = (0.0, 0.0);
                    for &i in &tree.order()[leaf[j].clone()] {
                        let (ci, di) = sample_bound(&scene, i as usize, pmf[i as usize], x, b);
                        leaf_c += ci;
                        leaf_dc += di;
                    }
                    let m_j = (c / leaf_c * f64::from(1u32 << 24)).floor().max(1.0);
                    let rel = 2.0 * dc / c
                        + leaf_dc / leaf_c
                        + depth * (2.0 * e + 3.0 * U)
                        + 1.0 / m_j
                        + 3.0 * U;
                    sum += pick.estimate;
                    bound += pick.estimate * rel;
                    flips += depth * (2.0 * e + 4.0 * U) + 2.0 * leaf_dc / leaf_c;
                }
                let spp_f = f64::from(spp);
                bound += (spp_f - 1.0) * U * sum;
                let (c, g) = (cpu_image[p as usize], image[p as usize]);
                assert!(g.is_finite() && g >= 0.0, "{what}: GPU pixel {p} = {g}");
                assert!((total * sum / spp_f - c).abs() <= 1e-9 * c.max(1e-300));
                fragile += usize::from(near);
                expected += flips.min(1.0);
                if (g - c).abs() > total * bound / spp_f {
                    beyond += 1;
                }
                mean_g += g / pixels;
                mean_c += c / pixels;
                var += acc.variance_per_sample(p as usize) / spp_f / (pixels * pixels);
            }
        }
        let allowed = 2.0 * expected + fragile as f64 + 3.0;
        eprintln!(
            "{what}: {beyond} of {pixels} pixels beyond their bound (allowed {allowed:.1}: \
             {expected:.1} expected flips, {fragile} near an edge); means GPU {mean_g:.6e} \
             CPU {mean_c:.6e}"
        );
        assert!(beyond as f64 <= allowed, "{what}: {beyond} pixels differ");
        assert!(
            (mean_g - mean_c).abs() <= 5.0 * var.sqrt(),
            "{what}: means {mean_g} vs {mean_c}"
        );
    }
}
