//! The app on a light `10^-150` above a pixel centre: the Trade panel and the convergence
//! table give a variance and an efficiency in every row — `V̂ ≈ 10^600`, efficiencies near
//! `10^-590`, beyond `f64` and shown as `1.234e-590` — never 0, `inf` or NaN, with the
//! efficiency and variance ratios between schemes of the same scene `10^150` times larger.

use egui_kittest::kittest::Queryable as _;
use glam::{dvec2, dvec3};
use lightpick::app::state::trade::{TradeMeasurement, measure, scheme_label};
use lightpick::app::{LightpickApp, PanelKind};
use lightpick::numbers;
use lightpick_core::render::{Efficiency, is_zero_variance_scaled};
use lightpick_core::scene::{ReceiverPlane, Scene};
use lightpick_core::{Scaled, Scheme};

use crate::common::{app_harness, bench_json, json, lightpick, panel, scratch_file, step_paused};

/// Two lights over 8×8 pixels, the geometry scaled by `z`: the first light `z` above the
/// centre of pixel (2, 2), the other at `(6, 2, 1)·z`. Every irradiance is `z^-2` times that
/// of `z = 1`, so every relative figure is the same.
fn similar(z: f64) -> Scene {
    Scene::from_parts(
        "near",
        ReceiverPlane {
            min: dvec2(0.0, 0.0),
            max: dvec2(8.0 * z, 8.0 * z),
            width: 8,
            height: 8,
        },
        vec![dvec3(2.5, 5.5, 1.0) * z, dvec3(6.0, 2.0, 1.0) * z],
        vec![1.0, 3.0],
    )
    .expect("valid scene")
}

/// A scene file of two equal lights over 4×4 pixels, the first `z` above the centre of
/// pixel (1, 2), written to the scratch directory `dir`.
fn near_scene_file(dir: &str, z: &str) -> std::path::PathBuf {
    scratch_file(
        dir,
        &format!("near_{z}.json"),
        format!(
            r#"{{"name": "near", "plane": {{"min": [0, 0], "max": [4, 4], "width": 4, "height": 4}},
                "lights": [{{"position": [1.5, 2.5, {z}], "power": 1}},
                           {{"position": [3, 1, 1], "power": 1}}]}}"#
        ),
    )
}

fn app_on(scene: Scene) -> LightpickApp {
    let mut app = LightpickApp::for_tests();
    app.state.load_scene(scene);
    app
}

/// Whether a row is the exact pick (zero variance up to rounding next to the largest).
fn exact(e: &Efficiency, m: &TradeMeasurement) -> bool {
    let largest = m
        .rows
        .iter()
        .map(|r| r.efficiency.normalized_variance)
        .fold(Scaled::ZERO, |a, b| if b > a { b } else { a });
    is_zero_variance_scaled(e.normalized_variance, largest)
}

/// Relative agreement of figures whose only difference is the rounding of the scaled
/// positions (a few ulps in each `G`; see `near_light.rs` in the core's tests).
const TOLERANCE: f64 = 1e-10;

#[test]
fn trade_panel_gives_an_efficiency_in_every_row() {
    let (base, near) = (
        measure(1, &similar(1.0), true),
        measure(1, &similar(1e-150), true),
    );
    let uniform = |m: &TradeMeasurement| m.rows[0].efficiency;
    assert_eq!(near.rows[0].scheme, Scheme::Uniform);
    for (rb, rn) in base.rows.iter().zip(&near.rows) {
        let (eb, en) = (rb.efficiency, rn.efficiency);
        assert_eq!(exact(&eb, &base), exact(&en, &near), "{}", rn.scheme);
        if exact(&en, &near) {
            continue;
        }
        assert!(
            en.efficiency.is_finite() && en.efficiency > Scaled::ZERO,
            "{}: {en:?}",
            rn.scheme
        );
        // 150 decades lower: V̂ 10^600 times larger, the efficiency 10^600 times smaller.
        assert!(
            (en.efficiency_log10 - eb.efficiency_log10 + 600.0).abs() < 1e-8,
            "{}: {en:?} vs {eb:?}",
            rn.scheme
        );
        assert!((en.normalized_variance_log10 - eb.normalized_variance_log10 - 600.0).abs() < 1e-8);
        let ratio = |e: Efficiency, u: Efficiency| (e.efficiency / u.efficiency).to_f64();
        let (a, b) = (ratio(en, uniform(&near)), ratio(eb, uniform(&base)));
        assert!((a - b).abs() <= TOLERANCE * b, "{}: {a} vs {b}", rn.scheme);
        let last = |r: &lightpick::app::state::trade::TradeRow| r.series.last().map(|p| p.rmse);
        assert!(
            last(rn).is_some_and(|r| r > 0.0 && r.is_finite()),
            "{}",
            rn.scheme
        );
    }

    // The panel shows each efficiency as its value beyond f64 (`1.234e-590`).
    let mut harness = panel(PanelKind::Trade, app_on(similar(1e-150)), [660.0, 560.0]);
    harness.run();
    let shown = harness
        .state()
        .state
        .trade
        .result
        .clone()
        .expect("measured on load (a small scene)");
    for row in shown.rows.iter().filter(|r| !exact(&r.efficiency, &shown)) {
        let text = numbers::short_scaled(row.efficiency.efficiency);
        assert!(
            text.contains("e-5") && !text.contains("inf"),
            "{}: {text}",
            row.scheme
        );
        assert!(
            harness.query_all_by_label(&text).next().is_some(),
            "{}'s efficiency {text} is not shown",
            scheme_label(row.scheme)
        );
    }
}

