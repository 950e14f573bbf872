//! The render kernel's interface: its WGSL sources, the per-light record it reads, its
//! parameter blocks and the assembly of its source. Shared by the renderer and the spatial
//! scheme's kernel (which reads the same common WGSL), below both.

use glam::{UVec2, Vec3};

use super::PICK_WGSL;
use super::emission::emission_source;
use super::split::{Access, ArrayLayout, SplitShape, declarations};

/// The accumulate kernel (`accumulate`), after the common WGSL and the light accessors.
pub(crate) const RENDER_WGSL: &str = include_str!("render.wgsl");
/// What the accumulate kernels (power picking and spatial) share: parameters, pixel sums,
/// the geometry term.
pub(crate) const RENDER_COMMON_WGSL: &str = include_str!("render_common.wgsl");
/// The tonemap kernel (`tonemap`).
pub(crate) const TONEMAP_WGSL: &str = include_str!("tonemap.wgsl");

/// Workgroups are 16×16 pixels.
pub(crate) const TILE: u32 = 16;
/// Samples (pixels × samples per pixel) per dispatch: long enough to amortize a submit,
/// short enough that no single dispatch runs for seconds on a real GPU.
pub(crate) const SAMPLES_PER_DISPATCH: u64 = 1 << 24;
/// Per-light GPU storage: `(x, y, z, p_i)` as four `f32` and the packed alias entry
/// `(threshold, alias)` as two `u32`, interleaved (`Light` in `render.wgsl`).
pub(crate) const BYTES_PER_LIGHT: u64 = 24;
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
pub(crate) struct GpuLight {
    pub(crate) position: Vec3,
    pub(crate) power: f32,
    pub(crate) entry: UVec2,
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

/// The accumulate kernels' uniform parameters (`Params` in `render_common.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct RenderParams {
    pub(crate) seed_lo: u32,
    pub(crate) seed_hi: u32,
    pub(crate) k_base: u32,
    pub(crate) k_count: u32,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) n_lights: u32,
    pub(crate) scheme: u32,
    pub(crate) plane_min_x: f32,
    pub(crate) plane_max_y: f32,
    pub(crate) plane_extent_x: f32,
    pub(crate) plane_extent_y: f32,
    pub(crate) n_f32: f32,
    pub(crate) spatial_root: u32,
    pub(crate) row_begin: u32,
    pub(crate) row_end: u32,
}

/// The tonemap kernel's uniform parameters (`Params` in `tonemap.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct TonemapParams {
    pub(crate) factor: f32,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) band_row: u32,
    pub(crate) factor_band: f32,
    pub(crate) row_begin: u32,
    pub(crate) pad: [u32; 2],
}
