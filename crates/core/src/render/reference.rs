//! The exact image: the sum over every light, at every pixel or at a fixed pixel subset.
//!
//! # What is computed
//! `E(x_p) = Φ_total · Σ_i p_i · G_i(x_p)` with `p_i = Φ_i/Φ_total` and
//! `G_i(x) = max(0, z_i)/(4π r_i³)` ([`crate::scene::geometry_term`]): the expectation of the
//! renderers' per-pixel estimate (same normalization, so the same `f64` range whatever the
//! powers). Lights with `z_i ≤ 0` or `p_i = 0` contribute exactly 0 and are dropped first;
//! the rest are summed as `(1/4π) · Σ_i c_i / (r_i²·√(r_i²))` with `c_i = p_i·z_i`
//! (algebraically `Σ p_i·G_i`; the rounding differs by a few ulps). A scene with a light
//! below `2^-300` sums `(1/4π) · Σ_i (c_i/r_i²)·(z_i/r_i)` with `c_i = p_i` instead, so that
//! neither `r_i³` nor `p_i·z_i·2^-s` (below) underflows: under a light `10^-150` above a
//! pixel the term is `≈ p_i·2^-s/z_i²`, near 1, while `p_i·z_i·2^-s ≈ 10^-450` is not an
//! `f64`. A scene with spots or ranges sums `p_i·G_i(x)·S_i(x)`
//! ([`crate::scene::light_term`]) light by light instead.
//!
//! # Scale
//! The sums run in the renderers' accumulation unit `U = Φ_total·2^s`
//! ([`crate::render::Accumulator::unit`]): `c_i = p_i·z_i·2^-s` (or `p_i·2^-s`), so they
//! neither overflow nor vanish whatever the powers, and scaling every power by `2^k` leaves
//! them unchanged bit for bit ([`Reference::in_unit`]). [`Reference::values`] are `U` times
//! them, in `f64`. Where a light is so close to a pixel that the irradiance itself exceeds
//! `f64` (a light `10^-160` above a pixel centre), [`Reference::overflow`] names the pixel
//! and the light.
//!
//! # Pixel subset
//! A full reference costs `N·P` light evaluations. When that exceeds the budget `B`
//! ([`DEFAULT_REFERENCE_BUDGET`] unless given), the reference covers
//! `m = max(⌊B/N⌋, MIN_REFERENCE_PIXELS)` pixels (at most `P`) placed by the R2
//! low-discrepancy sequence (Roberts 2018, the 2-D golden-ratio generalization):
//! sample `j` is pixel `(⌊W·frac(½ + j/g)⌋, ⌊H·frac(½ + j/g²)⌋)` with `g` the plastic number
//! (`g³ = g + 1`), duplicates removed. The subset is a fixed function of `(W, H, m)`:
//! it does not depend on the seed or the scene's content, it covers the image evenly, and it
//! does not alias with rows or columns the way a constant stride can. Metrics use exactly
//! the covered pixels ([`Reference::pixels`]).
//!
//! # Cost and determinism
//! Pixels are processed in blocks of [`PIXEL_BLOCK`] (in parallel), lights in chunks of
//! [`LIGHT_CHUNK`] that stay in the L1 cache while every pixel of the block sweeps them.
//! Each pixel's sum uses the same chunks and lanes in the same order whichever other
//! pixels are computed, so a pixel's value is identical bit for bit in a full and in a
//! subset reference, and for any thread count.

use glam::DVec2;
use rayon::prelude::*;

use crate::Scaled;
use crate::scene::{Scene, light_term, pixel_center};

/// Default light-pixel evaluation budget `B = 2^30 ≈ 1.07·10^9` (about a second on two
/// cores): a full reference for up to `B/P` lights (16 384 lights at 256 × 256), and for
/// `10^6` lights a subset of 1073 pixels.
pub const DEFAULT_REFERENCE_BUDGET: u64 = 1 << 30;

/// The fewest pixels a subset reference covers, whatever the budget: enough for the
/// RMSE to be estimated to a few percent.
pub const MIN_REFERENCE_PIXELS: usize = 256;

/// Pixels per parallel work item.
pub const PIXEL_BLOCK: usize = 16;

/// Lights per cache-resident chunk (`4 · 8 · 1024` bytes = 32 KiB of light data).
pub const LIGHT_CHUNK: usize = 1024;

