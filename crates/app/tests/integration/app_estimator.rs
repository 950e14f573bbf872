//! The estimator view: the worked example's shading point converging to 18 under uniform and
//! importance picking (reached from the walkthrough's last step), its figures against the
//! analytic ones (366 and 14.85), seeded steps equal to the core's, the powers followed
//! live, a pixel's point from the inspector, and a snapshot.

use crate::common::{app_harness as harness, shows, snapshot_options, wgpu_window};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;
use lightpick::app::state::estimator::EstimatorPoint;
use lightpick_core::WorkedExample;
use lightpick_core::point_estimate::PointEstimator;

/// Clicks the node labelled `label` and runs one frame (a running estimator keeps asking
/// for frames, so `run()` would not settle).
fn click(h: &mut Harness<'_, LightpickApp>, label: &str) {
    h.get_by_label(label).click();
    h.run_steps(2);
}

fn estimator<'h>(h: &'h Harness<'_, LightpickApp>) -> &'h PointEstimator {
    h.state()
        .state
        .estimator
        .estimator()
        .expect("the estimator is built")
}

#[test]
fn the_walkthroughs_last_step_opens_the_seed_point_converging_to_18() {
    let mut h = harness();
    h.state_mut().state.settings.show_walkthrough = true;
    h.run();
    for _ in 0..8 {
        h.get_by_label("Next →").click();
        h.run();
    }
    assert!(shows(&h, "Step 9 of 9"));
    click(&mut h, "Watch it converge →");
    assert!(h.state().state.estimator.open);
    assert!(h.state().state.estimator.running);
    // ~5 % more samples per frame: 200 frames pass 20 000 samples.
    h.run_steps(200);
    let e = estimator(&h);
    assert_eq!(e.exact(), WorkedExample::EXACT);
    let n = e.samples();
    assert!(n > 20_000, "{n} samples");
    let analytic = [
        WorkedExample::UNIFORM_VARIANCE,
        WorkedExample::POWER_VARIANCE,
    ];
    for (run, variance) in e.runs().iter().zip(analytic) {
        assert!(
            (run.analytic.variance - variance).abs() < 1e-9,
            "{}",
            run.name
        );
        let sigma = (variance / n as f64).sqrt();
        let mean = run.running().mean();
        assert!(
            (mean - 18.0).abs() < 5.0 * sigma,
            "{}: {mean} after {n}",
            run.name
        );
    }
    // The table: analytic variances, samples for 1 % (366/0.0324 → 11 297, 14.85/0.0324 →
    // 459) and the ratio 366/14.85 = 24.65: 24.6× fewer samples; uniform against itself.
    for label in ["366.0", "14.85", "11297", "459", "24.6× fewer", "the same"] {
        assert!(shows(&h, label), "{label} is not shown");
    }
    assert!(h.get_all_by_label_contains("exact total F = 18").count() >= 1);
}

#[test]
fn steps_are_the_cores_seeded_samples_and_reset_starts_over() {
    let mut h = harness();
    h.state_mut()
        .state
        .estimator
        .open_at(EstimatorPoint::WorkedExample);
    h.run();
    click(&mut h, "Step +1");
    click(&mut h, "+10");
    click(&mut h, "+1000");
    assert_eq!(estimator(&h).samples(), 1011);
    let seed = h.state().state.settings.seed;
    let mut core = PointEstimator::worked_example(seed);
    core.advance(1011);
    for (app, core) in estimator(&h).runs().iter().zip(core.runs()) {
        assert_eq!(app.running(), core.running(), "{}", app.name);
    }
    click(&mut h, "Reset samples");
    assert_eq!(estimator(&h).samples(), 0);
    assert!(shows(&h, "n = 0 samples per scheme · seed 1"));
}

#[test]
fn the_point_follows_the_powers_live() {
    let mut h = harness();
    h.state_mut()
        .state
        .estimator
        .open_at(EstimatorPoint::WorkedExample);
    h.run();
    click(&mut h, "+1000");
    // Light 1's power 2 → 7: its contribution g·Φ = 0.5·7 = 3.5, the total 20.5.
    let state = &mut h.state_mut().state;
    state.edit.powers_mut()[0] = 7.0;
    state.powers_changed();
    h.run();
    let e = estimator(&h);
    assert_eq!(e.contributions(), &[3.5, 2.0, 15.0]);
    assert_eq!(e.exact(), 20.5);
    assert_eq!(e.samples(), 0, "a new table starts the run over");
    assert!(h.get_all_by_label_contains("exact total F = 20.50").count() >= 1);
}

#[test]
fn the_inspector_opens_it_at_the_pixel_with_the_spatial_scheme() {
    let mut h = harness();
    h.state_mut().state.inspector.pixel = Some([40, 200]);
    h.run();
    click(&mut h, "Watch the estimate converge here");
    assert_eq!(
        h.state().state.estimator.point,
        EstimatorPoint::Pixel([40, 200])
    );
    h.state_mut().state.estimator.running = false;
    click(&mut h, "+1000");
    let e = estimator(&h);
    let names: Vec<&str> = e.runs().iter().map(|l| l.name).collect();
    assert_eq!(names, ["uniform", "power", "spatial"]);
    // Three lights: the spatial pick is exact, every sample the irradiance itself; the
    // analytic variance Σ f_i²/q_i − F² is then the cancellation of two terms of size F²,
    // each rounded to a few ulps.
    let spatial = &e.runs()[2];
    assert!(spatial.analytic.variance <= 1e-12 * e.exact() * e.exact());
    assert!((spatial.running().mean() - e.exact()).abs() <= 1e-12 * e.exact());
    assert!(shows(&h, "1 (exact)"));
    assert!(shows(&h, "∞ (zero variance)"));
}

#[test]
fn a_point_outside_the_image_is_named_not_a_panic() {
    let mut h = harness();
    h.state_mut()
        .state
        .estimator
        .open_at(EstimatorPoint::Pixel([9999, 3]));
    h.run();
    assert!(h.state().state.estimator.estimator().is_none());
    h.get_by_label_contains("pixel (9999, 3) is outside the 256×256 image");
    // Back to the worked example's point: the view works again.
    click(&mut h, "the worked example's point");
    assert!(h.state().state.estimator.estimator().is_some());
}

#[test]
fn estimator_snapshot() {
    let mut app = LightpickApp::for_tests();
    app.state.settings.dark = false;
    app.state.estimator.open_at(EstimatorPoint::WorkedExample);
    let mut h = wgpu_window(app, [1600.0, 1000.0]);
    h.run();
    h.state_mut().state.estimator.step(30_000);
    h.run();
    h.snapshot_options("estimator_seed", &snapshot_options());
}
