//! Snapshot tests of the headless drawings (`lightpick_core::draw`).
//!
//! Each test draws from fixed, deterministic data and compares the pixels with a golden PNG
//! in `tests/snapshots/` (tolerance: see `lightpick_tests::SNAPSHOT_CHANNEL_TOLERANCE`). On
//! a mismatch `NAME.new.png` and `NAME.diff.png` are written next to the golden; accept an
//! intended change with `UPDATE_SNAPSHOTS=1 cargo test --test draw_snapshots`, after
//! looking at the new images.

use lightpick_core::draw::{
    self, ConvergenceAxis, ConvergencePoint, ConvergenceSeries, HistogramData, SchemeCounts,
    SheetImages, Style, Theme,
};
use lightpick_core::{
    AliasTable, LightPowers, PointFreeSampler as _, Rng, Sampler, Scheme, WorkedExample,
};
use lightpick_tests::assert_snapshot;
fn snapshot(name: &str, pixmap: &lightpick_core::draw::Pixmap) {
    let png = draw::encode_png(pixmap).expect("PNG encoding");
    let decoded = image::load_from_memory(&png)
        .expect("a valid PNG")
        .to_rgba8();
    let (w, h) = decoded.dimensions();
    let rgba = decoded.into_raw();
    assert_eq!((w, h), (pixmap.width(), pixmap.height()));
    assert_eq!(rgba, draw::to_rgba8(pixmap), "PNG round trip is lossless");
    assert_snapshot(name, w, h, &rgba);
}

/// Picks `count` lights with `scheme`, sample `k` from stream `Rng::new(seed, k)` (the
/// layout of `lightpick sample`), and bundles the counts with the scheme's own pmf.
fn sample_counts(scheme: Scheme, powers: &LightPowers, count: u64, seed: u64) -> SchemeCounts {
    let sampler = Sampler::build(scheme, powers);
    let mut counts = vec![0u64; powers.len()];
    for k in 0..count {
        let mut rng = Rng::new(seed, k);
        counts[sampler.pick_light(&mut rng) as usize] += 1;
    }
    let expected = (0..powers.len()).map(|i| sampler.probability(i)).collect();
    SchemeCounts::new(scheme, counts, expected).expect("equal lengths")
}

#[test]
fn seed_table_diagram() {
    let powers = WorkedExample::powers();
    let table = AliasTable::build_exact(&powers);
    let denominator = draw::fraction_denominator(&powers);
    assert_eq!(denominator, Some(27));
    let pixmap = draw::table_diagram(&table, denominator, &Style::default()).expect("draws");
    snapshot("table_seed", &pixmap);
}

#[test]
fn twenty_light_table_diagram() {
    // Mid-size tables keep per-light colours but thin out their labels.
    let powers: Vec<f64> = (0..20u32).map(|i| f64::from(1 + (i * 7) % 11)).collect();
    let powers = LightPowers::new(powers).expect("valid powers");
    let table = AliasTable::build_exact(&powers);
    let pixmap = draw::table_diagram(
        &table,
        draw::fraction_denominator(&powers),
        &Style::default(),
    )
    .expect("draws");
    snapshot("table_20", &pixmap);
}

#[test]
fn large_table_summary() {
    // 5000 lights with a deterministic heavy tail: power ∝ 1/(1 + (i mod 97)).
    let powers: Vec<f64> = (0..5000u32)
        .map(|i| 1.0 / f64::from(1 + (i * 7919) % 97))
        .collect();
    let powers = LightPowers::new(powers).expect("valid powers");
    let table = AliasTable::build_exact(&powers);
    let pixmap = draw::table_diagram(
        &table,
        draw::fraction_denominator(&powers),
        &Style::default(),
    )
    .expect("draws");
    snapshot("table_large", &pixmap);
}

fn seed_histogram_data() -> HistogramData {
    let powers = WorkedExample::powers();
    let schemes = [Scheme::Uniform, Scheme::Alias]
        .into_iter()
        .map(|s| sample_counts(s, &powers, 10_000, 7))
        .collect::<Vec<_>>();
    for s in &schemes {
        assert_eq!(s.total(), 10_000);
        assert!(s.fit.p_value > 1e-3, "{}: {:?}", s.scheme, s.fit);
    }
    HistogramData {
        pmf: powers.pmf(),
        schemes,
    }
}

#[test]
fn seed_histogram() {
    let pixmap = draw::histogram(&seed_histogram_data(), &Style::default()).expect("draws");
    snapshot("histogram_seed", &pixmap);
}

#[test]
fn seed_histogram_dark() {
    let style = Style {
        theme: Theme::Dark,
        ..Style::default()
    };
    let pixmap = draw::histogram(&seed_histogram_data(), &style).expect("draws");
    snapshot("histogram_seed_dark", &pixmap);
}

#[test]
fn many_lights_histogram_shows_top_k() {
    let powers: Vec<f64> = (0..40u32).map(|i| f64::from(1 + (i * 13) % 40)).collect();
    let powers = LightPowers::new(powers).expect("valid powers");
    let data = HistogramData {
        pmf: powers.pmf(),
        schemes: vec![
            sample_counts(Scheme::Alias, &powers, 50_000, 11),
            sample_counts(Scheme::Cdf, &powers, 50_000, 11),
        ],
    };
    let pixmap = draw::histogram(&data, &Style::default()).expect("draws");
    snapshot("histogram_top_k", &pixmap);
}

