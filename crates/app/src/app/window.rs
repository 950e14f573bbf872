//! The desktop window: opening it with eframe on wgpu (or saying why it cannot), the wgpu
//! device the app asks for, the fonts, and the eframe `App` that hands each frame to
//! [`LightpickApp::ui`].

use egui::Ui;

use super::LightpickApp;
use super::images::GpuImages;

/// The message for a machine without a display.
const NO_DISPLAY: &str = "no display found (neither DISPLAY nor WAYLAND_DISPLAY is set): \
     the desktop app needs one. Use the headless subcommands instead, e.g. \
     `lightpick table --powers 2,5,20` (see `lightpick --help`)";

/// Opens the app on the worked example (or the last scene), or on a scene already read from a
/// file (`lightpick FILE`, what a desktop's "Open with" passes). Returns an error (exit code
/// 2) when no display exists.
pub fn run(
    opened: Option<(std::path::PathBuf, lightpick_core::scene::Loaded)>,
) -> anyhow::Result<()> {
    if !display_available() {
        anyhow::bail!(NO_DISPLAY);
    }
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_title("lightpick — point-light importance sampling")
            .with_inner_size([1440.0, 900.0])
            .with_min_inner_size([900.0, 600.0]),
        // Dithering costs a noise evaluation per fragment; on software rasterizers
        // (lavapipe) that is a large share of every frame, and the panels have no gradients.
        dithering: false,
        wgpu_options: wgpu_options(),
        ..Default::default()
    };
    eframe::run_native(
        "lightpick",
        options,
        Box::new(move |cc| {
            let mut app = LightpickApp::new(cc);
            if let Some((path, loaded)) = opened {
                app.open_loaded(&path, loaded);
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| {
        anyhow::anyhow!(
            "cannot open the app window ({e}). Without a working display use the headless \
             subcommands, e.g. `lightpick table --powers 2,5,20` (see `lightpick --help`)"
        )
    })
}

/// eframe's wgpu setup with the adapter's own limits: the compute renderers need storage
/// buffers (and, for millions of lights, large ones) that egui's defaults, sized for drawing
/// (WebGL2's on a GL adapter), leave out; and timestamp queries where the adapter has them.
fn wgpu_options() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.device_descriptor = std::sync::Arc::new(device_descriptor);
    WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(setup),
        ..Default::default()
    }
}

/// The device the app asks of `adapter`: its own limits (large storage buffers, compute on
/// GL) and, when it has them, timestamp queries, so the images' pass times come from the
/// GPU's clock. Tests ask the same of kittest's adapter.
pub fn device_descriptor(
    adapter: &eframe::wgpu::Adapter,
) -> eframe::wgpu::DeviceDescriptor<'static> {
    eframe::wgpu::DeviceDescriptor {
        label: Some("lightpick device"),
        required_features: adapter.features() & lightpick_core::gpu::GpuContext::TIMING_FEATURES,
        required_limits: adapter.limits(),
        ..Default::default()
    }
}

/// Whether a window can be opened at all: on Linux and the BSDs, `DISPLAY` or
/// `WAYLAND_DISPLAY` must name a display.
fn display_available() -> bool {
    if cfg!(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "openbsd",
        target_os = "netbsd"
    )) {
        ["DISPLAY", "WAYLAND_DISPLAY"]
            .iter()
            .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
    } else {
        true
    }
}

/// `DejaVu Sans` (the subset the headless drawings bundle) as a fallback after egui's own
/// font, for the arrows, `≥` and math signs the panels write.
static DEJAVU_SANS: &[u8] = lightpick_core::draw::text::REGULAR_FONT;

/// Adds [`DEJAVU_SANS`] to egui's fonts (once, on the first frame).
pub(super) fn install_fonts(ctx: &egui::Context) {
    use egui::epaint::text::{FontInsert, FontPriority, InsertFontFamily};
    ctx.add_font(FontInsert::new(
        "DejaVuSans",
        egui::FontData::from_static(DEJAVU_SANS),
        vec![
            InsertFontFamily {
                family: egui::FontFamily::Proportional,
                priority: FontPriority::Lowest,
            },
            InsertFontFamily {
                family: egui::FontFamily::Monospace,
                priority: FontPriority::Lowest,
            },
        ],
    ));
}

impl eframe::App for LightpickApp {
    fn ui(&mut self, ui: &mut Ui, frame: &mut eframe::Frame) {
        if self.gpu.is_none()
            && self.gpu_error.is_none()
            && let Some(render_state) = frame.wgpu_render_state()
        {
            self.gpu = Some(GpuImages::new(render_state));
            // A software rasterizer (lavapipe) pays per triangle: without feathering every
            // rectangle is 2 triangles instead of 10, which roughly halves the cost of a
            // frame of this text-and-plot-heavy window. Real GPUs keep anti-aliasing.
            if render_state.adapter.get_info().device_type == eframe::wgpu::DeviceType::Cpu {
                ui.ctx().tessellation_options_mut(|o| o.feathering = false);
            }
        }
        LightpickApp::ui(self, ui);
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.save_to(storage);
    }
}
