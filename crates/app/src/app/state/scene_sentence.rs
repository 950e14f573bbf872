//! The sentence under the images: what to look at on this scene and why, with its figures
//! computed from the scene itself (recomputed for every scene generation, never a figure
//! left from another scene).
//!
//! The figures are exact variances of one sample, `Var_q(x) = Σ f_i(x)²/q_i − E(x)²`
//! ([`PointInspection`]), under uniform (`q = 1/N`), power (`q = p`) and spatial picking
//! (`q = P(i | x)`), averaged over a grid of pixel centres: the mean over the plane of what
//! each pixel's estimate pays, whose ratios are the ratios of the images' variance per
//! sample up to the choice of pixels. The grid has up to [`MAX_GRID_SIDE`]² points, fewer
//! for many lights (each point costs `O(N)`), so it fits a background worker at `10^6`
//! lights. The reason the sentence gives comes from the scene: spots, equal powers, one
//! dominant light, or how much of the power the brightest lights hold; on the classic
//! three lights, the worked example's shading point (`f_i = Φ_i·g_i`, `g` = [`CLASSIC_GEOMETRY`]).

use lightpick_core::SceneSamplers;
use lightpick_core::inspect::PointInspection;
use lightpick_core::scene::pixel_center;
use lightpick_core::walkthrough::CLASSIC_GEOMETRY;

use crate::numbers;

/// Most grid points a side.
pub const MAX_GRID_SIDE: u32 = 8;
/// Light-point evaluations the grid may cost (`points · N ≤` this, at least 4 points).
const EVALUATION_BUDGET: usize = 1 << 22;
/// The brightest share of the lights whose power the heavy-tail sentence reports.
const TOP_FRACTION: f64 = 0.01;

/// The sentence under the images for one scene generation.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSentence {
    /// The scene generation it describes.
    pub generation: u64,
    /// What the class reads.
    pub text: String,
    /// How the figures were computed (the hover text).
    pub hover: String,
    /// Mean exact variance of one sample over the grid: uniform, power, spatial.
    pub variances: [f64; 3],
}

impl crate::app::background::OfGeneration for SceneSentence {
    fn generation(&self) -> u64 {
        self.generation
    }
}

/// The sentence of the scene `samplers` hold, for `generation`.
pub fn scene_sentence(generation: u64, samplers: &SceneSamplers) -> SceneSentence {
    let scene = samplers.scene();
    let n = scene.light_count();
    let side = grid_side(n);
    let spatial = samplers.spatial();
    let mut sums = [0.0; 3];
    for gy in 0..side {
        for gx in 0..side {
            let px = grid_pixel(gx, side, scene.plane.width);
            let py = grid_pixel(gy, side, scene.plane.height);
            let x = pixel_center(&scene.plane, px, py);
            let inspection = PointInspection::at_with_spatial(scene, x, &**spatial);
            sums[0] += inspection.uniform_variance();
            sums[1] += inspection.power_variance();
            sums[2] += inspection.spatial_variance().unwrap_or(0.0);
        }
    }
    let points = f64::from(side * side);
    let variances = sums.map(|s| s / points);
    let [uniform, power, spatial_v] = variances;
    let powers = scene.powers.as_slice();
    let spots = scene
        .emission
        .as_ref()
        .is_some_and(|e| e.iter().any(|e| e.spot().is_some()));
    let power_vs_uniform = numbers::compare(power, uniform, "higher", "lower");
    // With few lights the spatial pick is exact (q_i = s_i): its variance is the rounding
    // of zero, not a figure to compare.
    let spatial_exact = lightpick_core::render::is_zero_variance(spatial_v, uniform.max(power));
    let spatial_vs_power = if spatial_exact {
        "zero: it picks each light with its exact share of the pixel's light, so every \
         sample is the exact value"
            .to_owned()
    } else {
        format!(
            "{} than power's",
            numbers::compare(spatial_v, power, "higher", "lower")
        )
    };
    let reason = if spots {
        format!(
            "Spots: a spot's power says little about what it gives a pixel. Its cone lights a \
             small patch of the floor, so power picking (alias) spends most picks on spots \
             aimed elsewhere: its variance is {power_vs_uniform} than uniform's. The spatial \
             scheme weighs each group of spots by what it gives the plane here and never picks \
             one that cannot light the pixel: its variance is {spatial_vs_power}."
        )
    } else if n == CLASSIC_GEOMETRY.len() {
        seed_reason(powers, &power_vs_uniform, &spatial_vs_power)
    } else if let Some(reason) = equal_reason(powers, &power_vs_uniform, &spatial_vs_power) {
        reason
    } else if let Some(reason) = dominant_reason(powers, &power_vs_uniform, &spatial_vs_power) {
        reason
    } else {
        spread_reason(powers, &power_vs_uniform, &spatial_vs_power)
    };
    let text = format!("{} {reason}", winner_words(variances));
    let hover = format!(
        "Exact variance of one sample, Σ f_i²/q_i − E², averaged over {} pixel centres \
         ({side}×{side} grid): uniform {}, power {}, spatial {} (irradiance²). Click a pixel \
         for the same figures at one point.",
        side * side,
        numbers::short(uniform),
        numbers::short(power),
        numbers::short(spatial_v)
    );
    SceneSentence {
        generation,
        text,
        hover,
        variances,
    }
}