/// Below this height (`2^-300`) a light's `r³` may underflow, and so may `p·z·2^-s`: the
/// reference then sums `(c/r²)·(z/r)` with `c = p·2^-s` instead of `c/r³` with
/// `c = p·z·2^-s`.
const CLOSE_HEIGHT: f64 = 4.909_093_465_297_727e-91;

/// Independent partial sums per pixel and chunk (vectorizable lanes).
const LANES: usize = 4;

/// The plastic number `g`, the real root of `g³ = g + 1`.
const PLASTIC: f64 = 1.324_717_957_244_746;

/// The exact irradiance at every pixel, or at a fixed subset of pixels (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    width: u32,
    height: u32,
    pixels: Vec<u32>,
    values: Vec<f64>,
    in_unit: Vec<f64>,
    unit: Scaled,
    overflow: Option<IrradianceOverflow>,
}

/// A pixel whose irradiance exceeds `f64`, and the light that makes it so.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the irradiance at pixel ({x}, {y}) exceeds f64: light {light} is too close to it \
     (a light closer than about 1e-154 to the plane overflows)"
)]
pub struct IrradianceOverflow {
    /// Pixel column.
    pub x: u32,
    /// Pixel row.
    pub y: u32,
    /// The light (0-based) whose contribution there is beyond `f64`, or the largest one
    /// when only their sum is.
    pub light: usize,
}

/// The lights in structure-of-arrays form, zero contributors dropped, padded to a multiple
/// of [`LANES`] with lights of `c = 0` (which add exactly 0). `c_i = p_i·z_i·2^-s`, or
/// `p_i·2^-s` when `close` (some light below [`CLOSE_HEIGHT`]).
struct LightArrays {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    c: Vec<f64>,
    close: bool,
}

impl LightArrays {
    fn new(scene: &Scene, to_unit: f64) -> Self {
        let pmf = scene.powers.pmf();
        let contributes = |z: f64, p: f64| z > 0.0 && p > 0.0;
        let close = scene
            .positions
            .iter()
            .zip(&pmf)
            .any(|(pos, &p)| contributes(pos.z, p) && pos.z < CLOSE_HEIGHT);
        let mut arrays = LightArrays {
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            c: Vec::new(),
            close,
        };
        for (pos, &p) in scene.positions.iter().zip(&pmf) {
            if contributes(pos.z, p) {
                let c = if close {
                    p * to_unit
                } else {
                    p * pos.z * to_unit
                };
                arrays.push(pos.x, pos.y, pos.z, c);
            }
        }
        while !arrays.c.len().is_multiple_of(LANES) {
            arrays.push(0.0, 0.0, 1.0, 0.0);
        }
        arrays
    }

    fn push(&mut self, x: f64, y: f64, z: f64, c: f64) {
        self.x.push(x);
        self.y.push(y);
        self.z.push(z);
        self.c.push(c);
    }
}

/// `Σ_i c_i / (r_i²·√(r_i²))` over one chunk (its length a multiple of [`LANES`]), in
/// [`LANES`] partial sums added in a fixed order. `CLOSE`: a scene with lights so low
/// (`z < 2^-300`) that `r³` and `p·z·2^-s` may underflow, summed as `(c_i/r_i²)·(z_i/r_i)`
/// with `c_i = p_i·2^-s` instead: `c_i/r_i² ≤ p_i·2^-s/z_i²` stays near 1 at most, and
/// `z_i/r_i ≤ 1`.
#[inline]
fn chunk_sum<const CLOSE: bool>(x: &[f64], y: &[f64], z: &[f64], c: &[f64], at: DVec2) -> f64 {
    let mut lanes = [0.0f64; LANES];
    for (((xs, ys), zs), cs) in x
        .chunks_exact(LANES)
        .zip(y.chunks_exact(LANES))
        .zip(z.chunks_exact(LANES))
        .zip(c.chunks_exact(LANES))
    {
        for l in 0..LANES {
            let dx = xs[l] - at.x;
            let dy = ys[l] - at.y;
            let r2 = dx * dx + dy * dy + zs[l] * zs[l];
            lanes[l] += if CLOSE {
                (cs[l] / r2) * (zs[l] / r2.sqrt())
            } else {
                cs[l] / (r2 * r2.sqrt())
            };
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3])
}

impl Reference {
    /// The reference under [`DEFAULT_REFERENCE_BUDGET`].
    pub fn compute(scene: &Scene) -> Self {
        Self::with_budget(scene, DEFAULT_REFERENCE_BUDGET)
    }

