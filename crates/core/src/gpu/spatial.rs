//! The GPU side of [`Scheme::Spatial`](crate::Scheme::Spatial): the light tree's buffers
//! and the `accumulate_spatial` pipeline (`spatial.wgsl`), built only when the scheme is used.

use glam::{UVec4, Vec4};

use super::emission::{GpuShape, emission_source, shapes_layout};
use super::scheme::{SCHEME_SPATIAL_EXACT, SCHEME_SPATIAL_TREE};
use super::split::{Access, ArrayLayout, SplitArray, SplitShape, check_bindings, declarations};
use super::{GpuContext, GpuError};
use crate::spatial::{MappedLanes, SpatialLight, SpatialSampler, TREE_WIDTH, UnboundedLanes};

pub(crate) const SPATIAL_WGSL: &str = include_str!("spatial.wgsl");
pub(crate) const SPATIAL_BOUNDS_WGSL: &str = include_str!("spatial_bounds.wgsl");

/// GPU bytes per node's lanes over spots and ranges (bounds and maps): 28 `vec4<f32>`.
pub(crate) const BYTES_PER_NODE_BOUNDS: u64 = 448;

/// GPU bytes of a node's map codes: 4 lanes of [`crate::spatial::grid::GRID_CELLS`] bytes.
pub(crate) const BYTES_PER_NODE_CODES: u64 = 4 * crate::spatial::grid::GRID_CELLS as u64;

/// One node's lanes as `spatial_bounds.wgsl` reads them (`NodeBounds`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuNodeBounds {
    v: [Vec4; 28],
}

impl GpuNodeBounds {
    /// A node's lanes from what the CPU descent reads: their footprints, maps and
    /// intensities, and their boxes, cones and ranges where the node keeps them (lanes
    /// whose footprint is unbounded; elsewhere a reach that culls nothing, which the GPU,
    /// like the CPU, never asks for).
    fn of(mapped: &MappedLanes) -> Self {
        let mut v = [Vec4::ZERO; 28];
        let unbounded = mapped.unbounded.as_deref().unwrap_or(&UnboundedLanes::NONE);
        for (k, b) in unbounded.reach.iter().enumerate() {
            let [lo, hi] = mapped.footprint_of(k);
            let intensity = mapped.intensity[k];
            let [map_x, map_y, per_x, per_y, scale] = mapped.map;
            let [weight, c_x, c_y, c_z] = unbounded.lights;
            // Every bound rounded outwards into f32, so the f32 lane still reaches every
            // point the f64 one does: the box grows, the range grows, and the cones' cosines
            // drop by more than the axis's own rounding can turn it (3 f32 ulps of a unit
            // vector's components, under 2·10^-7 rad).
            v[7 * k] = Vec4::new(
                down(b.min.x),
                down(b.min.y),
                down(b.min.z),
                intensity as f32,
            );
            v[7 * k + 1] = Vec4::new(up(b.max.x), up(b.max.y), up(b.max.z), up(b.range));
            v[7 * k + 2] = b.axis.as_vec3().extend(cos_down(b.cos_spread));
            v[7 * k + 3] = Vec4::new(cos_down(b.cos_emission), scale[k] as f32, 0.0, 0.0);
            // Rounded outwards, so the f32 box still holds every lit point.
            v[7 * k + 4] = Vec4::new(down(lo.x), down(lo.y), up(hi.x), up(hi.y));
            v[7 * k + 5] = Vec4::new(
                map_x[k] as f32,
                map_y[k] as f32,
                per_x[k] as f32,
                per_y[k] as f32,
            );
            v[7 * k + 6] = Vec4::new(
                c_x[k] as f32,
                c_y[k] as f32,
                c_z[k] as f32,
                weight[k] as f32,
            );
        }
        GpuNodeBounds { v }
    }
}

/// The largest `f32` at or below `x` (`−∞` stays).
fn down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x { f.next_down() } else { f }
}

/// The smallest `f32` at or above `x` (`+∞` stays).
fn up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x { f.next_up() } else { f }
}

/// A cone's cosine as the GPU bound uses it: lowered by `4·10^-7` (wider than the axis's
/// `f32` rounding can narrow it) and rounded down; `−1` and below (no cone) stay as they are.
fn cos_down(cos: f64) -> f32 {
    if cos <= -1.0 {
        down(cos)
    } else {
        down((cos - 4e-7).max(-1.0))
    }
}

/// The split-array layout of the node bounds.
pub(crate) const BOUNDS_LAYOUT: ArrayLayout = ArrayLayout {
    name: "spatial_bounds",
    element: "NodeBounds",
    bytes: BYTES_PER_NODE_BOUNDS,
};