/// The grid's points a side for `n` lights: [`MAX_GRID_SIDE`] for small scenes, fewer as
/// `n` grows ([`EVALUATION_BUDGET`]), at least 2.
fn grid_side(n: usize) -> u32 {
    let points = (EVALUATION_BUDGET / n.max(1)).max(4);
    ((points as f64).sqrt().floor() as u32).clamp(2, MAX_GRID_SIDE)
}

/// The pixel of grid cell `k` of `side` over `pixels`: the cell's centre.
fn grid_pixel(k: u32, side: u32, pixels: u32) -> u32 {
    let at = (f64::from(k) + 0.5) / f64::from(side) * f64::from(pixels);
    (at as u32).min(pixels.saturating_sub(1))
}

/// Which scheme has the least variance over the plane.
fn winner_words([uniform, power, spatial]: [f64; 3]) -> String {
    let name = if spatial <= power.min(uniform) {
        "spatial"
    } else if power <= uniform {
        "power (alias)"
    } else {
        "uniform"
    };
    format!("Least variance per sample here: {name}.")
}

/// The classic three lights: the worked example's shading point against the whole plane.
fn seed_reason(powers: &[f64], power_vs_uniform: &str, spatial_vs_power: &str) -> String {
    let total: f64 = powers.iter().sum();
    let f: Vec<f64> = powers
        .iter()
        .zip(CLASSIC_GEOMETRY)
        .map(|(p, g)| p * g)
        .collect();
    let n = f.len() as f64;
    let uniform_point = lightpick_core::analytic_moments(&f, |_| 1.0 / n).variance;
    let power_point = lightpick_core::analytic_moments(&f, |i| powers[i] / total).variance;
    format!(
        "At the worked example's shading point (g = 1/2, 2/5, 3/4) power picking's variance is {} than \
         uniform's ({} against {}); over the images it is {power_vs_uniform}: the geometry \
         term G_i(x) varies across the plane, so the power pmf matches a pixel's contributions \
         only where every light's G is alike. Spatial picking follows G: its variance is \
         {spatial_vs_power}.",
        numbers::compare(power_point, uniform_point, "higher", "lower"),
        numbers::short(power_point),
        numbers::short(uniform_point),
    )
}

