// render_common.wgsl: what every render kernel shares (render.wgsl and spatial.wgsl): the
// dispatch parameters, the per-pixel sums, the geometry term and the pixel centres.

struct RenderParams {
    seed_lo: u32,
    seed_hi: u32,
    // First sample index k of this dispatch, and how many samples each pixel takes.
    k_base: u32,
    k_count: u32,
    width: u32,
    height: u32,
    n_lights: u32,
    scheme: u32,
    // The receiver rectangle: x of its left edge, y of its top edge, and its extents.
    plane_min_x: f32,
    plane_max_y: f32,
    plane_extent_x: f32,
    plane_extent_y: f32,
    // N as f32, for the uniform estimate N·p_i·G_i.
    n_f32: f32,
    // spatial.wgsl: the light tree's root child word, or the exact pick's light count.
    spatial_root: u32,
    // The rows of this dispatch, [row_begin, row_end): the grid covers them from row_begin.
    row_begin: u32,
    row_end: u32,
}

@group(0) @binding(0) var<uniform> params: RenderParams;
// Per pixel: (Σ ê, Σ ê²).
@group(0) @binding(1) var<storage, read_write> sums: array<vec2<f32>>;

const FOUR_PI: f32 = 12.566370614359172;

// 2^k as an f32, exactly, for k in [-126, 127].
fn pow2(k: i32) -> f32 {
    return bitcast<f32>(u32(k + 127) << 23u);
}

// G(x) = max(0, z)/(4π r³) in f32 without spurious overflow or underflow. With m the
// largest of |dx|, |dy|, z and 2^e the power of two just above it (m ∈ [2^(e−1), 2^e)),
// the offsets are scaled by 2^−e (exact), so s² = (r·2^−e)² lies in [1/4, 3] and
// G = [z·2^−e / (4π s³)] · 2^−e · 2^−e, the two final exact scalings rounding only when G
// itself leaves the f32 range. e is clamped to [−125, 126] so every 2^−e is a normal f32;
// the clamp only matters for m outside [2^−126, 2^126), where s² stays within [2^−48, 48].
fn geometry_term(light: vec3<f32>, x: vec2<f32>) -> f32 {
    let z = light.z;
    if !(z > 0.0) {
        return 0.0;
    }
    let dx = light.x - x.x;
    let dy = light.y - x.y;
    let m = max(max(abs(dx), abs(dy)), z);
    // For a normal m with biased exponent b, m ∈ [2^(b−127), 2^(b−126)): e = b − 126.
    let biased = i32((bitcast<u32>(m) >> 23u) & 0xffu);
    let down = pow2(-clamp(biased - 126, -125, 126));
    let sx = dx * down;
    let sy = dy * down;
    let sz = z * down;
    let s2 = sx * sx + sy * sy + sz * sz;
    let g = sz / (FOUR_PI * (s2 * sqrt(s2)));
    return (g * down) * down;
}

// The centre of pixel (px, py), as scene::pixel_center computes it.
fn pixel_center(px: u32, py: u32) -> vec2<f32> {
    let fx = (f32(px) + 0.5) / f32(params.width);
    let fy = (f32(py) + 0.5) / f32(params.height);
    return vec2<f32>(params.plane_min_x + fx * params.plane_extent_x,
                     params.plane_max_y - fy * params.plane_extent_y);
}
