//! The per-pixel inspector: a click on an image selects a pixel, and the inspector shows
//! that point's irradiance, each light's pmf beside its share, and the variance of each
//! scheme there, equal to the core's [`PointInspection`]; it follows a power change.

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::{LightpickApp, PanelKind};
use lightpick::numbers::short;
use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::pixel_center;
use lightpick_core::spatial::SpatialSampler;

use crate::common::painted::click_at;
use crate::common::{click, panel, shows_containing, snapshot_options, wgpu_panel};

fn whole_app() -> Harness<'static, LightpickApp> {
    let mut harness = crate::common::app_harness();
    harness.state_mut().step();
    harness.run();
    harness
}

/// The core's inspection of the selected pixel of the app's current scene.
fn expected(harness: &Harness<'static, LightpickApp>) -> PointInspection {
    let state = &harness.state().state;
    let pixel = state.inspector.pixel.expect("a pixel is selected");
    let scene = &state.built.scene;
    PointInspection::at(scene, pixel_center(&scene.plane, pixel[0], pixel[1]))
}

#[test]
fn clicking_an_image_inspects_that_pixel() {
    let mut harness = whole_app();
    assert!(harness.state().state.inspector.pixel.is_none());
    assert!(harness.query_by_label("Pixel inspector").is_none());
    // Below the caption of the importance image lies the image itself.
    let caption = harness.get_by_label("Power (alias)").rect();
    click_at(
        &mut harness,
        egui::pos2(caption.left() + 60.0, caption.bottom() + 40.0),
    );
    let pixel = harness
        .state()
        .state
        .inspector
        .pixel
        .expect("the click selected a pixel");
    let plane = &harness.state().state.built.scene.plane;
    assert!(pixel[0] < plane.width && pixel[1] < plane.height);
    assert!(
        pixel[0] > 0 && pixel[1] > 0,
        "{pixel:?} should lie inside, off the corner"
    );
    harness.get_by_label("Pixel inspector");
    let inspection = expected(&harness);
    assert!(inspection.irradiance > 0.0);
    let header = format!("pixel ({}, {})", pixel[0], pixel[1]);
    assert!(shows_containing(&harness, &header), "{header} missing");
    let irradiance = format!("E(x) = {}", short(inspection.irradiance));
    assert!(
        shows_containing(&harness, &irradiance),
        "{irradiance} missing"
    );
    for value in [
        inspection.uniform_relative_variance,
        inspection.power_relative_variance,
    ] {
        assert!(
            harness.query_all_by_label(&short(value)).next().is_some(),
            "variance {} missing",
            short(value)
        );
    }
    // Every light's share is listed (three lights).
    assert_eq!(inspection.lights.len(), 3);
    for light in &inspection.lights {
        assert!(
            harness
                .query_all_by_label(&short(light.share))
                .next()
                .is_some()
        );
    }
}

#[test]
fn the_inspection_follows_a_power_change() {
    let mut harness = whole_app();
    harness.state_mut().state.inspector.pixel = Some([40, 200]);
    harness.run();
    let before = expected(&harness);
    harness
        .get_by_role_and_label(Role::SpinButton, "power of light 1")
        .set_value_accesskit(200.0);
    harness.run();
    harness.run();
    let after = expected(&harness);
    assert_eq!(
        harness.state().state.built.scene.powers.as_slice(),
        &[200.0, 5.0, 20.0]
    );
    assert!(after.irradiance > before.irradiance);
    let irradiance = format!("E(x) = {}", short(after.irradiance));
    assert!(
        shows_containing(&harness, &irradiance),
        "{irradiance} missing"
    );
    assert!(!shows_containing(
        &harness,
        &format!("E(x) = {}", short(before.irradiance))
    ));
}

#[test]
fn closing_the_window_clears_the_selection() {
    let mut harness = whole_app();
    harness.state_mut().state.inspector.pixel = Some([10, 10]);
    harness.run();
    harness.get_by_label("Pixel inspector");
    click(&mut harness, "Close window");
    assert!(harness.state().state.inspector.pixel.is_none());
}

#[test]
fn inspector_snapshot() {
    let mut harness = wgpu_panel(
        PanelKind::Inspector,
        LightpickApp::for_tests(),
        [520.0, 560.0],
    );
    harness.state_mut().state.inspector.pixel = Some([64, 170]);
    harness.run();
    harness.snapshot_options("app_inspector", &snapshot_options());
}

