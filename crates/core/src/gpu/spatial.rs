//! The GPU side of [`Scheme::Spatial`](crate::Scheme::Spatial): the light tree's buffers
//! and the `accumulate_spatial` pipeline (`spatial.wgsl`), built only when the scheme is used.

use glam::{UVec4, Vec4};

use super::split::{Access, ArrayLayout, SplitArray, SplitShape, check_bindings, declarations};
use super::{GpuContext, GpuError};
use crate::spatial::{SpatialLight, SpatialSampler};

pub(crate) const SPATIAL_WGSL: &str = include_str!("spatial.wgsl");

/// Scheme word of the exact contribution pick (`N ≤` [`crate::spatial::EXACT_MAX_LIGHTS`]).
pub(crate) const SCHEME_SPATIAL_EXACT: u32 = 3;
/// Scheme word of the light-tree descent.
pub(crate) const SCHEME_SPATIAL_TREE: u32 = 4;
/// GPU bytes per contributing light: `(x, y, z, p_i)` as `f32`, in leaf order.
pub(crate) const BYTES_PER_LIGHT: u64 = 16;
/// GPU bytes per tree node: four `(c.xyz, Φ)` as `f32` and four child words.
pub(crate) const BYTES_PER_NODE: u64 = 80;

/// A tree node as `spatial.wgsl` reads it.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuNode {
    lane: [Vec4; 4],
    child: UVec4,
}

/// The uploaded spatial sampler: its lights in leaf order and its nodes (a one-node
/// placeholder for the exact pick), and the pipeline bound to them.
#[derive(Debug)]
pub(crate) struct SpatialGpu {
    /// [`SCHEME_SPATIAL_EXACT`] or [`SCHEME_SPATIAL_TREE`].
    pub(crate) code: u32,
    /// `params.spatial_root`: the tree's root child word, or the exact pick's light count.
    pub(crate) root: u32,
    /// GPU bytes of the lights and the nodes.
    pub(crate) bytes: u64,
    pub(crate) pipeline: wgpu::ComputePipeline,
    pub(crate) bind_group: wgpu::BindGroup,
}

/// `(x, y, z, p_i)` as `f32`.
fn light_vec4(l: &SpatialLight) -> Vec4 {
    l.position_in_world.as_vec3().extend(l.power as f32)
}

/// The source of the spatial kernel for lights and nodes split as given.
pub(crate) fn spatial_source(lights: SplitShape, nodes: SplitShape) -> String {
    let lights_wgsl = declarations(LIGHTS_LAYOUT, lights, 2, Access::Read);
    let nodes_wgsl = declarations(NODES_LAYOUT, nodes, 2 + lights.chunks as u32, Access::Read);
    super::shader_source(&[
        super::renderer::RENDER_COMMON_WGSL,
        &lights_wgsl,
        &nodes_wgsl,
        SPATIAL_WGSL,
    ])
}

/// The split-array layouts of the spatial kernel.
pub(crate) const LIGHTS_LAYOUT: ArrayLayout = ArrayLayout {
    name: "spatial_lights",
    element: "vec4<f32>",
    bytes: BYTES_PER_LIGHT,
};
pub(crate) const NODES_LAYOUT: ArrayLayout = ArrayLayout {
    name: "spatial_nodes",
    element: "SpatialNode",
    bytes: BYTES_PER_NODE,
};

impl SpatialGpu {
    /// Uploads the spatial sampler (built in `f64` on the CPU, as the CPU renderer's, so both
    /// descend the same tree) beside the renderer's `params` and `sums`.
    pub(crate) fn new(
        ctx: &GpuContext,
        sampler: &SpatialSampler,
        [params, sums]: [&wgpu::Buffer; 2],
    ) -> Result<Self, GpuError> {
        let (code, root, lights, nodes): (u32, u32, Vec<Vec4>, Vec<GpuNode>) = match sampler {
            SpatialSampler::Exact(exact) => {
                let lights: Vec<Vec4> = exact.lights().iter().map(|(_, l)| light_vec4(l)).collect();
                (
                    SCHEME_SPATIAL_EXACT,
                    lights.len() as u32,
                    lights,
                    Vec::new(),
                )
            }
            SpatialSampler::Tree(tree) => (
                SCHEME_SPATIAL_TREE,
                tree.root().bits(),
                tree.lights().iter().map(light_vec4).collect(),
                tree.nodes()
                    .iter()
                    .map(|n| GpuNode {
                        lane: std::array::from_fn(|k| {
                            n.centroid(k).as_vec3().extend(n.power(k) as f32)
                        }),
                        child: UVec4::from_array(std::array::from_fn(|k| n.child(k).bits())),
                    })
                    .collect(),
            ),
        };
        let bytes = lights.len() as u64 * BYTES_PER_LIGHT + nodes.len() as u64 * BYTES_PER_NODE;
        // Every binding holds at least one element (a zero placeholder when there is none).
        let lights = SplitArray::with_contents(
            ctx,
            "spatial lights (leaf order)",
            LIGHTS_LAYOUT,
            bytemuck::cast_slice(&lights),
            wgpu::BufferUsages::empty(),
        )?;
        let nodes = SplitArray::with_contents(
            ctx,
            "light tree nodes",
            NODES_LAYOUT,
            bytemuck::cast_slice(&nodes),
            wgpu::BufferUsages::empty(),
        )?;
        let storage = 1 + (lights.buffers().len() + nodes.buffers().len()) as u32;
        check_bindings(ctx, "the spatial render kernel", storage)?;
        let pipeline = super::compute_pipeline_from_source(
            ctx,
            "render accumulate spatial",
            spatial_source(lights.shape(), nodes.shape()),
            "accumulate_spatial",
        )?;
        let bind_group = super::scoped(ctx, "binding the light tree", || {
            let buffers: Vec<&wgpu::Buffer> = [params, sums]
                .into_iter()
                .chain(lights.buffers())
                .chain(nodes.buffers())
                .collect();
            Ok(super::bind_buffers(
                ctx,
                "render accumulate spatial",
                &pipeline,
                &buffers,
            ))
        })?;
        Ok(Self {
            code,
            root,
            bytes,
            pipeline,
            bind_group,
        })
    }
}
