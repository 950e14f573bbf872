// spatial.wgsl: Scheme::Spatial on the GPU, the twin of crates/core/src/spatial (the exact
// contribution pick for few lights, the 4-wide light tree with leaf clusters for many).
// Needs the RNG prelude, render_common.wgsl and the split arrays (split.rs)
// `spatial_lights` (vec4<f32>: x, y, z, p_i of the contributing lights, in leaf order) and
// `spatial_nodes` (SpatialNode) and `spatial_cuts` (u32: the tree's per-tile cuts), read
// through spatial_lights_at, spatial_nodes_at and spatial_cuts_at.
// The scene's emission profiles enter through fn light_emission(j, light, x) (leaf order;
// 1 for point lights) and fn lane_weights (for a tree over spots or ranges the lanes' maps
// and bounds of spatial_bounds.wgsl; for point lights point_lane_weights): both from
// spatial.rs.
// Same streams as the CPU: sample k of pixel p draws from rng_new(seed, p, k); the exact
// pick takes one draw (u = (r >> 8)·2^-24, exact in f32), the descent one draw per node and
// one in the leaf cluster, r >> 8 against the cumulative grid masses (a tile's cut: r >> 8
// through its alias columns).

// A tree node, 80 bytes: per lane, the child's power-weighted centroid (xyz) and power (w),
// and the child word: a node index, or 1 << 31 | count << 27 | first (count 0: no child).
struct SpatialNode {
    lane: array<vec4<f32>, 4>,
    child: vec4<u32>,
}

const SCHEME_SPATIAL_EXACT: u32 = 3u;
const SCHEME_SPATIAL_TREE: u32 = 4u;
const EXACT_MAX_LIGHTS: u32 = 16u;
const LEAF_SIZE: u32 = 8u;
const LEAF_BIT: u32 = 0x80000000u;
const COUNT_SHIFT: u32 = 27u;
const FIRST_MASK: u32 = 0x07ffffffu;
const GRID: u32 = 16777216u;
const GRID_CELL: f32 = 5.9604645e-8;
// spatial::importance::POWER_SHARE and IMPORTANCE_CAP (f32::MAX / 16).
const POWER_SHARE: f32 = 0.03125;
const IMPORTANCE_CAP: f32 = 2.1267647e37;

fn unit24(r: u32) -> f32 {
    return f32(r >> 8u) * (1.0 / 16777216.0);
}

// spatial::importance::representative_importance: Φ·G(c, x), 0 unless positive, capped.
fn representative_importance(lane: vec4<f32>, x: vec2<f32>) -> f32 {
    let i = lane.w * geometry_term(lane.xyz, x);
    return select(0.0, min(i, IMPORTANCE_CAP), i > 0.0);
}

// spatial::importance::grid_masses of one probability, before the remainder. The node (four
// lanes in vec4 registers) and the leaf (eight lights in an array) apply the remainder rule
// and the cumulative pick each in its own code: one function over array<_, 8> for both was
// measured 1.35–1.5× slower on lavapipe (the node's vec4s spilled to function memory).
fn floor_mass(p: f32) -> u32 {
    if !(p > 0.0) {
        return 0u;
    }
    return clamp(u32(floor(p * 16777216.0)), 1u, GRID);
}

// What the branch probabilities of a node's four lanes are made of: each lane's importance
// and its share of the defensive mixture.
struct LaneWeights {
    importance: vec4<f32>,
    share: vec4<f32>,
}

// Point lights: each lane's representative light, and its power.
fn point_lane_weights(node: ptr<function, SpatialNode>, x: vec2<f32>) -> LaneWeights {
    var w: LaneWeights;
    for (var k = 0u; k < 4u; k++) {
        let lane = (*node).lane[k];
        w.share[k] = lane.w;
        w.importance[k] = representative_importance(lane, x);
    }
    return w;
}

// branch_probabilities then grid_masses for the four lanes of node `at`.
fn node_masses(node: ptr<function, SpatialNode>, at: u32, x: vec2<f32>) -> vec4<u32> {
    let w = lane_weights(node, at, x);
    let importance = w.importance;
    let power = w.share;
    let total_importance = importance.x + importance.y + importance.z + importance.w;
    let total_power = power.x + power.y + power.z + power.w;
    if !(total_power > 0.0) {
        return vec4<u32>(0u);
    }
    let by_power = 1.0 / total_power;
    var p: vec4<f32>;
    // The importances are capped at f32::MAX / 16: their sum is finite.
    if total_importance > 0.0 {
        let by_importance = (1.0 - POWER_SHARE) / total_importance;
        let share = POWER_SHARE * by_power;
        p = importance * by_importance + power * share;
    } else {
        p = power * by_power;
    }
    var m = vec4<u32>(floor_mass(p.x), floor_mass(p.y), floor_mass(p.z), floor_mass(p.w));
    var largest = 0u;
    for (var k = 1u; k < 4u; k++) {
        if m[k] > m[largest] {
            largest = k;
        }
    }
    let sum = m.x + m.y + m.z + m.w;
    m[largest] = u32(clamp(i32(m[largest]) + i32(GRID) - i32(sum), 1, i32(GRID)));
    return m;
}

// spatial::importance::pick_on_grid over four lanes.
fn pick_lane(m: vec4<u32>, u: u32) -> u32 {
    var end = 0u;
    for (var k = 0u; k < 3u; k++) {
        end += m[k];
        if u < end {
            return k;
        }
    }
    return 3u;
}

// v · 2^e for any i32 e, as two exact power-of-two scalings (each within pow2's range).
fn scale_pow2(v: f32, e: i32) -> f32 {
    let c = clamp(e, -250, 250);
    let half = c / 2;
    return (v * pow2(half)) * pow2(c - half);
}

