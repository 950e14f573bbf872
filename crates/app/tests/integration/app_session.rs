//! Nothing the user made is lost between sessions: a scene of any size comes back (kept
//! beside the session in a compact file), and a session that cannot be read is said in the
//! status bar and kept aside, never dropped in silence.

use lightpick::app::LightpickApp;
use lightpick::app::state::MessageKind;

use crate::common::painted::light_bits;
use crate::common::session::{MemoryStorage, restored_in};
use crate::common::{scratch, step_paused, window};

/// The app's scene's powers and positions as bits.
fn bits(app: &LightpickApp) -> (Vec<u64>, Vec<[u64; 3]>) {
    light_bits(&app.state.built.scene)
}

/// Waits until the app has installed a scene of `n` lights (a build on a worker).
fn wait_for(harness: &mut egui_kittest::Harness<'static, LightpickApp>, n: usize) {
    let deadline = std::time::Instant::now() + crate::common::HANG_GUARD;
    while harness.state().state.built.len() != n || harness.state().state.is_building() {
        assert!(
            std::time::Instant::now() < deadline,
            "the scene never arrived"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
}

#[test]
fn an_edited_large_scene_comes_back_bit_for_bit() {
    let dir = scratch("session-large");
    let mut harness = window(LightpickApp::for_tests(), [1200.0, 800.0]);
    harness.run();
    // 60 000 generated lights (past what the session keeps light by light), one edited.
    harness.state_mut().state.generate(60_000);
    wait_for(&mut harness, 60_000);
    let state = &mut harness.state_mut().state;
    state.edit.powers_mut()[123] = 0.5;
    state.powers_changed();
    wait_for(&mut harness, 60_000);
    while harness.state().state.built.scene.powers.as_slice()[123] != 0.5 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        harness.step();
    }
    step_paused(&mut harness, 1);
    // The app as the window has it, with a session folder.
    let mut cc_storage = MemoryStorage::default();
    let mut app = restored_in(&MemoryStorage::default(), &dir);
    app.state
        .load_scene((*harness.state().state.built.scene).clone());
    app.state.edit.powers_mut()[7] = 1.25;
    app.state.powers_changed();
    while app.state.is_building() {
        std::thread::sleep(std::time::Duration::from_millis(20));
        app.state.poll_build();
    }
    eframe::App::save(&mut app, &mut cc_storage);
    let kept = dir.join(lightpick::app::session_files::SCENE_FILE);
    let size = std::fs::metadata(&kept)
        .expect("the scene is kept beside the session")
        .len();
    assert!(
        (32 * 60_000..32 * 60_000 + 1024).contains(&size),
        "{size} bytes"
    );
    // The next run: the same scene, bit for bit, the edit included.
    let back = restored_in(&cc_storage, &dir);
    assert_eq!(back.state.built.len(), 60_000);
    assert_eq!(bits(&back), bits(&app));
    assert_eq!(back.state.built.scene.powers.as_slice()[7], 1.25);
    assert!(back.state.status.is_none(), "{:?}", back.state.status);
    // A second save of the same scene does not write it again.
    let modified = std::fs::metadata(&kept)
        .and_then(|m| m.modified())
        .expect("time");
    eframe::App::save(&mut app, &mut cc_storage);
    assert_eq!(
        std::fs::metadata(&kept)
            .and_then(|m| m.modified())
            .expect("time"),
        modified
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_damaged_session_is_said_kept_aside_and_the_app_starts_on_defaults() {
    let dir = scratch("session-damaged");
    // A session file cut in half: eframe reads it as empty storage.
    std::fs::write(
        dir.join("app.ron"),
        "{\n    \"lightpick.settings\": \"(spp_per_frame:4,seed:99,pa",
    )
    .expect("written");
    let app = restored_in(&MemoryStorage::default(), &dir);
    let (message, kind) = app.state.status.clone().expect("a message");
    assert_eq!(kind, MessageKind::Error);
    assert!(
        message.starts_with("last session could not be read: "),
        "{message}"
    );
    assert!(
        message.contains("kept as ") && message.contains("app.ron.damaged-"),
        "{message}"
    );
    assert_eq!(app.state.built.scene.powers.as_slice(), [2.0, 5.0, 20.0]);
    let aside: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(aside.len(), 1);
    assert!(aside[0].starts_with("app.ron.damaged-"), "{aside:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_session_from_a_newer_or_an_older_lightpick_is_said() {
    let dir = scratch("session-versions");
    std::fs::write(dir.join("app.ron"), "{}").expect("written");
    // Newer: not read at all.
    let mut storage = MemoryStorage::default();
    storage
        .0
        .insert("lightpick.session_version".to_owned(), "99".to_owned());
    storage
        .0
        .insert("lightpick.scene_preset".to_owned(), "million".to_owned());
    let app = restored_in(&storage, &dir);
    let (message, _) = app.state.status.clone().expect("a message");
    assert!(
        message.contains("written by a newer lightpick"),
        "{message}"
    );
    assert!(message.contains("kept as "), "{message}");
    assert_eq!(
        app.state.built.len(),
        3,
        "defaults, not the newer session's scene"
    );
    // Older: settings that no longer parse are said, the rest is read.
    let mut storage = MemoryStorage::default();
    storage.0.insert(
        "lightpick.settings".to_owned(),
        "(spp_per_frame: \"four\")".to_owned(),
    );
    let app = restored_in(&storage, &dir);
    let (message, _) = app.state.status.clone().expect("a message");
    assert!(message.contains("settings could not be read"), "{message}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_session_whose_file_is_cut_comes_back_from_its_copy() {
    let dir = scratch("session-copy");
    let mut app = restored_in(&MemoryStorage::default(), &dir);
    app.state.settings.seed = 99;
    app.state.settings.spp_per_frame = 4;
    app.state.edit.powers_mut()[0] = 7.0;
    app.state.powers_changed();
    let mut storage = MemoryStorage::default();
    eframe::App::save(&mut app, &mut storage);
    assert!(
        dir.join(lightpick::app::session_files::SESSION_COPY)
            .exists()
    );
    // eframe's own file, cut in half mid-write: eframe would start on empty storage.
    std::fs::write(
        dir.join("app.ron"),
        "{\n    \"lightpick.settings\": \"(spp_per_fr",
    )
    .expect("w");
    let back = restored_in(&MemoryStorage::default(), &dir);
    let (message, _) = back.state.status.clone().expect("a message");
    assert!(
        message.starts_with("last session could not be read: "),
        "{message}"
    );
    assert!(
        message.contains("restored from its copy session.json"),
        "{message}"
    );
    assert_eq!(back.state.settings.seed, 99);
    assert_eq!(back.state.settings.spp_per_frame, 4);
    assert_eq!(back.state.built.scene.powers.as_slice(), [7.0, 5.0, 20.0]);
    let _ = std::fs::remove_dir_all(&dir);
}
