//! The CPU renderer: the estimator contract of [`crate::render`], parallel over rows.
//!
//! Every pixel sample is a pure function of `(seed, k, p)`, and each pixel's running sums are
//! updated by one thread in increasing `k`, so the image is identical bit for bit whatever
//! the thread count and however the samples are split into passes (`accumulate(2)` twice
//! equals `accumulate(4)` once).

use std::sync::Arc;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::Accumulator;
use super::convergence::{ProgressiveRenderer, SchemeSeries, convergence_series};
use super::reference::Reference;
use crate::SceneSamplers;
use crate::cpu_lights::CpuLights;
use crate::light_sampler::LightSampler;
use crate::powers::PmfScale;
use crate::rng::Rng;
use crate::sampler::{Sampler, Scheme};
use crate::scene::{Emission, ReceiverPlane, Scene, light_term, pixel_center};
use crate::scheme_sampler::SchemeSampler;
use crate::spatial::SpatialSampler;

/// A progressive CPU renderer of one scene with one scheme and one seed.
///
/// Pixel `p = py·width + px`, sample `k` (counted from 0 across passes) uses the stream
/// `Rng::new(seed, (k << 32) | p)`, picks light `i` with [`Sampler::pick_light`] and adds
/// the normalized estimate `ê = N·p_i·G_i(x_p)` or `G_i(x_p)` (see [`crate::render`]) in
/// the accumulator's unit, `ê' = ê·2^-s` (exact), and `ê'²` to the pixel's sums.
/// `E[ê] = Σ_i p_i·G_i(x_p)`, so `Φ_total·2^s · Σê' / spp` is an unbiased estimate of the
/// irradiance `E(x_p) = Σ_i Φ_i·G_i(x_p)`.
///
/// With [`Scheme::Spatial`] the sample instead draws from the same stream through
/// [`SpatialSampler::estimate`] at `x_p`: `ê = p_i·G_i(x_p) / P(i | x_p)`, same expectation.
#[derive(Clone, Debug)]
pub struct CpuRenderer {
    plane: ReceiverPlane,
    /// The scheme's sampler; its two kinds have their own row loops ([`render_row`],
    /// [`render_band_spatial`]), each drawing exactly the picks of [`LightSampler::pick_at`].
    picker: SchemeSampler,
    /// The scene's lights and emission profiles (shared with the scene's other renderers
    /// when built through [`CpuRenderer::from_samplers`]).
    lights: CpuLights,
    /// `N` for uniform picking (`w_i = N·p_i·2^-s`), `None` for power picking (`2^-s`).
    uniform_n: Option<f64>,
    seed: u64,
    /// `2^-s`, the factor from a normalized estimate into the accumulation unit.
    to_unit: f64,
    accumulator: Accumulator,
}

/// The accumulator of `scene` (its total power and [`Scene::irradiance_shift`]) and the
/// factor `2^-s` into its unit.
fn accumulator_for(scene: &Scene) -> (Accumulator, f64) {
    let shift = scene.irradiance_shift();
    let plane = &scene.plane;
    (
        Accumulator::new(
            plane.width,
            plane.height,
            scene.powers.total_scaled(),
            shift,
        ),
        crate::Scaled::pow2(-shift).to_f64(),
    )
}

impl CpuRenderer {
    /// Builds the sampler of `scheme` over the scene's powers (`O(N)`; the spatial light
    /// tree `O(N log N)`) and an empty accumulator with scale `Φ_total`.
    pub fn new(scene: &Scene, scheme: Scheme, seed: u64) -> Self {
        Self::with_scheme_sampler(scene, SchemeSampler::for_scene(scene, scheme), seed)
    }

    /// A renderer picking with `sampler`, already built over `scene` (any scheme).
    ///
    /// # Panics
    /// If the sampler's light count differs from the scene's.
    pub fn with_scheme_sampler(scene: &Scene, sampler: SchemeSampler, seed: u64) -> Self {
        match sampler {
            SchemeSampler::PointFree(sampler) => Self::with_sampler(scene, sampler, seed),
            SchemeSampler::Spatial(spatial) => Self::with_spatial(scene, spatial, seed),
        }
    }

