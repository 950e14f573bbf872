//! The app's GPU image path (`gpu_images.rs`): the three renderers on eframe's own wgpu device
//! (kittest's, here: lavapipe without a GPU), shown as native textures and read back for the
//! error figures. With the same seed they must give the CPU engine's numbers.
//!
//! Like every GPU test this fails, never skips, when no adapter exists, unless
//! `LIGHTPICK_SKIP_GPU_TESTS=1` is set.

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use lightpick::app::LightpickApp;
use lightpick::app::images::Published;
use lightpick::app::state::FileAction;
use lightpick_core::Scheme;
use lightpick_core::render::{CpuRenderer, Reference, rmse};

use crate::common::{HANG_GUARD, gpu_expected, scratch, step_paused, wgpu_eframe};

/// The whole app on kittest's wgpu device, paused, on the worked example.
fn gpu_app() -> Harness<'static, LightpickApp> {
    let mut harness = wgpu_eframe([1280.0, 800.0]);
    harness.run();
    harness
}

/// The app running (not paused) on `heavy-tail` at 512×512: 10^4 lights, the spatial run a
/// 14-level tree whose sample pass costs more than a frame allows on lavapipe.
fn running_on_a_costly_scene() -> Harness<'static, LightpickApp> {
    let mut harness = gpu_app();
    let mut scene = lightpick::app::scene_io::preset("heavy-tail").expect("preset");
    scene.plane.width = 512;
    scene.plane.height = 512;
    harness.state_mut().state.load_scene(scene);
    harness.state_mut().state.settings.paused = false;
    harness
}

