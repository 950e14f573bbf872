// probe.wgsl: evaluates the RNG prelude on given inputs so tests can compare it with the
// CPU bit for bit. One thread per input row.

struct ProbeParams {
    count: u32,
    draws: u32,
    threads_per_row: u32,
    // N of probe_pick_uniform (unused by the others).
    n: u32,
}

@group(0) @binding(0) var<uniform> params: ProbeParams;
// probe_rng, probe_pick_uniform: (seed_lo, seed_hi, stream_lo, stream_hi);
// probe_mulhi32: (a, b, -, -).
@group(0) @binding(1) var<storage, read> inputs: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> outputs: array<u32>;

fn probe_index(gid: vec3<u32>) -> u32 {
    return gid.y * params.threads_per_row + gid.x;
}

// outputs[i·draws + d] = draw d of Rng::new(seed_i, stream_i).
@compute @workgroup_size(256)
fn probe_rng(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = probe_index(gid);
    if i >= params.count {
        return;
    }
    let key = inputs[i];
    var state = rng_new(key.x, key.y, key.z, key.w);
    for (var d = 0u; d < params.draws; d++) {
        outputs[i * params.draws + d] = rng_next(&state);
    }
}

// outputs[2i] = high word, outputs[2i + 1] = low word of a_i·b_i.
@compute @workgroup_size(256)
fn probe_mulhi32(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = probe_index(gid);
    if i >= params.count {
        return;
    }
    let ab = inputs[i];
    outputs[2u * i] = mulhi32(ab.x, ab.y);
    outputs[2u * i + 1u] = ab.x * ab.y;
}

// outputs[2i] = pick_uniform(N, Rng::new(seed_i, stream_i)), outputs[2i + 1] = the draw that
// follows it (the alias path's keep draw): both must equal the CPU's Uniform::sample and
// the next_u32 after it, which checks the pick and how many draws it consumed.
@compute @workgroup_size(256)
fn probe_pick_uniform(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = probe_index(gid);
    if i >= params.count {
        return;
    }
    let key = inputs[i];
    var state = rng_new(key.x, key.y, key.z, key.w);
    outputs[2u * i] = pick_uniform(params.n, &state);
    outputs[2u * i + 1u] = rng_next(&state);
}