// TileCuts::pick for pixel (px, py): the entry its tile's alias columns give the draw's
// top 24 bits u, as (child word, mass); mass 0 when no entry of the tile has power (the
// pick ends with ê = 0). The cuts' words (spatial.rs, cut_words): tile side (0: no cuts),
// tiles along x, tile count T, T + 1 offsets of the tiles' words (after these), then per
// tile: its column count K (a power of two; 0: no power), K columns (threshold t < C in
// the low log2(C) bits, alias above; a full column is its own alias, threshold 0), per
// entry (mass, child word). Column u / C of C = 2^24 / K cells takes its own entry below t
// and its alias from there on.
fn spatial_cut_entry(px: u32, py: u32, state: ptr<function, u32>) -> vec2<u32> {
    let side = spatial_cuts_at(0u);
    let tile = (py / side) * spatial_cuts_at(1u) + px / side;
    let at = 4u + spatial_cuts_at(2u) + spatial_cuts_at(3u + tile);
    let k = spatial_cuts_at(at);
    let u = rng_next(state) >> 8u;
    if k == 0u {
        return vec2<u32>(0u, 0u);
    }
    let shift = 24u - countTrailingZeros(k);
    let column = u >> shift;
    let word = spatial_cuts_at(at + 1u + column);
    let cells = (1u << shift) - 1u;
    let entry = select(word >> shift, column, (u & cells) < (word & cells));
    let pair = at + 1u + k + 2u * entry;
    return vec2<u32>(spatial_cuts_at(pair + 1u), spatial_cuts_at(pair));
}

// LightTree::sample: with per-tile cuts one draw for the tile's entry, then one draw per node,
// one in the leaf cluster; ê = c_j / pdf with the pdf kept as a mantissa and a power of two
// (frexp after every factor), so that neither a deep product of small probabilities nor the
// final ratio under- or overflows early.
fn spatial_tree_estimate(x: vec2<f32>, px: u32, py: u32, state: ptr<function, u32>) -> f32 {
    var at = params.spatial_root;
    var pdf_m = 1.0;
    var pdf_e = 0i;
    if spatial_cuts_at(0u) != 0u {
        let entry = spatial_cut_entry(px, py, state);
        if entry.y == 0u {
            return 0.0;
        }
        at = entry.x;
        // m_e · 2^-24 is exact in f32 (m_e ≤ 2^24).
        let f = frexp(f32(entry.y) * GRID_CELL);
        pdf_m = f.fract;
        pdf_e = f.exp;
    }
    var node: SpatialNode;
    while (at & LEAF_BIT) == 0u {
        node = spatial_nodes_at(at);
        let m = node_masses(&node, at, x);
        let lane = pick_lane(m, rng_next(state) >> 8u);
        let f = frexp(pdf_m * (f32(m[lane]) * GRID_CELL));
        pdf_m = f.fract;
        pdf_e += f.exp;
        at = node.child[lane];
    }
    let count = min((at & ~LEAF_BIT) >> COUNT_SHIFT, LEAF_SIZE);
    let first = at & FIRST_MASK;
    if count == 0u {
        return 0.0;
    }
    // The leaf cluster: every c_j = p_j·G_j(x), then the pick by their grid masses.
    var c: array<f32, 8>;
    var total = 0.0;
    for (var j = 0u; j < count; j++) {
        let l = spatial_lights_at(first + j);
        c[j] = l.w * geometry_term(l.xyz, x);
        if c[j] > 0.0 {
            c[j] *= light_emission(first + j, l.xyz, x);
        }
        total += c[j];
    }
    let u = rng_next(state) >> 8u;
    if !(total > 0.0) {
        return 0.0;
    }
    let inv = 1.0 / total;
    var m: array<u32, 8>;
    var sum = 0u;
    var largest = 0u;
    for (var j = 0u; j < count; j++) {
        m[j] = floor_mass(c[j] * inv);
        sum += m[j];
        if m[j] > m[largest] {
            largest = j;
        }
    }
    m[largest] = u32(clamp(i32(m[largest]) + i32(GRID) - i32(sum), 1, i32(GRID)));
    var chosen = count - 1u;
    var end = 0u;
    for (var j = 0u; j < count; j++) {
        end += m[j];
        if u < end {
            chosen = j;
            break;
        }
    }
    let f = frexp(pdf_m * (f32(m[chosen]) * GRID_CELL));
    let cj = frexp(c[chosen]);
    if !(cj.fract > 0.0) || !(f.fract > 0.0) {
        return 0.0;
    }
    return scale_pow2(cj.fract / f.fract, cj.exp - pdf_e - f.exp);
}

// ExactSampler::sample: every c_j = p_j·G_j(x) of the contributing lights (at most 16,
// their count in params.spatial_root), one draw, the first light whose running sum exceeds
// u·S; the estimate is S whichever light is picked (zero variance). The pick itself is kept
// (its cost is part of the scheme) though without visibility nothing reads it.
fn spatial_exact_estimate(x: vec2<f32>, state: ptr<function, u32>) -> f32 {
    var c: array<f32, 16>;
    let n = min(params.spatial_root, EXACT_MAX_LIGHTS);
    var total = 0.0;
    for (var j = 0u; j < n; j++) {
        let l = spatial_lights_at(j);
        c[j] = l.w * geometry_term(l.xyz, x);
        if c[j] > 0.0 {
            c[j] *= light_emission(j, l.xyz, x);
        }
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
            e = spatial_tree_estimate(x, gid.x, py, &state);
        }
        acc += vec2<f32>(e, e * e);
    }
    sums[p] = acc;
}
