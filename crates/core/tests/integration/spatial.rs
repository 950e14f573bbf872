//! Contribution-aware (spatial) sampling: the light tree's pdf, unbiasedness, the exact
//! scheme's zero variance, the gain over power sampling, and extremes.

use glam::{DVec2, DVec3, dvec2, dvec3};
use lightpick_core::render::{CpuRenderer, Reference, mean_variance_per_sample};
use lightpick_core::scene::{ReceiverPlane, Scene, geometry_term, pixel_center};
use lightpick_core::spatial::{EXACT_MAX_LIGHTS, ExactSampler, LightTree, SpatialSampler};
use lightpick_core::{LightPowers, Rng, Scheme};

use crate::common::SplitMix;
use crate::common::fit::assert_picks_fit;
use crate::common::scenes::{preset_at, random_powers, scattered_positions, square_plane};

/// `n` lights in `[-2, 2]² × [0.1, 1]` (every 7th below the plane, every 5th at power 0),
/// powers over `decades` decades.
fn random_lights(n: usize, seed: u64, decades: f64) -> (Vec<DVec3>, LightPowers) {
    let mut d = SplitMix(seed);
    let positions = scattered_positions(&mut d, n, 1.0, 0.1..1.0, (7, 6));
    let powers = random_powers(&mut d, n, decades, 4);
    (positions, LightPowers::new(powers).expect("valid"))
}

const POINTS: [DVec2; 6] = [
    dvec2(0.0, 0.0),
    dvec2(1.9, -1.9),
    dvec2(-0.37, 1.21),
    dvec2(5.0, 5.0),
    dvec2(-40.0, 3.0),
    dvec2(0.5, 0.5),
];

/// The pdf summed over every light (each the product of the branch probabilities on its
/// root-to-leaf path) is 1, for trees of several sizes and at several points.
#[test]
fn tree_pdf_sums_to_one_over_every_leaf() {
    for (n, seed) in [(17, 1), (64, 2), (333, 3), (1000, 4)] {
        let (positions, powers) = random_lights(n, seed, 3.0);
        let tree = LightTree::build(&positions, &powers);
        let depth = f64::from(tree.draws());
        for x in POINTS {
            let total: f64 = (0..n).map(|i| tree.pdf(x, i)).sum();
            // Each level's two probabilities sum to 1 within 2 ulp; d levels: ≤ 4·d·ε.
            assert!(
                (total - 1.0).abs() <= 4.0 * depth * f64::EPSILON * 4.0,
                "n = {n}, x = {x:?}: Σ pdf = {total}"
            );
        }
    }
}

/// `P(i | x) > 0` wherever `p_i·G_i(x) > 0`, and 0 for zero-power or below-plane lights.
#[test]
fn tree_pdf_is_positive_exactly_where_the_light_contributes() {
    let (positions, powers) = random_lights(500, 7, 12.0);
    let tree = LightTree::build(&positions, &powers);
    let pmf = powers.pmf();
    for x in POINTS {
        for i in 0..positions.len() {
            let c = pmf[i] * geometry_term(positions[i], x);
            let pdf = tree.pdf(x, i);
            if c > 0.0 {
                assert!(pdf > 0.0, "light {i} contributes {c} at {x:?} but pdf 0");
            } else {
                assert_eq!(pdf, 0.0, "light {i} cannot contribute but pdf {pdf}");
            }
        }
    }
}

/// The picks realize the pdf: at one point, the counts of 200 000 picks over a 40-light tree
/// pass a chi-square test against `P(i | x)` (threshold: dof + 5·√(2·dof), a > 5σ event).
#[test]
fn tree_picks_follow_their_pdf_and_report_it() {
    let (positions, powers) = random_lights(40, 11, 1.0);
    let tree = LightTree::build(&positions, &powers);
    let x = dvec2(0.3, -0.4);
    let draws = 200_000u64;
    let mut counts = vec![0u64; positions.len()];
    for s in 0..draws {
        let pick = tree
            .sample(x, &mut Rng::new(5, s))
            .expect("lights contribute");
        let expected = tree.pdf(x, pick.light as usize);
        assert!((pick.pdf - expected).abs() <= 1e-12 * expected);
        counts[pick.light as usize] += 1;
    }
    assert_picks_fit(&counts, draws, |i| tree.pdf(x, i));
}

