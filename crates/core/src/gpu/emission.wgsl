// emission.wgsl: the twin of scene::Emission::factor, S(x) = g · t² · w(d), for scenes with
// spots or ranges (a kernel over point lights gets a stub returning 1 instead, and pays
// nothing). A Shape is 24 bytes: the spot axis octahedrally encoded in two f32 (exact to
// ~1e-7), cos θo, 1/(cos θi − cos θo) (0 for a light without a spot), the gain g and 1/r
// (0 without a range).
struct Shape {
    axis_u: f32,
    axis_v: f32,
    cos_outer: f32,
    cone_scale: f32,
    gain: f32,
    inv_range: f32,
}

// The unit vector of the octahedral coordinates (u, v) ∈ [-1, 1]².
fn octahedral_decode(u: f32, v: f32) -> vec3<f32> {
    var n = vec3<f32>(u, v, 1.0 - abs(u) - abs(v));
    if n.z < 0.0 {
        let x = (1.0 - abs(n.y)) * select(-1.0, 1.0, n.x >= 0.0);
        let y = (1.0 - abs(n.x)) * select(-1.0, 1.0, n.y >= 0.0);
        n = vec3<f32>(x, y, n.z);
    }
    return normalize(n);
}

// S(x) of a light at `light` (z > 0) for the point x of the plane. The offset is scaled by
// its largest component first, so that neither its length nor d/r overflows in f32.
fn emission_factor(s: Shape, light: vec3<f32>, x: vec2<f32>) -> f32 {
    let d = vec3<f32>(x.x - light.x, x.y - light.y, -light.z);
    let m = max(max(abs(d.x), abs(d.y)), abs(d.z));
    let dn = d / m;
    let len = length(dn);
    var f = s.gain;
    if s.cone_scale > 0.0 {
        let cos_a = dot(octahedral_decode(s.axis_u, s.axis_v), dn) / len;
        let t = clamp((cos_a - s.cos_outer) * s.cone_scale, 0.0, 1.0);
        f *= t * t;
    }
    if s.inv_range > 0.0 {
        let q = len * (m * s.inv_range);
        let q2 = q * q;
        f *= clamp(1.0 - q2 * q2, 0.0, 1.0);
    }
    return f;
}