#[test]
fn convergence_table_gives_an_efficiency_and_its_ratios() {
    let run = |z: f64| {
        let mut harness = panel(PanelKind::Convergence, app_on(similar(z)), [620.0, 380.0]);
        harness.run();
        step_paused(&mut harness, 8);
        let published = harness.state_mut().published().expect("a frame");
        (harness, published)
    };
    let (_, base) = run(1.0);
    let (harness, near) = run(1e-150);
    let pixels = 64;
    assert_eq!(near.power.spp, 8);
    let efficiency = |image: &lightpick::app::images::SchemeImage| {
        image.efficiency(pixels).expect("a variance and a time")
    };
    for (b, n) in [(&base.uniform, &near.uniform), (&base.power, &near.power)] {
        let e = efficiency(n);
        assert!(
            e.is_finite() && e > Scaled::ZERO && e.as_f64().is_none(),
            "{e:?}"
        );
        assert!((e.log10() - efficiency(b).log10() + 600.0).abs() < 1e-8);
        let text = numbers::short_scaled(e);
        assert!(
            harness.query_all_by_label(&text).next().is_some(),
            "efficiency {text} is not shown"
        );
    }
    // The importance row's ratios over uniform: the same as at z = 1, printed the same.
    let speedup = |p: &lightpick::app::images::Published| {
        (efficiency(&p.power) / efficiency(&p.uniform)).to_f64()
    };
    let (a, b) = (speedup(&near), speedup(&base));
    assert!((a - b).abs() <= TOLERANCE * b, "{a} vs {b}");
    let variance_ratio = |p: &lightpick::app::images::Published| {
        (p.uniform.normalized_variance / p.power.normalized_variance).to_f64()
    };
    let text = format!(
        "efficiency {} (variance {})",
        numbers::compare(speedup(&near), 1.0, "higher", "lower"),
        numbers::compare(1.0, variance_ratio(&near), "higher", "lower")
    );
    assert!(
        harness.query_all_by_label(&text).next().is_some(),
        "{text} is not shown"
    );
    assert!(
        (variance_ratio(&near) - variance_ratio(&base)).abs() <= TOLERANCE * variance_ratio(&base)
    );
}

#[test]
fn the_whole_app_draws_the_scene() {
    let mut harness = app_harness();
    harness.state_mut().state.load_scene(similar(1e-150));
    step_paused(&mut harness, 4);
    let published = harness.state_mut().published().expect("a frame");
    assert!(published.power.spp > 0);
    assert!(
        published
            .power
            .rmse
            .is_some_and(|r| r > 0.0 && r.is_finite()),
        "{:?}",
        published.power.rmse
    );
}

