//! Where the progressive images render: on the window's wgpu device or on the CPU renderer's
//! worker thread.
//!
//! On a real GPU the device wins without asking. On a software rasterizer
//! (`AdapterInfo::device_type == Cpu`: llvmpipe / lavapipe) both choices run on the same
//! cores, and the GPU runs also share the UI thread's frame (their work waits inside it),
//! so which is faster depends on the scene and the machine: in `Auto` the app measures it.
//! While the images run it renders [`TRIAL_SECONDS`] on the GPU, then as long on the CPU,
//! counting the samples per pixel each image gains per second (the mean of the three
//! images), and keeps the faster one for the rest of the session. `Gpu` and `Cpu` choose by
//! hand.
//!
//! Except on a large scene: above [`TRIAL_MAX_LIGHTS`] lights `Auto` on a software adapter
//! takes the CPU without a trial. The GPU runs would upload about 47 bytes per light, and a
//! software device (lavapipe) gives a dropped buffer's memory back only with the device, so
//! a trial would leave that memory resident for the rest of the session whichever renderer
//! won — and on this kind of adapter the GPU runs share the CPU's cores anyway (on the
//! development machine the trial measured the CPU 4.4× faster even on three lights).

use std::time::Instant;

use crate::app::state::settings::Device;

/// The most lights a scene may have for `Auto` to try the software GPU on it (4 MB of GPU
/// runs at about 47 bytes per light).
pub const TRIAL_MAX_LIGHTS: usize = 1 << 17;

/// Seconds of running images each candidate is measured for.
pub const TRIAL_SECONDS: f64 = 1.5;

/// Where the images render this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    /// The GPU runs on eframe's device.
    Gpu,
    /// The CPU renderer on its worker thread.
    Cpu,
}

/// One candidate being measured.
#[derive(Clone, Copy, Debug)]
struct Trial {
    renderer: Renderer,
    /// When and at which total spp (three images) the measurement started, once a frame
    /// of this renderer was seen.
    start: Option<(Instant, f64)>,
}

/// The measured choice (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct RendererChoice {
    trial: Option<Trial>,
    /// Measured spp per second of the GPU and the CPU, once known.
    gpu_rate: Option<f64>,
    cpu_rate: Option<f64>,
    decided: Option<Renderer>,
    /// The light count that made `Auto` take the CPU without a trial, when it did.
    skipped_for: Option<usize>,
}

/// What the adapter is, as far as the choice cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Adapter {
    /// No usable wgpu compute device (or it failed).
    None,
    /// A software rasterizer on the CPU's cores.
    Software,
    /// A hardware GPU.
    Hardware,
}

impl RendererChoice {
    /// Whether `Auto` on a software adapter is still measuring which renderer is faster:
    /// until it decides, both keep their images (the app drops the idle one's afterwards).
    pub fn is_measuring(&self, device: Device, adapter: Adapter) -> bool {
        device == Device::Auto && adapter == Adapter::Software && self.decided.is_none()
    }

    /// Takes the CPU without a trial in `Auto` on a software adapter while undecided, when
    /// the scene has more than [`TRIAL_MAX_LIGHTS`] lights (see the module docs).
    pub fn skip_trial_on_large_scene(&mut self, device: Device, adapter: Adapter, lights: usize) {
        if self.is_measuring(device, adapter) && lights > TRIAL_MAX_LIGHTS {
            self.decided = Some(Renderer::Cpu);
            self.trial = None;
            self.skipped_for = Some(lights);
        }
    }

    /// The renderer for this frame under `device` on `adapter`.
    pub fn renderer(&self, device: Device, adapter: Adapter) -> Renderer {
        match (device, adapter) {
            (_, Adapter::None) | (Device::Cpu, _) => Renderer::Cpu,
            (Device::Gpu, _) | (Device::Auto, Adapter::Hardware) => Renderer::Gpu,
            (Device::Auto, Adapter::Software) => self
                .decided
                .or(self.trial.map(|t| t.renderer))
                .unwrap_or(Renderer::Gpu),
        }
    }