    /// A renderer of `scheme` over a scene whose samplers are already built and shared: the
    /// alias schemes take `samplers`' table, the spatial scheme its spatial sampler (built
    /// now if no one has yet), uniform and CDF build their own (`O(1)`, `O(N)`).
    ///
    /// The lights are read from the scene's own arrays ([`CpuRenderer::shares_lights_with`]
    /// the scene's other renderers).
    pub fn from_samplers(samplers: &SceneSamplers, scheme: Scheme, seed: u64) -> Self {
        let scene = samplers.scene();
        match samplers.sampler(scheme) {
            SchemeSampler::PointFree(sampler) => {
                Self::with_lights(scene, sampler, samplers.cpu_lights().clone(), seed)
            }
            SchemeSampler::Spatial(spatial) => Self::with_spatial(scene, spatial, seed),
        }
    }

    /// A [`Scheme::Spatial`] renderer with a spatial sampler already built over the scene
    /// (owned, or shared through an `Arc`).
    ///
    /// # Panics
    /// If the sampler's light count differs from the scene's.
    pub fn with_spatial(scene: &Scene, spatial: impl Into<Arc<SpatialSampler>>, seed: u64) -> Self {
        let spatial = spatial.into();
        assert_eq!(
            spatial.light_count(),
            scene.light_count(),
            "sampler built for another scene"
        );
        let (accumulator, to_unit) = accumulator_for(scene);
        Self {
            plane: scene.plane.clone(),
            picker: SchemeSampler::Spatial(spatial),
            lights: CpuLights::none(),
            uniform_n: None,
            seed,
            to_unit,
            accumulator,
        }
    }

    /// Like [`CpuRenderer::new`] with a sampler already built over `scene.powers` (the app
    /// shares one table between its views).
    ///
    /// # Panics
    /// If the sampler's light count differs from the scene's.
    pub fn with_sampler(scene: &Scene, sampler: Sampler, seed: u64) -> Self {
        Self::with_lights(scene, sampler, CpuLights::of(scene), seed)
    }

    /// [`CpuRenderer::with_sampler`] over records already built for `scene`.
    fn with_lights(scene: &Scene, sampler: Sampler, lights: CpuLights, seed: u64) -> Self {
        assert_eq!(
            LightSampler::light_count(&sampler),
            scene.light_count(),
            "sampler built for another scene"
        );
        let uniform = sampler.scheme() == Scheme::Uniform;
        let (accumulator, to_unit) = accumulator_for(scene);
        Self {
            plane: scene.plane.clone(),
            picker: SchemeSampler::PointFree(sampler),
            lights,
            uniform_n: uniform.then_some(scene.light_count() as f64),
            seed,
            to_unit,
            accumulator,
        }
    }

    /// Adds `samples_per_pixel` samples to every pixel, continuing the sample index `k` from
    /// the samples already accumulated. The total is capped at `u32::MAX` samples per pixel
    /// (the stream key holds `k` in 32 bits).
    pub fn accumulate(&mut self, samples_per_pixel: u32) {
        let k0 = self.accumulator.samples_per_pixel;
        let spp = samples_per_pixel.min(u32::MAX - k0);
        let width = self.plane.width as usize;
        if spp == 0 || width == 0 {
            return;
        }
        let Self {
            plane,
            picker,
            lights,
            uniform_n,
            seed,
            to_unit,
            accumulator,
        } = self;
        let (plane, picker, seed, to_unit) = (&*plane, &*picker, *seed, *to_unit);
        let lights = Lights {
            positions: &lights.positions,
            powers: &lights.powers,
            emission: lights.emission.as_deref(),
            uniform: uniform_n.map(|n| (n, lights.pmf)),
            to_unit,
        };
        let (sum, sum_sq) = (&mut accumulator.sum, &mut accumulator.sum_sq);
        match picker {
            SchemeSampler::PointFree(sampler) => sum
                .par_chunks_mut(width)
                .zip(sum_sq.par_chunks_mut(width))
                .enumerate()
                .for_each(|(py, (sum_row, sq_row))| {
                    render_row(
                        plane,
                        sampler,
                        &lights,
                        seed,
                        py as u32,
                        (k0, spp),
                        sum_row,
                        sq_row,
                    );
                }),
            SchemeSampler::Spatial(spatial) => sum
                .par_chunks_mut(width * SPATIAL_BAND)
                .zip(sum_sq.par_chunks_mut(width * SPATIAL_BAND))
                .enumerate()
                .for_each(|(band, (sum_band, sq_band))| {
                    render_band_spatial(
                        plane,
                        (spatial, to_unit),
                        seed,
                        (band * SPATIAL_BAND) as u32,
                        (k0, spp),
                        sum_band,
                        sq_band,
                    );
                }),
        }
        accumulator.samples_per_pixel = k0 + spp;
    }

