//! The GPU renderer follows the estimator contract of `lightpick_core::render`: the same
//! picks as the CPU for every (pixel, sample), and `f32` estimates within a derived bound.

use crate::common;

use crate::common::SplitMix;
use crate::common::scenes::{random_powers, scattered};
use lightpick_core::gpu::{GpuError, GpuRenderer};
use lightpick_core::render::tonemap_rgba8;
use lightpick_core::scene::{Scene, geometry_term, pixel_center};
use lightpick_core::{LightPowers, Rng, Sampler, Scheme, rejection_threshold};

const GPU_SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::AliasOneRandom];
/// The unit roundoff of f32.
const U: f64 = 1.0 / (1u64 << 24) as f64;

/// The CPU reference, written from the contract: sample `k` of pixel `p` picks from
/// `Rng::new(seed, (k << 32) | p)`; the normalized estimate is `N·p_i·G_i` (uniform) or
/// `G_i` (power-proportional); the image is `Φ_total · Σê / spp`. All in f64.
fn cpu_image(scene: &Scene, scheme: Scheme, seed: u64, spp: u32) -> Vec<f64> {
    let sampler = Sampler::build(scheme, &scene.powers);
    let pmf = scene.powers.pmf();
    let n = scene.light_count() as f64;
    let total = scene.powers.total();
    let plane = &scene.plane;
    let mut image = Vec::with_capacity(plane.pixel_count());
    for py in 0..plane.height {
        for px in 0..plane.width {
            let p = u64::from(py * plane.width + px);
            let x = pixel_center(plane, px, py);
            let mut sum = 0.0;
            for k in 0..u64::from(spp) {
                let mut rng = Rng::new(seed, (k << 32) | p);
                let i = sampler.pick_light(&mut rng) as usize;
                let g = geometry_term(scene.positions[i], x);
                sum += if scheme == Scheme::Uniform {
                    n * pmf[i] * g
                } else {
                    g
                };
            }
            image.push(total * sum / f64::from(spp));
        }
    }
    image
}

/// The relative bound on |GPU − CPU| per pixel, in units of the f32 unit roundoff
/// `u = 2^-24`, derived from WGSL's accuracy rules (+, −, × correctly rounded; ÷ within
/// 2.5 ULP; sqrt inherited from 1/inverseSqrt, ≈ 4.5 ULP; 1 ULP ≤ 2u):
///
/// * the pixel centre `min + ((px + 0.5)/w)·extent` and the light position are rounded to
///   f32, so each offset `dx, dy` carries an absolute error ≤ 19·u·B (B bounds |coords|);
/// * in `r² = dx² + dy² + z²` that is a relative error ≤ 38·u·B/z, since
///   `2|dx|·z ≤ dx² + z² ≤ r²`; with z's rounding and the arithmetic, ≤ (38 B/z + 5)·u;
/// * `r³ = r²·sqrt(r²)` multiplies that by 1.5 and adds ≈ 10u; `4π·`, the division and
///   z's rounding add ≈ 8u; the power-of-two rescalings are exact. One estimate `G` is
///   thus within (57 B/z + 26)·u relative; the uniform `(N·p_i)·G` adds 3u;
/// * summing `spp` non-negative terms in f32 adds at most (spp − 1)·u relative to the sum.
///
/// Picks are integer arithmetic and agree exactly, so the terms summed are the same on
/// both sides, and the bound applies to each pixel's sum: `(57 B/z_min + 29 + spp)·u`.
fn tolerance(scene: &Scene, spp: u32) -> f64 {
    let plane = &scene.plane;
    let mut b = plane.min[0]
        .abs()
        .max(plane.max[0].abs())
        .max(plane.min[1].abs())
        .max(plane.max[1].abs());
    let mut z_min = f64::INFINITY;
    for p in scene.positions.iter() {
        b = b.max(p[0].abs()).max(p[1].abs());
        if p[2] > 0.0 {
            z_min = z_min.min(p[2]);
        }
    }
    (57.0 * b / z_min + 29.0 + f64::from(spp)) * U
}

