//! The GPU side of [`Scheme::Spatial`](crate::Scheme::Spatial): the light tree's buffers
//! and the `accumulate_spatial` pipeline (`spatial.wgsl`), built only when the scheme is used.

use super::{GpuContext, GpuError, PICK_WGSL};
use crate::spatial::SpatialSampler;

pub(crate) const SPATIAL_WGSL: &str = include_str!("spatial.wgsl");

/// Scheme word of the exact contribution pick (`N ≤` [`crate::spatial::EXACT_MAX_LIGHTS`]).
pub(crate) const SCHEME_SPATIAL_EXACT: u32 = 3;
/// Scheme word of the light-tree descent.
pub(crate) const SCHEME_SPATIAL_TREE: u32 = 4;
/// GPU bytes per internal tree node: `min.xyz, Φ, max.xyz, pad` as `f32`.
pub(crate) const BYTES_PER_NODE: u64 = 32;
/// GPU bytes per leaf: its scene index.
pub(crate) const BYTES_PER_LEAF: u64 = 4;

/// The uploaded spatial sampler: tree nodes and leaf order (one-word placeholders for the
/// exact pick, which reads only the lights), and the pipeline bound to them.
#[derive(Debug)]
pub(crate) struct SpatialGpu {
    /// [`SCHEME_SPATIAL_EXACT`] or [`SCHEME_SPATIAL_TREE`].
    pub(crate) code: u32,
    /// Leaves of the tree (0 for the exact pick).
    pub(crate) leaves: u32,
    /// GPU bytes of the nodes and the leaf order.
    pub(crate) bytes: u64,
    pub(crate) pipeline: wgpu::ComputePipeline,
    pub(crate) bind_group: wgpu::BindGroup,
}

impl SpatialGpu {
    /// Uploads the spatial sampler (built in `f64` on the CPU, as the CPU renderer's, so both
    /// descend the same tree) beside the renderer's `params`, `lights` and `sums`.
    pub(crate) fn new(
        ctx: &GpuContext,
        sampler: &SpatialSampler,
        buffers: [&wgpu::Buffer; 3],
    ) -> Result<Self, GpuError> {
        let (code, node_words, order): (u32, Vec<[u32; 8]>, Vec<u32>) = match sampler {
            SpatialSampler::Exact(_) => (SCHEME_SPATIAL_EXACT, Vec::new(), Vec::new()),
            SpatialSampler::Tree(tree) => (
                SCHEME_SPATIAL_TREE,
                tree.nodes()
                    .iter()
                    .map(|n| {
                        let f = |v: f64| (v as f32).to_bits();
                        [
                            f(n.min[0]),
                            f(n.min[1]),
                            f(n.min[2]),
                            f(n.power),
                            f(n.max[0]),
                            f(n.max[1]),
                            f(n.max[2]),
                            0,
                        ]
                    })
                    .collect(),
                tree.order().to_vec(),
            ),
        };
        let bytes = node_words.len() as u64 * BYTES_PER_NODE + order.len() as u64 * BYTES_PER_LEAF;
        // A binding holds at least one node: a placeholder for the exact pick and one leaf.
        let placeholder = [[0u32; 8]];
        let node_slice = if node_words.is_empty() {
            &placeholder[..]
        } else {
            &node_words[..]
        };
        let nodes = super::storage_buffer(
            ctx,
            "light tree nodes",
            bytemuck::cast_slice(node_slice),
            wgpu::BufferUsages::empty(),
        )?;
        let order_buffer = super::storage_buffer(
            ctx,
            "light tree leaf order",
            bytemuck::cast_slice(&order),
            wgpu::BufferUsages::empty(),
        )?;
        let pipeline = super::compute_pipeline(
            ctx,
            "render accumulate spatial",
            &[PICK_WGSL, super::renderer::RENDER_WGSL, SPATIAL_WGSL],
            "accumulate_spatial",
        )?;
        let [params, lights, sums] = buffers;
        let bind_group = super::scoped(ctx, "binding the light tree", || {
            Ok(super::bind_buffers(
                ctx,
                "render accumulate spatial",
                &pipeline,
                &[params, lights, sums, &nodes, &order_buffer],
            ))
        })?;
        Ok(Self {
            code,
            leaves: order.len() as u32,
            bytes,
            pipeline,
            bind_group,
        })
    }
}
