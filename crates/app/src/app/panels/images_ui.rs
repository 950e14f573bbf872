//! The images panel: uniform, power and spatial progressive images side by side, the
//! exact reference, the error maps and the variance maps ([`variance_ui`]), with spp, RMSE
//! and frame time under each.

pub mod variance_ui;

use egui::{ColorImage, TextureHandle, TextureOptions, Ui};
use lightpick_core::Scheme;

use super::inspector_ui;
use crate::app::colors;
use crate::app::images::{Published, SchemeImage};
use crate::app::state::AppState;
use crate::app::state::settings::BudgetMode;
use crate::numbers;

/// The textures of the latest published frame.
#[derive(Default)]
pub struct ImageTextures {
    /// Native (GPU) textures of the uniform, power and spatial images, which replace
    /// the uploaded ones while the GPU renders.
    pub native: Option<[egui::TextureId; 3]>,
    frame: Option<(u64, u64)>,
    uniform: Option<TextureHandle>,
    power: Option<TextureHandle>,
    spatial: Option<TextureHandle>,
    reference: Option<TextureHandle>,
    uniform_error: Option<TextureHandle>,
    power_error: Option<TextureHandle>,
    spatial_error: Option<TextureHandle>,
}

impl ImageTextures {
    /// Uploads `published` when it is a frame not yet uploaded.
    pub fn update(&mut self, ctx: &egui::Context, published: &Published) {
        let key = (published.generation, published.frame);
        if self.frame == Some(key) {
            return;
        }
        self.frame = Some(key);
        let size = [published.width as usize, published.height as usize];
        upload(
            ctx,
            &mut self.uniform,
            "uniform",
            size,
            Some(&published.uniform.rgba),
        );
        upload(
            ctx,
            &mut self.power,
            "power",
            size,
            Some(&published.power.rgba),
        );
        upload(
            ctx,
            &mut self.spatial,
            "spatial",
            size,
            Some(&published.spatial.rgba),
        );
        upload(
            ctx,
            &mut self.reference,
            "reference",
            size,
            published.reference_rgba.as_deref(),
        );
        upload(
            ctx,
            &mut self.uniform_error,
            "uniform_error",
            size,
            published.uniform.error_rgba.as_deref(),
        );
        upload(
            ctx,
            &mut self.power_error,
            "power_error",
            size,
            published.power.error_rgba.as_deref(),
        );
        upload(
            ctx,
            &mut self.spatial_error,
            "spatial_error",
            size,
            published.spatial.error_rgba.as_deref(),
        );
    }
}

fn upload(
    ctx: &egui::Context,
    slot: &mut Option<TextureHandle>,
    name: &str,
    size: [usize; 2],
    rgba: Option<&[u8]>,
) {
    let Some(rgba) = rgba.filter(|r| r.len() == size[0] * size[1] * 4) else {
        *slot = None;
        return;
    };
    let image = ColorImage::from_rgba_unmultiplied(size, rgba);
    match slot {
        Some(handle) if handle.size() == size => handle.set(image, TextureOptions::NEAREST),
        _ => {
            *slot =
                Some(ctx.load_texture(format!("lightpick_{name}"), image, TextureOptions::NEAREST));
        }
    }
}