/// The tree estimate is unbiased: at several points, the mean of 100 000 estimates is within
/// 5 standard errors of the exact `Σ p_i·G_i(x)`.
#[test]
fn tree_estimator_is_unbiased() {
    let (positions, powers) = random_lights(300, 13, 2.0);
    let sampler = SpatialSampler::Tree(LightTree::build(&positions, &powers));
    let pmf = powers.pmf();
    for (k, x) in POINTS.iter().enumerate() {
        let exact: f64 = (0..positions.len())
            .map(|i| pmf[i] * geometry_term(positions[i], *x))
            .sum();
        let m = 100_000u64;
        let (mut s, mut q) = (0.0, 0.0);
        for j in 0..m {
            let e = sampler.estimate(*x, &mut Rng::new(k as u64, j));
            s += e;
            q += e * e;
        }
        let mean = s / m as f64;
        let var = (q / m as f64 - mean * mean).max(0.0);
        let se = (var / m as f64).sqrt();
        assert!(
            (mean - exact).abs() <= 5.0 * se + 1e-12 * exact,
            "x = {x:?}: mean {mean} vs exact {exact} (se {se})"
        );
    }
}

/// The exact scheme (N ≤ 16) has zero variance: every estimate is `Σ p_j·G_j(x)`, so the
/// rendered image equals the reference within rounding and the per-sample variance is 0 up
/// to the cancellation of `Σê² − (Σê)²/n` (≤ 1e-12 of the squared mean).
#[test]
fn exact_scheme_has_zero_variance_per_pixel() {
    let scene = Scene::preset("worked-example").expect("preset");
    assert!(scene.light_count() <= EXACT_MAX_LIGHTS);
    let small = preset_at("worked-example", 64, 64);
    let mut r = CpuRenderer::new(&small, Scheme::Spatial, 3);
    assert!(matches!(r.spatial(), Some(SpatialSampler::Exact(_))));
    r.accumulate(16);
    let reference = Reference::compute(&small);
    let acc = r.accumulator();
    let image = reference.image().expect("complete");
    for (p, &exact) in image.iter().enumerate() {
        assert!((acc.mean(p) - exact).abs() <= 1e-13 * exact, "pixel {p}");
        assert!(
            acc.variance_per_sample(p) <= 1e-12 * exact * exact,
            "pixel {p}"
        );
    }
}

/// Exact-sampler picks follow `c_i / S`, and the pdf sums to 1.
#[test]
fn exact_picks_follow_the_contributions() {
    let (positions, powers) = random_lights(12, 17, 1.0);
    let exact = ExactSampler::build(&positions, &powers);
    let x = dvec2(0.2, 0.1);
    let total: f64 = (0..12).map(|i| exact.pdf(x, i)).sum();
    assert!((total - 1.0).abs() < 1e-14);
    let draws = 100_000u64;
    let mut counts = [0u64; 12];
    for s in 0..draws {
        counts[exact.sample(x, &mut Rng::new(9, s)).expect("some").light as usize] += 1;
    }
    assert_picks_fit(&counts, draws, |i| exact.pdf(x, i));
}

/// A 32 × 32 grid of equal lights at height 0.25 spread over a 16 × 16 plane: power
/// sampling picks a far light almost always, the tree a near one. The tree's mean variance
/// per sample is at least 20× lower (measured: printed).
#[test]
fn spatial_beats_power_sampling_on_spread_out_equal_lights() {
    let positions: Vec<DVec3> = (0..32 * 32)
        .map(|k| {
            let (i, j) = (f64::from(k % 32), f64::from(k / 32));
            dvec3(-7.75 + 0.5 * i, -7.75 + 0.5 * j, 0.25)
        })
        .collect();
    let powers = LightPowers::new(vec![1.0; positions.len()]).expect("valid");
    let scene = Scene::new("grid", square_plane(8.0, 48), positions, powers);
    let variance = |scheme| {
        let mut r = CpuRenderer::new(&scene, scheme, 21);
        r.accumulate(64);
        mean_variance_per_sample(r.accumulator())
    };
    let power = variance(Scheme::Alias);
    let spatial = variance(Scheme::Spatial);
    let ratio = power / spatial;
    eprintln!(
        "grid 32×32: variance per sample power {power:.4e}, spatial {spatial:.4e}, ratio {ratio:.1}"
    );
    assert!(ratio >= 20.0, "ratio {ratio}");
}