    /// Feeds one frame: `total_spp` is the mean of the three images' samples per pixel
    /// (with the fraction of a pass in progress) of the renderer that produced the latest
    /// frame, `None` before it produced one; `running` whether the images accumulate.
    /// Advances the measurement in `Auto` on a software adapter.
    pub fn observe(
        &mut self,
        device: Device,
        adapter: Adapter,
        shown: Renderer,
        total_spp: Option<f64>,
        running: bool,
        now: Instant,
    ) {
        if device != Device::Auto || adapter != Adapter::Software || self.decided.is_some() {
            return;
        }
        let trial = self.trial.get_or_insert(Trial {
            renderer: Renderer::Gpu,
            start: None,
        });
        if !running || shown != trial.renderer {
            // Paused, or the other renderer's frame is still on screen: measure afresh.
            trial.start = None;
            return;
        }
        let Some(spp) = total_spp else {
            return;
        };
        let Some((started, spp0)) = trial.start else {
            trial.start = Some((now, spp));
            return;
        };
        if spp < spp0 {
            // A restart (new scene or reset): measure from here.
            trial.start = Some((now, spp));
            return;
        }
        let elapsed = (now - started).as_secs_f64();
        if elapsed < TRIAL_SECONDS {
            return;
        }
        let rate = (spp - spp0) / elapsed;
        match trial.renderer {
            Renderer::Gpu => {
                self.gpu_rate = Some(rate);
                self.trial = Some(Trial {
                    renderer: Renderer::Cpu,
                    start: None,
                });
            }
            Renderer::Cpu => {
                self.cpu_rate = Some(rate);
                let gpu = self.gpu_rate.unwrap_or(0.0);
                self.decided = Some(if rate > gpu {
                    Renderer::Cpu
                } else {
                    Renderer::Gpu
                });
                self.trial = None;
            }
        }
    }

    /// The status bar's words for the choice: where, and why.
    pub fn describe(&self, device: Device, adapter: Adapter, adapter_name: &str) -> String {
        let here = match self.renderer(device, adapter) {
            Renderer::Gpu => format!("GPU ({adapter_name})"),
            Renderer::Cpu => "CPU renderer".to_owned(),
        };
        let why = match (device, adapter) {
            (_, Adapter::None) => "no wgpu compute device".to_owned(),
            (Device::Gpu | Device::Cpu, _) => "chosen by hand".to_owned(),
            (Device::Auto, Adapter::Hardware) => "auto: a hardware GPU".to_owned(),
            (Device::Auto, Adapter::Software) if self.skipped_for.is_some() => format!(
                "auto: no trial of the software GPU on {} lights, whose memory it would keep",
                self.skipped_for.unwrap_or(0)
            ),
            (Device::Auto, Adapter::Software) => match (self.decided, self.gpu_rate) {
                (Some(_), Some(gpu)) => format!(
                    "auto, measured: {} spp/s per image on the CPU, {} on the software GPU",
                    rate_text(self.cpu_rate.unwrap_or(0.0)),
                    rate_text(gpu)
                ),
                (None, _) => format!(
                    "auto: measuring the {} (software GPU adapter)",
                    match self.renderer(device, adapter) {
                        Renderer::Gpu => "GPU",
                        Renderer::Cpu => "CPU",
                    }
                ),
                (Some(_), None) => "auto".to_owned(),
            },
        };
        format!("images on the {here} ({why})")
    }

    /// The measured samples per pixel per second (per image) of the GPU and the CPU, when
    /// measured.
    pub fn rates(&self) -> (Option<f64>, Option<f64>) {
        (self.gpu_rate, self.cpu_rate)
    }
}

