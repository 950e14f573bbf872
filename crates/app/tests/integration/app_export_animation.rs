//! File → "Export animation…": the app records the CLI's convergence animation from its
//! running state on a worker thread, and the file is the one `lightpick plot animation`
//! writes for the same scene, seed, exposure, size and theme.

#![allow(clippy::unwrap_used)] // Test helpers unwrap: a panic is the failure report.

use egui_kittest::kittest::Queryable as _;
use lightpick::app::LightpickApp;

use crate::common::{HANG_GUARD, app_harness, click, gif_frames, run_ok, scratch};

#[test]
fn the_export_job_writes_the_cli_animation_of_the_running_state() {
    let dir = scratch("app-animation");
    let path = dir.join("job.gif");
    let mut app = LightpickApp::for_tests();
    let state = &mut app.state;
    state.settings.seed = 7;
    state.animation_export.frames = 3;
    state.animation_export.max_spp = 4;
    let job = state.animation_job(&path);
    let plane = &job.recording.scene.plane;
    let (width, height) = (plane.width, plane.height);
    assert_eq!(
        (width, height),
        (
            state.built.scene.plane.width,
            state.built.scene.plane.height
        )
    );
    state.animation_export.start(job);
    let exported = state
        .animation_export
        .wait()
        .expect("an export ran")
        .clone()
        .expect("the export succeeded");
    assert_eq!(exported.frames, 3);
    assert_eq!(gif_frames(&path).len(), 3);
    assert!(
        exported.message().contains("job.gif"),
        "{}",
        exported.message()
    );
    assert!(!state.animation_export.is_running());

    // The CLI with the same figures writes the same bytes.
    let cli = dir.join("cli.gif");
    let exposure = format!("{:?}", state.settings.exposure);
    let (w, h) = (width.to_string(), height.to_string());
    let mut args = vec![
        "plot",
        "animation",
        "--preset",
        "worked-example",
        "--seed",
        "7",
        "--exposure",
        &exposure,
        "--width",
        &w,
        "--height",
        &h,
        "--frames",
        "3",
        "--max-spp",
        "4",
        "--out",
        cli.to_str().unwrap(),
    ];
    if state.dark() {
        args.push("--dark");
    }
    run_ok(&args);
    assert!(
        std::fs::read(&cli).unwrap() == std::fs::read(&path).unwrap(),
        "the app's and the CLI's animations differ"
    );

    // A failure is a sentence, and the state is ready for the next export.
    let mut bad = state.animation_job(dir.join("no-such-dir").join("x.gif"));
    bad.recording.frames = 1;
    bad.recording.max_spp = 1;
    state.animation_export.start(bad);
    let err = state.animation_export.wait().unwrap().clone().unwrap_err();
    assert!(
        err.contains("cannot write") && err.contains("no-such-dir"),
        "{err}"
    );
}

#[test]
fn the_file_menu_exports_an_animation_in_the_background() {
    let dir = scratch("app-animation-menu");
    let path = dir.join("menu.gif");
    let mut harness = app_harness();
    click(&mut harness, "File");
    click(&mut harness, "Export animation…");
    assert!(harness.state().state.animation_export.open);
    {
        let export = &mut harness.state_mut().state.animation_export;
        export.path = path.to_str().unwrap().to_owned();
        export.frames = 2;
        export.max_spp = 2;
    }
    harness.run();
    click(&mut harness, "Export");
    // The export runs on its worker thread; the app collects it when it ends.
    let started = std::time::Instant::now();
    while harness.state().state.animation_export.is_running() {
        assert!(started.elapsed() < HANG_GUARD, "the export did not end");
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.run();
    }
    harness.run();
    let state = &harness.state().state;
    let exported = state
        .animation_export
        .last
        .clone()
        .expect("an export ended")
        .expect("the export succeeded");
    assert_eq!(exported.frames, 2);
    assert_eq!(gif_frames(&path).len(), 2);
    // The status bar and the window say where the file went.
    let (message, _) = state.status.clone().expect("a status message");
    assert!(message.contains("menu.gif"), "{message}");
    assert!(
        harness
            .query_all_by_label_contains("exported animation")
            .count()
            >= 1
    );
}