/// All powers equal: power picking is uniform picking; only the geometry differs.
fn equal_reason(powers: &[f64], power_vs_uniform: &str, spatial_vs_power: &str) -> Option<String> {
    let first = *powers.first()?;
    if first <= 0.0 || powers.iter().any(|p| *p != first) {
        return None;
    }
    Some(format!(
        "All {} lights have the same power, so power picking is uniform picking \
         ({power_vs_uniform}). What differs from pixel to pixel is the distance: a light \
         overhead gives far more than one across the plane, and only the spatial scheme, \
         which picks by each light's contribution at the pixel, sees it: its variance is \
         {spatial_vs_power}.",
        powers.len()
    ))
}

/// One light holds at least half of the power.
fn dominant_reason(
    powers: &[f64],
    power_vs_uniform: &str,
    spatial_vs_power: &str,
) -> Option<String> {
    let total: f64 = powers.iter().sum();
    let (index, largest) = powers
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let share = largest / total;
    if share.is_nan() || share < 0.5 {
        return None;
    }
    Some(format!(
        "Light {} holds {} % of the power and gives most pixels most of their light: power \
         picking sends {} % of its samples there, uniform picking 1 in {}. Power's variance \
         is {power_vs_uniform} than uniform's; spatial's is {spatial_vs_power}.",
        index + 1,
        numbers::three_significant(100.0 * share),
        numbers::three_significant(100.0 * share),
        powers.len()
    ))
}

/// Powers spread unevenly: how much the brightest lights hold.
fn spread_reason(powers: &[f64], power_vs_uniform: &str, spatial_vs_power: &str) -> String {
    let total: f64 = powers.iter().sum();
    let top = ((powers.len() as f64 * TOP_FRACTION).ceil() as usize).max(1);
    let mut sorted = powers.to_vec();
    sorted.sort_unstable_by(|a, b| b.total_cmp(a));
    let top_share: f64 = sorted[..top].iter().sum::<f64>() / total;
    let whose = if top == 1 {
        "The brightest light holds".to_owned()
    } else {
        format!("The brightest {top} lights (1 %) hold")
    };
    format!(
        "{whose} {} % of the power: uniform picking spends most samples on lights that give \
         little, power picking goes where the light is ({power_vs_uniform} variance than \
         uniform). Spatial picking adds each light's distance to the pixel: its variance is \
         {spatial_vs_power}.",
        numbers::three_significant(100.0 * top_share),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn sentence_of(powers: &[f64]) -> SceneSentence {
        let mut scene = crate::app::scene_io::worked_example_scene();
        scene.powers = lightpick_core::LightPowers::new(powers.to_vec()).expect("valid powers");
        let samplers = SceneSamplers::new(Arc::new(scene), lightpick_core::Construction::Exact);
        scene_sentence(1, &samplers)
    }

    #[test]
    fn the_seed_point_figure_follows_the_powers() {
        // 2, 5, 20: 366 against 14.85 at the worked example's point (24.6× lower).
        let seed = sentence_of(&[2.0, 5.0, 20.0]);
        assert!(
            seed.text
                .contains("24.6× lower than uniform's (14.85 against 366.0)"),
            "{}",
            seed.text
        );
        // 7, 5, 20: 303.5 against 21.35 (14.2× lower).
        let edited = sentence_of(&[7.0, 5.0, 20.0]);
        assert!(
            edited
                .text
                .contains("14.2× lower than uniform's (21.35 against 303.5)"),
            "{}",
            edited.text
        );
        assert!(!edited.text.contains("24.6"), "{}", edited.text);
    }

    #[test]
    fn the_grid_shrinks_with_the_lights_and_keeps_two_points_a_side() {
        assert_eq!(grid_side(3), MAX_GRID_SIDE);
        assert_eq!(grid_side(1 << 16), 8);
        assert_eq!(grid_side(1 << 20), 2);
        assert_eq!(grid_side(1 << 24), 2);
        assert_eq!(grid_pixel(0, 8, 64), 4);
        assert_eq!(grid_pixel(7, 8, 64), 60);
        assert_eq!(grid_pixel(0, 2, 1), 0);
    }
}
