//! Files in and out of the app: opening a scene (File → Open, a dropped file, `lightpick
//! FILE`), saving it, and exporting the images and the alias-table diagram as PNGs; a
//! failure says why and keeps the current scene.

use std::path::Path;

use super::images::Published;
use super::state::MessageKind;
use super::state::figure::Figure;
use super::state::file_dialog::FileAction;
use super::{LightpickApp, scene_io};

impl LightpickApp {
    /// Opens the scene file at `path` (any format the loader reads, the receiver at the
    /// file's ground) and says what came in; on failure says why in the status bar and keeps
    /// the current scene. The door of a dropped file; File → Open goes through
    /// [`Self::file_action`], `lightpick FILE` through [`Self::open_loaded`]: all three end in
    /// [`Self::open_loaded`].
    pub fn open_path(&mut self, path: &Path) {
        if let Err(e) = self.open_scene(path) {
            self.state.message(
                format!("Open scene: {e} — nothing changed"),
                MessageKind::Error,
            );
        }
    }

    /// Reads the scene at `path` with the one loader (`lightpick_core::scene::load`) and
    /// shows it ([`Self::open_loaded`]); returns the status line, or why not (the path and
    /// the place in the file).
    fn open_scene(&mut self, path: &Path) -> Result<String, String> {
        let loaded =
            lightpick_core::scene::load(path, &lightpick_core::scene::LoadOptions::default())
                .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(self.open_loaded(path, loaded))
    }

    /// Shows a scene read from `path` (what every door ends in): the scene replaces the
    /// edit, and the status bar says what came in ("opened level.glb: 402 lights: 362
    /// points, 40 spots; skipped 1 directional light 'Sun'"). Returns that line.
    pub fn open_loaded(&mut self, path: &Path, loaded: lightpick_core::scene::Loaded) -> String {
        let message = format!("opened {}: {}", path.display(), loaded.report.summary());
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        self.state.history.name_next(format!("open '{name}'"));
        self.state.load_scene(loaded.scene);
        self.state.message(message.clone(), MessageKind::Success);
        message
    }

    /// Opens a file dropped on the window (the first, when several are).
    pub(super) fn open_dropped(&mut self, ctx: &egui::Context) {
        if let Some(file) = ctx.input(|i| i.raw.dropped_files.first().cloned()) {
            self.open_path(file.path());
        }
    }

    /// Carries out a confirmed file action; on failure the message is shown in the dialog
    /// and the status bar, and the current scene is kept.
    pub fn file_action(&mut self, action: FileAction, path: &str, published: Option<&Published>) {
        let result = match action {
            FileAction::OpenScene => self.open_scene(Path::new(path)),
            FileAction::SaveScene => scene_io::save(Path::new(path), &self.state.built.scene)
                .map(|()| format!("saved {path}")),
            FileAction::ExportImages | FileAction::ExportFigure(Figure::Images) => {
                let fit = match action {
                    FileAction::ExportImages => None,
                    _ => Some(self.state.settings.figure_size),
                };
                // GPU images are native textures: read them back first.
                let exposure = self.state.settings.exposure;
                let from_gpu = if self.uses_gpu() {
                    self.gpu.as_mut().map(|gpu| gpu.frame_with_images(exposure))
                } else {
                    None
                };
                match from_gpu {
                    Some(Ok(frame)) => Ok(frame),
                    Some(Err(e)) => Err(e),
                    None => published
                        .cloned()
                        .ok_or_else(|| "no image has been rendered yet".to_owned()),
                }
                .and_then(|frame| export_images(Path::new(path), &frame, fit))
                .map(|()| format!("exported {path}"))
            }
            FileAction::ExportData => {
                super::data_export::export_data(Path::new(path), &mut self.state, published).map(
                    |files| {
                        let names: Vec<String> = files
                            .iter()
                            .filter_map(|f| f.file_name())
                            .map(|n| n.to_string_lossy().into_owned())
                            .collect();
                        format!("exported {}", names.join(", "))
                    },
                )
            }
            FileAction::ExportFigure(figure) => {
                let size = self.state.settings.figure_size;
                super::figure_export::figure_pixmap(figure, &mut self.state, published, size)
                    .and_then(|pixmap| {
                        lightpick_core::draw::write_png(&pixmap, Path::new(path))
                            .map_err(|e| e.to_string())
                    })
                    .map(|()| format!("exported {path}"))
            }
        };
        match result {
            Ok(message) => {
                // The next dialog starts in this file's folder, in this session and the next.
                let folder = self
                    .state
                    .file_dialog
                    .folder()
                    .join(path)
                    .parent()
                    .map(Path::to_path_buf);
                if let Some(folder) = folder.filter(|f| f.is_dir()) {
                    self.state.file_dialog.folder = Some(folder.clone());
                    self.state.settings.last_folder = Some(folder);
                }
                self.state.file_dialog.action = None;
                self.state.file_dialog.error = None;
                self.state.message(message, MessageKind::Success);
            }
            Err(e) => {
                self.state.file_dialog.error = Some(e.clone());
                self.state.message(
                    format!("{}: {e} — nothing changed", action.title()),
                    MessageKind::Error,
                );
            }
        }
    }
}

