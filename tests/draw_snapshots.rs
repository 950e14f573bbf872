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
    AliasTable, LightPowers, LightSampler as _, Rng, Sampler, Scheme, SeedExample,
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
    let powers = SeedExample::powers();
    let table = AliasTable::build(&powers);
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
    let table = AliasTable::build(&powers);
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
    let table = AliasTable::build(&powers);
    let pixmap = draw::table_diagram(
        &table,
        draw::fraction_denominator(&powers),
        &Style::default(),
    )
    .expect("draws");
    snapshot("table_large", &pixmap);
}

fn seed_histogram_data() -> HistogramData {
    let powers = SeedExample::powers();
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

fn synthetic_convergence() -> Vec<ConvergenceSeries> {
    vec![
        synthetic_series(Scheme::Uniform, 0.9, 1.0e-3),
        synthetic_series(Scheme::Alias, 0.14, 1.1e-3),
        synthetic_series(Scheme::Cdf, 0.15, 1.9e-3),
    ]
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

/// A small receiver plane lit by the seed lights, rendered for real: the exact sum and
/// `spp`-sample Monte Carlo estimates `Φᵢ·Gᵢ / p(i)` with each scheme's picks.
fn small_renders(spp: u64) -> (usize, usize, Vec<f64>, Vec<f64>, Vec<f64>) {
    let (w, h) = (80usize, 50usize);
    let powers = SeedExample::powers();
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
    (
        w,
        h,
        estimate(Scheme::Uniform),
        estimate(Scheme::Alias),
        reference,
    )
}

#[test]
fn image_sheet_of_small_renders() {
    let spp = 4;
    let (width, height, uniform, importance, reference) = small_renders(spp);
    let sheet = SheetImages {
        width,
        height,
        uniform: &uniform,
        importance: &importance,
        reference: &reference,
        spp,
        exposure: None,
    };
    let pixmap = draw::image_sheet(&sheet, &Style::default()).expect("draws");
    snapshot("image_sheet", &pixmap);
}
