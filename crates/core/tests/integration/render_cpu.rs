//! The CPU renderer: the estimator contract, determinism, unbiasedness and variance, each
//! checked against exact per-pixel moments of the one-sample estimator.
//!
//! # Statistical bounds
//! Pixels use distinct random streams, so their estimates are independent. For a mean over
//! `P` pixels of independent terms, the CLT makes the mean normal to a very good
//! approximation (`P ≥ 4096` here); every test compares it with its exact expectation and
//! fails beyond `K = 5` standard deviations (two-sided normal tail `5.7·10^-7`). The seeds
//! are fixed, so a pass is reproducible; the bound is what makes the test meaningful.

#![allow(clippy::unwrap_used)] // Tests unwrap: a failure is the test failing.

use crate::common::scenes::preset_at;
use glam::{DVec3, dvec2};
use lightpick_core::render::{
    Accumulator, CpuRenderer, Reference, convergence_series, mean_variance_per_sample,
};
use lightpick_core::scene::{ReceiverPlane, Scene, geometry_term, pixel_center};
use lightpick_core::{PointFreeSampler as _, Rng, Sampler, Scheme, analytic_moments};

/// Standard deviations allowed between a statistic and its exact expectation.
const K: f64 = 5.0;

/// Exact moments of one pixel's sample, in irradiance units.
#[derive(Clone, Copy, Debug)]
struct PixelMoments {
    mean: f64,
    variance: f64,
    /// Fourth central moment `μ4 = Σ_i q_i (e_i − μ)^4`.
    mu4: f64,
}

/// For every pixel, the exact moments of `Φ_total · ê` with `ê = w_i·G_i` drawn with the
/// scheme's pmf `q` (uniform: `q_i = 1/N`, `w_i = N·p_i`; power: `q_i = p_i`, `w_i = 1`).
/// The variance comes from `lightpick_core::analytic_moments` with `f_i = p_i·G_i`.
fn exact_moments(scene: &Scene, scheme: Scheme) -> Vec<PixelMoments> {
    let pmf = scene.powers.pmf();
    let n = pmf.len() as f64;
    let q = |i: usize| {
        if scheme == Scheme::Uniform {
            1.0 / n
        } else {
            pmf[i]
        }
    };
    let scale = scene.powers.total();
    let plane = &scene.plane;
    let mut out = Vec::with_capacity(plane.pixel_count());
    for py in 0..plane.height {
        for px in 0..plane.width {
            let x = pixel_center(plane, px, py);
            let f: Vec<f64> = scene
                .positions
                .iter()
                .zip(&pmf)
                .map(|(&pos, &p)| p * geometry_term(pos, x))
                .collect();
            let m = analytic_moments(&f, q);
            let mu4: f64 = (0..f.len())
                .filter(|&i| q(i) > 0.0)
                .map(|i| q(i) * (f[i] / q(i) - m.mean).powi(4))
                .sum();
            out.push(PixelMoments {
                mean: scale * m.mean,
                variance: scale * scale * m.variance,
                mu4: scale.powi(4) * mu4,
            });
        }
    }
    out
}

fn render(scene: &Scene, scheme: Scheme, seed: u64, spp: u32) -> Accumulator {
    let mut r = CpuRenderer::new(scene, scheme, seed);
    r.accumulate(spp);
    r.accumulator().clone()
}

// ---------------------------------------------------------------- the contract