fn assert_images_close(gpu: &[f64], cpu: &[f64], rel: f64, what: &str) {
    assert_eq!(gpu.len(), cpu.len());
    let mut worst = 0.0f64;
    for (p, (&g, &c)) in gpu.iter().zip(cpu).enumerate() {
        assert!(
            (g - c).abs() <= rel * c,
            "{what}: pixel {p}: GPU {g:e} vs CPU {c:e} (rel {:e} > {rel:e})",
            (g - c).abs() / c
        );
        if c > 0.0 {
            worst = worst.max((g - c).abs() / c);
        }
    }
    eprintln!("{what}: worst relative difference {worst:.2e} (bound {rel:.2e})");
}

/// Renders `7 + 9` samples per pixel (two calls, so `k` continues) and compares.
fn check_against_cpu(scene: &Scene, seed: u64, what: &str) {
    let Some(ctx) = common::context() else {
        return;
    };
    for scheme in GPU_SCHEMES {
        let mut renderer = GpuRenderer::new(ctx, scene, scheme, seed).expect("renderer");
        renderer.accumulate(7).expect("accumulate 7");
        renderer.accumulate(9).expect("accumulate 9");
        let acc = renderer.readback().expect("readback");
        assert_eq!(acc.samples_per_pixel, 16);
        assert_eq!(acc.total_power, scene.powers.total_scaled());
        assert_eq!(acc.shift, scene.irradiance_shift());
        let cpu = cpu_image(scene, scheme, seed, 16);
        assert!(cpu.iter().any(|&c| c > 0.0), "{what}: the scene is lit");
        assert_images_close(
            &acc.image(),
            &cpu,
            tolerance(scene, 16),
            &format!("{what} {scheme}"),
        );
    }
}

#[test]
fn seed_scene_matches_the_cpu_reference() {
    let scene = scattered(3, 1, 1.0, vec![2.0, 5.0, 20.0]);
    check_against_cpu(&scene, 42, "worked-example");
}

#[test]
fn many_lights_with_zeros_match_the_cpu_reference() {
    let scene = scattered(700, 2, 1.0, random_powers(&mut SplitMix(3), 700, 3.0, 3));
    check_against_cpu(&scene, 9, "700 lights");
}

/// `N = 2 147 484` lights (`t = 2^32 mod N ≈ N`, see `gpu_histogram.rs`) on 96 × 72 pixels:
/// about 55 of the 110 592 picks reject a first draw, and the GPU must redraw from the same
/// stream as the CPU (a different light would land far outside the tolerance).
#[test]
fn rejected_column_draws_render_like_the_cpu() {
    let n = 2_147_484usize;
    let mut scene = scattered(n, 12, 1.0, random_powers(&mut SplitMix(13), n, 3.0, 3));
    scene.plane.width = 96;
    scene.plane.height = 72;
    let seed = 5;
    let t = rejection_threshold(n as u32);
    let rejected = (0..16u64)
        .flat_map(|k| (0..96 * 72u64).map(move |p| (k << 32) | p))
        .filter(|&stream| {
            let r = Rng::new(seed, stream).next_u32();
            ((u64::from(r) * n as u64) as u32) < t
        })
        .count();
    eprintln!("{rejected} picks reject their first draw");
    assert!(rejected > 20, "{rejected}");
    check_against_cpu(&scene, seed, "2 147 484 lights");
}

#[test]
fn powers_from_1e_minus_30_to_1e30_match_the_cpu_reference() {
    // Raw powers overflow f32; only normalized ones reach the GPU, and Φ_total stays f64.
    let scene = scattered(200, 4, 1.0, random_powers(&mut SplitMix(5), 200, 30.0, 3));
    let Some(ctx) = common::context() else {
        return;
    };
    // Power-proportional only: the uniform estimate N·p_i·G of a light with p_i ≈ 1e-60
    // underflows f32 by design (its contribution is 1e-60 of the pixel's).
    for scheme in [Scheme::Alias, Scheme::AliasOneRandom] {
        let mut renderer = GpuRenderer::new(ctx, &scene, scheme, 3).expect("renderer");
        renderer.accumulate(16).expect("accumulate");
        let acc = renderer.readback().expect("readback");
        let cpu = cpu_image(&scene, scheme, 3, 16);
        assert_images_close(&acc.image(), &cpu, tolerance(&scene, 16), "extreme powers");
    }
}

