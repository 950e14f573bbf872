//! The app's time per sample is the bench's: the GPU images time their passes as
//! `lightpick bench` does (`gpu::measure_passes`, the device's own clock), so on the same
//! scene and device the app's `T` per scheme agrees with the bench path's within 1.5×, and
//! the ratios between schemes within 1.3× (the issue that asked for this saw spatial look
//! 4× more efficient than importance in the app while the bench measured 0.3×).
//!
//! Timing on a shared machine is noisy, so these tests have a test binary of their own and
//! take the machine in turn (`crate::machine`); both sides take the fastest of several
//! frames of 32 samples per pixel (a uniform pass of ~40 ms: long against lavapipe's thread
//! wake-ups), interleaved (a busy moment slows both), after the app's reference (computed on
//! a worker thread) has arrived; and a measurement outside the bounds is taken again, up to three
//! times in all: a busy moment passes, a clock that measures the wrong thing does not. The
//! scene is `heavy-tail` (10^4 lights, 256×256), where a spatial pass costs ~20 uniform ones:
//! a clock that counted other queued work would move the ratios far outside the bounds.
//! Fails, never skips, without an adapter (unless `LIGHTPICK_SKIP_GPU_TESTS=1`).

use std::sync::Arc;

use egui_kittest::Harness;
use lightpick::app::LightpickApp;
use lightpick::app::images::SchemeImage;
use lightpick_core::Scheme;
use lightpick_core::gpu::{self, GpuContext};

const ROUNDS: usize = 7;

/// The app on kittest's adapter with the device the app itself asks for (timestamps
/// included when the adapter has them), paused on `heavy-tail`.
fn app_on_heavy_tail() -> Harness<'static, LightpickApp> {
    let mut setup = egui_kittest::wgpu::default_wgpu_setup();
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(create) = &mut setup {
        create.device_descriptor = Arc::new(lightpick::app::device_descriptor);
    }
    let mut harness = Harness::builder()
        .with_size([1280.0, 800.0])
        .wgpu_setup(setup)
        .build_eframe(|_cc| LightpickApp::for_tests_on("heavy-tail"));
    harness.run();
    harness
}

/// The app's seconds per pixel sample of the last frame's pass, per scheme.
fn app_frame_t(image: &SchemeImage, pixels: f64, spp: u32) -> f64 {
    image.last_frame_seconds / (pixels * f64::from(spp))
}

/// Samples per pixel each run adds per frame (and the bench per measurement).
const SPP: u32 = 32;
/// Measurements of the whole comparison before the bounds are declared missed.
const ATTEMPTS: usize = 3;

/// The fastest `T` per scheme (uniform, alias, spatial) of the app and of the bench path over
/// [`ROUNDS`] interleaved rounds.
fn measure(app: &mut Harness<'static, LightpickApp>, ctx: &GpuContext) -> ([f64; 3], [f64; 3]) {
    let scene = app.state().state.built.scene.clone();
    let seed = app.state().state.settings.seed;
    let pixels = scene.plane.pixel_count() as f64;
    let mut app_t = [f64::INFINITY; 3];
    let mut bench_t = [f64::INFINITY; 3];
    for _ in 0..ROUNDS {
        app.state_mut().step();
        app.run();
        let published = app.state_mut().published().expect("a GPU frame");
        assert!(
            published.device_note.starts_with("GPU: "),
            "{}",
            published.device_note
        );
        for (k, image) in [&published.uniform, &published.power, &published.spatial]
            .into_iter()
            .enumerate()
        {
            app_t[k] = app_t[k].min(app_frame_t(image, pixels, SPP));
        }
        for (k, scheme) in SCHEMES.into_iter().enumerate() {
            let m =
                gpu::measure_passes(ctx, &scene, scheme, seed, SPP, 0.0, SPP).expect("bench pass");
            bench_t[k] = bench_t[k].min(m.seconds_per_sample);
        }
    }
    (app_t, bench_t)
}

const SCHEMES: [Scheme; 3] = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial];

/// Why the app's and the bench's `T` disagree beyond the bounds, if they do.
fn disagreement(app_t: [f64; 3], bench_t: [f64; 3]) -> Option<String> {
    for k in 0..3 {
        let ratio = app_t[k] / bench_t[k];
        if !(1.0 / 1.5..=1.5).contains(&ratio) {
            return Some(format!(
                "{:?}: app {:.3e} s vs bench {:.3e} s per sample",
                SCHEMES[k], app_t[k], bench_t[k]
            ));
        }
    }
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let app_ratio = app_t[b] / app_t[a];
        let bench_ratio = bench_t[b] / bench_t[a];
        if !(1.0 / 1.3..=1.3).contains(&(app_ratio / bench_ratio)) {
            return Some(format!(
                "T({:?})/T({:?}): app {app_ratio:.3}, bench {bench_ratio:.3}",
                SCHEMES[b], SCHEMES[a]
            ));
        }
    }
    None
}