/// On `equal` (64 lights spread over the plane: a light tree) the inspector adds the spatial
/// scheme: its pick probabilities and its variance, the core's, and lower than power
/// sampling's at that point (most lights are far from it, and power sampling ignores that).
#[test]
fn the_inspector_shows_the_spatial_pick_and_its_variance() {
    let app = LightpickApp::for_tests_on("equal");
    let mut harness = panel(PanelKind::Inspector, app, [520.0, 700.0]);
    harness.state_mut().state.inspector.pixel = Some([100, 60]);
    harness.run();
    let state = &harness.state().state;
    let scene = &state.built.scene;
    let x = pixel_center(&scene.plane, 100, 60);
    // The scene's own sampler, cut per tile of its pixels as the renderers' is.
    let sampler = SpatialSampler::for_scene(scene);
    assert!(matches!(&sampler, SpatialSampler::Tree(t) if t.tile_cuts().is_some()));
    let inspection = PointInspection::at_with_spatial(scene, x, &sampler);
    let spatial = inspection.spatial_relative_variance.expect("spatial");
    assert!(
        spatial < inspection.power_relative_variance,
        "spatial {spatial} vs power {}",
        inspection.power_relative_variance
    );
    assert!(
        harness.query_all_by_label(&short(spatial)).next().is_some(),
        "spatial variance {} missing",
        short(spatial)
    );
    assert!(shows_containing(&harness, "spatial (q = P(i | x))"));
    let top = inspection.lights[0];
    let q = short(top.spatial.expect("spatial q"));
    assert!(
        harness.query_all_by_label(&q).next().is_some(),
        "spatial q {q} of light {} missing",
        top.index + 1
    );
}

/// On `stage` (spots) the inspector adds each listed light's cone term `t²` at the point, the
/// core's, and the images say why power picking fails there and what the spatial scheme
/// uses instead.
#[test]
fn spot_scenes_show_the_cone_term_and_why_power_picking_fails() {
    let app = LightpickApp::for_tests_on("stage");
    let mut harness = panel(PanelKind::Inspector, app, [620.0, 700.0]);
    harness.state_mut().state.inspector.pixel = Some([126, 81]);
    harness.run();
    let state = &harness.state().state;
    let scene = &state.built.scene;
    let inspection = PointInspection::at(scene, pixel_center(&scene.plane, 126, 81));
    assert!(shows_containing(&harness, "cone t²"), "the cone column");
    let top = inspection.lights[0];
    let cone = top.cone.expect("stage's lights are spots");
    assert!(
        cone > 0.0,
        "the largest share comes from a spot that shines here"
    );
    assert!(
        harness.query_all_by_label(&short(cone)).next().is_some(),
        "cone term {} of light {} missing",
        short(cone),
        top.index + 1
    );
    // A spot aimed elsewhere is listed too (by its pmf), with no cone term here.
    assert!(
        inspection.lights.iter().any(|l| l.cone == Some(0.0)),
        "some listed spot is dark here"
    );

    let mut images = panel(
        PanelKind::Images,
        LightpickApp::for_tests_on("stage"),
        [900.0, 520.0],
    );
    images.state_mut().step();
    images.run();
    assert!(
        shows_containing(&images, "a spot's power says little about what it gives"),
        "the note under the images"
    );
}

/// The top views' numbers are the inspector's: for every light the table lists, the
/// overlay's power, spatial and ideal probabilities equal the inspection's, bit for bit;
/// each view's probabilities sum to one (spatial: at most one).
#[test]
fn the_pick_overlay_shows_the_inspectors_numbers() {
    for preset in ["worked-example", "grid", "stage"] {
        let mut app = LightpickApp::for_tests_on(preset);
        app.state.inspector.pixel = Some([37, 91]);
        let mut harness = crate::common::window(app, [1560.0, 960.0]);
        harness.run();
        assert!(
            shows_containing(&harness, "Where each scheme picks at this pixel"),
            "{preset}: no top views"
        );
        let state = &mut harness.state_mut().state;
        let built = std::sync::Arc::clone(&state.built);
        let inspection = state
            .inspector
            .inspection(&built)
            .expect("inspected")
            .clone();
        let overlay = state.inspector.overlay(&built).expect("drawn").clone();
        assert_eq!(overlay.x, inspection.x);
        for l in &inspection.lights {
            assert_eq!(overlay.power[l.index], l.pmf, "{preset} light {}", l.index);
            assert_eq!(
                Some(overlay.spatial[l.index]),
                l.spatial,
                "{preset} light {}",
                l.index
            );
            assert_eq!(
                overlay.ideal[l.index], l.share,
                "{preset} light {}",
                l.index
            );
        }
        let sum = |v: &[f64]| v.iter().sum::<f64>();
        assert!((sum(&overlay.power) - 1.0).abs() < 1e-12);
        assert!((sum(&overlay.ideal) - 1.0).abs() < 1e-12 || inspection.irradiance == 0.0);
        assert!(sum(&overlay.spatial) <= 1.0 + 1e-9);
    }
}