    /// The running sums.
    pub fn accumulator(&self) -> &Accumulator {
        &self.accumulator
    }

    /// Samples per pixel accumulated so far.
    pub fn samples_per_pixel(&self) -> u32 {
        self.accumulator.samples_per_pixel
    }

    /// Drops every sample (the next pass starts again at `k = 0`).
    pub fn reset(&mut self) {
        self.accumulator = self.accumulator.emptied();
    }

    /// The scheme lights are picked with.
    pub fn scheme(&self) -> Scheme {
        self.picker.scheme()
    }

    /// The sampler lights are picked with, whatever its scheme.
    pub fn scheme_sampler(&self) -> &SchemeSampler {
        &self.picker
    }

    /// The point-free sampler lights are picked with (`None` for [`Scheme::Spatial`]).
    pub fn sampler(&self) -> Option<&Sampler> {
        match &self.picker {
            SchemeSampler::PointFree(sampler) => Some(sampler),
            SchemeSampler::Spatial(_) => None,
        }
    }

    /// The spatial sampler (`Some` only for [`Scheme::Spatial`]).
    pub fn spatial(&self) -> Option<&SpatialSampler> {
        match &self.picker {
            SchemeSampler::PointFree(_) => None,
            SchemeSampler::Spatial(spatial) => Some(spatial),
        }
    }

    /// The seed of every pixel stream.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Heap bytes the renderer holds per light beyond the scene's: none for point lights
    /// (the power schemes read the scene's positions and powers, the spatial one its
    /// sampler), the emission profiles' copy for spots and ranges; profiles shared with
    /// another renderer are counted by each ([`CpuRenderer::shares_lights_with`]).
    pub fn light_bytes(&self) -> usize {
        self.lights.heap_bytes()
    }

    /// Whether this renderer reads the very lights (and profiles) of `other` (both built
    /// through [`CpuRenderer::from_samplers`] from one scene's samplers), so that they are
    /// held once.
    pub fn shares_lights_with(&self, other: &CpuRenderer) -> bool {
        self.lights.shares_with(&other.lights)
    }

    /// Heap bytes of the accumulator's per-pixel sums (16 bytes per pixel).
    pub fn pixel_bytes(&self) -> usize {
        let a = &self.accumulator;
        (a.sum.capacity() + a.sum_sq.capacity()) * std::mem::size_of::<f64>()
    }
}

/// The lights a power-picking pass reads, and the emission profiles when the scene has any.
#[derive(Clone, Copy)]
struct Lights<'a> {
    positions: &'a [DVec3],
    powers: &'a [f64],
    emission: Option<&'a [Emission]>,
    /// `N` and the pmf's scale for uniform picking, `None` for power picking
    /// ([`CpuRenderer::uniform_n`]).
    uniform: Option<(f64, PmfScale)>,
    /// `2^-s`.
    to_unit: f64,
}

impl Lights<'_> {
    /// `ê' = w_i · G_i(x)·S_i(x)` of light `i` at `x`, with `w_i = N·p_i·2^-s` (uniform) or
    /// `2^-s` (power), evaluated in that order. Always inlined: left to itself the compiler
    /// made this a call in the power schemes' batch loop once `light_term` had another
    /// inlined caller, and an alias sample took a tenth longer.
    #[allow(
        clippy::inline_always,
        reason = "measured: a call here costs an alias sample a tenth"
    )]
    #[inline(always)]
    fn estimate(&self, i: u32, x: DVec2) -> f64 {
        let i = i as usize;
        let weight = match self.uniform {
            Some((n, pmf)) => n * pmf.of(self.powers[i]) * self.to_unit,
            None => self.to_unit,
        };
        weight * light_term(self.positions[i], self.emission.map(|e| e[i].shape()), x)
    }
}

/// Samples handled together: their picks first, then their lights, so that the
/// random memory accesses of a batch (alias table entries, light positions: cache misses for
/// large `N`) are independent loads in short loops, which the CPU overlaps.
const BATCH: usize = 16;

/// Calls `pixel(x_p, p, Σê, Σê²)` for every pixel `p` of row `py` (centre `x_p`), with the
/// pixel's running sums to add to.
#[inline]
fn for_each_pixel(
    plane: &ReceiverPlane,
    py: u32,
    sum_row: &mut [f64],
    sq_row: &mut [f64],
    mut pixel: impl FnMut(DVec2, u64, &mut f64, &mut f64),
) {
    let row_start = u64::from(py) * u64::from(plane.width);
    for (px, (sum, sq)) in sum_row.iter_mut().zip(sq_row.iter_mut()).enumerate() {
        let (mut s, mut q) = (*sum, *sq);
        pixel(
            pixel_center(plane, px as u32, py),
            row_start + px as u64,
            &mut s,
            &mut q,
        );
        *sum = s;
        *sq = q;
    }
}

