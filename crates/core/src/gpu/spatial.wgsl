// spatial.wgsl: Scheme::Spatial on the GPU, the twin of crates/core/src/spatial (exact
// contribution sampling for few lights, light-tree descent for many). Appended after
// pick.wgsl and render.wgsl (it uses params, lights, sums, geometry_term, pixel_center).
// Same streams as the CPU: sample k of pixel p draws from rng_new(seed, p, k); the exact
// pick takes one draw (u = (r >> 8)·2^-24, exact in f32), the descent one draw per level,
// r >> 8 compared with the branch threshold.

// An internal tree node (32 bytes): the box of its lights and their normalized power.
// Children are implicit (depth-first order): left = node + 1, right = node + (mid − lo).
struct TreeNode {
    min_x: f32,
    min_y: f32,
    min_z: f32,
    power: f32,
    max_x: f32,
    max_y: f32,
    max_z: f32,
    _pad: u32,
}

@group(0) @binding(3) var<storage, read> tree_nodes: array<TreeNode>;
// Scene index of each leaf, in leaf order.
@group(0) @binding(4) var<storage, read> tree_order: array<u32>;

const SCHEME_SPATIAL_EXACT: u32 = 3u;
const SCHEME_SPATIAL_TREE: u32 = 4u;
const EXACT_MAX_LIGHTS: u32 = 16u;
// f32::MAX / 4: importances are capped here so that two of them add without overflow.
const IMPORTANCE_CAP: f32 = 8.507059e37;
const MIN_NORMAL: f32 = 1.1754944e-38;

fn unit24(r: u32) -> f32 {
    return f32(r >> 8u) * (1.0 / 16777216.0);
}

fn light_position(i: u32) -> vec3<f32> {
    return vec3<f32>(lights[i].x, lights[i].y, lights[i].z);
}

// spatial::importance::node_importance in f32: Φ·cos_bound / (4π·max(|x − c|², h²)).
fn node_importance(n: TreeNode, x: vec2<f32>) -> f32 {
    if !(n.max_z > 0.0) || !(n.power > 0.0) {
        return 0.0;
    }
    let gap_x = max(max(n.min_x - x.x, x.x - n.max_x), 0.0);
    let gap_y = max(max(n.min_y - x.y, x.y - n.max_y), 0.0);
    let rho2 = gap_x * gap_x + gap_y * gap_y;
    // z_max / √(ρ² + z_max²) with inverseSqrt (no division; f32 keeps the two factors
    // apart so that d²·√(ρ² + z²) cannot overflow for large scenes).
    let cos_bound = n.max_z * inverseSqrt(rho2 + n.max_z * n.max_z);
    let dx = 0.5 * (n.min_x + n.max_x) - x.x;
    let dy = 0.5 * (n.min_y + n.max_y) - x.y;
    let dz = 0.5 * (n.min_z + n.max_z);
    let hx = 0.5 * (n.max_x - n.min_x);
    let hy = 0.5 * (n.max_y - n.min_y);
    let hz = 0.5 * (n.max_z - n.min_z);
    let d2 = max(max(dx * dx + dy * dy + dz * dz, hx * hx + hy * hy + hz * hz), MIN_NORMAL);
    let importance = n.power * cos_bound / (FOUR_PI * d2);
    if !(importance > 0.0) {
        return 0.0;
    }
    return min(importance, IMPORTANCE_CAP);
}

// (importance, power) of the child covering leaves [lo, hi), internal node `node` if wider
// than one leaf; a single leaf has the exact importance p_i·G_i(x).
fn child_importance(lo: u32, hi: u32, node: u32, x: vec2<f32>) -> vec2<f32> {
    if hi - lo == 1u {
        let i = tree_order[lo];
        return vec2<f32>(lights[i].p * geometry_term(light_position(i), x), lights[i].p);
    }
    let n = tree_nodes[node];
    return vec2<f32>(node_importance(n, x), n.power);
}

// spatial::importance::branch_probabilities: (P_left, P_right).
fn branch_probabilities(l: vec2<f32>, r: vec2<f32>) -> vec2<f32> {
    let s = l.x + r.x;
    if s > 0.0 {
        let inv = 1.0 / s;
        return vec2<f32>(l.x * inv, r.x * inv);
    }
    let t = l.y + r.y;
    if t > 0.0 {
        return vec2<f32>(l.y / t, r.y / t);
    }
    return vec2<f32>(0.5, 0.5);
}

