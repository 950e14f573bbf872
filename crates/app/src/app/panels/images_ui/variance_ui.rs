//! The images panel's variance maps (see [`crate::app::state::variance_maps`]): each
//! scheme's per-pixel variance of one sample under its image, all three through one
//! logarithmic colour scale ([`VarianceScale::shared`], the scale of `lightpick plot
//! variance`), and a line under the images saying whether they are exact or estimated and
//! the mean of each.

use egui::{ColorImage, TextureHandle, TextureOptions, Ui};
use lightpick_core::draw::{
    VarianceScale, variance_method_line, variance_rgba, variance_scheme_name,
};

use crate::app::colors;
use crate::app::state::AppState;
use crate::app::state::variance_maps::{VARIANCE_SCHEMES, VarianceMaps};

/// The textures of one generation's maps, kept in egui's memory between frames.
#[derive(Clone)]
struct VarianceTextures {
    generation: u64,
    textures: [TextureHandle; 3],
}

/// Polls (and for a new scene starts) the maps' background job, and returns the textures
/// of the current scene's maps once they are computed (uploaded once per generation).
pub(super) fn variance_textures(ui: &Ui, state: &mut AppState) -> Option<[TextureHandle; 3]> {
    state.update_variance_maps();
    if state.variance_maps.is_measuring() {
        // Look for the result even while the app is paused and idle.
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_millis(100));
    }
    let maps = state.current_variance_maps()?;
    let id = egui::Id::unique("lightpick_variance_textures");
    let ctx = ui.ctx();
    if let Some(cached) = ctx
        .data(|d| d.get_temp::<VarianceTextures>(id))
        .filter(|c| c.generation == maps.generation)
    {
        return Some(cached.textures);
    }
    let [w, h] = maps.size();
    let values: Vec<&[f64]> = maps.maps.iter().map(|m| m.values.as_slice()).collect();
    let scale = VarianceScale::shared(&values);
    let textures = std::array::from_fn(|k| {
        let rgba = variance_rgba(&maps.maps[k].values, &scale);
        let image = ColorImage::from_rgba_unmultiplied([w as usize, h as usize], &rgba);
        ctx.load_texture(
            format!("lightpick_variance_{k}"),
            image,
            TextureOptions::NEAREST,
        )
    });
    ctx.data_mut(|d| {
        d.insert_temp(
            id,
            VarianceTextures {
                generation: maps.generation,
                textures: textures.clone(),
            },
        );
    });
    Some(textures)
}

/// A mean variance as every variance caption writes it (`1.234e-3`).
pub fn mean_text(mean: f64) -> String {
    format!("{mean:.3e}")
}

/// The line under the images: the maps' method, their shared scale and each mean.
pub fn variance_note(maps: &VarianceMaps) -> String {
    let means = maps.means();
    let values: Vec<&[f64]> = maps.maps.iter().map(|m| m.values.as_slice()).collect();
    let scale = VarianceScale::shared(&values);
    let [w, h] = maps.size();
    let means: Vec<String> = VARIANCE_SCHEMES
        .iter()
        .zip(means)
        .map(|(&s, m)| format!("{} {}", variance_scheme_name(s), mean_text(m)))
        .collect();
    format!(
        "Variance maps, one sample per pixel ({w}×{h}), {}. One log scale for the three: \
         darkest ≤ {}, brightest {}. Mean variance: {}.",
        variance_method_line(maps.exact(), maps.samples_per_pixel()),
        mean_text(scale.min()),
        mean_text(scale.max),
        means.join(", ")
    )
}

/// The line under the images, or that the maps are being computed.
pub(super) fn variance_note_ui(ui: &mut Ui, state: &AppState) {
    let dark = state.dark();
    match state.current_variance_maps() {
        Some(maps) => {
            ui.label(egui::RichText::new(variance_note(maps)).color(colors::foreground(dark)))
                .on_hover_text(format!(
                    "V(x) = Σ s_i²/q_i − E² at each pixel centre: what one sample's estimate \
                     of that pixel pays (computed in {:.2} s)",
                    maps.seconds
                ));
        }
        None => {
            ui.label(
                egui::RichText::new("computing the variance maps…").color(colors::muted(dark)),
            );
        }
    }
}

/// Body-text rows the variance line may take at a panel `width` (it wraps).
pub(super) fn note_rows(ui: &Ui, width: f32) -> f32 {
    let per_row = (width / (0.52 * crate::app::text_size::body_size(ui))).max(20.0);
    // The line is about 230 characters with its figures.
    (230.0 / per_row).ceil()
}