/// The whole panel.
pub fn images_ui(
    ui: &mut Ui,
    state: &mut AppState,
    published: Option<&Published>,
    textures: &ImageTextures,
) {
    options_ui(ui, state, published);
    let Some(published) = published else {
        ui.label("waiting for the first frame…");
        return;
    };
    let stale = published.generation != state.built.generation;
    let dims = [published.width, published.height];
    let variance = if state.settings.show_variance {
        variance_ui::variance_textures(ui, state)
    } else {
        None
    };
    let rows = ImageRows::of(state);
    let mut columns = columns(state, textures);
    let mut size = image_size(ui, columns, rows, dims);
    // A narrow panel (a 1024×768 projector, or zoomed in): three readable images rather
    // than four thumbnails; the reference comes back when the panel is wide enough.
    let reference_hidden = columns == 4 && size.x < MIN_IMAGE_SIDE && {
        let three = image_size(ui, 3, rows, dims);
        three.x > size.x
    };
    if reference_hidden {
        columns = 3;
        size = image_size(ui, 3, rows, dims);
    }
    let ids = textures.native.map_or_else(
        || {
            [
                textures.uniform.as_ref().map(TextureHandle::id),
                textures.power.as_ref().map(TextureHandle::id),
                textures.spatial.as_ref().map(TextureHandle::id),
            ]
        },
        |[u, i, s]| [Some(u), Some(i), Some(s)],
    );
    let (width, height) = (published.width, published.height);
    let dark = state.dark();
    // The estimator at a pixel keeps that pixel marked after the inspector closes: the
    // text that speaks of the pixel and the chip that shows it go together.
    let estimated = match state.estimator.point {
        crate::app::state::estimator::EstimatorPoint::Pixel(pixel) if state.estimator.open => {
            Some(pixel)
        }
        _ => None,
    };
    let inspector = &mut state.inspector;
    let mut inspect = |ui: &Ui, response: Option<egui::Response>| {
        let Some(response) = response else { return };
        if let Some(pixel) = inspector_ui::clicked_pixel(&response, width, height) {
            inspector.pixel = Some(pixel);
            inspector.raise = true;
        }
        if let Some(pixel) = inspector.pixel.or(estimated) {
            inspector_ui::mark_pixel_ui(ui, response.rect, pixel, width, height, dark);
        }
    };
    let show_error = state.settings.show_error;
    let schemes = [
        (
            "Uniform",
            Scheme::Uniform,
            &published.uniform,
            &textures.uniform_error,
        ),
        (
            "Power (alias)",
            Scheme::Alias,
            &published.power,
            &textures.power_error,
        ),
        (
            "Spatial",
            Scheme::Spatial,
            &published.spatial,
            &textures.spatial_error,
        ),
    ];
    ui.horizontal_top(|ui| {
        for (k, ((title, scheme, image, error), id)) in schemes.into_iter().zip(ids).enumerate() {
            let error = error.as_ref().filter(|_| show_error);
            let maps = [error, variance.as_ref().map(|v| &v[k])];
            let response = image_column(ui, title, scheme, image, id, maps, size);
            inspect(ui, response);
        }
        if columns == 4
            && let Some(reference) = &textures.reference
        {
            ui.vertical(|ui| {
                ui.set_max_width(size.x);
                ui.colored_label(colors::reference(), "Reference (exact)");
                let response = ui
                    .add(egui::Image::new((reference.id(), size)).sense(egui::Sense::click()))
                    .on_hover_text(
                        "Exact irradiance: the sum over every light. Click a pixel to inspect it",
                    );
                inspect(ui, Some(response));
            });
        }
    });
    if reference_hidden {
        ui.label(
            egui::RichText::new(
                "The reference is hidden to keep the three images large: widen the panel or \
                 maximize it (the button at its header's right) to see it.",
            )
            .color(colors::muted(dark)),
        );
    }
    if state.settings.show_variance {
        variance_ui::variance_note_ui(ui, state);
    }
    notes_ui(ui, state, published, stale);
}

/// The least side, in points, at which the images are shown four abreast: below it the
/// reference column gives its width to the three schemes.
pub const MIN_IMAGE_SIDE: f32 = 160.0;

/// The reference and error-map switches, and the image size and budget mode.
fn options_ui(ui: &mut Ui, state: &mut AppState, published: Option<&Published>) {
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut state.settings.show_reference, "reference")
            .on_hover_text("Show the exact reference image (sum over every light)");
        ui.checkbox(&mut state.settings.show_error, "error maps")
            .on_hover_text("Show |estimate − reference| per pixel under each image");
        ui.checkbox(&mut state.settings.show_variance, "variance maps")
            .on_hover_text(
                "Show each scheme's variance of one sample per pixel under its image, on one \
                 log scale for the three (exact for small scenes, estimated beyond)",
            );
        if let Some(published) = published {
            let mode = match state.settings.budget {
                BudgetMode::EqualSamples => "equal samples",
                BudgetMode::EqualTime => "equal time",
            };
            ui.label(
                egui::RichText::new(format!(
                    "{}×{} px · {mode}",
                    published.width, published.height
                ))
                .color(colors::muted(state.dark())),
            )
            .on_hover_text("Image resolution, and how the frame's work is shared between schemes");
        }
    });
}

