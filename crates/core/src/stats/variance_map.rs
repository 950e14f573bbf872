//! The variance of one sample, pixel by pixel: where on the plane a scheme is noisy.
//!
//! At a pixel centre `x` light `i` gives `s_i(x) = p_i·G_i(x)·S_i(x)`
//! ([`crate::scene::light_term`] in normalized power `p_i = Φ_i/ΣΦ`), and the irradiance is
//! `E(x) = Σ_i s_i(x)`. A scheme picking light `i` with pmf `q_i(x)` and estimating
//! `s_i/q_i` has the per-sample variance
//!
//! `V(x) = Σ_{q_i > 0} s_i(x)²/q_i(x) − E(x)²`
//!
//! ([`crate::analytic_moments`]; `E` here over the lights the scheme can pick, the mean of
//! its estimate). The map evaluates it **exactly** (`O(N)` per pixel) when `N × pixels` is
//! within a budget ([`VARIANCE_MAP_EXACT_BUDGET`]), else **estimates** it from `k` samples per
//! pixel: the unbiased sample variance of `k` estimates ([`crate::Welford`]) drawn with the
//! scheme itself, so the result says which it is ([`VarianceMap::exact`]).
//!
//! Schemes: uniform (`q_i = 1/N`), power ([`Scheme::Alias`], [`Scheme::AliasOneRandom`],
//! [`Scheme::Cdf`]: the pmf each realizes) and spatial (`q_i = P(i | x)`), all through the one
//! interface ([`LightSampler::pmfs_at`], [`LightSampler::pick_at`]); the spatial exact pick
//! (few lights) gives `V ≡ 0` up to rounding.

use rayon::prelude::*;

use super::moments::analytic_moments;
use super::welford::Welford;
use crate::sampling::light_sampler::{LightSampler, ShadingContext};
use crate::sampling::rng::Rng;
use crate::sampling::sampler::Scheme;
use crate::scene::{Scene, pixel_center};
use crate::scheme_sampler::SchemeSampler;

/// The most `N × pixels` light evaluations for which [`VarianceMap::compute`] is exact.
pub const VARIANCE_MAP_EXACT_BUDGET: u64 = 50_000_000;

/// Per-pixel variance of one sample of a scheme over the scene's pixel grid.
#[derive(Clone, Debug, PartialEq)]
pub struct VarianceMap {
    /// Pixel columns (the scene's).
    pub width: u32,
    /// Pixel rows (the scene's; row 0 at the top, `y = max.y`, as [`pixel_center`]).
    pub height: u32,
    /// `V(x)` at each pixel centre, row by row (normalized units: powers summing to 1).
    pub values: Vec<f64>,
    /// Whether `values` are the exact `Σ s_i²/q_i − E²` (else sample variances).
    pub exact: bool,
    /// Samples per pixel behind an estimated map (0 when exact).
    pub samples_per_pixel: u32,
}

impl VarianceMap {
    /// The map of `scheme` over `scene`: exact when `N × pixels ≤`
    /// [`VARIANCE_MAP_EXACT_BUDGET`], else estimated from `samples_per_pixel` samples per
    /// pixel (pixel `k` from stream `Rng::new(seed, k)`).
    pub fn compute(scene: &Scene, scheme: Scheme, samples_per_pixel: u32, seed: u64) -> Self {
        Self::with_budget(
            scene,
            scheme,
            VARIANCE_MAP_EXACT_BUDGET,
            samples_per_pixel,
            seed,
        )
    }

    /// [`VarianceMap::compute`] with the exact evaluation's budget `budget` (`N × pixels`).
    pub fn with_budget(
        scene: &Scene,
        scheme: Scheme,
        budget: u64,
        samples_per_pixel: u32,
        seed: u64,
    ) -> Self {
        let sampler = SchemeSampler::for_scene(scene, scheme);
        Self::of_sampler(scene, &sampler, budget, samples_per_pixel, seed)
    }

    /// The map of any scheme's `sampler` built over `scene` (shared, say, from
    /// [`crate::SceneSamplers::sampler`]), through the one interface: `q_i(x)` from
    /// [`LightSampler::pmfs_at`] where exact, picks from [`LightSampler::pick_at`] where
    /// estimated; `budget` and the rest as [`VarianceMap::with_budget`].
    ///
    /// # Panics
    /// If the sampler was built for another number of lights.
    pub fn of_sampler(
        scene: &Scene,
        sampler: &(impl LightSampler + Sync + ?Sized),
        budget: u64,
        samples_per_pixel: u32,
        seed: u64,
    ) -> Self {
        assert_eq!(
            sampler.light_count(),
            scene.light_count(),
            "sampler built for another scene"
        );
        let plane = &scene.plane;
        let pixels = plane.pixel_count();
        let exact = (scene.powers.len() as u64).saturating_mul(pixels as u64) <= budget;
        let pmf = scene.powers.pmf();
        let width = plane.width.max(1) as usize;
        let values = (0..pixels)
            .into_par_iter()
            .map(|k| {
                let x = pixel_center(plane, (k % width) as u32, (k / width) as u32);
                let at = ShadingContext::at(x);
                if exact {
                    exact_variance(scene, &pmf, sampler, &at)
                } else {
                    let mut rng = Rng::new(seed, k as u64);
                    sampled_variance(scene, &pmf, sampler, &at, samples_per_pixel, &mut rng)
                }
            })
            .collect();
        VarianceMap {
            width: plane.width,
            height: plane.height,
            values,
            exact,
            samples_per_pixel: if exact { 0 } else { samples_per_pixel },
        }
    }

    /// `V` at pixel `(px, py)`.
    ///
    /// # Panics
    /// Outside the map.
    pub fn at(&self, px: u32, py: u32) -> f64 {
        assert!(px < self.width && py < self.height, "pixel outside the map");
        self.values[py as usize * self.width as usize + px as usize]
    }
}

/// `Σ_{q_i > 0} s_i²/q_i − E²` at `at` ([`analytic_moments`]).
fn exact_variance(
    scene: &Scene,
    pmf: &[f64],
    sampler: &(impl LightSampler + ?Sized),
    at: &ShadingContext,
) -> f64 {
    let s = scene.weighted_terms(pmf, at.point_on_plane);
    let q = sampler.pmfs_at(at);
    analytic_moments(&s, |i| q[i]).variance
}

/// The unbiased sample variance of `k` estimates `s_I/q_I` at `at` drawn from `rng` (0 for a
/// pick that finds no light: nothing contributes there).
fn sampled_variance(
    scene: &Scene,
    pmf: &[f64],
    sampler: &(impl LightSampler + ?Sized),
    at: &ShadingContext,
    k: u32,
    rng: &mut Rng,
) -> f64 {
    let mut w = Welford::new();
    for _ in 0..k {
        let estimate = sampler.pick_at(at, rng).map_or(0.0, |pick| {
            let i = pick.light as usize;
            pmf[i] * scene.light_term(i, at.point_on_plane) / pick.probability
        });
        w.push(estimate);
    }
    w.variance()
}
