//! The progressive renderer on the GPU, the twin of the CPU estimator contract: the
//! renderer and its state here; its sample passes (`passes.rs`), its outputs (`output.rs`)
//! and what it is built on (`targets.rs`) beside it.

mod output;
mod passes;
mod targets;
mod tile_pass;

use std::sync::Arc;

use glam::UVec2;

use super::pass_timer::PassTimer;
use super::render_kernel::{BYTES_PER_LIGHT, GpuLight};
use super::scheme::scheme_code;
use super::spatial::SpatialGpu;
use super::split::SplitArray;
use super::{GpuContext, GpuError};
use crate::scene::Scene;
use crate::{Construction, LightPowers, SceneSamplers, Scheme};
use targets::{Targets, check_image_size, light_buffers};

/// Progressive rendering of a [`Scene`] on the GPU, following the estimator contract of
/// [`crate::render`]: pixel `p` takes its `k`-th sample from
/// `Rng::new(seed, (k << 32) | p)`, picks light `i` exactly as
/// [`crate::Sampler::pick_light`] does, and accumulates the normalized estimate `ê` and
/// `ê²` in `f32`:
///
/// * uniform: `ê = N · p_i · G_i(x)`,
/// * alias and alias-one-random (power-proportional): `ê = G_i(x)` (the power cancels),
/// * spatial: `ê = p_i·G_i(x) / P(i | x)` from `spatial.wgsl`, the twin of
///   [`crate::spatial`] (the exact pick for `N ≤` [`crate::spatial::EXACT_MAX_LIGHTS`], else
///   the light tree, built in `f64` on the CPU as the CPU renderer builds it and uploaded as
///   `f32` arrays the first time the scheme is used: its contributing lights in leaf order,
///   16 bytes each, and its 80-byte nodes, about 20 more bytes per light in all),
///
/// with `G_i(x) = z_i / (4π r³)` evaluated in `f32` with power-of-two rescaling, so it
/// neither overflows nor underflows before `G` itself leaves the `f32` range. The image is
/// `Φ_total · Σ ê / spp` ([`crate::render::Accumulator::image`] after [`GpuRenderer::readback`]).
///
/// Per light the GPU holds `(x, y, z, p_i)` as `f32` and the packed alias entry
/// `(threshold, alias)` of its column as `u32`, interleaved in one 24-byte record so that a
/// column kept by the alias test finds its light in the cache line just read. Raw powers
/// are never uploaded (an `f32` cannot hold `10^±300`); only the normalized `p_i`, needed
/// by the uniform estimate.
#[derive(Debug)]
pub struct GpuRenderer {
    ctx: GpuContext,
    scheme: Scheme,
    seed: u64,
    width: u32,
    height: u32,
    /// The scene, its alias table and its spatial sampler, shared with whoever else renders
    /// or shows the scene (no copy of the positions or powers of its own).
    samplers: SceneSamplers,
    spatial: Option<SpatialGpu>,
    total_power: f64,
    /// `Φ_total` whatever its magnitude, and the scene's accumulation shift `s`
    /// ([`crate::scene::Scene::irradiance_shift`]) the read-back sums are put in.
    total_scaled: crate::Scaled,
    shift: i32,
    samples_per_pixel: u32,
    /// Rows `0..band_row` already hold sample `k = samples_per_pixel` (a pass in progress,
    /// [`GpuRenderer::accumulate_rows`]); 0 when none is.
    band_row: u32,
    plane: [f32; 4],
    /// The lights, shared with the scene's other renderers when built by
    /// [`GpuRenderer::from_samplers_sharing`].
    lights: Arc<SplitArray>,
    /// The lights' emission profiles, for a scene with spots or ranges (shared likewise).
    shapes: Option<Arc<SplitArray>>,
    /// The per-pixel sums, the output texture, the kernels and their bindings.
    targets: Targets,
    timer: PassTimer,
}