/// The split-array layout of the maps' codes (`u32` words of four codes).
pub(crate) const CODES_LAYOUT: ArrayLayout = ArrayLayout {
    name: "spatial_codes",
    element: "u32",
    bytes: 4,
};

/// How the emission data of a spatial kernel over spots or ranges is split: the profiles
/// (leaf order), the node bounds and the maps' codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ShapedSplit {
    pub(crate) shapes: SplitShape,
    pub(crate) bounds: SplitShape,
    pub(crate) codes: SplitShape,
}

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

/// The source of the spatial kernel for lights and nodes split as given, and for a scene
/// with spots or ranges its profiles and node bounds; the tree's per-tile cuts take the
/// bindings after them (`cuts`).
pub(crate) fn spatial_source(
    lights: SplitShape,
    nodes: SplitShape,
    shaped: Option<ShapedSplit>,
    cuts: SplitShape,
) -> String {
    let lights_wgsl = declarations(LIGHTS_LAYOUT, lights, 2, Access::Read);
    let mut binding = 2 + lights.chunks as u32;
    let nodes_wgsl = declarations(NODES_LAYOUT, nodes, binding, Access::Read);
    binding += nodes.chunks as u32;
    let cuts_first = binding
        + shaped.map_or(0, |s| {
            (s.shapes.chunks + s.bounds.chunks + s.codes.chunks) as u32
        });
    let cuts_wgsl = declarations(CUTS_LAYOUT, cuts, cuts_first, Access::Read);
    let (emission_wgsl, bounds_wgsl) = match shaped {
        Some(ShapedSplit {
            shapes,
            bounds,
            codes,
        }) => {
            let emission = emission_source("spatial_shapes", Some((shapes, binding)));
            binding += shapes.chunks as u32;
            let bounds_wgsl = declarations(BOUNDS_LAYOUT, bounds, binding, Access::Read);
            binding += bounds.chunks as u32;
            let codes_wgsl = declarations(CODES_LAYOUT, codes, binding, Access::Read);
            (
                emission,
                format!("{bounds_wgsl}\n{codes_wgsl}\n{SPATIAL_BOUNDS_WGSL}"),
            )
        }
        None => (
            emission_source("spatial_shapes", None),
            "fn lane_weights(node: ptr<function, SpatialNode>, at: u32, x: vec2<f32>) -> LaneWeights { return point_lane_weights(node, x); }\n".to_owned(),
        ),
    };
    super::shader_source(&[
        super::render_kernel::RENDER_COMMON_WGSL,
        &lights_wgsl,
        &nodes_wgsl,
        &cuts_wgsl,
        &emission_wgsl,
        SPATIAL_WGSL,
        &bounds_wgsl,
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
/// The per-tile cuts' words ([`cut_words`]).
pub(crate) const CUTS_LAYOUT: ArrayLayout = ArrayLayout {
    name: "spatial_cuts",
    element: "u32",
    bytes: 4,
};

/// The tree's per-tile cuts ([`crate::spatial::TileCuts`]) as `spatial.wgsl` reads them, one
/// `u32` array: the tile side in pixels (0: no cuts, every pick from the root), the tiles
/// along `x`, the tile count `T`; each tile's offset into the words after these `T + 4`
/// (and one past the last tile's); then each tile's words: its column count `K` (0: no
/// entry has power), its `K` alias columns (threshold in bits 0–24, alias above), and per
/// entry its mass on the `2^24` grid and its child word.
fn cut_words(sampler: &SpatialSampler, plane: &crate::scene::ReceiverPlane) -> Vec<u32> {
    let SpatialSampler::Tree(tree) = sampler else {
        return vec![0];
    };
    let Some(cuts) = tree.tile_cuts() else {
        return vec![0];
    };
    // The kernel finds a pixel's tile from its indices: the cuts split this very grid
    // (the sampler is the scene's, built over the plane the renderer draws).
    debug_assert_eq!(
        (cuts.plane().width, cuts.plane().height),
        (plane.width, plane.height)
    );
    let [tiles_x, tiles_y] = cuts.tiles();
    let (offsets, tiles) = cuts.gpu_words(tree);
    let mut words = vec![cuts.tile_side(), tiles_x, tiles_x * tiles_y];
    words.extend_from_slice(&offsets);
    words.extend_from_slice(&tiles);
    words
}

impl SpatialGpu {
    /// Uploads the spatial sampler (built in `f64` on the CPU, as the CPU renderer's, so both
    /// descend the same tree) beside the renderer's `params` and `sums`.
    pub(crate) fn new(
        ctx: &GpuContext,
        (sampler, plane): (&SpatialSampler, &crate::scene::ReceiverPlane),
        [params, sums]: [&wgpu::Buffer; 2],
    ) -> Result<Self, GpuError> {
        let (code, root, lights, nodes) = sampler_arrays(sampler);
        let cuts = cut_words(sampler, plane);
        // Spots or ranges: the profiles in the lights' order, the tree's node bounds and
        // the maps' codes.
        let shaped = shaped_arrays(sampler);
        let bytes = lights.len() as u64 * BYTES_PER_LIGHT
            + nodes.len() as u64 * BYTES_PER_NODE
            + cuts.len() as u64 * 4
            + shaped.as_ref().map_or(0, |(s, b, _)| {
                s.len() as u64 * super::emission::BYTES_PER_SHAPE
                    + b.len() as u64 * (BYTES_PER_NODE_BOUNDS + BYTES_PER_NODE_CODES)
            });
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
        let shaped = shaped
            .map(|arrays| upload_shaped(ctx, arrays))
            .transpose()?;
        let cuts = SplitArray::with_contents(
            ctx,
            "light tree tile cuts",
            CUTS_LAYOUT,
            bytemuck::cast_slice(&cuts),
            wgpu::BufferUsages::empty(),
        )?;
        let shaped_bindings = shaped.as_ref().map_or(0, |(s, b, c)| {
            s.buffers().len() + b.buffers().len() + c.buffers().len()
        });
        let storage = 1
            + (lights.buffers().len()
                + nodes.buffers().len()
                + shaped_bindings
                + cuts.buffers().len()) as u32;
        check_bindings(ctx, "the spatial render kernel", storage)?;
        let pipeline = super::compute_pipeline_from_source(
            ctx,
            "render accumulate spatial",
            spatial_source(
                lights.shape(),
                nodes.shape(),
                shaped.as_ref().map(|(s, b, c)| ShapedSplit {
                    shapes: s.shape(),
                    bounds: b.shape(),
                    codes: c.shape(),
                }),
                cuts.shape(),
            ),
            "accumulate_spatial",
        )?;
        let bind_group = super::scoped(ctx, "binding the light tree", || {
            let buffers: Vec<&wgpu::Buffer> =
                [params, sums]
                    .into_iter()
                    .chain(lights.buffers())
                    .chain(nodes.buffers())
                    .chain(shaped.iter().flat_map(|(s, b, c)| {
                        s.buffers().iter().chain(b.buffers()).chain(c.buffers())
                    }))
                    .chain(cuts.buffers())
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

/// The spatial kernel's scheme word, its `spatial_root`, and the sampler's lights and
/// nodes as the kernel reads them (no nodes for the exact pick).
fn sampler_arrays(sampler: &SpatialSampler) -> (u32, u32, Vec<Vec4>, Vec<GpuNode>) {
    match sampler {
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
    }
}

/// For lights with spots or ranges: their profiles in the lights' order, the tree's node
/// bounds and its lane maps' codes.
fn shaped_arrays(sampler: &SpatialSampler) -> Option<(Vec<GpuShape>, Vec<GpuNodeBounds>, Vec<u8>)> {
    match sampler {
        SpatialSampler::Exact(exact) => exact.emission(0).map(|_| {
            let shapes = (0..exact.lights().len())
                .filter_map(|k| exact.emission(k).map(GpuShape::of))
                .collect();
            (shapes, Vec::new(), Vec::new())
        }),
        SpatialSampler::Tree(tree) => (!tree.emission().is_empty()).then(|| {
            let shapes = tree.emission().iter().map(GpuShape::of).collect();
            let lanes = (0..tree.nodes().len()).filter_map(|k| tree.mapped(k));
            let bounds = lanes.clone().map(GpuNodeBounds::of).collect();
            let codes = lanes
                .flat_map(|m| (0..TREE_WIDTH).flat_map(|k| m.codes(k).iter().copied()))
                .collect();
            (shapes, bounds, codes)
        }),
    }
}

/// Uploads the profiles, node bounds and map codes of [`shaped_arrays`].
fn upload_shaped(
    ctx: &GpuContext,
    (shapes, bounds, codes): (Vec<GpuShape>, Vec<GpuNodeBounds>, Vec<u8>),
) -> Result<(SplitArray, SplitArray, SplitArray), GpuError> {
    Ok((
        SplitArray::with_contents(
            ctx,
            "spatial lights' emission profiles (leaf order)",
            shapes_layout("spatial_shapes"),
            bytemuck::cast_slice(&shapes),
            wgpu::BufferUsages::empty(),
        )?,
        SplitArray::with_contents(
            ctx,
            "light tree node bounds",
            BOUNDS_LAYOUT,
            bytemuck::cast_slice(&bounds),
            wgpu::BufferUsages::empty(),
        )?,
        SplitArray::with_contents(
            ctx,
            "light tree lane maps",
            CODES_LAYOUT,
            &codes,
            wgpu::BufferUsages::empty(),
        )?,
    ))
}
