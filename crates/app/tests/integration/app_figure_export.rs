//! File → Export figure: every figure the app draws (the images with their captions, the
//! alias-table diagram, histogram, convergence, Trade plot, light tree) written as a PNG at
//! the size chosen in the menu (the images within it, their aspect kept); a
//! figure without data yet says what to do first and writes nothing.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;
use lightpick::app::state::figure::Figure;

use crate::common::{click, scratch, step_paused, submit_path, window};

/// Opens File → Export figure → `figure`, types `path` and confirms.
fn export(harness: &mut Harness<'static, LightpickApp>, figure: Figure, path: &std::path::Path) {
    click(harness, "File");
    click(harness, "Export figure (PNG)");
    harness
        .get_by_label(&format!("{}…", figure.title()))
        .click();
    harness.run();
    submit_path(harness, path);
}

#[test]
fn every_figure_exports_at_the_chosen_size() {
    let dir = scratch("app-figures");
    let mut harness = window(LightpickApp::for_tests(), [1600.0, 1000.0]);
    harness.run();
    let size = [900, 560];
    harness.state_mut().state.settings.figure_size = size;
    // Data for each figure: images and histograms (paused steps), a Trade measurement and
    // a stepped pick on the tree.
    step_paused(&mut harness, 6);
    harness.state_mut().state.settings.show_trade = true;
    harness.run();
    click(&mut harness, "Measure");
    harness
        .state_mut()
        .state
        .light_tree
        .select_pixel([100, 120]);
    harness.state_mut().state.light_tree.stage = 1;
    harness.run();
    for figure in Figure::ALL {
        let path = dir.join(format!("{}.png", figure.file_suffix()));
        export(&mut harness, figure, &path);
        let png = image::open(&path).unwrap_or_else(|e| panic!("{}: {e}", figure.title()));
        if figure == Figure::Images {
            // The sheet keeps its aspect: the largest size within the chosen one.
            assert!(png.width() <= size[0] && png.height() <= size[1]);
            assert!(
                png.width() == size[0] || png.height() == size[1],
                "{}×{}",
                png.width(),
                png.height()
            );
        } else {
            assert_eq!([png.width(), png.height()], size, "{}", figure.title());
        }
        // Not a blank canvas: some pixels differ from the corner's background.
        let rgb = png.to_rgb8();
        let background = *rgb.get_pixel(0, 0);
        let drawn = rgb.pixels().filter(|p| **p != background).count();
        assert!(drawn > 1000, "{}: {drawn} drawn pixels", figure.title());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_figure_without_data_says_what_to_do_first() {
    let dir = scratch("app-figures-empty");
    let mut harness = window(LightpickApp::for_tests(), [1600.0, 1000.0]);
    harness.run();
    let path = dir.join("trade.png");
    export(&mut harness, Figure::Trade, &path);
    assert!(!path.exists(), "nothing written");
    let error = harness.state().state.file_dialog.error.clone();
    assert!(
        error
            .as_deref()
            .is_some_and(|e| e.contains("has not measured this scene")),
        "{error:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