/// Samples `k ∈ k0 .. k0 + spp` of every pixel of row `py`, added in increasing `k`.
#[allow(clippy::too_many_arguments)] // The disjoint borrows of one renderer, split for rayon.
#[inline]
fn render_row(
    plane: &ReceiverPlane,
    sampler: &Sampler,
    lights: &Lights<'_>,
    seed: u64,
    py: u32,
    (k0, spp): (u32, u32),
    sum_row: &mut [f64],
    sq_row: &mut [f64],
) {
    let end = k0 + spp;
    let mut picks = [0u32; BATCH];
    if (spp as usize) < BATCH {
        // Few samples per pixel (the app adds one per frame): batch across pixels instead,
        // so the random loads still overlap. Each pixel still adds its samples in increasing
        // `k`, so the sums are bit for bit those of the per-pixel loop below.
        let row_start = u64::from(py) * u64::from(plane.width);
        for first in (0..sum_row.len()).step_by(BATCH) {
            let count = (sum_row.len() - first).min(BATCH);
            for k in k0..end {
                let batch = &mut picks[..count];
                pick_batch_across(sampler, seed, row_start + first as u64, k, batch);
                for (j, &i) in batch.iter().enumerate() {
                    let px = first + j;
                    let x = pixel_center(plane, px as u32, py);
                    let e = lights.estimate(i, x);
                    sum_row[px] += e;
                    sq_row[px] += e * e;
                }
            }
        }
        return;
    }
    for_each_pixel(plane, py, sum_row, sq_row, |x, p, s, q| {
        let mut k = k0;
        while k < end {
            let batch = &mut picks[..((end - k) as usize).min(BATCH)];
            pick_batch(sampler, seed, p, k, batch);
            for &i in batch.iter() {
                let e = lights.estimate(i, x);
                *s += e;
                *q += e * e;
            }
            k += batch.len() as u32;
        }
    });
}

/// Pixels whose spatial samples are drawn together ([`SpatialSampler::estimate_many`]).
const SPATIAL_BATCH: usize = 8;

/// Rows of pixels one spatial task renders together, in blocks of [`SPATIAL_BATCH`] columns
/// (a pass of one sample per pixel then reads each tile's cut and subtrees for a block of
/// neighbouring pixels at a time, not once per row).
const SPATIAL_BAND: usize = 8;

/// [`render_row`] for [`Scheme::Spatial`] over the rows `py0 ..` of a band
/// (`sum_band.len() / width` of them): sample `k` of pixel `p` is
/// `spatial.estimate(x_p, &mut Rng::new(seed, (k << 32) | p))` times `to_unit = 2^-s`, drawn
/// for [`SPATIAL_BATCH`] neighbouring pixels at a time (their descents interleaved), block
/// by block of [`SPATIAL_BATCH`] columns and the band's rows, each pixel still adding its
/// samples in increasing `k`: the same sums, bit for bit, whatever the order of the pixels.
#[inline]
fn render_band_spatial(
    plane: &ReceiverPlane,
    sampler: (&SpatialSampler, f64),
    seed: u64,
    py0: u32,
    ks: (u32, u32),
    sum_band: &mut [f64],
    sq_band: &mut [f64],
) {
    let width = plane.width as usize;
    let rows = sum_band.len() / width;
    for first in (0..width).step_by(SPATIAL_BATCH) {
        let columns = first..(first + SPATIAL_BATCH).min(width);
        for row in 0..rows {
            let pixels = row * width + columns.start..row * width + columns.end;
            render_pixels_spatial(
                plane,
                sampler,
                seed,
                [columns.start as u32, py0 + row as u32],
                ks,
                &mut sum_band[pixels.clone()],
                &mut sq_band[pixels],
            );
        }
    }
}

