//! The progressive renderer on the GPU, the twin of the CPU estimator contract.

use std::ops::Range;
use std::sync::Arc;

use glam::{UVec2, Vec3};

use super::emission::{GpuShape, emission_source, shapes_layout};
use super::pass_timer::{PassClock, PassTimer};
use super::spatial::SpatialGpu;
use super::split::{Access, ArrayLayout, SplitArray, SplitShape, check_bindings, declarations};
use super::{GpuContext, GpuError, PICK_WGSL};
use crate::render::Accumulator;
use crate::scene::Scene;
use crate::{Construction, LightPowers, SceneSamplers, Scheme};

pub(crate) const RENDER_WGSL: &str = include_str!("render.wgsl");
pub(crate) const RENDER_COMMON_WGSL: &str = include_str!("render_common.wgsl");
pub(crate) const TONEMAP_WGSL: &str = include_str!("tonemap.wgsl");

/// Workgroups are 16×16 pixels.
const TILE: u32 = 16;
/// Samples (pixels × samples per pixel) per dispatch: long enough to amortize a submit,
/// short enough that no single dispatch runs for seconds on a real GPU.
const SAMPLES_PER_DISPATCH: u64 = 1 << 24;
/// Per-light GPU storage: `(x, y, z, p_i)` as four `f32` and the packed alias entry
/// `(threshold, alias)` as two `u32`, interleaved (`Light` in `render.wgsl`).
const BYTES_PER_LIGHT: u64 = 24;
/// The split-array layout of the lights: `fn lights_at(i: u32) -> Light` in `render.wgsl`.
pub(crate) const LIGHTS_LAYOUT: ArrayLayout = ArrayLayout {
    name: "lights",
    element: "Light",
    bytes: BYTES_PER_LIGHT,
};

/// One light as `render.wgsl` reads it (`Light`): position and `p_i` as `f32`, then the
/// packed alias entry `(threshold, alias)` of its column.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuLight {
    position: Vec3,
    power: f32,
    entry: UVec2,
}