    /// The reference over every pixel if `N·P ≤ budget`, else over the R2 subset of
    /// `max(⌊budget/N⌋, MIN_REFERENCE_PIXELS)` pixels (see the module docs).
    pub fn with_budget(scene: &Scene, budget: u64) -> Self {
        let plane = &scene.plane;
        let pixel_count = plane.pixel_count();
        let n = scene.light_count() as u64;
        let full = n.saturating_mul(pixel_count as u64) <= budget;
        let pixels = if full {
            (0..pixel_count as u32).collect()
        } else {
            let m = ((budget / n.max(1)) as usize).max(MIN_REFERENCE_PIXELS);
            subset_pixels(plane.width, plane.height, m)
        };
        Self::at_pixels(scene, pixels)
    }

    /// The reference at the given pixels (row-major indices `py·width + px`), which are
    /// sorted and deduplicated.
    ///
    /// # Panics
    /// If a pixel index is outside the plane.
    pub fn at_pixels(scene: &Scene, mut pixels: Vec<u32>) -> Self {
        let plane = &scene.plane;
        pixels.sort_unstable();
        pixels.dedup();
        if let Some(&last) = pixels.last() {
            assert!(
                (last as usize) < plane.pixel_count(),
                "pixel {last} outside a {}×{} plane",
                plane.width,
                plane.height
            );
        }
        let width = plane.width;
        let shift = scene.irradiance_shift();
        let to_unit = Scaled::pow2(-shift).to_f64();
        let unit = scene.powers.total_scaled() * Scaled::pow2(shift);
        let mut values = vec![0.0; pixels.len()];
        if let Some(emission) = &scene.emission {
            let pmf = scene.powers.pmf();
            values
                .par_chunks_mut(PIXEL_BLOCK)
                .zip(pixels.par_chunks(PIXEL_BLOCK))
                .for_each(|(out, block)| {
                    for (o, &p) in out.iter_mut().zip(block) {
                        let at = pixel_center(plane, p % width, p / width);
                        let sum: f64 = scene
                            .positions
                            .iter()
                            .zip(&pmf)
                            .zip(emission)
                            .map(|((&pos, &pi), e)| pi * to_unit * light_term(pos, Some(e), at))
                            .sum();
                        *o = sum;
                    }
                });
            return Self::from_unit_values(scene, pixels, values, unit, to_unit);
        }
        let lights = LightArrays::new(scene, to_unit);
        let close = lights.close;
        values
            .par_chunks_mut(PIXEL_BLOCK)
            .zip(pixels.par_chunks(PIXEL_BLOCK))
            .for_each(|(out, block)| {
                let centers: Vec<DVec2> = block
                    .iter()
                    .map(|&p| pixel_center(plane, p % width, p / width))
                    .collect();
                let mut sums = [0.0f64; PIXEL_BLOCK];
                for start in (0..lights.c.len()).step_by(LIGHT_CHUNK) {
                    let end = (start + LIGHT_CHUNK).min(lights.c.len());
                    let (x, y, z, c) = (
                        &lights.x[start..end],
                        &lights.y[start..end],
                        &lights.z[start..end],
                        &lights.c[start..end],
                    );
                    for (sum, &at) in sums.iter_mut().zip(&centers) {
                        *sum += if close {
                            chunk_sum::<true>(x, y, z, c, at)
                        } else {
                            chunk_sum::<false>(x, y, z, c, at)
                        };
                    }
                }
                for (o, s) in out.iter_mut().zip(sums) {
                    *o = s / (4.0 * std::f64::consts::PI);
                }
            });
        Self::from_unit_values(scene, pixels, values, unit, to_unit)
    }

    /// The reference from its values in the unit `unit`, with the first pixel whose value
    /// is not finite named with its light.
    fn from_unit_values(
        scene: &Scene,
        pixels: Vec<u32>,
        in_unit: Vec<f64>,
        unit: Scaled,
        to_unit: f64,
    ) -> Self {
        let overflow = find_overflow(scene, &pixels, &in_unit, to_unit);
        let values = in_unit.iter().map(|&v| unit.mul_f64(v).to_f64()).collect();
        Self {
            width: scene.plane.width,
            height: scene.plane.height,
            pixels,
            values,
            in_unit,
            unit,
            overflow,
        }
    }