/// [`render_band_spatial`]'s samples for the pixels from `(px0, py)` along its row (one sum
/// each in `sum`, `sq`): a full batch of [`SPATIAL_BATCH`] drawn together, fewer one by one.
#[inline]
fn render_pixels_spatial(
    plane: &ReceiverPlane,
    (spatial, to_unit): (&SpatialSampler, f64),
    seed: u64,
    [px0, py]: [u32; 2],
    (k0, spp): (u32, u32),
    sum: &mut [f64],
    sq: &mut [f64],
) {
    let p0 = u64::from(py) * u64::from(plane.width) + u64::from(px0);
    let stream = |k: u32, j: usize| Rng::new(seed, (u64::from(k) << 32) | (p0 + j as u64));
    if sum.len() == SPATIAL_BATCH {
        let points: [DVec2; SPATIAL_BATCH] =
            std::array::from_fn(|j| pixel_center(plane, px0 + j as u32, py));
        for k in k0..k0 + spp {
            let mut rngs = std::array::from_fn(|j| stream(k, j));
            // The pass's first sample of these pixels finds their tiles' cuts cold.
            let estimates = if k == k0 {
                spatial.estimate_many_cold(&points, &mut rngs)
            } else {
                spatial.estimate_many(&points, &mut rngs)
            };
            for (j, e) in estimates.into_iter().enumerate() {
                let e = e * to_unit;
                sum[j] += e;
                sq[j] += e * e;
            }
        }
        return;
    }
    for (j, (s, q)) in sum.iter_mut().zip(sq.iter_mut()).enumerate() {
        let x = pixel_center(plane, px0 + j as u32, py);
        for k in k0..k0 + spp {
            let e = spatial.estimate(x, &mut stream(k, j)) * to_unit;
            *s += e;
            *q += e * e;
        }
    }
}

/// `out[j]` = the light of sample `k + j` of pixel `p`: exactly
/// `sampler.pick_light(&mut Rng::new(seed, ((k + j) << 32) | p))` ([`pick_streams`]).
#[inline]
fn pick_batch(sampler: &Sampler, seed: u64, p: u64, k: u32, out: &mut [u32]) {
    pick_streams(sampler, seed, |j| (u64::from(k + j as u32) << 32) | p, out);
}

/// `out[j]` = the light of sample `k` of pixel `p0 + j`: exactly
/// `sampler.pick_light(&mut Rng::new(seed, (k << 32) | (p0 + j)))` ([`pick_streams`]).
#[inline]
fn pick_batch_across(sampler: &Sampler, seed: u64, p0: u64, k: u32, out: &mut [u32]) {
    pick_streams(
        sampler,
        seed,
        |j| (u64::from(k) << 32) | (p0 + j as u64),
        out,
    );
}

/// `out[j]` = `sampler.pick_light(&mut Rng::new(seed, stream(j)))`. For the alias table the
/// column pick and the keep draw of every pick are made first and the table lookups after:
/// the same [`crate::AliasTable::pick_column`] (Lemire's rejection, redrawing from the
/// pick's own stream) and the same next draw that [`crate::AliasTable::sample`] uses, so the
/// same picks, with the batch's random loads independent of each other.
#[inline]
fn pick_streams(sampler: &Sampler, seed: u64, stream: impl Fn(usize) -> u64, out: &mut [u32]) {
    if let Sampler::Alias(table) = sampler {
        let mut draws = [(0usize, 0u32); BATCH];
        for (j, d) in draws[..out.len()].iter_mut().enumerate() {
            let mut rng = Rng::new(seed, stream(j));
            let column = table.pick_column(&mut rng);
            *d = (column, rng.next_u32());
        }
        for (o, &(column, r2)) in out.iter_mut().zip(&draws) {
            *o = table.resolve(column, r2);
        }
    } else {
        for (j, o) in out.iter_mut().enumerate() {
            *o = sampler.pick_light(&mut Rng::new(seed, stream(j)));
        }
    }
}

impl ProgressiveRenderer for CpuRenderer {
    fn accumulate(&mut self, samples_per_pixel: u32) {
        CpuRenderer::accumulate(self, samples_per_pixel);
    }

    fn accumulator(&self) -> &Accumulator {
        CpuRenderer::accumulator(self)
    }
}

/// A [`convergence_series`] per scheme on the CPU, each from a fresh [`CpuRenderer`] with
/// the same `seed`.
///
/// # Panics
/// If the reference was computed for another image size than the scene's.
pub fn cpu_convergence(
    scene: &Scene,
    reference: &Reference,
    schemes: &[Scheme],
    seed: u64,
    max_spp: u32,
) -> Vec<SchemeSeries> {
    schemes
        .iter()
        .map(|&scheme| {
            let mut renderer = CpuRenderer::new(scene, scheme, seed);
            SchemeSeries {
                scheme,
                series: convergence_series(&mut renderer, reference, max_spp),
            }
        })
        .collect()
}