/// A rate with three significant digits ("55.3", "0.412", "1234").
fn rate_text(rate: f64) -> String {
    if rate >= 100.0 || rate <= 0.0 {
        format!("{rate:.0}")
    } else {
        let decimals = (2 - rate.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{rate:.decimals$}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(start: Instant, s: f64) -> Instant {
        start + Duration::from_secs_f64(s)
    }

    #[test]
    fn a_large_scene_takes_the_cpu_without_a_trial_on_a_software_adapter() {
        let mut p = RendererChoice::default();
        p.skip_trial_on_large_scene(Device::Auto, Adapter::Software, TRIAL_MAX_LIGHTS);
        assert!(
            p.is_measuring(Device::Auto, Adapter::Software),
            "small enough to try"
        );
        assert_eq!(p.renderer(Device::Auto, Adapter::Software), Renderer::Gpu);
        p.skip_trial_on_large_scene(Device::Auto, Adapter::Software, TRIAL_MAX_LIGHTS + 1);
        assert!(!p.is_measuring(Device::Auto, Adapter::Software));
        assert_eq!(p.renderer(Device::Auto, Adapter::Software), Renderer::Cpu);
        assert!(
            p.describe(Device::Auto, Adapter::Software, "llvmpipe")
                .contains("no trial of the software GPU on 131073 lights")
        );
        // By hand, and on hardware, nothing changes.
        let mut q = RendererChoice::default();
        q.skip_trial_on_large_scene(Device::Gpu, Adapter::Software, 1 << 20);
        assert_eq!(q.renderer(Device::Gpu, Adapter::Software), Renderer::Gpu);
        q.skip_trial_on_large_scene(Device::Auto, Adapter::Hardware, 1 << 20);
        assert_eq!(q.renderer(Device::Auto, Adapter::Hardware), Renderer::Gpu);
    }

    #[test]
    fn hand_choices_and_hardware_skip_the_measurement() {
        let p = RendererChoice::default();
        assert_eq!(p.renderer(Device::Cpu, Adapter::Hardware), Renderer::Cpu);
        assert_eq!(p.renderer(Device::Gpu, Adapter::Software), Renderer::Gpu);
        assert_eq!(p.renderer(Device::Auto, Adapter::Hardware), Renderer::Gpu);
        assert_eq!(p.renderer(Device::Auto, Adapter::None), Renderer::Cpu);
    }

    #[test]
    fn auto_on_software_measures_both_and_keeps_the_faster() {
        let mut p = RendererChoice::default();
        let t0 = Instant::now();
        let (auto, sw) = (Device::Auto, Adapter::Software);
        assert_eq!(p.renderer(auto, sw), Renderer::Gpu);
        // GPU: 3 spp/s over 1.5 s (a pause in between restarts the clock).
        p.observe(auto, sw, Renderer::Gpu, Some(0.0), true, t0);
        p.observe(auto, sw, Renderer::Gpu, Some(1.0), false, at(t0, 0.5));
        p.observe(auto, sw, Renderer::Gpu, Some(1.0), true, at(t0, 1.0));
        p.observe(auto, sw, Renderer::Gpu, Some(5.5), true, at(t0, 2.5));
        assert_eq!(p.rates().0, Some(3.0));
        assert_eq!(p.renderer(auto, sw), Renderer::Cpu);
        // The GPU's last frame is still shown: not a CPU measurement.
        p.observe(auto, sw, Renderer::Gpu, Some(5.5), true, at(t0, 2.6));
        p.observe(auto, sw, Renderer::Cpu, Some(0.0), true, at(t0, 2.7));
        p.observe(auto, sw, Renderer::Cpu, Some(45.0), true, at(t0, 4.2));
        assert_eq!(p.rates(), (Some(3.0), Some(30.0)));
        assert_eq!(p.renderer(auto, sw), Renderer::Cpu);
        assert!(
            p.describe(auto, sw, "llvmpipe")
                .contains("30.0 spp/s per image on the CPU, 3.00 on"),
            "{}",
            p.describe(auto, sw, "llvmpipe")
        );
        // Decided: later frames change nothing.
        p.observe(auto, sw, Renderer::Cpu, Some(46.0), true, at(t0, 9.0));
        assert_eq!(p.renderer(auto, sw), Renderer::Cpu);
    }

    #[test]
    fn the_gpu_is_kept_when_it_is_faster() {
        let mut p = RendererChoice::default();
        let t0 = Instant::now();
        let (auto, sw) = (Device::Auto, Adapter::Software);
        p.observe(auto, sw, Renderer::Gpu, Some(0.0), true, t0);
        p.observe(auto, sw, Renderer::Gpu, Some(60.0), true, at(t0, 2.0));
        p.observe(auto, sw, Renderer::Cpu, Some(0.0), true, at(t0, 2.1));
        p.observe(auto, sw, Renderer::Cpu, Some(20.0), true, at(t0, 4.1));
        assert_eq!(p.renderer(auto, sw), Renderer::Gpu);
    }
}