/// Steps `frames` frames, then runs until the reference (a worker thread) has arrived and the
/// latest frame carries every RMSE.
fn step_until_measured(harness: &mut Harness<'static, LightpickApp>, frames: usize) -> Published {
    step_paused(harness, frames);
    let deadline = Instant::now() + HANG_GUARD;
    loop {
        harness.state_mut().step();
        harness.run();
        let latest = harness.state_mut().published().expect("a GPU frame");
        if latest.uniform.rmse.is_some() && latest.spatial.rmse.is_some() {
            return (*latest).clone();
        }
        assert!(Instant::now() < deadline, "the reference never arrived");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Asserts that each of `schemes`' GPU images has the RMSE the CPU renderer reaches, within
/// 1e-3 relative, with the app's scene, its shared table and tree (the table the panels
/// show) and seed at the image's spp.
fn assert_cpu_rmses(
    harness: &Harness<'static, LightpickApp>,
    published: &Published,
    schemes: &[Scheme],
) {
    let app = harness.state();
    let samplers = app.state.built.samplers.clone();
    let seed = app.state.settings.seed;
    let reference = Reference::compute(samplers.scene());
    let spp = published.uniform.spp;
    for &scheme in schemes {
        let image = match scheme {
            Scheme::Uniform => &published.uniform,
            Scheme::Alias => &published.power,
            Scheme::Spatial => &published.spatial,
            other => panic!("no GPU image of {other:?}"),
        };
        let mut r = CpuRenderer::from_samplers(&samplers, scheme, seed);
        r.accumulate(spp);
        let cpu = rmse(r.accumulator(), &reference);
        let gpu = image.rmse.expect("rmse");
        assert!(
            (gpu - cpu).abs() <= 1e-3 * cpu,
            "{scheme:?} at {spp} spp: GPU RMSE {gpu} vs CPU {cpu}"
        );
    }
}

#[test]
fn the_gpu_renders_the_three_images_with_the_cpu_engines_numbers() {
    if !gpu_expected() {
        return;
    }
    let mut harness = gpu_app();
    let published = step_until_measured(&mut harness, 4);
    assert!(
        published.device_note.starts_with("GPU: "),
        "the GPU renders the images: {}",
        published.device_note
    );
    let spp = published.uniform.spp;
    assert!(spp >= 5, "{spp} spp after at least 5 steps");
    assert_eq!(published.power.spp, spp);
    assert_eq!(published.spatial.spp, spp);

    // Same picks (the RNG and the pick are bit for bit the CPU's); the per-pixel f32
    // estimates and sums differ by ~1e-6 relative, so the RMSEs agree far within 1e-3.
    assert_cpu_rmses(&harness, &published, &[Scheme::Uniform, Scheme::Alias]);
    // Three lights: the exact contribution pick, whose only error on the GPU is f32 rounding.
    let uniform = published.uniform.rmse.expect("rmse");
    let spatial = published.spatial.rmse.expect("rmse");
    assert!(spatial <= 1e-4 * uniform, "spatial GPU RMSE {spatial}");
    assert!(published.power.error_rgba.is_some(), "error maps read back");
}

#[test]
fn equal_time_mode_runs_on_the_gpu_too() {
    if !gpu_expected() {
        return;
    }
    let mut harness = gpu_app();
    harness.state_mut().state.settings.budget = lightpick::app::state::BudgetMode::EqualTime;
    let published = step_until_measured(&mut harness, 6);
    assert!(published.device_note.starts_with("GPU: "));
    assert!(
        !published.device_note.contains("CPU only"),
        "{}",
        published.device_note
    );
    for image in [&published.uniform, &published.power, &published.spatial] {
        assert!(image.spp >= 7, "every run advances: {} spp", image.spp);
        assert!(image.seconds > 0.0);
    }
}

/// Exporting the images while the GPU renders them reads the native textures' sums back
/// (the images are not on the CPU otherwise) and writes the full sheet.
#[test]
fn exporting_reads_the_gpu_images_back() {
    if !gpu_expected() {
        return;
    }
    let mut harness = gpu_app();
    let published = step_until_measured(&mut harness, 2);
    assert!(published.uniform.rgba.is_empty(), "native textures only");
    let path = scratch("gpu-export").join("images.png");
    let path_text = path.to_str().expect("utf-8 path").to_owned();
    harness
        .state_mut()
        .file_action(FileAction::ExportImages, &path_text, None);
    let sheet = image::open(&path).expect("the PNG was written").to_rgba8();
    let _ = std::fs::remove_file(&path);
    let (w, h) = (published.width, published.height);
    // A caption band (scheme, spp, RMSE) over the two rows of images.
    assert_eq!(sheet.width(), 4 * w);
    let band = sheet.height() - 2 * h;
    assert!((20..=48).contains(&band), "caption band of {band} px");
    // The worked example lights the middle of every image: not black.
    for column in 0..3 {
        let p = sheet.get_pixel(column * w + w / 2, band + h / 2);
        assert!(p[0] > 0 || p[1] > 0 || p[2] > 0, "image {column} is black");
    }
}

/// Running (not stepping), each frame gets the GPU work its budget allows: whole passes or a
/// band of rows of one. Either way every run stays at equal samples per pixel and draws
/// exactly the samples of whole passes, so the figures read back at pass boundaries are the
/// CPU renderer's at that spp. `heavy-tail` at 512×512: 10^4 lights, the spatial run a
/// 14-level tree whose pass costs more than a frame allows on lavapipe, so bands are used.
#[test]
fn running_frames_within_the_budget_give_the_cpu_numbers() {
    if !gpu_expected() {
        return;
    }
    let mut harness = running_on_a_costly_scene();
    let deadline = Instant::now() + HANG_GUARD;
    let mut banded = false;
    let published = loop {
        harness.step();
        let latest = harness.state_mut().published();
        banded |= latest.as_ref().is_some_and(|p| {
            let progress = [&p.uniform, &p.power, &p.spatial].map(|i| i.pass_progress);
            // Equal samples: every run is at the same row of the same pass.
            assert!(progress.iter().all(|&f| f == progress[0]), "{progress:?}");
            progress[0] > 0.0
        });
        if let Some(p) = latest.filter(|p| {
            p.generation == harness.state().state.built.generation
                && p.uniform.spp >= 3
                && [&p.uniform, &p.power, &p.spatial]
                    .iter()
                    .all(|i| i.rmse.is_some() && i.series.last().is_some_and(|s| s.spp == i.spp))
        }) {
            break (*p).clone();
        }
        assert!(Instant::now() < deadline, "the images never reached 3 spp");
    };
    eprintln!("row bands used: {banded}");
    let spp = published.uniform.spp;
    assert_eq!(published.power.spp, spp);
    assert_eq!(published.spatial.spp, spp);
    assert_cpu_rmses(
        &harness,
        &published,
        &[Scheme::Uniform, Scheme::Alias, Scheme::Spatial],
    );
}

/// Exporting while a costly pass is spread over frames (row bands) completes the pass first:
/// the sums of a pass in progress cannot be read, and an image must have one sample count.
#[test]
fn exporting_in_the_middle_of_a_pass_completes_it() {
    if !gpu_expected() {
        return;
    }
    let mut harness = running_on_a_costly_scene();
    // Run until a pass is in progress (on lavapipe the tree's pass never fits in a frame;
    // a fast GPU may fit every pass, so after a minute the export runs between passes: the
    // verdict below holds either way, this wait only makes the harder case likely).
    let deadline = Instant::now() + Duration::from_mins(1);
    let mid_pass = loop {
        harness.step();
        let latest = harness.state_mut().published();
        if let Some(p) = latest.filter(|p| p.generation == harness.state().state.built.generation)
            && p.uniform.spp >= 1
            && (p.spatial.pass_progress > 0.0 || Instant::now() > deadline)
        {
            break p.spatial.pass_progress > 0.0;
        }
    };
    eprintln!("exporting in the middle of a pass: {mid_pass}");
    harness.state_mut().state.settings.paused = true;
    let path = scratch("mid-pass").join("images.png");
    let path_text = path.to_str().expect("utf-8 path").to_owned();
    harness
        .state_mut()
        .file_action(FileAction::ExportImages, &path_text, None);
    let status = harness.state().state.status.clone();
    let sheet = image::open(&path).unwrap_or_else(|e| panic!("not written ({e}): {status:?}"));
    let _ = std::fs::remove_file(&path);
    // 10^4 lights × 512² pixels exceeds the reference budget: the reference is a pixel
    // subset, so there is no reference image and no error maps, only the three images.
    assert_eq!(sheet.width(), 3 * 512);
    assert!(
        (512 + 20..=512 + 48).contains(&sheet.height()),
        "one row of images under a caption band: {}",
        sheet.height()
    );
    let (message, _) = status.expect("a status message");
    assert!(message.contains("exported"), "{message}");
}