#[test]
fn huge_and_tiny_scene_scales_do_not_overflow_f32() {
    // At scale 1e15, r³ ≈ 1e45 overflows f32 and at 1e-15, r³ ≈ 1e-45 underflows it,
    // although G itself (≈ 1e-31 and 1e29) is a normal f32: the rescaled G must hold.
    for scale in [1e15, 1e-15] {
        let scene = scattered(50, 6, scale, random_powers(&mut SplitMix(7), 50, 2.0, 3));
        check_against_cpu(&scene, 11, &format!("scale {scale:e}"));
    }
}

#[test]
fn reset_restarts_the_streams_and_set_powers_rebuilds() {
    let Some(ctx) = common::context() else {
        return;
    };
    let a = scattered(40, 8, 1.0, random_powers(&mut SplitMix(9), 40, 2.0, 3));
    let mut renderer = GpuRenderer::new(ctx, &a, Scheme::Alias, 5).expect("renderer");
    renderer.accumulate(4).expect("accumulate");
    let first = renderer.readback().expect("readback");
    renderer.reset();
    let cleared = renderer.readback().expect("readback");
    assert_eq!(cleared.samples_per_pixel, 0);
    assert!(cleared.sum.iter().all(|&s| s == 0.0));
    renderer.accumulate(4).expect("accumulate again");
    assert_eq!(renderer.readback().expect("readback"), first);

    // New powers: the same image as a fresh renderer built with them.
    let b_powers = random_powers(&mut SplitMix(10), 40, 2.0, 3);
    let mut b = a.clone();
    b.powers = LightPowers::new(b_powers.clone()).expect("valid");
    renderer
        .set_powers(&LightPowers::new(b_powers).expect("valid"))
        .expect("set_powers");
    assert_eq!(renderer.samples_per_pixel(), 0);
    renderer.accumulate(4).expect("accumulate b");
    let mut fresh = GpuRenderer::new(ctx, &b, Scheme::Alias, 5).expect("fresh");
    fresh.accumulate(4).expect("accumulate fresh");
    let rebuilt = renderer.readback().expect("readback");
    assert_eq!(rebuilt, fresh.readback().expect("readback fresh"));
    assert_ne!(rebuilt.sum, first.sum);

    // A scheme switch restarts too, and matches a fresh renderer of that scheme.
    renderer.set_scheme(Scheme::Uniform).expect("uniform");
    renderer.accumulate(2).expect("accumulate uniform");
    let mut uniform = GpuRenderer::new(ctx, &b, Scheme::Uniform, 5).expect("uniform");
    uniform.accumulate(2).expect("accumulate");
    assert_eq!(
        renderer.readback().expect("a"),
        uniform.readback().expect("b")
    );
    assert_eq!(renderer.gpu_bytes_per_light(), 24);
}

#[test]
fn refusals_name_the_problem() {
    let Some(ctx) = common::context() else {
        return;
    };
    let s = scattered(3, 1, 1.0, vec![2.0, 5.0, 20.0]);
    let err = GpuRenderer::new(ctx, &s, Scheme::Cdf, 1).expect_err("cdf");
    assert!(matches!(err, GpuError::UnsupportedScheme { .. }), "{err}");
    assert!(err.to_string().contains("cdf"), "{err}");

    let mut renderer = GpuRenderer::new(ctx, &s, Scheme::Alias, 1).expect("renderer");
    let err = renderer.set_scheme(Scheme::Cdf).expect_err("cdf");
    assert!(matches!(err, GpuError::UnsupportedScheme { .. }), "{err}");
    assert_eq!(renderer.scheme(), Scheme::Alias);

    let err = renderer
        .set_powers(&LightPowers::new(vec![1.0, 2.0]).expect("valid"))
        .expect_err("two powers for three lights");
    assert_eq!(
        err,
        GpuError::LightCountMismatch {
            expected: 3,
            got: 2
        }
    );
    assert_eq!(err.to_string(), "2 powers given for a scene of 3 lights");

    renderer.accumulate(1).expect("one sample");
    let err = renderer.accumulate(u32::MAX).expect_err("past u32::MAX");
    assert!(matches!(err, GpuError::TooManySamples { .. }), "{err}");
    assert_eq!(renderer.samples_per_pixel(), 1);

    let mut empty = s.clone();
    empty.plane.width = 0;
    let err = GpuRenderer::new(ctx, &empty, Scheme::Alias, 1).expect_err("empty image");
    assert!(matches!(err, GpuError::ImageSize { width: 0, .. }), "{err}");
}