impl GpuRenderer {
    /// Uploads `scene` (positions, normalized powers, alias table) and prepares an empty
    /// accumulation with `scheme` and `seed`: [`GpuRenderer::from_samplers`] over a copy of
    /// the scene and its integer-built table.
    pub fn new(
        ctx: &GpuContext,
        scene: &Scene,
        scheme: Scheme,
        seed: u64,
    ) -> Result<Self, GpuError> {
        if scene.positions.len() != scene.powers.len() {
            return Err(GpuError::LightCountMismatch {
                expected: scene.positions.len(),
                got: scene.powers.len(),
            });
        }
        let samplers = SceneSamplers::new(Arc::new(scene.clone()), Construction::default());
        Self::from_samplers(ctx, &samplers, scheme, seed)
    }

    /// Uploads the scene of `samplers` with its own alias table (the one the app's panels
    /// show) and, for [`Scheme::Spatial`], its spatial sampler, sharing them rather than
    /// building its own; then prepares an empty accumulation with `scheme` and `seed`.
    ///
    /// Refuses [`Scheme::Cdf`] ([`GpuError::UnsupportedScheme`]), an empty image or one
    /// beyond the device's texture size ([`GpuError::ImageSize`]), a scene the `f32` upload
    /// cannot hold ([`GpuRenderer::check_scene`], [`GpuError::BeyondF32`]), pixel sums
    /// beyond one binding ([`GpuError::BufferTooLarge`]) and lights needing more bindings
    /// than a shader stage has ([`GpuError::TooManyBindings`]); lights beyond one binding are
    /// split over several ([`crate::gpu`] § Limits).
    pub fn from_samplers(
        ctx: &GpuContext,
        samplers: &SceneSamplers,
        scheme: Scheme,
        seed: u64,
    ) -> Result<Self, GpuError> {
        Self::build(ctx, samplers, scheme, seed, None)
    }

    /// [`GpuRenderer::from_samplers`] reading the lights `lights_of` uploaded (positions,
    /// `p_i`, alias entries and emission profiles: 24 bytes per light, 48 with profiles)
    /// instead of uploading them again, when `lights_of` renders the same scene and table
    /// ([`SceneSamplers::scene`], [`SceneSamplers::table`]) on the same device; otherwise
    /// exactly [`GpuRenderer::from_samplers`]. The app's three images share one upload this
    /// way. The same images bit for bit: the buffers hold the same bytes.
    pub fn from_samplers_sharing(
        ctx: &GpuContext,
        samplers: &SceneSamplers,
        scheme: Scheme,
        seed: u64,
        lights_of: &GpuRenderer,
    ) -> Result<Self, GpuError> {
        let same = ctx.device() == lights_of.ctx.device()
            && Arc::ptr_eq(samplers.scene(), lights_of.samplers.scene())
            && Arc::ptr_eq(samplers.table(), lights_of.samplers.table());
        let shared = same.then(|| (Arc::clone(&lights_of.lights), lights_of.shapes.clone()));
        Self::build(ctx, samplers, scheme, seed, shared)
    }

    /// Whether this renderer reads the very light buffers of `other`
    /// ([`GpuRenderer::from_samplers_sharing`]), so that the device holds them once.
    pub fn shares_lights_with(&self, other: &GpuRenderer) -> bool {
        Arc::ptr_eq(&self.lights, &other.lights)
    }

    /// [`GpuRenderer::from_samplers`], over the light buffers `shared` when given (already
    /// holding the scene's lights), else over new ones.
    fn build(
        ctx: &GpuContext,
        samplers: &SceneSamplers,
        scheme: Scheme,
        seed: u64,
        shared: Option<(Arc<SplitArray>, Option<Arc<SplitArray>>)>,
    ) -> Result<Self, GpuError> {
        let scene: &Scene = samplers.scene();
        scheme_code(scheme)?;
        let (width, height) = (scene.plane.width, scene.plane.height);
        check_image_size(ctx, width, height)?;
        if scene.positions.len() != scene.powers.len() {
            return Err(GpuError::LightCountMismatch {
                expected: scene.positions.len(),
                got: scene.powers.len(),
            });
        }
        Self::check_scene(scene)?;
        let plane = &scene.plane;
        let plane = [
            plane.min.x as f32,
            plane.max.y as f32,
            (plane.max.x - plane.min.x) as f32,
            (plane.max.y - plane.min.y) as f32,
        ];
        let is_shared = shared.is_some();
        let (lights, shapes) = match shared {
            Some(shared) => shared,
            None => light_buffers(ctx, scene)?,
        };
        let targets = Targets::new(ctx, width, height, &lights, shapes.as_deref())?;

        let mut renderer = Self {
            ctx: ctx.clone(),
            scheme,
            seed,
            width,
            height,
            samplers: samplers.clone(),
            spatial: None,
            total_power: 0.0,
            total_scaled: crate::Scaled::ZERO,
            shift: 0,
            samples_per_pixel: 0,
            band_row: 0,
            plane,
            lights,
            shapes,
            targets,
            timer: PassTimer::new(ctx),
        };
        if is_shared {
            renderer.adopt_lights()?;
        } else {
            renderer.upload_lights()?;
        }
        Ok(renderer)
    }