#[test]
fn pixel_sums_follow_the_stream_contract() {
    let scene = preset_at("zeros", 16, 16);
    for scheme in Scheme::ALL {
        let seed = 77;
        let mut r = CpuRenderer::new(&scene, scheme, seed);
        r.accumulate(3);
        r.accumulate(2);
        let acc = r.accumulator();
        let sampler = Sampler::build(scheme, &scene.powers);
        let pmf = scene.powers.pmf();
        let n = pmf.len() as f64;
        for (px, py) in [(0u32, 0u32), (5, 9), (15, 15)] {
            let p = (py * scene.plane.width + px) as usize;
            let x = pixel_center(&scene.plane, px, py);
            let (mut sum, mut sq) = (0.0, 0.0);
            for k in 0..5u64 {
                let mut rng = Rng::new(seed, (k << 32) | p as u64);
                let i = sampler.pick_light(&mut rng) as usize;
                let g = geometry_term(scene.positions[i], x);
                let e = if scheme == Scheme::Uniform {
                    n * pmf[i] * g
                } else {
                    g
                };
                // In the accumulation unit: ê·2^-s, an exact scaling.
                let e = e * lightpick_core::Scaled::pow2(-scene.irradiance_shift()).to_f64();
                sum += e;
                sq += e * e;
            }
            assert_eq!(acc.sum[p], sum, "{scheme} pixel {p}");
            assert_eq!(acc.sum_sq[p], sq, "{scheme} pixel {p}");
        }
        assert_eq!(acc.samples_per_pixel, 5);
        assert_eq!(acc.total_power, scene.powers.total_scaled());
        assert_eq!(acc.total_power.to_f64(), scene.powers.total());
        assert_eq!(acc.shift, scene.irradiance_shift());
        assert_eq!(r.scheme(), scheme);
        assert_eq!(sampler.light_count(), scene.light_count());
    }
}

/// The spatial scheme renders bands of rows block by block, eight pixels drawn together:
/// every pixel's sums are still exactly those of `spatial.estimate` on its own stream,
/// sample after sample, on a plane whose sides are not multiples of the block (partial
/// blocks at the right edge, a partial band at the bottom) and over two passes.
#[test]
fn spatial_pixel_sums_follow_the_stream_contract_in_every_block() {
    let scene = preset_at("heavy-tail", 21, 13);
    let seed = 5;
    let mut r = CpuRenderer::new(&scene, Scheme::Spatial, seed);
    r.accumulate(3);
    r.accumulate(2);
    let spatial = r.spatial().expect("a spatial renderer");
    assert!(matches!(
        spatial,
        lightpick_core::spatial::SpatialSampler::Tree(_)
    ));
    let to_unit = lightpick_core::Scaled::pow2(-scene.irradiance_shift()).to_f64();
    let acc = r.accumulator();
    for py in 0..13u32 {
        for px in 0..21u32 {
            let p = (py * 21 + px) as usize;
            let x = pixel_center(&scene.plane, px, py);
            let (mut sum, mut sq) = (0.0, 0.0);
            for k in 0..5u64 {
                let e = spatial.estimate(x, &mut Rng::new(seed, (k << 32) | p as u64)) * to_unit;
                sum += e;
                sq += e * e;
            }
            assert_eq!(acc.sum[p], sum, "pixel ({px}, {py})");
            assert_eq!(acc.sum_sq[p], sq, "pixel ({px}, {py})");
        }
    }
}

