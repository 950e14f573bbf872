//! The spatial (contribution-aware) scheme in the app, beyond the worked example's exact pick:
//! on the `equal` preset (64 lights, a light tree) it is the third image, the third
//! convergence curve and a trade row, and it ends closer to the reference than power
//! sampling.

use egui_kittest::kittest::Queryable as _;
use lightpick::app::{LightpickApp, PanelKind};

use crate::common::{step_paused, wgpu_panel};

#[test]
fn spatial_is_a_third_image_and_curve_and_wins_on_spread_out_lights() {
    let mut harness = wgpu_panel(
        PanelKind::Convergence,
        LightpickApp::for_tests_on("equal"),
        [620.0, 380.0],
    );
    harness.run();
    step_paused(&mut harness, 16);
    let published = harness.state_mut().published().expect("a frame");
    assert_eq!(published.spatial.spp, 16);
    assert_eq!(published.spatial.series.len(), 16);
    let (a, s) = (
        published.power.rmse.expect("rmse"),
        published.spatial.rmse.expect("rmse"),
    );
    // Measured variance ratio ≈ 16 on this preset (`lightpick bench`): RMSE ≈ 4× lower.
    assert!(s * 2.0 < a, "spatial RMSE {s} vs power {a}");
    assert!(
        published.spatial.variance.significand() > 0.0,
        "a tree, not the exact pick"
    );
    assert!(
        harness
            .query_all_by_label("spatial (by contribution)")
            .next()
            .is_some(),
        "the spatial curve is in the legend"
    );
}