/// The source of the accumulate kernel for lights split as `lights`, and emission profiles
/// split as `shapes` for a scene with spots or ranges.
pub(crate) fn render_source(lights: SplitShape, shapes: Option<SplitShape>) -> String {
    let shapes_binding = 2 + lights.chunks as u32;
    super::shader_source(&[
        PICK_WGSL,
        RENDER_COMMON_WGSL,
        &declarations(LIGHTS_LAYOUT, lights, 2, Access::Read),
        &emission_source("shapes", shapes.map(|s| (s, shapes_binding))),
        RENDER_WGSL,
    ])
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct RenderParams {
    seed_lo: u32,
    seed_hi: u32,
    k_base: u32,
    k_count: u32,
    width: u32,
    height: u32,
    n_lights: u32,
    scheme: u32,
    plane_min_x: f32,
    plane_max_y: f32,
    plane_extent_x: f32,
    plane_extent_y: f32,
    n_f32: f32,
    spatial_root: u32,
    row_begin: u32,
    row_end: u32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TonemapParams {
    factor: f32,
    width: u32,
    height: u32,
    band_row: u32,
    factor_band: f32,
    row_begin: u32,
    pad: [u32; 2],
}

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
/// `Φ_total · Σ ê / spp` ([`Accumulator::image`] after [`GpuRenderer::readback`]).
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
    params: wgpu::Buffer,
    /// The lights, shared with the scene's other renderers when built by
    /// [`GpuRenderer::from_samplers_sharing`].
    lights: Arc<SplitArray>,
    /// The lights' emission profiles, for a scene with spots or ranges (shared likewise).
    shapes: Option<Arc<SplitArray>>,
    sums: wgpu::Buffer,
    accumulate_pipeline: wgpu::ComputePipeline,
    accumulate_bind_group: wgpu::BindGroup,
    tonemap_params: wgpu::Buffer,
    tonemap_pipeline: wgpu::ComputePipeline,
    tonemap_bind_group: wgpu::BindGroup,
    output: wgpu::Texture,
    output_view: wgpu::TextureView,
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
        super::scheme_code(scheme)?;
        let (width, height) = (scene.plane.width, scene.plane.height);
        let limits = ctx.device().limits();
        let max = limits.max_texture_dimension_2d.min(
            limits
                .max_compute_workgroups_per_dimension
                .saturating_mul(TILE),
        );
        let pixels = u64::from(width) * u64::from(height);
        if width == 0 || height == 0 || width > max || height > max || pixels > 1 << 32 {
            return Err(GpuError::ImageSize { width, height, max });
        }
        if scene.positions.len() != scene.powers.len() {
            return Err(GpuError::LightCountMismatch {
                expected: scene.positions.len(),
                got: scene.powers.len(),
            });
        }
        Self::check_scene(scene)?;
        let n = scene.positions.len() as u64;
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
            None => (
                Arc::new(SplitArray::zeroed(
                    ctx,
                    "lights (positions, powers, alias table)",
                    LIGHTS_LAYOUT,
                    n,
                    wgpu::BufferUsages::empty(),
                )?),
                match &scene.emission {
                    Some(emission) => {
                        let shapes: Vec<GpuShape> = emission.iter().map(GpuShape::of).collect();
                        Some(Arc::new(SplitArray::with_contents(
                            ctx,
                            "lights' emission profiles (spots, ranges)",
                            shapes_layout("shapes"),
                            bytemuck::cast_slice(&shapes),
                            wgpu::BufferUsages::empty(),
                        )?))
                    }
                    None => None,
                },
            ),
        };
        let shape_bindings = shapes.as_ref().map_or(0, |s| s.buffers().len());
        check_bindings(
            ctx,
            "the render kernel",
            1 + (lights.buffers().len() + shape_bindings) as u32,
        )?;
        let sums = super::zeroed_storage_buffer(
            ctx,
            "pixel sums",
            pixels * 8,
            wgpu::BufferUsages::COPY_SRC,
        )?;
        let params = super::uniform_buffer(
            ctx,
            "render params",
            std::mem::size_of::<RenderParams>() as u64,
        );
        let tonemap_params = super::uniform_buffer(
            ctx,
            "tonemap params",
            std::mem::size_of::<TonemapParams>() as u64,
        );
        let accumulate_pipeline = super::compute_pipeline_from_source(
            ctx,
            "render accumulate",
            render_source(lights.shape(), shapes.as_deref().map(SplitArray::shape)),
            "accumulate",
        )?;
        let tonemap_pipeline =
            super::compute_pipeline(ctx, "render tonemap", &[TONEMAP_WGSL], "tonemap")?;

        let (output, output_view, accumulate_bind_group, tonemap_bind_group) =
            super::scoped(ctx, "creating the render targets", || {
                let output = ctx.device().create_texture(&wgpu::TextureDescriptor {
                    label: Some("lightpick render output"),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::Rgba8Unorm,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING
                        | wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                });
                let output_view = output.create_view(&wgpu::TextureViewDescriptor::default());
                let buffers: Vec<&wgpu::Buffer> = [&params, &sums]
                    .into_iter()
                    .chain(lights.buffers())
                    .chain(shapes.iter().flat_map(|s| s.buffers()))
                    .collect();
                let accumulate_bind_group =
                    super::bind_buffers(ctx, "render accumulate", &accumulate_pipeline, &buffers);
                let tonemap_bind_group =
                    ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("render tonemap"),
                        layout: &tonemap_pipeline.get_bind_group_layout(0),
                        entries: &[
                            wgpu::BindGroupEntry {
                                binding: 0,
                                resource: tonemap_params.as_entire_binding(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 1,
                                resource: sums.as_entire_binding(),
                            },
                            wgpu::BindGroupEntry {
                                binding: 2,
                                resource: wgpu::BindingResource::TextureView(&output_view),
                            },
                        ],
                    });
                Ok((
                    output,
                    output_view,
                    accumulate_bind_group,
                    tonemap_bind_group,
                ))
            })?;

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
            params,
            lights,
            shapes,
            sums,
            accumulate_pipeline,
            accumulate_bind_group,
            tonemap_params,
            tonemap_pipeline,
            tonemap_bind_group,
            output,
            output_view,
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
                self.samplers.spatial(),
                [&self.params, &self.sums],
            )?);
        }
        Ok(())
    }

    /// Switches the selection scheme and restarts the accumulation; [`Scheme::Cdf`] is
    /// refused ([`GpuError::UnsupportedScheme`]) and leaves the renderer unchanged.
    /// [`Scheme::Spatial`] builds and uploads its light tree the first time.
    pub fn set_scheme(&mut self, scheme: Scheme) -> Result<(), GpuError> {
        super::scheme_code(scheme)?;
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
        encoder.clear_buffer(&self.sums, 0, None);
        self.ctx.queue().submit([encoder.finish()]);
    }

    /// Adds `samples_per_pixel` samples to every pixel: sample indices
    /// `k = spp, …, spp + samples_per_pixel − 1` continue the previous calls. A pass in
    /// progress ([`GpuRenderer::accumulate_rows`]) is completed first and counts as the
    /// first of them. The work is queued, not waited for ([`GpuRenderer::readback`] waits).
    /// The total per pixel may not pass `u32::MAX` (the stream's high word), else
    /// [`GpuError::TooManySamples`].
    pub fn accumulate(&mut self, samples_per_pixel: u32) -> Result<(), GpuError> {
        let total = self
            .samples_per_pixel
            .checked_add(samples_per_pixel)
            .ok_or(GpuError::TooManySamples {
                accumulated: self.samples_per_pixel,
                requested: samples_per_pixel,
                max: u32::MAX,
            })?;
        if samples_per_pixel == 0 {
            return Ok(());
        }
        let pixels = u64::from(self.width) * u64::from(self.height);
        let per_dispatch = (SAMPLES_PER_DISPATCH / pixels).clamp(1, u64::from(u32::MAX)) as u32;
        let mut k = self.samples_per_pixel;
        if self.band_row > 0 {
            self.dispatch(k, 1, self.band_row..self.height)?;
            self.band_row = 0;
            k += 1;
        }
        while k < total {
            let k_count = per_dispatch.min(total - k);
            self.dispatch(k, k_count, 0..self.height)?;
            k += k_count;
        }
        self.samples_per_pixel = total;
        Ok(())
    }

    /// Adds sample `k = spp` to at most `max_rows` (at least 1) more rows of the image,
    /// continuing the pass in progress from where it stopped (from the top row). When the
    /// pass reaches the bottom row every pixel holds `spp + 1` samples: the pass is complete,
    /// [`GpuRenderer::samples_per_pixel`] grows by one and `Ok(true)` is returned.
    ///
    /// This splits one sample pass of a costly scheme (the light tree on a million lights)
    /// over several UI frames. While a pass is in progress, [`GpuRenderer::tonemap`] divides
    /// each row by its own sample count and [`GpuRenderer::readback`] is refused
    /// ([`GpuError::PassInProgress`]); [`GpuRenderer::finish_pass`] completes it. The same
    /// samples as [`GpuRenderer::accumulate`] are drawn, so the sums are identical.
    pub fn accumulate_rows(&mut self, max_rows: u32) -> Result<bool, GpuError> {
        if self.samples_per_pixel == u32::MAX {
            return Err(GpuError::TooManySamples {
                accumulated: self.samples_per_pixel,
                requested: 1,
                max: u32::MAX,
            });
        }
        let end = self
            .band_row
            .saturating_add(max_rows.max(1))
            .min(self.height);
        self.dispatch(self.samples_per_pixel, 1, self.band_row..end)?;
        if end == self.height {
            self.band_row = 0;
            self.samples_per_pixel += 1;
            Ok(true)
        } else {
            self.band_row = end;
            Ok(false)
        }
    }

    /// Completes the pass in progress, if any ([`GpuRenderer::accumulate_rows`]).
    pub fn finish_pass(&mut self) -> Result<(), GpuError> {
        if self.band_row > 0 {
            self.accumulate_rows(self.height)?;
        }
        Ok(())
    }

    /// The seconds the device spent in this renderer's sample passes since the last call
    /// (waits for the passes queued so far): pass time only, never tonemapping, readback or
    /// other work on the device. See [`PassClock`] for where the time comes from.
    pub fn take_pass_seconds(&mut self) -> Result<f64, GpuError> {
        self.timer.take_seconds(&self.ctx)
    }

    /// Where [`GpuRenderer::take_pass_seconds`] reads its time: the device's timestamps
    /// when it has `TIMESTAMP_QUERY`, else the CPU clock over each pass alone.
    pub fn pass_clock(&self) -> PassClock {
        self.timer.clock()
    }

    /// Rows of the pass in progress done so far (0 when no pass is in progress).
    pub fn pass_rows_done(&self) -> u32 {
        self.band_row
    }

    /// Queues `k_count` samples `k_base, …` for the pixels of `rows`.
    fn dispatch(&mut self, k_base: u32, k_count: u32, rows: Range<u32>) -> Result<(), GpuError> {
        if self.scheme == Scheme::Spatial {
            self.ensure_spatial()?;
        }
        let (pipeline, bind_group, spatial_root, scheme) = match &self.spatial {
            Some(s) if self.scheme == Scheme::Spatial => {
                (&s.pipeline, &s.bind_group, s.root, s.code)
            }
            _ => (
                &self.accumulate_pipeline,
                &self.accumulate_bind_group,
                0,
                super::scheme_code(self.scheme)?,
            ),
        };
        let params = RenderParams {
            seed_lo: self.seed as u32,
            seed_hi: (self.seed >> 32) as u32,
            k_base,
            k_count,
            width: self.width,
            height: self.height,
            n_lights: self.samplers.scene().light_count() as u32,
            scheme,
            plane_min_x: self.plane[0],
            plane_max_y: self.plane[1],
            plane_extent_x: self.plane[2],
            plane_extent_y: self.plane[3],
            n_f32: self.samplers.scene().light_count() as f32,
            spatial_root,
            row_begin: rows.start,
            row_end: rows.end,
        };
        let timestamp_writes = self.timer.begin_pass(&self.ctx)?;
        super::scoped(&self.ctx, "dispatching render samples", || {
            self.ctx
                .queue()
                .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
            let mut encoder =
                self.ctx
                    .device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("render accumulate"),
                    });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("render accumulate"),
                    timestamp_writes,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, bind_group, &[]);
                pass.dispatch_workgroups(
                    self.width.div_ceil(TILE),
                    (rows.end - rows.start).div_ceil(TILE),
                    1,
                );
            }
            self.ctx.queue().submit([encoder.finish()]);
            Ok(())
        })?;
        self.timer.end_pass(&self.ctx)
    }

    /// Waits for the queued samples and returns the sums as an [`Accumulator`] (`f32`
    /// sums widened to `f64` and put in the CPU renderer's unit: `Σê·2^-s`, `Σê²·2^-2s`,
    /// exact scalings, with the same total power and shift `s`).
    ///
    /// Precision: each `Σ ê` is a running `f32` sum of non-negative terms, so it is within
    /// `(spp − 1)·2^-24` relative of the exact sum of the `f32` estimates (typically
    /// `√spp·2^-24`). `Σ ê²` overflows to `+inf` once a single estimate exceeds about
    /// `1.8·10^19` (`G` of a light closer than about `10^-10` scene units).
    pub fn readback(&self) -> Result<Accumulator, GpuError> {
        if self.band_row > 0 {
            return Err(GpuError::PassInProgress {
                rows_done: self.band_row,
                height: self.height,
            });
        }
        let pixels = u64::from(self.width) * u64::from(self.height);
        let bytes = super::read_buffer(&self.ctx, "pixel sums", &self.sums, pixels * 8)?;
        let words = super::words(&bytes);
        let mut acc = Accumulator::new(self.width, self.height, self.total_scaled, self.shift);
        acc.samples_per_pixel = self.samples_per_pixel;
        let to_unit = crate::Scaled::pow2(-self.shift).to_f64();
        for ((sum, sum_sq), pair) in acc
            .sum
            .iter_mut()
            .zip(acc.sum_sq.iter_mut())
            .zip(words.chunks_exact(2))
        {
            *sum = f64::from(f32::from_bits(pair[0])) * to_unit;
            *sum_sq = f64::from(f32::from_bits(pair[1])) * to_unit * to_unit;
        }
        Ok(acc)
    }

    /// Writes the tonemapped image into [`GpuRenderer::output_view`]: the WGSL twin of
    /// [`crate::render::tonemap_value`] applied to `exposure · Φ_total · Σê / n`, where
    /// the factor `exposure · Φ_total / n` is computed in `f64` and clamped to the finite
    /// `f32` range (black before any sample), and `n` is the row's sample count: `spp`, or
    /// `spp + 1` for the rows a pass in progress has reached. The work is queued, not waited
    /// for.
    pub fn tonemap(&mut self, exposure: f64) -> Result<(), GpuError> {
        self.tonemap_rows(exposure, 0..self.height)
    }

    /// [`GpuRenderer::tonemap`] of the rows `rows` only (clamped to the image): after
    /// [`GpuRenderer::accumulate_rows`] only the band just rendered changed, so only it needs
    /// writing until the pass completes (then every row's sample count has changed).
    pub fn tonemap_rows(&mut self, exposure: f64, rows: Range<u32>) -> Result<(), GpuError> {
        let rows = rows.start.min(self.height)..rows.end.min(self.height);
        if rows.is_empty() {
            return Ok(());
        }
        let factor = |samples: u32| {
            let f = if samples == 0 {
                0.0
            } else {
                exposure * self.total_power / f64::from(samples)
            };
            if f.is_nan() {
                0.0
            } else {
                f.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32
            }
        };
        let params = TonemapParams {
            factor: factor(self.samples_per_pixel),
            width: self.width,
            height: self.height,
            band_row: self.band_row,
            factor_band: factor(self.samples_per_pixel.saturating_add(1)),
            row_begin: rows.start,
            pad: [0; 2],
        };
        super::scoped(&self.ctx, "dispatching the tonemap", || {
            self.ctx
                .queue()
                .write_buffer(&self.tonemap_params, 0, bytemuck::bytes_of(&params));
            let mut encoder =
                self.ctx
                    .device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("render tonemap"),
                    });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("render tonemap"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.tonemap_pipeline);
                pass.set_bind_group(0, &self.tonemap_bind_group, &[]);
                pass.dispatch_workgroups(
                    self.width.div_ceil(TILE),
                    (rows.end - rows.start).div_ceil(TILE),
                    1,
                );
            }
            self.ctx.queue().submit([encoder.finish()]);
            Ok(())
        })
    }

    /// Copies the output texture to the CPU as row-major `RGBA8` (4 bytes per pixel),
    /// waiting for queued work first.
    pub fn read_output_rgba8(&self) -> Result<Vec<u8>, GpuError> {
        let row_bytes = self.width * 4;
        let padded = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let size = u64::from(padded) * u64::from(self.height);
        let staging = super::scoped(&self.ctx, "reading the output texture", || {
            let staging = self.ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some("render output readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder =
                self.ctx
                    .device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("render output readback"),
                    });
            encoder.copy_texture_to_buffer(
                self.output.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded),
                        rows_per_image: Some(self.height),
                    },
                },
                wgpu::Extent3d {
                    width: self.width,
                    height: self.height,
                    depth_or_array_layers: 1,
                },
            );
            self.ctx.queue().submit([encoder.finish()]);
            Ok(staging)
        })?;
        let bytes = super::map_and_copy(&self.ctx, "render output", &staging)?;
        Ok(bytes
            .chunks_exact(padded as usize)
            .flat_map(|row| &row[..row_bytes as usize])
            .copied()
            .collect())
    }

    /// The tonemapped `Rgba8Unorm` output (usage `TEXTURE_BINDING | STORAGE_BINDING |
    /// COPY_SRC`), for the app to register with egui.
    pub fn output_view(&self) -> &wgpu::TextureView {
        &self.output_view
    }

    /// The output texture itself.
    pub fn output_texture(&self) -> &wgpu::Texture {
        &self.output
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