#[test]
fn coordinates_beyond_f32_are_refused_by_name() {
    // Finite f64 values that become ±inf as f32 (f32::MAX ≈ 3.4028235e38).
    let base = scattered(3, 1, 1.0, vec![2.0, 5.0, 20.0]);
    let mut light = base.clone();
    std::sync::Arc::make_mut(&mut light.positions)[2][1] = -1e39;
    let mut corner = base.clone();
    corner.plane.max[0] = 4e38;
    // Both corners fit, their difference (the extent the shader uses) does not.
    let mut extent = base.clone();
    extent.plane.min[1] = -3e38;
    extent.plane.max[1] = 3e38;
    let cases = [
        (&light, "lights[2].position[1]", "-1e39"),
        (&corner, "plane.max[0]", "4e38"),
        (&extent, "plane.max[1] − plane.min[1]", "6e38"),
    ];
    for (scene, field, value) in cases {
        let expected = GpuError::BeyondF32 {
            field: field.to_owned(),
            value: value.to_owned(),
        };
        assert_eq!(GpuRenderer::check_scene(scene), Err(expected.clone()));
        assert!(
            expected
                .to_string()
                .starts_with(&format!("{field} = {value} is beyond the f32 range")),
            "{expected}"
        );
    }
    // Just inside the range is accepted: f32::MAX itself, as an f64.
    let mut edge = base.clone();
    std::sync::Arc::make_mut(&mut edge.positions)[0][2] = f64::from(f32::MAX);
    assert_eq!(GpuRenderer::check_scene(&edge), Ok(()));
    assert_eq!(GpuRenderer::check_scene(&base), Ok(()));

    let Some(ctx) = common::context() else {
        return;
    };
    for (scene, field, _) in cases {
        for scheme in [Scheme::Alias, Scheme::Spatial] {
            let err = GpuRenderer::new(ctx, scene, scheme, 1).expect_err("beyond f32");
            assert!(
                matches!(&err, GpuError::BeyondF32 { field: f, .. } if f == field),
                "{scheme}: {err}"
            );
        }
    }
}

#[test]
fn gpu_tonemap_matches_the_cpu_tonemap() {
    let Some(ctx) = common::context() else {
        return;
    };
    let s = scattered(300, 12, 1.0, random_powers(&mut SplitMix(13), 300, 2.0, 3));
    let mut renderer = GpuRenderer::new(ctx, &s, Scheme::Alias, 8).expect("renderer");
    // Before any sample the output is black.
    renderer.tonemap(1.0).expect("tonemap");
    let black = renderer.read_output_rgba8().expect("read");
    assert!(black.chunks_exact(4).all(|px| px == [0, 0, 0, 255]));

    renderer.accumulate(8).expect("accumulate");
    let image = renderer.readback().expect("readback").image();
    let mean = image.iter().sum::<f64>() / image.len() as f64;
    for exposure in [0.1 / mean, 1.0 / mean, 10.0 / mean] {
        renderer.tonemap(exposure).expect("tonemap");
        let gpu = renderer.read_output_rgba8().expect("read");
        let cpu = tonemap_rgba8(&image, exposure);
        assert_eq!(gpu.len(), cpu.len());
        // Both tonemap the same f32 sums; they differ only by the f32 rounding of the
        // factor and of pow() (a few ULP, ~1e-6 of the display value), which moves
        // round(255·v) by one level only when 255·v lies within ~1e-3 of a half-integer.
        let mut exact = 0;
        for (i, (&g, &c)) in gpu.iter().zip(&cpu).enumerate() {
            assert!(g.abs_diff(c) <= 1, "byte {i}: GPU {g} vs CPU {c}");
            exact += usize::from(g == c);
        }
        assert!(
            exact * 100 >= cpu.len() * 99,
            "{exact} of {} exact",
            cpu.len()
        );
        let levels: std::collections::BTreeSet<u8> = gpu.iter().step_by(4).copied().collect();
        assert!(
            levels.len() > 20,
            "exposure {exposure:e}: only {} grey levels",
            levels.len()
        );
    }
}