/// The notes under the images: the scene's sentence (what to look at and why, its figures
/// computed from the current scene; see [`crate::app::state::scene_sentence`]), a restart in
/// progress (`stale`), why there is no reference. Body text, like everything the class reads.
fn notes_ui(ui: &mut Ui, state: &AppState, published: &Published, stale: bool) {
    let dark = state.dark();
    match state.current_scene_sentence() {
        Some(sentence) => {
            ui.label(egui::RichText::new(&sentence.text).color(colors::foreground(dark)))
                .on_hover_text(&sentence.hover);
        }
        None => {
            ui.label(
                egui::RichText::new("computing what this scene shows…").color(colors::muted(dark)),
            );
        }
    }
    if stale {
        ui.label("restarting on the new table…");
    }
    if let Some(note) = &published.reference_note {
        ui.label(note);
    }
}

/// Text rows under each image: title, spp, RMSE, time (which may wrap to two rows).
const TEXT_ROWS_PER_IMAGE: f32 = 5.0;

/// What each column stacks: the image, its error map and its variance map when shown, and
/// the text rows under the images.
#[derive(Clone, Copy, Debug)]
struct ImageRows {
    /// Images in each column (1 to 3).
    images: f32,
    /// Whether the variance maps' line is under the images.
    variance_note: bool,
    /// Characters of the scene's sentence (0 while it is computed).
    sentence_chars: usize,
}

impl ImageRows {
    fn of(state: &AppState) -> Self {
        let (error, variance) = (state.settings.show_error, state.settings.show_variance);
        Self {
            images: 1.0 + f32::from(u8::from(error)) + f32::from(u8::from(variance)),
            variance_note: variance,
            sentence_chars: state
                .current_scene_sentence()
                .map_or(0, |s| s.text.chars().count()),
        }
    }

    /// Body-text rows under the images besides each image's own: with the variance maps,
    /// their line and the scene's sentence below it (which the images then leave room for).
    fn note_rows(self, ui: &Ui, width: f32) -> f32 {
        if self.variance_note {
            variance_ui::note_rows(ui, width) + sentence_rows(ui, width, self.sentence_chars)
        } else {
            0.0
        }
    }
}

/// The rows the scene's sentence of `chars` characters takes in body text at `width`
/// (about half an em a character); one row while it is being computed.
fn sentence_rows(ui: &Ui, width: f32, chars: usize) -> f32 {
    let per_row = (width / (0.52 * crate::app::text_size::body_size(ui))).max(20.0);
    (chars as f32 / per_row).ceil().max(1.0)
}

/// The on-screen size of each image: `columns` side by side in the panel's width, and the
/// image (plus its error and variance maps when shown) and its text rows within the panel's
/// height.
fn image_size(ui: &Ui, columns: usize, rows: ImageRows, [width, height]: [u32; 2]) -> egui::Vec2 {
    let spacing = ui.spacing().item_spacing;
    let aspect = height as f32 / width.max(1) as f32;
    let by_width = side_by_width(ui, ui.available_width(), columns);
    let images = rows.images;
    let text = TEXT_ROWS_PER_IMAGE + rows.note_rows(ui, ui.available_width());
    let by_height =
        (ui.available_height() - text_rows(ui, text) - images * spacing.y) / (images * aspect);
    let side = by_width.min(by_height).max(48.0);
    egui::vec2(side, side * aspect)
}

/// The side of a square image when `columns` of them share `width`.
fn side_by_width(ui: &Ui, width: f32, columns: usize) -> f32 {
    (width - ui.spacing().item_spacing.x * (columns as f32 - 1.0)) / columns as f32
}

/// The height of `rows` rows of body text.
fn text_rows(ui: &Ui, rows: f32) -> f32 {
    rows * (ui.text_style_height(&egui::TextStyle::Body) + ui.spacing().item_spacing.y)
}

/// The panel's header row (a heading: taller than body text), in body rows.
const HEADER_ROWS: f32 = 1.6;