/// Writes uniform | power | spatial | reference side by side as one PNG, with the
/// three error maps in a second row when there is a reference image; with `fit`, scaled
/// (aspect kept) to the largest size within `fit` pixels: pixel for pixel (nearest) when
/// enlarged, so that the noise stays as it was rendered, filtered when reduced.
fn export_images(path: &Path, p: &Published, fit: Option<[u32; 2]>) -> Result<(), String> {
    let pixels = p.width as usize * p.height as usize * 4;
    if [&p.uniform, &p.power, &p.spatial]
        .iter()
        .any(|s| s.rgba.len() != pixels)
    {
        return Err("the images are not ready yet".into());
    }
    let (w, h0) = (p.width as usize, p.height as usize);
    let schemes = [&p.uniform, &p.power, &p.spatial];
    let mut top: Vec<&[u8]> = schemes.iter().map(|s| s.rgba.as_slice()).collect();
    if let Some(r) = &p.reference_rgba {
        top.push(r);
    }
    let errors: Option<Vec<&[u8]>> = schemes.iter().map(|s| s.error_rgba.as_deref()).collect();
    let columns = top.len();
    let rows = if errors.is_some() { 2 } else { 1 };
    let total_w = w * columns;
    // A caption band above the images: each scheme's name, spp and RMSE, as the GIF has.
    let caption = caption_style(w);
    let band = (2.6 * caption.size).ceil() as usize;
    let h_total = band + h0 * rows;
    // Opaque black where a row has no image (under the reference).
    let mut out: Vec<u8> = [0, 0, 0, 255].repeat(total_w * h_total);
    let mut place = |row: usize, column: usize, part: &[u8]| {
        for y in 0..h0 {
            let src = &part[y * w * 4..(y + 1) * w * 4];
            let dst = ((band + row * h0 + y) * total_w + column * w) * 4;
            out[dst..dst + w * 4].copy_from_slice(src);
        }
    };
    for (k, part) in top.iter().enumerate() {
        place(0, k, part);
    }
    for (k, part) in errors.iter().flatten().enumerate() {
        place(1, k, part);
    }
    let out = captioned(&out, [total_w, h_total], w, &captions(p), &caption)?;
    let sheet = image::RgbaImage::from_raw(total_w as u32, h_total as u32, out)
        .ok_or("the image sheet has the wrong size")?;
    let sheet = match fit {
        Some(fit) => fitted(&sheet, fit),
        None => sheet,
    };
    let mut png = std::io::Cursor::new(Vec::new());
    sheet
        .write_to(&mut png, image::ImageFormat::Png)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    // Atomically: a failed write (a full disk, a read-only folder) leaves the old file.
    lightpick_core::atomic_file::write_bytes_atomically(path, png.get_ref()).map_err(|e| {
        format!(
            "cannot write {}: {e} — the old file is unchanged",
            path.display()
        )
    })
}

/// `sheet` scaled, aspect kept, to the largest size within `fit`.
fn fitted(sheet: &image::RgbaImage, [fit_w, fit_h]: [u32; 2]) -> image::RgbaImage {
    let (w, h) = (f64::from(sheet.width()), f64::from(sheet.height()));
    let scale = (f64::from(fit_w) / w).min(f64::from(fit_h) / h);
    let (new_w, new_h) = (
        ((w * scale).round() as u32).max(1),
        ((h * scale).round() as u32).max(1),
    );
    let filter = if scale >= 1.0 {
        image::imageops::FilterType::Nearest
    } else {
        image::imageops::FilterType::Triangle
    };
    image::imageops::resize(sheet, new_w, new_h, filter)
}

/// The captions of the exported columns: scheme, samples per pixel and RMSE; "exact
/// reference" over the reference.
fn captions(p: &Published) -> Vec<[String; 2]> {
    let mut out: Vec<[String; 2]> = [
        ("uniform", &p.uniform),
        ("power (alias)", &p.power),
        ("spatial", &p.spatial),
    ]
    .into_iter()
    .map(|(name, image)| {
        let rmse = image.rmse.map_or_else(
            || "no reference".to_owned(),
            |r| format!("RMSE {}", crate::numbers::short(r)),
        );
        [name.to_owned(), format!("{} spp · {rmse}", image.spp)]
    })
    .collect();
    if p.reference_rgba.is_some() {
        out.push(["exact reference".to_owned(), "(errors below)".to_owned()]);
    }
    out
}

/// The captions' text style for columns `width` pixels wide: readable, and two lines of it
/// fit the band.
fn caption_style(width: usize) -> lightpick_core::draw::text::TextStyle {
    let size = (width as f32 / 14.0).clamp(11.0, 18.0);
    lightpick_core::draw::text::TextStyle::new(
        size,
        lightpick_core::draw::Rgba8::rgb(235, 235, 235),
    )
}

/// `rgba` (`size`, opaque) with `captions[k]` written in the top band over column `k`.
fn captioned(
    rgba: &[u8],
    [width, height]: [usize; 2],
    column: usize,
    captions: &[[String; 2]],
    style: &lightpick_core::draw::text::TextStyle,
) -> Result<Vec<u8>, String> {
    use lightpick_core::draw::text::{HAlign, VAlign, draw_text};
    let mut pixmap = lightpick_core::draw::Pixmap::new(width as u32, height as u32)
        .ok_or("the images are empty")?;
    // Opaque pixels are their own premultiplied form.
    pixmap.data_mut().copy_from_slice(rgba);
    for (k, [name, figures]) in captions.iter().enumerate() {
        let x = (k * column) as f32 + 0.5 * style.size;
        let bold = style.bold();
        draw_text(
            &mut pixmap,
            name,
            (x, 0.3 * style.size),
            (HAlign::Left, VAlign::Top),
            &bold,
        )
        .map_err(|e| e.to_string())?;
        draw_text(
            &mut pixmap,
            figures,
            (x, 1.4 * style.size),
            (HAlign::Left, VAlign::Top),
            style,
        )
        .map_err(|e| e.to_string())?;
    }
    Ok(lightpick_core::draw::to_rgba8(&pixmap))
}