/// The `grid` preset (1024 unit lights at `z ∈ [0.2, 0.4]` over `[-8, 8]²`) is where the
/// spatial scheme wins: its mean variance per sample is far below power sampling's (which,
/// with equal powers, is uniform sampling). `lightpick bench` measures about 108× at
/// 256² px and 64 spp; here at 48² px and 64 spp (the ratio of two per-pixel variance
/// means, each over 2304 pixels × 64 samples) the bound is 30×.
#[test]
fn spatial_beats_power_sampling_on_the_grid_preset() {
    let scene = preset_at("grid", 48, 48);
    let variance = |scheme| {
        let mut r = CpuRenderer::new(&scene, scheme, 3);
        r.accumulate(64);
        mean_variance_per_sample(r.accumulator())
    };
    let power = variance(Scheme::Alias);
    let spatial = variance(Scheme::Spatial);
    let ratio = power / spatial;
    eprintln!(
        "grid preset 48²: variance per sample power {power:.4e}, spatial {spatial:.4e}, \
         ratio {ratio:.1}"
    );
    assert!(ratio >= 30.0, "ratio {ratio}");
}

/// The rendered spatial image is unbiased against the reference: the summed error over all
/// pixels, `Σ_p (Ê_p − E_p)`, is within 5 of its standard errors `√(Σ_p s_p²/n)` (pixels are
/// independent; standardizing each pixel separately would be biased for skewed estimates).
#[test]
fn spatial_render_matches_the_reference_statistically() {
    let (positions, powers) = random_lights(2000, 23, 2.0);
    let scene = Scene::new("random", square_plane(2.0, 32), positions, powers);
    let mut r = CpuRenderer::new(&scene, Scheme::Spatial, 4);
    assert!(matches!(r.spatial(), Some(SpatialSampler::Tree(_))));
    let spp = 64;
    r.accumulate(spp);
    let reference = Reference::compute(&scene);
    let acc = r.accumulator();
    let (mut error, mut variance) = (0.0, 0.0);
    for (p, exact) in reference.iter() {
        error += acc.mean(p) - exact;
        variance += acc.variance_per_sample(p) / f64::from(spp);
    }
    let se = variance.sqrt();
    assert!(
        error.abs() <= 5.0 * se,
        "summed error {error}, standard error {se}"
    );
}

fn assert_finite_image(scene: &Scene, spp: u32) -> Vec<f64> {
    let mut r = CpuRenderer::new(scene, Scheme::Spatial, 8);
    r.accumulate(spp);
    let image = r.accumulator().image();
    for (p, v) in image.iter().enumerate() {
        assert!(
            v.is_finite() && *v >= 0.0,
            "{}: pixel {p} = {v}",
            scene.name
        );
    }
    image
}

/// One light, every light below the plane, half the powers zero, `extreme-range` (powers
/// 1e-30 … 1e30) and `million`: finite, non-negative images; exact where they must be.
#[test]
fn extremes_give_finite_images() {
    let one = Scene::new(
        "one",
        square_plane(2.0, 16),
        vec![dvec3(0.3, 0.2, 0.5)],
        LightPowers::new(vec![7.0]).expect("valid"),
    );
    let image = assert_finite_image(&one, 4);
    let reference = Reference::compute(&one);
    for (p, exact) in reference.iter() {
        assert!((image[p] - exact).abs() <= 1e-13 * exact);
    }

    let below = Scene::new(
        "below",
        square_plane(2.0, 16),
        (0..40)
            .map(|i| dvec3(f64::from(i) * 0.1, 0.0, -0.5))
            .collect::<Vec<_>>(),
        LightPowers::new(vec![1.0; 40]).expect("valid"),
    );
    assert!(assert_finite_image(&below, 4).iter().all(|&v| v == 0.0));

    for name in ["zeros", "extreme-range", "heavy-tail", "million"] {
        let scene = preset_at(name, 24, 24);
        let image = assert_finite_image(&scene, 4);
        assert!(image.iter().any(|&v| v > 0.0), "{name}");
    }
}