/// RMSE `c/√spp` with a deterministic wobble, and seconds = spp × cost per sample.
fn synthetic_series(scheme: Scheme, c: f64, cost: f64) -> ConvergenceSeries {
    let points = (0..=10)
        .map(|k| {
            let spp = 1u64 << k;
            let wobble = 1.0 + 0.06 * (f64::from(k) * 1.7 + c).sin();
            ConvergencePoint {
                spp,
                rmse: c / (spp as f64).sqrt() * wobble,
                seconds: spp as f64 * cost,
            }
        })
        .collect();
    ConvergenceSeries::for_scheme(scheme, points)
}

/// Uniform, alias and cdf curves, and a zero-variance spatial series (the exact pick: RMSE
/// at the rounding level, ~1e-16), which must stay off the axes and be named in the legend.
fn synthetic_convergence() -> Vec<ConvergenceSeries> {
    let mut exact = synthetic_series(Scheme::Spatial, 3e-16, 1.2e-3);
    for p in &mut exact.points {
        p.rmse = 3e-16 * (1.0 + 0.3 * (p.spp as f64).sin());
    }
    vec![
        synthetic_series(Scheme::Uniform, 0.9, 1.0e-3),
        synthetic_series(Scheme::Alias, 0.14, 1.1e-3),
        synthetic_series(Scheme::Cdf, 0.15, 1.9e-3),
        exact,
    ]
}

#[test]
fn the_zero_variance_series_is_recognized() {
    assert_eq!(
        draw::zero_variance_series(&synthetic_convergence()),
        [false, false, false, true]
    );
}

#[test]
fn convergence_vs_spp() {
    let pixmap = draw::convergence(
        &synthetic_convergence(),
        ConvergenceAxis::Spp,
        &Style::default(),
    )
    .expect("draws");
    snapshot("convergence_spp", &pixmap);
}

#[test]
fn convergence_vs_seconds() {
    let pixmap = draw::convergence(
        &synthetic_convergence(),
        ConvergenceAxis::Seconds,
        &Style::default(),
    )
    .expect("draws");
    snapshot("convergence_seconds", &pixmap);
}

/// The images of [`small_renders`]: uniform, alias, spatial (exact pick), reference.
struct SmallRenders {
    width: usize,
    height: usize,
    uniform: Vec<f64>,
    importance: Vec<f64>,
    spatial: Vec<f64>,
    reference: Vec<f64>,
}

/// A small receiver plane lit by the worked example's lights, rendered for real: the exact sum and
/// `spp`-sample Monte Carlo estimates `Φᵢ·Gᵢ / p(i)` with each scheme's picks, the spatial
/// one picking `i` with `P(i | x) = Φᵢ·Gᵢ(x) / Σⱼ Φⱼ·Gⱼ(x)` (the exact pick of three lights,
/// so its estimate is the exact sum up to rounding).
fn small_renders(spp: u64) -> SmallRenders {
    let (w, h) = (80usize, 50usize);
    let powers = WorkedExample::powers();
    let lights = [(0.35, 0.30, 0.10), (1.20, 0.68, 0.12), (0.80, 0.45, 0.30)];
    let geometry = |light: usize, p: usize| {
        let (x, y) = ((p % w) as f64 + 0.5, (p / w) as f64 + 0.5);
        let (x, y) = (x / h as f64, y / h as f64);
        let (lx, ly, lz) = lights[light];
        let d2 = (x - lx) * (x - lx) + (y - ly) * (y - ly) + lz * lz;
        lz / (d2 * d2.sqrt())
    };
    let n = w * h;
    let reference: Vec<f64> = (0..n)
        .map(|p| (0..3).map(|i| powers.as_slice()[i] * geometry(i, p)).sum())
        .collect();
    let estimate = |scheme: Scheme| -> Vec<f64> {
        let sampler = Sampler::build(scheme, &powers);
        (0..n)
            .map(|p| {
                let sum: f64 = (0..spp)
                    .map(|k| {
                        let mut rng = Rng::new(5, (k << 32) | p as u64);
                        let pick = sampler.pick(&mut rng);
                        let i = pick.light as usize;
                        powers.as_slice()[i] * geometry(i, p) / pick.probability
                    })
                    .sum();
                sum / spp as f64
            })
            .collect()
    };
    let spatial: Vec<f64> = (0..n)
        .map(|p| {
            let c: Vec<f64> = (0..3)
                .map(|i| powers.as_slice()[i] * geometry(i, p))
                .collect();
            let total: f64 = c.iter().sum();
            let sum: f64 = (0..spp)
                .map(|k| {
                    let mut rng = Rng::new(5, (k << 32) | p as u64);
                    let u = rng.next_unit() * total;
                    let mut below = 0.0;
                    let i = (0..3)
                        .find(|&i| {
                            below += c[i];
                            u < below
                        })
                        .unwrap_or(2);
                    c[i] / (c[i] / total)
                })
                .sum();
            sum / spp as f64
        })
        .collect();
    SmallRenders {
        width: w,
        height: h,
        uniform: estimate(Scheme::Uniform),
        importance: estimate(Scheme::Alias),
        spatial,
        reference,
    }
}

#[test]
fn image_sheet_of_small_renders() {
    let spp = 4;
    let r = small_renders(spp);
    // The exact pick's estimate is the exact sum up to rounding.
    for (s, e) in r.spatial.iter().zip(&r.reference) {
        assert!((s - e).abs() <= 1e-14 * e, "{s} vs {e}");
    }
    let sheet = SheetImages {
        width: r.width,
        height: r.height,
        uniform: &r.uniform,
        importance: &r.importance,
        spatial: &r.spatial,
        reference: &r.reference,
        spp,
        exposure: None,
    };
    let pixmap = draw::image_sheet(&sheet, &Style::default()).expect("draws");
    snapshot("image_sheet", &pixmap);
}
