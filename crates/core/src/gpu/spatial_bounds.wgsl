// spatial_bounds.wgsl: the twin of spatial::LaneBounds and spatial::grid::MappedLanes for a
// light tree over spots or ranges. A node's lanes are 28 vec4 (448 bytes), seven per lane k:
// (min.xyz, intensity Σ p·g), (max.xyz, range), (axis.xyz, cos θo of the axes' cone),
// (cos θe, map scale, 0, 0), the footprint on the plane (min.xy, max.xy), the map's corner
// and cells per unit (lo.xy, per.xy), and the unbounded lights (centroid.xyz, Σ p·g).
// The maps' 8-bit codes are the split array `spatial_codes` (u32 words, 64 a lane: cell c of
// lane k of node n is byte c % 4 of word (4n + k)·64 + c / 4). Needs the split arrays
// `spatial_bounds` (fn spatial_bounds_at(i: u32) -> NodeBounds) and `spatial_codes`.
struct NodeBounds {
    v: array<vec4<f32>, 28>,
}

// spatial::grid::GRID_SIDE and the fractional octaves 2^(−r/8) of grid::decode.
const MAP_SIDE: f32 = 16.0;
const EIGHTH_OCTAVES = array<f32, 8>(1.0, 0.9170040432, 0.8408964153, 0.7711054127,
                                      0.7071067812, 0.6484197773, 0.5946035575, 0.5452538663);

// grid::decode: code c > 0 stands for 2^((c − 255)/8) of the map's scale.
fn map_decode(code: u32) -> f32 {
    if code == 0u {
        return 0.0;
    }
    let below = 255u - code;
    return EIGHTH_OCTAVES[below % 8u] * pow2(-i32(below / 8u));
}

// The code of cell `cell` of lane k of node `at`.
fn map_code(at: u32, k: u32, cell: u32) -> u32 {
    let word = spatial_codes_at((at * 4u + k) * 64u + cell / 4u);
    return (word >> (8u * (cell % 4u))) & 0xffu;
}

// LaneBounds::reach past the footprint, for a lane whose footprint is unbounded: 0 when no
// light of lane k can light x (beyond every range, or outside every cone), else 1. Each test
// culls only with a margin of 10^-5 (relative) beyond the CPU's, so the f32 rounding never
// culls a lane the f64 test keeps.
fn lane_reach(b: ptr<function, NodeBounds>, k: u32, x: vec2<f32>) -> f32 {
    let v0 = (*b).v[7u * k];
    let v1 = (*b).v[7u * k + 1u];
    let v2 = (*b).v[7u * k + 2u];
    let v3 = (*b).v[7u * k + 3u];
    let p = vec3<f32>(x, 0.0);
    let outside = max(max(v0.xyz - p, p - v1.xyz), vec3<f32>(0.0));
    if dot(outside, outside) >= v1.w * v1.w * 1.00001 {
        return 0.0;
    }
    if v2.w <= -1.0 || v3.x <= -1.0 {
        return 1.0;
    }
    let centre = 0.5 * (v0.xyz + v1.xyz);
    let half = 0.5 * (v1.xyz - v0.xyz);
    let radius2 = dot(half, half);
    let to_point = p - centre;
    let d2 = dot(to_point, to_point);
    if d2 <= radius2 {
        return 1.0;
    }
    let d = sqrt(d2);
    let cos_w = clamp(dot(v2.xyz, to_point) / d, -1.0, 1.0);
    let sin_w = sqrt(max(1.0 - cos_w * cos_w, 0.0));
    let sin_o = sqrt(max(1.0 - v2.w * v2.w, 0.0));
    let sin2_b = radius2 / d2;
    let cos_b = sqrt(max(1.0 - sin2_b, 0.0));
    let sin_b = sqrt(sin2_b);
    var cos_x = 1.0;
    var sin_x = 0.0;
    if !(cos_w > v2.w) {
        cos_x = cos_w * v2.w + sin_w * sin_o;
        sin_x = max(sin_w * v2.w - cos_w * sin_o, 0.0);
    }
    var cos_p = 1.0;
    if !(cos_x > cos_b) {
        cos_p = cos_x * cos_b + sin_x * sin_b;
    }
    return select(1.0, 0.0, cos_p <= v3.x - 0.00001);
}

// MappedLanes::weights: each lane's importance (its map's value in the cell holding x, plus
// its unbounded lights' representative light) and share (Σ p·g), both 0 where its bounds
// exclude x.
fn lane_weights(node: ptr<function, SpatialNode>, at: u32, x: vec2<f32>) -> LaneWeights {
    var b = spatial_bounds_at(at);
    var w: LaneWeights;
    for (var k = 0u; k < 4u; k++) {
        let footprint = b.v[7u * k + 4u];
        let inside = x.x >= footprint.x && x.y >= footprint.y && x.x <= footprint.z
            && x.y <= footprint.w;
        var reach = select(0.0, 1.0, inside);
        let bounded = footprint.x > -3.0e38 && footprint.y > -3.0e38 && footprint.z < 3.0e38
            && footprint.w < 3.0e38;
        if inside && !bounded {
            reach = lane_reach(&b, k, x);
        }
        let map = b.v[7u * k + 5u];
        let c = (x - map.xy) * map.zw;
        var importance = 0.0;
        if c.x >= 0.0 && c.y >= 0.0 && c.x < MAP_SIDE && c.y < MAP_SIDE {
            let cell = u32(c.y) * 16u + u32(c.x);
            importance = b.v[7u * k + 3u].y * map_decode(map_code(at, k, cell));
        }
        let unbounded = b.v[7u * k + 6u];
        if unbounded.w > 0.0 && reach > 0.0 {
            importance += unbounded.w * geometry_term(unbounded.xyz, x);
        }
        w.importance[k] = min(reach * importance, IMPORTANCE_CAP);
        w.share[k] = reach * b.v[7u * k].w;
    }
    return w;
}