/// Zero-power lights are never picked (they are not even in the tree).
#[test]
fn zero_power_lights_are_never_picked() {
    let (positions, powers) = random_lights(200, 29, 1.0);
    let sampler = SpatialSampler::build(&positions, &powers);
    for s in 0..20_000u64 {
        let x = dvec2((s % 7) as f64 * 0.5 - 1.5, (s % 5) as f64 * 0.5 - 1.0);
        if let Some(pick) = sampler.sample(x, &mut Rng::new(1, s)) {
            let i = pick.light as usize;
            assert!(
                powers.as_slice()[i] > 0.0 && positions[i].z > 0.0,
                "light {i}"
            );
        }
    }
}

/// Pixel centres used by the renderer are the points the sampler is asked about.
#[test]
fn renderer_uses_the_sampler_at_pixel_centres() {
    let (positions, powers) = random_lights(100, 31, 1.0);
    let scene = Scene::new(
        "check",
        square_plane(2.0, 8),
        positions.clone(),
        powers.clone(),
    );
    let mut r = CpuRenderer::new(&scene, Scheme::Spatial, 77);
    r.accumulate(3);
    // The scene's sampler: its tree cut per tile of these pixels.
    let sampler = SpatialSampler::for_scene(&scene);
    assert!(matches!(&sampler, SpatialSampler::Tree(t) if t.tile_cuts().is_some()));
    for py in 0..8 {
        for px in 0..8 {
            let p = u64::from(py * 8 + px);
            let x = pixel_center(&scene.plane, px, py);
            // In the renderer's accumulation unit, 2^-s (exact).
            let to_unit = lightpick_core::Scaled::pow2(-scene.irradiance_shift()).to_f64();
            let sum: f64 = (0..3u64)
                .map(|k| sampler.estimate(x, &mut Rng::new(77, (k << 32) | p)) * to_unit)
                .sum();
            assert_eq!(r.accumulator().sum[p as usize], sum);
        }
    }
}

/// `pdfs(x)` (one traversal) equals `pdf(x, i)` (one path per light) for every light, for
/// the exact sampler and trees of several sizes, and sums to 1.
#[test]
fn all_pdfs_at_once_equal_the_pdf_of_each_light() {
    for (n, seed) in [(12, 41), (17, 42), (300, 43)] {
        let (positions, powers) = random_lights(n, seed, 4.0);
        let sampler = SpatialSampler::build(&positions, &powers);
        for x in POINTS {
            let all = sampler.pdfs(x);
            assert_eq!(all.len(), n);
            for (i, &q) in all.iter().enumerate() {
                assert_eq!(q, sampler.pdf(x, i), "n = {n}, light {i} at {x:?}");
            }
            let total: f64 = all.iter().sum();
            assert!((total - 1.0).abs() < 1e-12, "n = {n}: Σ = {total}");
        }
    }
}

/// `tree.sample_many` and `tree.sample_many_cold` over `sets` sets of 8 points
/// (`point(set, b)`) each equal 8 single `sample`s, draw for draw.
fn assert_interleaved_equal_single(
    tree: &LightTree,
    sets: u64,
    point: impl Fn(u64, usize) -> DVec2,
) {
    for s in 0..sets {
        let points: [DVec2; 8] = std::array::from_fn(|b| point(s, b));
        for cold in [false, true] {
            let mut rngs: [Rng; 8] = std::array::from_fn(|b| Rng::new(s, b as u64));
            let many = if cold {
                tree.sample_many_cold(&points, &mut rngs)
            } else {
                tree.sample_many(&points, &mut rngs)
            };
            for b in 0..8 {
                let mut rng = Rng::new(s, b as u64);
                assert_eq!(
                    many[b],
                    tree.sample(points[b], &mut rng),
                    "s = {s}, b = {b}, cold: {cold}"
                );
                assert_eq!(rngs[b], rng, "the same draws");
            }
        }
    }
}