    /// Whether the GPU can hold `scene`'s coordinates: the upload converts every light
    /// position `(x, y, z)`, the plane's corners `plane.min[0]`, `plane.max[1]` and its
    /// extents `plane.max[k] − plane.min[k]` to `f32`, and a finite `f64` beyond
    /// `f32::MAX ≈ 3.4·10^38` in magnitude becomes `±inf` there (the image would be NaN).
    /// The first such value is refused with [`GpuError::BeyondF32`], naming its field
    /// (`lights[i].position[k]`, `plane.min[k]`, …). Needs no device (the app and the CLI
    /// ask before choosing one). The light tree's bounds are taken from the positions, so
    /// they are covered, and normalized powers lie in `[0, 1]`.
    pub fn check_scene(scene: &Scene) -> Result<(), GpuError> {
        let fits = |v: f64| (v as f32).is_finite();
        let refuse = |field: String, v: f64| GpuError::BeyondF32 {
            field,
            value: format!("{v:e}"),
        };
        let plane = &scene.plane;
        for k in 0..2 {
            let extent = plane.max[k] - plane.min[k];
            if !fits(plane.min[k]) {
                return Err(refuse(format!("plane.min[{k}]"), plane.min[k]));
            }
            if !fits(plane.max[k]) {
                return Err(refuse(format!("plane.max[{k}]"), plane.max[k]));
            }
            if !fits(extent) {
                return Err(refuse(format!("plane.max[{k}] − plane.min[{k}]"), extent));
            }
        }
        for (i, p) in scene.positions.iter().enumerate() {
            if let Some(k) = p.to_array().iter().position(|&v| !fits(v)) {
                return Err(refuse(format!("lights[{i}].position[{k}]"), p[k]));
            }
        }
        Ok(())
    }

    /// Replaces the light powers (same number of lights): rebuilds the alias table
    /// (`O(N)`, integer construction), uploads it and the normalized powers, and restarts the
    /// accumulation. The renderer's samplers are then its own (the scene changed).
    pub fn set_powers(&mut self, powers: &LightPowers) -> Result<(), GpuError> {
        let n = self.samplers.scene().light_count();
        if powers.len() != n {
            return Err(GpuError::LightCountMismatch {
                expected: n,
                got: powers.len(),
            });
        }
        let mut scene = Scene::clone(self.samplers.scene());
        scene.powers = powers.clone();
        let samplers = SceneSamplers::new(Arc::new(scene), Construction::default());
        if Arc::strong_count(&self.lights) > 1 {
            // The light buffers are shared with renderers of the old powers: new ones.
            *self = Self::from_samplers(&self.ctx, &samplers, self.scheme, self.seed)?;
            return Ok(());
        }
        self.samplers = samplers;
        self.upload_lights()
    }

    /// Uploads the positions, normalized powers and packed alias entries of the scene's
    /// lights, and restarts the accumulation.
    fn upload_lights(&mut self) -> Result<(), GpuError> {
        let scene = self.samplers.scene();
        let lights: Vec<GpuLight> = scene
            .positions
            .iter()
            .zip(scene.powers.pmf())
            .zip(self.samplers.table().packed())
            .map(|((p, pmf), e)| GpuLight {
                position: p.as_vec3(),
                power: pmf as f32,
                entry: UVec2::new(e.threshold, e.alias),
            })
            .collect();
        self.lights.write(
            &self.ctx,
            "uploading the lights",
            bytemuck::cast_slice(&lights),
        )?;
        self.adopt_lights()
    }