/// The renderer batches its picks (all column picks and keep draws first, the table lookups
/// after); with `N = 2 147 484` lights (`t = 2^32 mod N = 2 146 780 ≈ N`) about 5·10⁻⁴ of
/// the picks reject their first draw and redraw from the same stream. Every pixel's sums
/// must still be exactly those of `Sampler::pick_light`, sample after sample.
#[test]
fn batched_picks_equal_pick_light_through_rejected_draws() {
    let n = 2_147_484u32;
    let t = lightpick_core::rejection_threshold(n);
    let hash = |i: u32, salt: u32| f64::from(lightpick_core::pcg_hash(i ^ salt)) / 4_294_967_296.0;
    let scene = Scene::new(
        "rejections",
        ReceiverPlane {
            min: dvec2(-1.0, -1.0),
            max: dvec2(1.0, 1.0),
            width: 48,
            height: 40,
        },
        (0..n)
            .map(|i| {
                [
                    4.0 * hash(i, 1) - 2.0,
                    4.0 * hash(i, 2) - 2.0,
                    0.5 + hash(i, 3),
                ]
            })
            .map(DVec3::from)
            .collect::<Vec<_>>(),
        lightpick_core::LightPowers::new(
            (0..n)
                .map(|i| if i % 7 == 3 { 0.0 } else { 1e-3 + hash(i, 4) })
                .collect(),
        )
        .unwrap(),
    );
    let (seed, spp) = (19u64, 24u32);
    let pixels = u64::from(scene.plane.width * scene.plane.height);
    let rejected = (0..u64::from(spp))
        .flat_map(|k| (0..pixels).map(move |p| (k << 32) | p))
        .filter(|&stream| {
            let r = Rng::new(seed, stream).next_u32();
            ((u64::from(r) * u64::from(n)) as u32) < t
        })
        .count();
    eprintln!(
        "{rejected} of {} picks reject their first draw",
        u64::from(spp) * pixels
    );
    assert!(rejected > 10, "{rejected}");
    let pmf = scene.powers.pmf();
    // The renderer's accumulation unit 2^-s (an exact scaling).
    let to_unit = lightpick_core::Scaled::pow2(-scene.irradiance_shift()).to_f64();
    for scheme in [Scheme::Alias, Scheme::Uniform] {
        let sampler = Sampler::build(scheme, &scene.powers);
        let mut r = CpuRenderer::with_sampler(&scene, sampler.clone(), seed);
        r.accumulate(spp);
        let acc = r.accumulator();
        for py in 0..scene.plane.height {
            for px in 0..scene.plane.width {
                let p = u64::from(py * scene.plane.width + px);
                let x = pixel_center(&scene.plane, px, py);
                let (mut sum, mut sq) = (0.0, 0.0);
                for k in 0..u64::from(spp) {
                    let i = sampler.pick_light(&mut Rng::new(seed, (k << 32) | p)) as usize;
                    let g = geometry_term(scene.positions[i], x);
                    let e = if scheme == Scheme::Uniform {
                        f64::from(n) * pmf[i] * g
                    } else {
                        g
                    } * to_unit;
                    sum += e;
                    sq += e * e;
                }
                assert_eq!(acc.sum[p as usize], sum, "{scheme} pixel {p}");
                assert_eq!(acc.sum_sq[p as usize], sq, "{scheme} pixel {p}");
            }
        }
    }
}

#[test]
fn reset_restarts_the_sample_index() {
    let scene = preset_at("worked-example", 8, 8);
    let mut r = CpuRenderer::new(&scene, Scheme::Alias, 5);
    r.accumulate(4);
    let first = r.accumulator().clone();
    r.accumulate(4);
    r.reset();
    assert_eq!(r.samples_per_pixel(), 0);
    assert!(r.accumulator().sum.iter().all(|&s| s == 0.0));
    r.accumulate(4);
    assert_eq!(*r.accumulator(), first);
}

// ---------------------------------------------------------------- determinism

#[test]
fn same_seed_same_image_and_passes_do_not_matter() {
    let scene = preset_at("heavy-tail", 24, 24);
    for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::Cdf] {
        let once = render(&scene, scheme, 11, 8);
        assert_eq!(once, render(&scene, scheme, 11, 8));
        let mut split = CpuRenderer::new(&scene, scheme, 11);
        for spp in [1, 2, 5] {
            split.accumulate(spp);
        }
        assert_eq!(*split.accumulator(), once, "{scheme}");
        assert_ne!(render(&scene, scheme, 12, 8).sum, once.sum);
    }
}

#[test]
fn thread_count_does_not_change_the_image() {
    let scene = preset_at("zeros", 40, 40);
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&scene, Scheme::Alias, 3, 6))
    };
    let one = in_pool(1);
    assert_eq!(one, in_pool(2));
    assert_eq!(one, in_pool(5));
}

// ---------------------------------------------------------------- unbiasedness

/// `D = (1/P) Σ_p (Ê_p − E_p)` has mean 0 and variance `(1/P²) Σ_p σ_p²/n`; `σ_p²` is
/// estimated by the accumulated sample variance `s_p²` (consistent, 60+ samples per pixel),
/// and `|D|` must stay below `K` of those standard deviations.
fn assert_unbiased(scene: &Scene, scheme: Scheme, spp: u32) {
    let acc = render(scene, scheme, 2024, spp);
    let reference = Reference::compute(scene);
    assert!(reference.is_complete());
    let p = reference.pixels().len() as f64;
    let n = f64::from(spp);
    let mut d = 0.0;
    let mut var_d = 0.0;
    for (pixel, exact) in reference.iter() {
        d += acc.mean(pixel) - exact;
        var_d += acc.variance_per_sample(pixel) / n;
    }
    d /= p;
    let sd = var_d.sqrt() / p;
    assert!(sd > 0.0, "{scheme}: no variance?");
    assert!(
        d.abs() <= K * sd,
        "{} {scheme}: mean error {d:e} vs sd {sd:e}",
        scene.name
    );
}