    /// The values in the accumulation unit ([`Reference::unit`]), in the order of
    /// [`Reference::pixels`]: the same bits whatever power of two scales the powers.
    pub fn in_unit(&self) -> &[f64] {
        &self.in_unit
    }

    /// The unit `U = Φ_total·2^s` of [`Reference::in_unit`] (that of the CPU renderer's
    /// [`crate::render::Accumulator`] for the same scene).
    pub fn unit(&self) -> Scaled {
        self.unit
    }

    /// The first covered pixel whose irradiance exceeds `f64`, with the light responsible.
    pub fn overflow(&self) -> Option<IrradianceOverflow> {
        self.overflow
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The covered pixels, row-major indices in increasing order.
    pub fn pixels(&self) -> &[u32] {
        &self.pixels
    }

    /// The exact irradiance at each covered pixel, in the order of [`Reference::pixels`].
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// `(pixel, exact irradiance)` for every covered pixel.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.pixels
            .iter()
            .zip(&self.values)
            .map(|(&p, &v)| (p as usize, v))
    }

    /// Whether every pixel is covered.
    pub fn is_complete(&self) -> bool {
        self.pixels.len() == self.width as usize * self.height as usize
    }

    /// The whole exact image (row-major) when the reference is complete.
    pub fn image(&self) -> Option<&[f64]> {
        self.is_complete().then_some(self.values.as_slice())
    }

    /// Heap bytes held, by capacity: per covered pixel its index (4 bytes) and its
    /// irradiance in two units (16); nothing per light.
    pub fn heap_bytes(&self) -> usize {
        self.pixels.capacity() * std::mem::size_of::<u32>()
            + (self.values.capacity() + self.in_unit.capacity()) * std::mem::size_of::<f64>()
    }
}

/// The first covered pixel whose irradiance does not fit `f64`, and its light: a light whose
/// term `p_i·2^-s·G_i(x)` is not finite there (only lights with `z ≲ 10^-154` can have
/// one: they are found first, in `O(N)`, then checked at the covered pixels), or, where the
/// sum alone overflows, the largest term of that pixel.
fn find_overflow(
    scene: &Scene,
    pixels: &[u32],
    in_unit: &[f64],
    to_unit: f64,
) -> Option<IrradianceOverflow> {
    let width = scene.plane.width;
    let pmf = scene.powers.pmf_scale();
    let term = |i: usize, at: DVec2| {
        pmf.of(scene.powers.as_slice()[i]) * to_unit * scene.light_term(i, at)
    };
    let at = |p: u32| pixel_center(&scene.plane, p % width, p / width);
    let named = |p: u32, light: usize| IrradianceOverflow {
        x: p % width,
        y: p / width,
        light,
    };
    let close: Vec<usize> = (0..scene.light_count())
        .filter(|&i| {
            let z = scene.positions[i].z;
            z > 0.0 && !(1.0 / (z * z)).is_finite() && scene.powers.as_slice()[i] > 0.0
        })
        .collect();
    if !close.is_empty() {
        for &p in pixels {
            if let Some(&i) = close.iter().find(|&&i| !term(i, at(p)).is_finite()) {
                return Some(named(p, i));
            }
        }
    }
    let (&p, _) = pixels.iter().zip(in_unit).find(|(_, v)| !v.is_finite())?;
    let light = (0..scene.light_count())
        .max_by(|&a, &b| term(a, at(p)).total_cmp(&term(b, at(p))))
        .unwrap_or(0);
    Some(named(p, light))
}

/// The R2 subset of about `m` pixels of a `width × height` image (see the module docs),
/// sorted and deduplicated; every pixel when `m ≥ width·height`.
pub fn subset_pixels(width: u32, height: u32, m: usize) -> Vec<u32> {
    let total = width as usize * height as usize;
    if m >= total {
        return (0..total as u32).collect();
    }
    let (a1, a2) = (1.0 / PLASTIC, 1.0 / (PLASTIC * PLASTIC));
    let mut pixels: Vec<u32> = (0..m)
        .map(|j| {
            let u = (0.5 + j as f64 * a1).fract();
            let v = (0.5 + j as f64 * a2).fract();
            let px = ((u * f64::from(width)) as u32).min(width - 1);
            let py = ((v * f64::from(height)) as u32).min(height - 1);
            py * width + px
        })
        .collect();
    pixels.sort_unstable();
    pixels.dedup();
    pixels
}
