//! What a renderer is built on: the image size it may have, its light buffers (positions,
//! `p_i`, alias entries, emission profiles) and its per-pixel targets (the sums, the
//! output texture, the two pipelines and their bind groups).

use std::sync::Arc;

use crate::gpu::emission::{GpuShape, shapes_layout};
use crate::gpu::render_kernel::{
    LIGHTS_LAYOUT, RenderParams, TILE, TONEMAP_WGSL, TonemapParams, render_source,
};
use crate::gpu::split::{SplitArray, check_bindings};
use crate::gpu::{self, GpuContext, GpuError};
use crate::scene::{Emission, Scene};

/// Refuses an empty image, or one beyond the device's texture size or its workgroup
/// count per dimension ([`GpuError::ImageSize`]).
pub(super) fn check_image_size(ctx: &GpuContext, width: u32, height: u32) -> Result<(), GpuError> {
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
    Ok(())
}

/// New light buffers for `scene`, zeroed (the renderer uploads them), and its emission
/// profiles, uploaded, when it has any.
pub(super) fn light_buffers(
    ctx: &GpuContext,
    scene: &Scene,
) -> Result<(Arc<SplitArray>, Option<Arc<SplitArray>>), GpuError> {
    let n = scene.positions.len() as u64;
    let lights = Arc::new(SplitArray::zeroed(
        ctx,
        "lights (positions, powers, alias table)",
        LIGHTS_LAYOUT,
        n,
        wgpu::BufferUsages::empty(),
    )?);
    let shapes = match &scene.emission {
        Some(emission) => {
            let shapes: Vec<GpuShape> = emission
                .iter()
                .map(Emission::shape)
                .map(GpuShape::of)
                .collect();
            Some(Arc::new(SplitArray::with_contents(
                ctx,
                "lights' emission profiles (spots, ranges)",
                shapes_layout("shapes"),
                bytemuck::cast_slice(&shapes),
                wgpu::BufferUsages::empty(),
            )?))
        }
        None => None,
    };
    Ok((lights, shapes))
}

/// A renderer's per-pixel buffers, output texture, pipelines and bind groups.
#[derive(Debug)]
pub(super) struct Targets {
    /// The accumulate kernels' parameters ([`RenderParams`]).
    pub(super) params: wgpu::Buffer,
    /// `(Σê, Σê²)` per pixel as two `f32`.
    pub(super) sums: wgpu::Buffer,
    pub(super) accumulate_pipeline: wgpu::ComputePipeline,
    pub(super) accumulate_bind_group: wgpu::BindGroup,
    /// The tonemap kernel's parameters ([`TonemapParams`]).
    pub(super) tonemap_params: wgpu::Buffer,
    pub(super) tonemap_pipeline: wgpu::ComputePipeline,
    pub(super) tonemap_bind_group: wgpu::BindGroup,
    /// The tonemapped image (`Rgba8Unorm`).
    pub(super) output: wgpu::Texture,
    pub(super) output_view: wgpu::TextureView,
}

impl Targets {
    /// The targets of a `width × height` image over `lights` (and `shapes`): refuses lights
    /// needing more bindings than a shader stage has, and sums beyond one binding.
    pub(super) fn new(
        ctx: &GpuContext,
        width: u32,
        height: u32,
        lights: &SplitArray,
        shapes: Option<&SplitArray>,
    ) -> Result<Self, GpuError> {
        let pixels = u64::from(width) * u64::from(height);
        let shape_bindings = shapes.map_or(0, |s| s.buffers().len());
        check_bindings(
            ctx,
            "the render kernel",
            1 + (lights.buffers().len() + shape_bindings) as u32,
        )?;
        let sums = gpu::zeroed_storage_buffer(
            ctx,
            "pixel sums",
            pixels * 8,
            wgpu::BufferUsages::COPY_SRC,
        )?;
        let params = gpu::uniform_buffer(
            ctx,
            "render params",
            std::mem::size_of::<RenderParams>() as u64,
        );
        let tonemap_params = gpu::uniform_buffer(
            ctx,
            "tonemap params",
            std::mem::size_of::<TonemapParams>() as u64,
        );
        let accumulate_pipeline = gpu::compute_pipeline_from_source(
            ctx,
            "render accumulate",
            render_source(lights.shape(), shapes.map(SplitArray::shape)),
            "accumulate",
        )?;
        let tonemap_pipeline =
            gpu::compute_pipeline(ctx, "render tonemap", &[TONEMAP_WGSL], "tonemap")?;
        gpu::scoped(ctx, "creating the render targets", || {
            let output = output_texture(ctx, width, height);
            let output_view = output.create_view(&wgpu::TextureViewDescriptor::default());
            let buffers: Vec<&wgpu::Buffer> = [&params, &sums]
                .into_iter()
                .chain(lights.buffers())
                .chain(shapes.iter().flat_map(|s| s.buffers()))
                .collect();
            let accumulate_bind_group =
                gpu::bind_buffers(ctx, "render accumulate", &accumulate_pipeline, &buffers);
            let tonemap_bind_group = ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
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
            Ok(Targets {
                params,
                sums,
                accumulate_pipeline,
                accumulate_bind_group,
                tonemap_params,
                tonemap_pipeline,
                tonemap_bind_group,
                output,
                output_view,
            })
        })
    }
}

/// The `Rgba8Unorm` output texture: sampled by a UI, written by the tonemap kernel, copied
/// for readback.
fn output_texture(ctx: &GpuContext, width: u32, height: u32) -> wgpu::Texture {
    ctx.device().create_texture(&wgpu::TextureDescriptor {
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
    })
}