#[test]
fn every_scheme_is_unbiased_on_the_seed_scene() {
    let scene = preset_at("worked-example", 64, 64);
    for scheme in Scheme::ALL {
        assert_unbiased(&scene, scheme, 64);
    }
}

#[test]
fn every_scheme_is_unbiased_with_zero_power_lights() {
    let scene = preset_at("zeros", 64, 64);
    for scheme in Scheme::ALL {
        assert_unbiased(&scene, scheme, 64);
    }
}

#[test]
fn uniform_and_power_are_unbiased_on_the_dominant_scene() {
    let scene = preset_at("dominant", 64, 64);
    assert_unbiased(&scene, Scheme::Uniform, 256);
    assert_unbiased(&scene, Scheme::Alias, 64);
}

#[test]
fn power_sampling_is_unbiased_across_thirty_decades_of_power() {
    let scene = preset_at("extreme-range", 48, 48);
    assert_unbiased(&scene, Scheme::Alias, 64);
    assert_unbiased(&scene, Scheme::Cdf, 64);
}

// ---------------------------------------------------------------- variance

/// The accumulated mean variance `V̂ = (1/P) Σ s_p²` against its exact expectation
/// `(1/P) Σ σ_p²`: `Var(s_p²) = μ4/n − σ⁴(n−3)/(n(n−1))`, so
/// `sd(V̂) = √(Σ_p Var(s_p²))/P`. Returns the exact mean variance.
fn assert_variance_matches(scene: &Scene, scheme: Scheme, spp: u32) -> f64 {
    let exact = exact_moments(scene, scheme);
    let acc = render(scene, scheme, 99, spp);
    let n = f64::from(spp);
    let p = exact.len() as f64;
    let expected = exact.iter().map(|m| m.variance).sum::<f64>() / p;
    let var_of_mean = exact
        .iter()
        .map(|m| m.mu4 / n - m.variance.powi(2) * (n - 3.0) / (n * (n - 1.0)))
        .sum::<f64>()
        / (p * p);
    let measured = mean_variance_per_sample(&acc);
    assert!(
        (measured - expected).abs() <= K * var_of_mean.sqrt(),
        "{} {scheme}: measured {measured:e}, exact {expected:e} ± {:e}",
        scene.name,
        var_of_mean.sqrt()
    );
    // The exact per-pixel means are the reference values.
    let reference = Reference::compute(scene);
    for (pixel, value) in reference.iter() {
        let m = exact[pixel].mean;
        assert!(
            (m - value).abs() <= 1e-12 * value.abs(),
            "{pixel}: {m} vs {value}"
        );
    }
    expected
}

#[test]
fn power_sampling_beats_uniform_on_the_seed_scene() {
    let scene = preset_at("worked-example", 64, 64);
    let uniform = assert_variance_matches(&scene, Scheme::Uniform, 64);
    let alias = assert_variance_matches(&scene, Scheme::Alias, 64);
    let cdf = assert_variance_matches(&scene, Scheme::Cdf, 64);
    assert_eq!(alias, cdf, "same pmf, same exact variance");
    assert!(alias < uniform, "alias {alias:e} vs uniform {uniform:e}");
}

#[test]
fn power_sampling_beats_uniform_by_orders_on_the_dominant_scene() {
    let scene = preset_at("dominant", 64, 64);
    let uniform = assert_variance_matches(&scene, Scheme::Uniform, 128);
    let alias = assert_variance_matches(&scene, Scheme::Alias, 128);
    assert!(
        alias * 100.0 < uniform,
        "alias {alias:e} vs uniform {uniform:e}"
    );
}