// spatial::importance::branch_threshold: y = P_left·2^24, clamped so that a branch of
// positive probability stays reachable; left iff f32(r >> 8) < y (exact: r >> 8 < 2^24),
// that is iff r >> 8 < t = ⌈y⌉, with probability exactly t/2^24 (f32(t) exact: t ≤ 2^24).
fn branch_threshold(p: vec2<f32>) -> f32 {
    let lo = select(0.0, 1.0, p.x > 0.0);
    let hi = select(16777216.0, 16777215.0, p.y > 0.0);
    return clamp(p.x * 16777216.0, lo, hi);
}

// v · 2^e for any i32 e, as two exact power-of-two scalings (each within pow2's range).
fn scale_pow2(v: f32, e: i32) -> f32 {
    let c = clamp(e, -250, 250);
    let half = c / 2;
    return (v * pow2(half)) * pow2(c - half);
}

// LightTree::sample: one draw per level; ê = p_i·G_i(x)/pdf with the pdf kept as a
// mantissa and a power of two (frexp after every level), so that neither a deep product of
// small branch probabilities nor a tiny p_i under- or overflows before the final ratio.
fn spatial_tree_estimate(x: vec2<f32>, state: ptr<function, u32>) -> f32 {
    let m = params.tree_leaves;
    if m == 0u {
        return 0.0;
    }
    var lo = 0u;
    var hi = m;
    var node = 0u;
    var pdf_m = 1.0;
    var pdf_e = 0i;
    while hi - lo > 1u {
        let mid = lo + (hi - lo) / 2u;
        let left = child_importance(lo, mid, node + 1u, x);
        let right = child_importance(mid, hi, node + (mid - lo), x);
        let y = branch_threshold(branch_probabilities(left, right));
        let t = ceil(y);
        if f32(rng_next(state) >> 8u) < y {
            pdf_m *= t * (1.0 / 16777216.0);
            node = node + 1u;
            hi = mid;
        } else {
            pdf_m *= (16777216.0 - t) * (1.0 / 16777216.0);
            node = node + (mid - lo);
            lo = mid;
        }
        let f = frexp(pdf_m);
        pdf_m = f.fract;
        pdf_e += f.exp;
    }
    let i = tree_order[lo];
    let g = geometry_term(light_position(i), x);
    let pw = frexp(lights[i].p);
    if !(g > 0.0) || !(pw.fract > 0.0) || !(pdf_m > 0.0) {
        return 0.0;
    }
    return scale_pow2(pw.fract * g / pdf_m, pw.exp - pdf_e);
}

// ExactSampler::sample: every c_j = p_j·G_j(x), one draw, the first light whose running sum
// exceeds u·S; the estimate is S whichever light is picked (zero variance). The pick itself
// is kept (its cost is part of the scheme) though without visibility nothing reads it.
fn spatial_exact_estimate(x: vec2<f32>, state: ptr<function, u32>) -> f32 {
    var c: array<f32, 16>;
    let n = min(params.n_lights, EXACT_MAX_LIGHTS);
    var total = 0.0;
    for (var j = 0u; j < n; j++) {
        c[j] = lights[j].p * geometry_term(light_position(j), x);
        total += c[j];
    }
    let u = unit24(rng_next(state));
    if !(total > 0.0) {
        return 0.0;
    }
    let threshold = u * total;
    var running = 0.0;
    var chosen = n;
    for (var j = 0u; j < n; j++) {
        if c[j] > 0.0 {
            chosen = j;
            running += c[j];
            if running > threshold {
                break;
            }
        }
    }
    return select(0.0, total, chosen < n);
}

@compute @workgroup_size(16, 16)
fn accumulate_spatial(@builtin(global_invocation_id) gid: vec3<u32>) {
    let py = params.row_begin + gid.y;
    if gid.x >= params.width || py >= params.row_end {
        return;
    }
    let p = py * params.width + gid.x;
    let x = pixel_center(gid.x, py);
    var acc = sums[p];
    for (var j = 0u; j < params.k_count; j++) {
        var state = rng_new(params.seed_lo, params.seed_hi, p, params.k_base + j);
        var e: f32;
        if params.scheme == SCHEME_SPATIAL_EXACT {
            e = spatial_exact_estimate(x, &state);
        } else {
            e = spatial_tree_estimate(x, &state);
        }
        acc += vec2<f32>(e, e * e);
    }
    sums[p] = acc;
}
