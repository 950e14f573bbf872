// render.wgsl: the estimator contract of crates/core/src/render/mod.rs on the GPU.
// Pixel p = py·width + px takes sample k from Rng::new(seed, (k << 32) | p), that is
// stream_lo = p and stream_hi = k, picks light i with pick_light, and adds the normalized
// estimate ê (uniform: N·p_i·G_i(x); power-proportional: G_i(x)) and ê² to its sums.
// Needs the RNG prelude, pick.wgsl, render_common.wgsl, the split array `lights`
// (split.rs: its bindings from 2 on and fn lights_at(i: u32) -> Light) and
// fn light_emission(i, light, x) (emission.rs: a spot's or range's factor S_i(x), or 1).

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

fn alias_entry(column: u32) -> vec2<u32> {
    let light = lights_at(column);
    return vec2<u32>(light.threshold, light.alias_light);
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
        let light = lights_at(i);
        let position = vec3<f32>(light.x, light.y, light.z);
        var e = geometry_term(position, x);
        if e > 0.0 {
            e *= light_emission(i, position, x);
        }
        if params.scheme == SCHEME_UNIFORM {
            e = (params.n_f32 * light.p) * e;
        }
        acc += vec2<f32>(e, e * e);
    }
    sums[p] = acc;
}