    /// Takes the scene's totals and shift (the lights are on the device already), uploads
    /// the spatial sampler for [`Scheme::Spatial`], and restarts the accumulation.
    fn adopt_lights(&mut self) -> Result<(), GpuError> {
        let scene = self.samplers.scene();
        self.total_power = scene.powers.total();
        self.total_scaled = scene.powers.total_scaled();
        self.shift = scene.irradiance_shift();
        self.spatial = None;
        if self.scheme == Scheme::Spatial {
            self.ensure_spatial()?;
        }
        self.reset();
        Ok(())
    }

    /// Uploads the spatial sampler (built by the first of the scene's users) unless it is
    /// there already.
    fn ensure_spatial(&mut self) -> Result<(), GpuError> {
        if self.spatial.is_none() {
            self.spatial = Some(SpatialGpu::new(
                &self.ctx,
                (self.samplers.spatial(), &self.samplers.scene().plane),
                [&self.targets.params, &self.targets.sums],
            )?);
        }
        Ok(())
    }

    /// Switches the selection scheme and restarts the accumulation; [`Scheme::Cdf`] is
    /// refused ([`GpuError::UnsupportedScheme`]) and leaves the renderer unchanged.
    /// [`Scheme::Spatial`] builds and uploads its light tree the first time.
    pub fn set_scheme(&mut self, scheme: Scheme) -> Result<(), GpuError> {
        scheme_code(scheme)?;
        if scheme == Scheme::Spatial {
            self.ensure_spatial()?;
        }
        self.scheme = scheme;
        self.reset();
        Ok(())
    }

    /// Switches the seed and restarts the accumulation.
    pub fn set_seed(&mut self, seed: u64) {
        self.seed = seed;
        self.reset();
    }

    /// Forgets every sample: the sums return to zero and the next sample index is `k = 0`.
    pub fn reset(&mut self) {
        self.samples_per_pixel = 0;
        self.band_row = 0;
        let mut encoder =
            self.ctx
                .device()
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("render reset"),
                });
        encoder.clear_buffer(&self.targets.sums, 0, None);
        self.ctx.queue().submit([encoder.finish()]);
    }

    /// Samples per pixel accumulated so far (the next sample index `k`).
    pub fn samples_per_pixel(&self) -> u32 {
        self.samples_per_pixel
    }

    /// The selection scheme in use.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The seed of every stream.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Image size `(width, height)` in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// `Φ_total = Σ Φ_i` in `f64`, the accumulator's scale.
    pub fn total_power(&self) -> f64 {
        self.total_power
    }

    /// GPU bytes per light: 16 for `(x, y, z, p_i)` as `f32`, 8 for the packed alias entry,
    /// and for a scene with spots or ranges 24 for each light's emission profile (48 in
    /// all); with the spatial light tree uploaded, its lights in leaf order (16 bytes each,
    /// plus their profiles) and its 80-byte nodes (one per ~22 lights; with spots or
    /// ranges 320 more bytes of lane bounds each), rounded up.
    pub fn gpu_bytes_per_light(&self) -> u64 {
        let n = self.samplers.scene().light_count() as u64;
        self.gpu_light_bytes().div_ceil(n.max(1))
    }

    /// GPU bytes of the lights, their profiles and the spatial sampler (what
    /// [`GpuRenderer::gpu_bytes_per_light`] divides by the light count).
    pub fn gpu_light_bytes(&self) -> u64 {
        let tree = self.spatial.as_ref().map_or(0, |s| s.bytes);
        self.lights_upload_bytes() + tree
    }

    /// GPU bytes of the lights and their profiles alone (shared with the renderers built
    /// by [`GpuRenderer::from_samplers_sharing`] from this one): 24 bytes per light, 48
    /// with profiles.
    pub fn lights_upload_bytes(&self) -> u64 {
        let n = self.samplers.scene().light_count() as u64;
        n * BYTES_PER_LIGHT + self.shapes.as_deref().map_or(0, SplitArray::bytes)
    }

    /// GPU bytes held by the renderer: lights, table, profiles, spatial sampler, per-pixel
    /// sums (8 bytes) and the output texture (4 bytes per pixel).
    pub fn gpu_bytes(&self) -> u64 {
        let pixels = u64::from(self.width) * u64::from(self.height);
        self.gpu_light_bytes() + pixels * 12
    }

    /// The context the renderer runs on.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }
}