/// The issue's table through the CLI: `render --scheme alias --spp 4 --device cpu` of two
/// equal lights over 4×4 pixels, one `z` above a pixel centre. relMSE reads the same in
/// every row (the other light's share is `O(z²)`, `10^-6` relative at `z = 10^-3`), and
/// every row has an efficiency: JSON `null` with `efficiency_log10` beyond `f64`, text
/// `1.234e-400`, never `0.000e0`.
#[test]
fn render_reports_rel_mse_and_efficiency_at_every_height() {
    let mut rows = Vec::new();
    for z in ["1e-3", "1e-50", "1e-100", "1e-140", "1e-150"] {
        let path = near_scene_file("near-light", z);
        let scene = path.to_str().expect("utf-8");
        let args = [
            "render", "--scene", scene, "--scheme", "alias", "--spp", "4", "--device", "cpu",
        ];
        let v = json(&[&args[..], &["--json"]].concat());
        let out = lightpick(&args);
        assert!(out.status.success(), "{z}");
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        rows.push((z, v, text));
    }
    let field = |text: &str, name: &str| {
        let at = text
            .find(name)
            .unwrap_or_else(|| panic!("no {name} in {text}"));
        text[at + name.len()..]
            .split_whitespace()
            .next()
            .expect("a value")
            .to_owned()
    };
    let (_, first, first_text) = &rows[0];
    let rel_mse = first["rel_mse"].as_f64().expect("relMSE");
    for (z, v, text) in &rows {
        let r = v["rel_mse"].as_f64().expect("relMSE");
        assert!(
            (r - rel_mse).abs() <= 1e-5 * rel_mse,
            "z = {z}: {r} vs {rel_mse}"
        );
        assert_eq!(
            field(text, "relMSE "),
            field(first_text, "relMSE "),
            "z = {z}"
        );
        let log = v["efficiency_log10"].as_f64().expect("efficiency_log10");
        assert!(log.is_finite(), "z = {z}: {v}");
        match v["efficiency"].as_f64() {
            Some(e) => assert!(e > 0.0 && (e.log10() - log).abs() < 1e-9, "z = {z}: {v}"),
            None => assert!(log < -300.0, "null only beyond f64: {v}"),
        }
        assert!(
            v["normalized_variance_log10"]
                .as_f64()
                .is_some_and(f64::is_finite)
        );
        // 1/(V̂·T): the logs add up to −log10 T, whatever the clock said.
        let t = v["seconds_per_sample"].as_f64().expect("T");
        let variance_log = v["normalized_variance_log10"].as_f64().expect("log10 V̂");
        assert!(
            (log + variance_log + t.log10()).abs() < 1e-9,
            "z = {z}: {v}"
        );
        // The text run has its own clock: a number `m.mmme±X`, `1 ≤ m < 10`. Whatever `T`
        // (between a picosecond and an hour), `V̂ ∝ z^-4` puts it below `10^-300` from
        // `z = 10^-100` on, where an `f64` would print 0.
        let shown = field(text, "efficiency ");
        let (mantissa, decade) = shown
            .split_once('e')
            .and_then(|(m, d)| Some((m.parse::<f64>().ok()?, d.parse::<f64>().ok()?)))
            .unwrap_or_else(|| panic!("z = {z}: efficiency {shown}"));
        assert!((1.0..10.0).contains(&mantissa), "z = {z}: {shown}");
        if z.parse::<f64>().is_ok_and(|z| z <= 1e-100) {
            assert!(decade < -300.0, "z = {z}: {shown}");
        }
    }
}

/// `bench` on the issue's scene (`z = 10^-150`): its own 4×4 pixels (the app's rows) put the
/// light above a pixel centre, `V̂ ≈ 10^596`, so `V`, `V̂` and the efficiencies are `null`
/// with their `log10` (efficiency near `10^-590`), uniform's and alias's alike (equal
/// powers: the same pmf, the same `V̂`); the exact spatial pick is the only zero variance.
/// The renders at 64×64 put it between centres, where every figure is an ordinary number.
#[test]
fn bench_reports_efficiencies_beyond_f64_by_their_log10() {
    let path = near_scene_file("near-light-bench", "1e-150");
    let v = bench_json(&[
        "--presets",
        "none",
        "--scene",
        path.to_str().expect("utf-8"),
        "--spp",
        "16",
    ]);
    let f = |x: &serde_json::Value| x.as_f64().unwrap_or(f64::NAN);
    let app_rows = v["app_renders"][0]["schemes"].as_array().expect("app rows");
    assert_eq!(app_rows.len(), 3);
    for s in app_rows {
        if s["scheme"] == "spatial" {
            assert_eq!(s["zero_variance"], true, "{s}");
            continue;
        }
        assert_eq!(s["zero_variance"], false, "{s}");
        for key in ["efficiency", "normalized_variance", "variance_per_sample"] {
            assert!(s[key].is_null(), "{key} beyond f64 is null: {s}");
        }
        let log = f(&s["efficiency_log10"]);
        assert!(log.is_finite() && log < -500.0, "{s}");
        let variance_log = f(&s["normalized_variance_log10"]);
        assert!(variance_log.is_finite() && variance_log > 500.0, "{s}");
        // 1/(V̂·T): the logs add up to −log10 T.
        let t = f(&s["core_seconds_per_sample"]);
        assert!((log + variance_log + t.log10()).abs() < 1e-9, "{s}");
    }
    for s in v["renders"][0]["schemes"].as_array().expect("renders") {
        if s["zero_variance"] == true {
            continue;
        }
        for key in ["efficiency", "core_efficiency", "normalized_variance"] {
            let x = f(&s[key]);
            let log = f(&s[&format!("{key}_log10")]);
            assert!(x > 0.0 && (x.log10() - log).abs() < 1e-9, "{key}: {s}");
        }
    }
}