/// A tree large enough for its interleaved descents to prefetch each pick's next node and
/// leaf (`2^15` lights and more) still picks as single descents do, draw for draw, from
/// the root and from its tiles' cuts.
#[test]
fn prefetching_descents_equal_single_ones_bit_for_bit() {
    let (positions, powers) = random_lights(40_000, 41, 3.0);
    let SpatialSampler::Tree(tree) = SpatialSampler::build(&positions, &powers) else {
        panic!("40 000 lights take the tree");
    };
    assert_interleaved_equal_single(&tree, 100, |s, b| POINTS[(s as usize + b) % POINTS.len()]);
    let plane = ReceiverPlane {
        min: dvec2(-2.0, -1.0),
        max: dvec2(2.0, 1.0),
        width: 64,
        height: 32,
    };
    let cut = tree.with_tile_cuts(&plane);
    assert!(cut.tile_cuts().is_some());
    assert_interleaved_equal_single(&cut, 100, |s, b| {
        pixel_center(&plane, (s as u32 * 7 + b as u32) % 64, (s as u32) % 32)
    });
}

/// `sample_many` (the descents interleaved) is `sample` for each point, draw for draw, and
/// the renderer's batches of pixels (an 11-pixel row: one batch of 8 and 3 single pixels)
/// add exactly the sequential estimates.
#[test]
fn interleaved_descents_equal_single_ones_bit_for_bit() {
    let (positions, powers) = random_lights(3000, 37, 3.0);
    let SpatialSampler::Tree(tree) = SpatialSampler::build(&positions, &powers) else {
        panic!("3000 lights take the tree");
    };
    assert_interleaved_equal_single(&tree, 200, |s, b| POINTS[(s as usize + b) % POINTS.len()]);
    let scene = Scene::new(
        "row",
        ReceiverPlane {
            min: dvec2(-2.0, -1.0),
            max: dvec2(2.0, 1.0),
            width: 11,
            height: 5,
        },
        positions.clone(),
        powers.clone(),
    );
    let mut r = CpuRenderer::new(&scene, Scheme::Spatial, 19);
    r.accumulate(2);
    r.accumulate(3);
    // The renderer's sampler is the scene's, cut per tile; its interleaved picks equal its
    // single ones too.
    let sampler = SpatialSampler::for_scene(&scene);
    let SpatialSampler::Tree(cut) = &sampler else {
        panic!("3000 lights take the tree");
    };
    assert_eq!(cut.clone().with_cuts(None), tree, "the same tree, cut");
    assert_interleaved_equal_single(cut, 50, |s, b| {
        pixel_center(&scene.plane, (s as u32 + b as u32) % 11, (s as u32 / 3) % 5)
    });
    // Its cold picks ask for their cuts' lines ahead where a cut holds more than 32 entries
    // (64 alias columns and more): some do here. Points off the plane, which start at the root,
    // mixed into the same batches.
    let cuts = cut.tile_cuts().expect("cuts");
    let [tiles_x, tiles_y] = cuts.tiles();
    assert!(
        (0..(tiles_x * tiles_y) as usize).any(|tile| cuts.entries(cut, tile).count() > 32),
        "a cut of more than 32 entries"
    );
    assert_interleaved_equal_single(cut, 50, |s, b| {
        if (s as usize + b).is_multiple_of(3) {
            POINTS[(s as usize + b) % POINTS.len()] + dvec2(5.0, 0.0)
        } else {
            pixel_center(
                &scene.plane,
                (s as u32 * 5 + b as u32) % 11,
                (s as u32 + b as u32) % 5,
            )
        }
    });
    let to_unit = lightpick_core::Scaled::pow2(-scene.irradiance_shift()).to_f64();
    for py in 0..5 {
        for px in 0..11 {
            let p = u64::from(py * 11 + px);
            let x = pixel_center(&scene.plane, px, py);
            let (mut sum, mut sq) = (0.0, 0.0);
            for k in 0..5u64 {
                let e = sampler.estimate(x, &mut Rng::new(19, (k << 32) | p)) * to_unit;
                sum += e;
                sq += e * e;
            }
            assert_eq!(r.accumulator().sum[p as usize], sum, "pixel ({px}, {py})");
            assert_eq!(r.accumulator().sum_sq[p as usize], sq, "pixel ({px}, {py})");
        }
    }
}