#[test]
fn an_image_beyond_the_storage_limit_is_refused_before_allocating() {
    let Some(ctx) = common::context() else {
        return;
    };
    let limits = ctx.device().limits();
    let limit = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    // The per-pixel sums take 8 bytes per pixel: the smallest height past the limit.
    let width = limits.max_texture_dimension_2d;
    let height = limit / (8 * u64::from(width)) + 1;
    let Ok(height) = u32::try_from(height) else {
        panic!("height {height} does not fit u32");
    };
    if height > limits.max_texture_dimension_2d {
        eprintln!("skipped: {limit} bytes of storage exceed any {width}² image's sums");
        return;
    }
    let mut s = scattered(3, 1, 1.0, vec![2.0, 5.0, 20.0]);
    s.plane.width = width;
    s.plane.height = height;
    let err = GpuRenderer::new(ctx, &s, Scheme::Alias, 1).expect_err("too large");
    assert!(
        matches!(err, GpuError::BufferTooLarge { what: "pixel sums", bytes, .. } if bytes > limit),
        "{err}"
    );
    assert!(err.to_string().contains("pixel sums"), "{err}");
}

#[test]
fn a_context_wrapping_a_shared_device_renders_the_same_image() {
    let Some(ctx) = common::context() else {
        return;
    };
    let shared = lightpick_core::gpu::GpuContext::from_device(
        ctx.device().clone(),
        ctx.queue().clone(),
        ctx.info().clone(),
    );
    assert_eq!(shared.description(), ctx.description());
    let s = scattered(20, 14, 1.0, random_powers(&mut SplitMix(15), 20, 1.0, 3));
    let mut a = GpuRenderer::new(ctx, &s, Scheme::AliasOneRandom, 77).expect("a");
    let mut b = GpuRenderer::new(&shared, &s, Scheme::AliasOneRandom, 77).expect("b");
    a.accumulate(3).expect("a");
    b.accumulate(3).expect("b");
    let image = a.readback().expect("a");
    assert!(image.sum.iter().any(|&x| x > 0.0));
    assert_eq!(image, b.readback().expect("b"));
}

/// A sample pass split into row bands (`accumulate_rows`, for the app's frame budget) draws
/// exactly the samples of whole passes: the sums are bit for bit those of `accumulate`, for
/// every scheme the GPU runs; the tonemap divides each row by its own sample count while a
/// pass is in progress, and reading the sums back then is refused.
#[test]
fn passes_split_into_row_bands_equal_whole_passes() {
    let Some(ctx) = common::context() else {
        return;
    };
    let s = scattered(300, 61, 1.0, random_powers(&mut SplitMix(62), 300, 3.0, 3));
    let height = s.plane.height;
    for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::Spatial] {
        let mut whole = GpuRenderer::new(ctx, &s, scheme, 5).expect("renderer");
        whole.accumulate(3).expect("accumulate");
        let mut banded = GpuRenderer::new(ctx, &s, scheme, 5).expect("renderer");
        let mut passes = 0;
        while passes < 3 {
            if banded.accumulate_rows(7).expect("band") {
                passes += 1;
                assert_eq!(banded.pass_rows_done(), 0);
            } else {
                assert!(
                    banded.pass_rows_done().is_multiple_of(7) && banded.pass_rows_done() < height
                );
            }
        }
        assert_eq!(banded.samples_per_pixel(), 3);
        assert_eq!(
            banded.readback().expect("readback"),
            whole.readback().expect("readback"),
            "{scheme:?}"
        );

        // A pass in progress: the sums are refused; accumulate() completes it first.
        assert!(!banded.accumulate_rows(10).expect("band"));
        assert!(matches!(
            banded.readback(),
            Err(GpuError::PassInProgress { rows_done: 10, height: h }) if h == height
        ));
        banded.accumulate(2).expect("accumulate");
        whole.accumulate(2).expect("accumulate");
        assert_eq!(banded.samples_per_pixel(), 5);
        assert_eq!(
            banded.readback().expect("readback"),
            whole.readback().expect("readback"),
            "{scheme:?} after completing a partial pass"
        );
    }
}

