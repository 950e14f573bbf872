// render.wgsl: the estimator contract of crates/core/src/render/mod.rs on the GPU.
// Pixel p = py·width + px takes sample k from Rng::new(seed, (k << 32) | p), that is
// stream_lo = p and stream_hi = k, picks light i with pick_light, and adds the normalized
// estimate ê (uniform: N·p_i·G_i(x); power-proportional: G_i(x)) and ê² to its sums.
// Needs the RNG prelude and pick.wgsl.

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
    // Leaves of the spatial light tree (spatial.wgsl), 0 for the other schemes.
    tree_leaves: u32,
    // The rows of this dispatch, [row_begin, row_end): the grid covers them from row_begin.
    row_begin: u32,
    row_end: u32,
}

@group(0) @binding(0) var<uniform> params: RenderParams;
// One light, 24 bytes: its position, its normalized power p_i = Φ_i / Φ_total, and the
// packed alias entry of its column. Interleaved so that a kept column's light data shares
// the cache line of the entry just read (one random memory access instead of two).
struct Light {
    x: f32,
    y: f32,
    z: f32,
    p: f32,
    threshold: u32,
    alias_light: u32,
}

@group(0) @binding(1) var<storage, read> lights: array<Light>;
// Per pixel: (Σ ê, Σ ê²).
@group(0) @binding(2) var<storage, read_write> sums: array<vec2<f32>>;

fn alias_entry(column: u32) -> vec2<u32> {
    return vec2<u32>(lights[column].threshold, lights[column].alias_light);
}

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

@compute @workgroup_size(16, 16)
fn accumulate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let py = params.row_begin + gid.y;
    if gid.x >= params.width || py >= params.row_end {
        return;
    }
    let p = py * params.width + gid.x;
    let x = pixel_center(gid.x, py);
    // A running sum, sample after sample, in the order k = k_base, k_base + 1, ...
    var acc = sums[p];
    for (var j = 0u; j < params.k_count; j++) {
        var state = rng_new(params.seed_lo, params.seed_hi, p, params.k_base + j);
        let i = pick_light(params.scheme, params.n_lights, &state);
        var e = geometry_term(vec3<f32>(lights[i].x, lights[i].y, lights[i].z), x);
        if params.scheme == SCHEME_UNIFORM {
            e = (params.n_f32 * lights[i].p) * e;
        }
        acc += vec2<f32>(e, e * e);
    }
    sums[p] = acc;
}
