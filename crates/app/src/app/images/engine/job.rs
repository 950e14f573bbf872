//! One scene's CPU rendering: a [`Job`] holds the three runs (uniform, power,
//! spatial), each a `CpuRenderer` over the scene's shared samplers with its totals and
//! convergence series, and the exact reference; it advances a frame (or the worker's batch)
//! and publishes what the panels show.

use std::time::Instant;

use lightpick_core::render::{
    CpuRenderer, Reference, mean_variance_scaled, normalized_variance_per_sample,
    pool_core_seconds, tonemap_rgba8,
};
use lightpick_core::{SceneSamplers, Scheme};

use crate::app::images::published::{
    ConvergencePoint, EngineConfig, Published, RendererBytes, SchemeImage,
};
use crate::app::images::reference::{error_map, error_scale, reference, thin};
use crate::app::state::settings::BudgetMode;

/// Compute time each scheme gets per frame in equal-time mode (on average: the run furthest
/// behind in time runs next, so the totals stay within one pass of each other).
const EQUAL_TIME_SLICE_S: f64 = 0.012;

/// The worker renders passes of every scheme for about this long per frame the window shows.
pub(super) const WORKER_BATCH_S: f64 = 0.012;

/// Virtual seconds per pixel sample in inline mode (deterministic timings for tests): a
/// model of the schemes' relative costs (uniform 1, alias 1.25, spatial 4; the order of
/// `lightpick bench`'s CPU figures), so equal time and equal samples differ in tests too.
fn virtual_seconds_per_sample(scheme: Scheme) -> f64 {
    match scheme {
        Scheme::Alias | Scheme::AliasOneRandom | Scheme::Cdf => 1.25e-8,
        Scheme::Spatial => 4.0e-8,
        Scheme::Uniform => 1.0e-8,
    }
}

/// The device note of the threaded engine.
pub(super) const CPU_NOTE: &str = "CPU renderer";
/// The device note of the inline (test) engine, whose timings are virtual.
pub(super) const INLINE_NOTE: &str = "CPU renderer (inline, virtual time)";

/// Whether a frame published with `device_note` has virtual timings.
fn virtual_time_note(device_note: &str) -> bool {
    device_note == INLINE_NOTE
}

/// One scheme's renderer and totals.
struct SchemeRun {
    scheme: Scheme,
    renderer: CpuRenderer,
    seconds: f64,
    last_frame_seconds: f64,
    series: Vec<ConvergencePoint>,
}

impl SchemeRun {
    fn new(samplers: &SceneSamplers, scheme: Scheme, seed: u64) -> Self {
        Self {
            scheme,
            renderer: CpuRenderer::from_samplers(samplers, scheme, seed),
            seconds: 0.0,
            last_frame_seconds: 0.0,
            series: Vec::new(),
        }
    }

    /// Adds `spp` samples per pixel; returns the core seconds spent: the CPU time of the
    /// render threads in the pass ([`pool_core_seconds`]), which neither the window sharing
    /// the cores nor the pool's size changes (virtual in tests).
    fn run(&mut self, spp: u32, virtual_time: bool, pixels: usize) -> f64 {
        if virtual_time {
            self.renderer.accumulate(spp);
            f64::from(spp) * pixels as f64 * virtual_seconds_per_sample(self.scheme)
        } else {
            pool_core_seconds(|| self.renderer.accumulate(spp)).1
        }
    }
}

/// The state of one scene's rendering.
pub(super) struct Job {
    pub(super) generation: u64,
    pub(super) samplers: SceneSamplers,
    uniform: SchemeRun,
    power: SchemeRun,
    spatial: SchemeRun,
    reference: Reference,
    reference_note: Option<String>,
    frame: u64,
}

impl Job {
    pub(super) fn new(generation: u64, samplers: SceneSamplers, seed: u64) -> Self {
        let (reference, reference_note) = reference(samplers.scene());
        Self {
            generation,
            uniform: SchemeRun::new(&samplers, Scheme::Uniform, seed),
            power: SchemeRun::new(&samplers, Scheme::Alias, seed),
            spatial: SchemeRun::new(&samplers, Scheme::Spatial, seed),
            samplers,
            reference,
            reference_note,
            frame: 0,
        }
    }

    fn pixels(&self) -> usize {
        self.samplers.scene().plane.pixel_count()
    }

    /// What the three runs and the reference hold.
    pub(super) fn bytes(&self) -> RendererBytes {
        let runs = [&self.uniform, &self.power, &self.spatial];
        // Records shared with an earlier run are held once.
        let lights = (0..runs.len())
            .filter(|&k| {
                !runs[..k]
                    .iter()
                    .any(|l| runs[k].renderer.shares_lights_with(&l.renderer))
            })
            .map(|k| runs[k].renderer.light_bytes())
            .sum();
        RendererBytes {
            lights,
            pixels: runs.iter().map(|l| l.renderer.pixel_bytes()).sum::<usize>()
                + self.reference.heap_bytes(),
        }
    }

    /// The worker's frame: [`Job::advance`] again while the batch took less than
    /// [`WORKER_BATCH_S`] (equal samples; an equal-time frame is one advance), so cheap
    /// scenes gain several samples per pixel for each frame the window shows. Returns the
    /// seconds the batch took.
    pub(super) fn advance_batch(&mut self, config: &EngineConfig) -> f64 {
        let started = Instant::now();
        loop {
            self.advance(config, false);
            let elapsed = started.elapsed().as_secs_f64();
            if config.budget == BudgetMode::EqualTime || elapsed >= WORKER_BATCH_S {
                return elapsed;
            }
        }
    }