#[test]
fn equal_powers_give_equal_exact_variances() {
    // With equal powers the power pmf is the uniform one: same estimator, same moments.
    let scene = preset_at("equal", 16, 16);
    let u = exact_moments(&scene, Scheme::Uniform);
    let a = exact_moments(&scene, Scheme::Alias);
    for (x, y) in u.iter().zip(&a) {
        assert!((x.variance - y.variance).abs() <= 1e-12 * x.variance);
    }
    assert_variance_matches(&scene, Scheme::Uniform, 64);
    assert_variance_matches(&scene, Scheme::Alias, 64);
}

// ---------------------------------------------------------------- convergence

/// `MSE_n = (1/P) Σ_p (m_p − μ_p)²` after `n` samples has expectation `(1/P) Σ σ_p²/n` and,
/// from `E[(m − μ)^4] = μ4/n³ + 3(n−1)σ⁴/n³`, variance
/// `(1/P²) Σ_p (μ4/n³ + 3(n−1)σ⁴/n³ − σ⁴/n²)`. Each point of the series must lie within `K`
/// standard deviations of its expectation.
#[test]
fn convergence_series_follows_the_exact_mse() {
    let scene = preset_at("worked-example", 64, 64);
    let reference = Reference::compute(&scene);
    for scheme in [Scheme::Uniform, Scheme::Alias] {
        let exact = exact_moments(&scene, scheme);
        let p = exact.len() as f64;
        let mut renderer = CpuRenderer::new(&scene, scheme, 7);
        let series = convergence_series(&mut renderer, &reference, 256);
        let spps: Vec<u32> = series.iter().map(|s| s.spp).collect();
        assert_eq!(spps, [1, 2, 4, 8, 16, 32, 64, 128, 256]);
        assert_eq!(renderer.samples_per_pixel(), 256);
        assert_eq!(*renderer.accumulator(), render(&scene, scheme, 7, 256));
        for point in &series {
            let n = f64::from(point.spp);
            let expected = exact.iter().map(|m| m.variance / n).sum::<f64>() / p;
            let var = exact
                .iter()
                .map(|m| {
                    let s4 = m.variance * m.variance;
                    m.mu4 / n.powi(3) + 3.0 * (n - 1.0) * s4 / n.powi(3) - s4 / (n * n)
                })
                .sum::<f64>()
                / (p * p);
            let mse = point.rmse * point.rmse;
            assert!(
                (mse - expected).abs() <= K * var.sqrt(),
                "{scheme} spp {}: mse {mse:e}, expected {expected:e} ± {:e}",
                point.spp,
                var.sqrt()
            );
        }
        assert!(series.windows(2).all(|w| w[0].seconds <= w[1].seconds));
    }
}

/// One sample per pass (batched across pixels, as the app renders) gives bit for bit the
/// sums of one pass of many samples (batched within each pixel), for every power scheme.
#[test]
fn passes_of_one_sample_equal_one_pass_of_many_bit_for_bit() {
    let scene = preset_at("heavy-tail", 37, 5); // 37: not a multiple of the batch
    for scheme in [
        Scheme::Uniform,
        Scheme::Alias,
        Scheme::AliasOneRandom,
        Scheme::Cdf,
    ] {
        let mut one_by_one = CpuRenderer::new(&scene, scheme, 3);
        for _ in 0..20 {
            one_by_one.accumulate(1);
        }
        let mut at_once = CpuRenderer::new(&scene, scheme, 3);
        at_once.accumulate(20);
        let (a, b) = (one_by_one.accumulator(), at_once.accumulator());
        assert_eq!(a.samples_per_pixel, b.samples_per_pixel);
        assert!(
            a.sum
                .iter()
                .zip(&b.sum)
                .all(|(x, y)| x.to_bits() == y.to_bits()),
            "{scheme}: sums differ"
        );
        assert!(
            a.sum_sq
                .iter()
                .zip(&b.sum_sq)
                .all(|(x, y)| x.to_bits() == y.to_bits()),
            "{scheme}: sums of squares differ"
        );
    }
}