/// While a pass is in progress its rows hold one sample more, and the tonemap divides by
/// that count: the first pass's top rows are lit, the rest still black; once the pass is
/// finished the output equals a whole pass's.
#[test]
fn the_tonemap_of_a_partial_pass_uses_each_rows_sample_count() {
    let Some(ctx) = common::context() else {
        return;
    };
    let s = scattered(3, 63, 1.0, vec![2.0, 5.0, 20.0]);
    let width = s.plane.width as usize;
    let mut r = GpuRenderer::new(ctx, &s, Scheme::Alias, 9).expect("renderer");
    assert!(!r.accumulate_rows(12).expect("band"));
    r.tonemap(1.0).expect("tonemap");
    let rgba = r.read_output_rgba8().expect("output");
    let row_lit = |row: usize| {
        rgba[row * width * 4..(row + 1) * width * 4]
            .chunks_exact(4)
            .any(|px| px[0] > 0)
    };
    assert!((0..12).all(row_lit), "rows with their first sample are lit");
    assert!(
        !(12..s.plane.height as usize).any(row_lit),
        "rows without are black"
    );
    r.finish_pass().expect("finish");
    r.tonemap(1.0).expect("tonemap");
    let mut whole = GpuRenderer::new(ctx, &s, Scheme::Alias, 9).expect("renderer");
    whole.accumulate(1).expect("accumulate");
    whole.tonemap(1.0).expect("tonemap");
    assert_eq!(
        r.read_output_rgba8().expect("output"),
        whole.read_output_rgba8().expect("output")
    );
    // Two passes in, a third partial: rows already at 3 samples are tonemapped with 1/3,
    // exactly as the whole three-pass image's rows.
    r.accumulate(1).expect("accumulate");
    assert!(!r.accumulate_rows(12).expect("band"));
    r.tonemap(1.0).expect("tonemap");
    let partial = r.read_output_rgba8().expect("output");
    whole.accumulate(2).expect("accumulate");
    whole.tonemap(1.0).expect("tonemap");
    let three = whole.read_output_rgba8().expect("output");
    assert_eq!(partial[..12 * width * 4], three[..12 * width * 4]);
}

/// After a band, tonemapping only its rows gives the output a full tonemap gives (the other
/// rows' sample counts did not change).
#[test]
fn tonemapping_the_band_alone_equals_a_full_tonemap() {
    let Some(ctx) = common::context() else {
        return;
    };
    let s = scattered(40, 64, 1.0, random_powers(&mut SplitMix(65), 40, 2.0, 3));
    let mut banded = GpuRenderer::new(ctx, &s, Scheme::Alias, 3).expect("renderer");
    let mut full = GpuRenderer::new(ctx, &s, Scheme::Alias, 3).expect("renderer");
    for r in [&mut banded, &mut full] {
        r.accumulate(2).expect("accumulate");
        r.tonemap(0.7).expect("tonemap");
    }
    for band in [0..9, 9..20] {
        assert!(!banded.accumulate_rows(band.end - band.start).expect("band"));
        banded.tonemap_rows(0.7, band).expect("tonemap rows");
    }
    full.accumulate_rows(20).expect("band");
    full.tonemap(0.7).expect("tonemap");
    assert_eq!(
        banded.read_output_rgba8().expect("output"),
        full.read_output_rgba8().expect("output")
    );
}