#[test]
fn the_apps_time_per_sample_is_the_benchs() {
    if !crate::common::gpu_expected() {
        return;
    }
    let _machine = crate::machine();
    let mut app = app_on_heavy_tail();
    app.state_mut().state.settings.spp_per_frame = SPP;
    let ctx = GpuContext::new().expect("a wgpu adapter (lavapipe in CI)");
    // The reference is computed on a worker thread (a second of both cores on this scene):
    // time nothing while it runs.
    let deadline = std::time::Instant::now() + crate::common::HANG_GUARD;
    loop {
        app.state_mut().step();
        app.run();
        let published = app.state_mut().published().expect("a GPU frame");
        if published.uniform.rmse.is_some() {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the reference never arrived"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let mut last = String::new();
    for attempt in 1..=ATTEMPTS {
        let (app_t, bench_t) = measure(&mut app, &ctx);
        eprintln!("attempt {attempt}: T per sample (s), app {app_t:?}, bench {bench_t:?}");
        match disagreement(app_t, bench_t) {
            None => return,
            Some(why) => last = why,
        }
    }
    panic!("the app's time per sample disagrees with the bench's: {last}");
}

/// The CPU images' engine (its worker thread and render pool, as in the app) measures the
/// core time per sample that `lightpick bench`'s "as the app renders it" rows measure
/// (`measure_cpu_passes`: the render threads' CPU clocks), on the same scene and table.
///
/// Core time is what a thread ran, but on a loaded machine even that varies (a busy
/// sibling hyperthread or a shared cache slows every instruction; measured here under two
/// busy loops: the bench's alias T moved 1.8e-8 – 3.0e-8 between runs). So the two sides are
/// measured interleaved, never at once: in each round the engine runs alone for a window of
/// 8 samples per pixel (its `T` over the window, from the published core seconds and
/// samples), then is paused while the bench path measures alone; each side keeps its
/// fastest round. A load slows both sides' rounds alike; a clock that counted the wrong
/// thing, the wall time or the window's work would still be off by 2× or more.
#[test]
fn the_cpu_engines_time_per_sample_is_the_benchs() {
    use lightpick::app::images::{Engine, EngineConfig, Published};
    use lightpick::app::state::{BudgetMode, Built};
    use lightpick_core::render::measure_cpu_passes;

    let _machine = crate::machine();
    let scene = lightpick_core::scene::Scene::preset("heavy-tail").expect("preset");
    let built = Built::new(1, scene);
    let pixels = built.scene.plane.pixel_count() as f64;
    let ctx = egui::Context::default();
    let mut engine = Engine::threaded(&ctx);
    assert!(engine.is_threaded());
    let config = |running| EngineConfig {
        spp_per_frame: 1,
        budget: BudgetMode::EqualSamples,
        exposure: 1.0,
        seed: 1,
        running,
    };
    engine.sync_config(config(true));
    engine.sync_scene(built.generation, &built.samplers, false);
    let images = |p: &Published| [p.uniform.clone(), p.power.clone(), p.spatial.clone()];
    // The latest frame once the engine has published `at_least` spp of every image.
    let wait_for = |engine: &mut Engine, at_least: u32| {
        let deadline = std::time::Instant::now() + crate::common::HANG_GUARD;
        loop {
            if let Some(p) = engine.latest()
                && p.uniform.spp.min(p.power.spp).min(p.spatial.spp) >= at_least
            {
                return p;
            }
            assert!(std::time::Instant::now() < deadline, "the engine stalled");
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
    };
    // Pauses the engine and waits until its worker has published its last frame.
    let pause = |engine: &mut Engine| {
        engine.sync_config(config(false));
        let deadline = std::time::Instant::now() + crate::common::HANG_GUARD;
        let mut last = engine.latest().map(|p| p.frame);
        loop {
            std::thread::sleep(std::time::Duration::from_millis(100));
            let now = engine.latest().map(|p| p.frame).or(last);
            if now == last {
                return;
            }
            last = now;
            assert!(
                std::time::Instant::now() < deadline,
                "the engine never paused"
            );
        }
    };
    // The reference and a first frame, so that no round times the start-up.
    let _ = wait_for(&mut engine, 1);
    let mut last = String::new();
    for attempt in 1..=ATTEMPTS {
        let mut app_t = [f64::INFINITY; 3];
        let mut bench_t = [f64::INFINITY; 3];
        for _ in 0..ROUNDS {
            engine.sync_config(config(true));
            let start = wait_for(&mut engine, 0);
            let spp0 = start.spatial.spp.max(start.uniform.spp);
            let end = wait_for(&mut engine, spp0 + 8);
            pause(&mut engine);
            for (k, (a, b)) in images(&start).iter().zip(images(&end).iter()).enumerate() {
                let samples = f64::from(b.spp - a.spp) * pixels;
                app_t[k] = app_t[k].min((b.seconds - a.seconds) / samples);
            }
            for (k, scheme) in SCHEMES.into_iter().enumerate() {
                let m = measure_cpu_passes(&built.samplers, scheme, 1, 1, 0.25, 256);
                bench_t[k] = bench_t[k].min(m.core_seconds_per_sample);
            }
        }
        eprintln!("attempt {attempt}: CPU core T per sample (s), app {app_t:?}, bench {bench_t:?}");
        match disagreement(app_t, bench_t) {
            None => return,
            Some(why) => last = why,
        }
    }
    panic!("the CPU engine's time per sample disagrees with the bench's: {last}");
}