    /// Accumulates one frame of every scheme: the same samples per pixel each (equal
    /// samples), or the same time each (equal time, [`Job::advance_equal_time`]).
    pub(super) fn advance(&mut self, config: &EngineConfig, virtual_time: bool) {
        let pixels = self.pixels();
        let mut spent = [0.0; 3];
        match config.budget {
            BudgetMode::EqualSamples => {
                // Rotate which scheme goes first, so none is always timed right after the
                // window's own frame work (a bias in the time per frame on a loaded machine).
                let first = (self.frame % 3) as usize;
                for k in (0..3).map(|j| (j + first) % 3) {
                    let run = self.run_mut(k);
                    spent[k] = run.run(config.spp_per_frame.max(1), virtual_time, pixels);
                    run.seconds += spent[k];
                }
            }
            BudgetMode::EqualTime => spent = self.advance_equal_time(virtual_time, pixels),
        }
        let reference = &self.reference;
        for (run, spent) in [&mut self.uniform, &mut self.power, &mut self.spatial]
            .into_iter()
            .zip(spent)
        {
            run.last_frame_seconds = spent;
            let acc = run.renderer.accumulator();
            run.series.push(ConvergencePoint {
                spp: acc.samples_per_pixel,
                seconds: run.seconds,
                rmse: lightpick_core::render::rmse(acc, reference),
            });
            thin(&mut run.series);
        }
    }

    /// Equal time: one pass at a time of the run with the least time so far (ties to the
    /// first), until the frame has spent three slices ([`EQUAL_TIME_SLICE_S`]; in virtual
    /// time three passes of the dearest scheme). Every run's total time then stays within
    /// one of its passes of the others': a scheme whose pass costs a tenth gets about ten
    /// times the samples. Returns each run's seconds this frame.
    fn advance_equal_time(&mut self, virtual_time: bool, pixels: usize) -> [f64; 3] {
        let budget = if virtual_time {
            let dearest = [Scheme::Uniform, Scheme::Alias, Scheme::Spatial]
                .map(virtual_seconds_per_sample)
                .into_iter()
                .fold(0.0, f64::max);
            3.0 * dearest * pixels as f64
        } else {
            3.0 * EQUAL_TIME_SLICE_S
        };
        let mut spent = [0.0; 3];
        loop {
            let behind = (0..3)
                .min_by(|&a, &b| self.run(a).seconds.total_cmp(&self.run(b).seconds))
                .unwrap_or(0);
            let run = self.run_mut(behind);
            let seconds = run.run(1, virtual_time, pixels);
            run.seconds += seconds;
            spent[behind] += seconds;
            // A pass that measured no time (a clock's resolution) still counts as work done.
            if spent.iter().sum::<f64>() >= budget || seconds <= 0.0 {
                return spent;
            }
        }
    }

    /// Run `k`: uniform, power, spatial.
    fn run(&self, k: usize) -> &SchemeRun {
        match k {
            0 => &self.uniform,
            1 => &self.power,
            _ => &self.spatial,
        }
    }

    /// Run `k`, mutably.
    fn run_mut(&mut self, k: usize) -> &mut SchemeRun {
        match k {
            0 => &mut self.uniform,
            1 => &mut self.power,
            _ => &mut self.spatial,
        }
    }

    pub(super) fn publish(&mut self, config: &EngineConfig, device_note: &str) -> Published {
        self.frame += 1;
        let reference = &self.reference;
        let full = reference.image();
        let exposure = config.exposure;
        let error_scale = full.map(error_scale);
        let scheme_image = |run: &SchemeRun| {
            let acc = run.renderer.accumulator();
            let image = acc.image();
            SchemeImage {
                rgba: tonemap_rgba8(&image, exposure),
                error_rgba: full
                    .zip(error_scale)
                    .map(|(r, scale)| error_map(&image, r, scale)),
                spp: acc.samples_per_pixel,
                pass_progress: 0.0,
                seconds: run.seconds,
                last_frame_seconds: run.last_frame_seconds,
                rmse: Some(lightpick_core::render::rmse(acc, reference)),
                variance: mean_variance_scaled(acc),
                normalized_variance: normalized_variance_per_sample(acc),
                series: run.series.clone(),
            }
        };
        Published {
            generation: self.generation,
            frame: self.frame,
            width: self.samplers.scene().plane.width,
            height: self.samplers.scene().plane.height,
            light_count: self.samplers.scene().light_count(),
            uniform: scheme_image(&self.uniform),
            power: scheme_image(&self.power),
            spatial: scheme_image(&self.spatial),
            reference_rgba: full.map(|r| tonemap_rgba8(r, exposure)),
            reference_note: self.reference_note.clone(),
            device_note: device_note.to_owned(),
            time_source: if virtual_time_note(device_note) {
                "virtual time (inline test engine: 10, 12.5 and 40 ns per pixel sample for \
                 uniform, alias and spatial)"
                    .to_owned()
            } else {
                format!(
                    "CPU core time per pixel sample: the CPU time of the {} render thread(s) in \
                     each scheme's pass (not the window's), excluding tonemap and error maps; \
                     `lightpick bench`'s \"core ns\"",
                    rayon::current_num_threads()
                )
            },
        }
    }
}