/// Images side by side: the three schemes, and the reference when shown and complete.
fn columns(state: &AppState, textures: &ImageTextures) -> usize {
    if state.settings.show_reference && textures.reference.is_some() {
        4
    } else {
        3
    }
}

/// The height the Images panel needs in `width` to show its square images (and their error
/// maps when shown) as large as the width allows: what the window's layout leaves it before
/// giving the rest to the Convergence panel.
pub fn wanted_height(ui: &Ui, width: f32, state: &AppState, textures: &ImageTextures) -> f32 {
    let mut side = side_by_width(ui, width, columns(state, textures));
    if side < MIN_IMAGE_SIDE {
        // Narrow: three images abreast, the reference hidden (see `images_ui`).
        side = side.max(side_by_width(ui, width, 3));
    }
    let rows = ImageRows::of(state);
    let images = rows.images;
    // The scene's sentence in body text, wrapped to the width.
    let note_rows = sentence_rows(ui, width, rows.sentence_chars);
    let variance_rows = if rows.variance_note {
        variance_ui::note_rows(ui, width)
    } else {
        0.0
    };
    images * (side + ui.spacing().item_spacing.y)
        + text_rows(
            ui,
            TEXT_ROWS_PER_IMAGE + HEADER_ROWS + note_rows + variance_rows,
        )
}

fn image_column(
    ui: &mut Ui,
    title: &str,
    scheme: Scheme,
    image: &SchemeImage,
    texture: Option<egui::TextureId>,
    [error, variance]: [Option<&TextureHandle>; 2],
    size: egui::Vec2,
) -> Option<egui::Response> {
    ui.vertical(|ui| {
        // The labels wrap within the image's width, so four columns fit side by side.
        ui.set_max_width(size.x);
        ui.colored_label(colors::scheme(scheme), title);
        let response = texture.map(|t| {
            ui.add(egui::Image::new((t, size)).sense(egui::Sense::click()))
                .on_hover_text(format!(
                    "{title} ({}): progressive estimate, {} spp. Click a pixel to inspect it",
                    scheme_hint(scheme),
                    image.spp
                ))
        });
        if image.pass_progress > 0.0 {
            ui.label(format!(
                "spp {} (+{:.0} %)",
                image.spp,
                100.0 * image.pass_progress
            ))
            .on_hover_text(
                "Samples per pixel accumulated; the next sample pass is this far down the \
                 image (a costly pass is spread over frames to keep the window responsive)",
            );
        } else {
            ui.label(format!("spp {}", image.spp))
                .on_hover_text("Samples per pixel accumulated");
        }
        if let Some(rmse) = image.rmse {
            ui.label(format!("RMSE {}", numbers::short(rmse)))
                .on_hover_text("Root-mean-square error against the reference");
        }
        ui.label(format!(
            "{:.1} ms/frame, {:.2} s",
            image.last_frame_seconds * 1e3,
            image.seconds
        ))
        .on_hover_text("Render time of the last frame, and in total so far");
        if let Some(e) = error {
            // Outlined: a zero-error map is as dark as the panel (the exact spatial pick).
            let response = ui.image((e.id(), size));
            ui.painter().rect_stroke(
                response.rect,
                0.0,
                egui::Stroke::new(1.0, colors::reference()),
                egui::StrokeKind::Outside,
            );
            response.on_hover_text(format!(
                "{title}: |estimate − reference| (brighter = larger)"
            ));
        }
        if let Some(v) = variance {
            let response = ui.image((v.id(), size));
            ui.painter().rect_stroke(
                response.rect,
                0.0,
                egui::Stroke::new(1.0, colors::scheme(scheme)),
                egui::StrokeKind::Outside,
            );
            response.on_hover_text(format!(
                "{title}: variance of one sample at each pixel, log scale shared with the \
                 other two (brighter = noisier)"
            ));
        }
        response
    })
    .inner
}

/// How each scheme picks its light, for the image's hover text.
fn scheme_hint(scheme: Scheme) -> &'static str {
    match scheme {
        Scheme::Uniform => "every light equally likely",
        Scheme::Spatial => {
            "by contribution p_i·G_i(x) at each pixel: exact for ≤ 16 lights, a light tree beyond"
        }
        _ => "in proportion to power",
    }
}
