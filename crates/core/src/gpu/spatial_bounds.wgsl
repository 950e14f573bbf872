// spatial_bounds.wgsl: the twin of spatial::LaneBounds for a light tree over spots or
// ranges. A node's bounds are 20 vec4 (320 bytes), five per lane k: (min.xyz, intensity),
// (max.xyz, range), (axis.xyz, cos θo of the axes' cone), (cos θe, 0, 0, 0) and the
// footprint on the plane (min.xy, max.xy). Needs the split array `spatial_bounds`
// (fn spatial_bounds_at(i: u32) -> NodeBounds).
struct NodeBounds {
    v: array<vec4<f32>, 20>,
}

// LaneBounds::reach: 0 when no light of lane k can light x (outside the footprint, beyond
// every range, or outside every cone), else 1.
fn lane_reach(b: ptr<function, NodeBounds>, k: u32, x: vec2<f32>) -> f32 {
    let v0 = (*b).v[5u * k];
    let v1 = (*b).v[5u * k + 1u];
    let v2 = (*b).v[5u * k + 2u];
    let v3 = (*b).v[5u * k + 3u];
    let v4 = (*b).v[5u * k + 4u];
    if !(x.x >= v4.x && x.y >= v4.y && x.x <= v4.z && x.y <= v4.w) {
        return 0.0;
    }
    let p = vec3<f32>(x, 0.0);
    let outside = max(max(v0.xyz - p, p - v1.xyz), vec3<f32>(0.0));
    if dot(outside, outside) >= v1.w * v1.w {
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
    return select(1.0, 0.0, cos_p <= v3.x);
}

// TreeNode::masses_bounded's importances: each lane's intensity at its centroid, times its
// reach.
fn bounded_importances(node: ptr<function, SpatialNode>, at: u32, x: vec2<f32>,
                       importance: vec4<f32>) -> vec4<f32> {
    var b = spatial_bounds_at(at);
    var out = vec4<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let lane = (*node).lane[k];
        let intensity = b.v[5u * k].w;
        out[k] = representative_importance(vec4<f32>(lane.xyz, intensity), x) * lane_reach(&b, k, x);
    }
    return out;
}
