// histogram.wgsl: counts the lights picked by samples base .. base + count − 1, where
// sample k draws from Rng::new(seed, k) exactly as Sampler::pick_light does on the CPU.
// Needs the RNG prelude, pick.wgsl and the split arrays (split.rs) `alias_table`
// (vec2<u32> per column, read through alias_table_at) and `counts` (atomic<u32> per light,
// added to through counts_add), bound from binding 1 on.

struct HistogramParams {
    seed_lo: u32,
    seed_hi: u32,
    // First sample index of this dispatch, as 64-bit (lo, hi).
    base_lo: u32,
    base_hi: u32,
    // Samples in this dispatch (at most 2^31, so no bin and no index can wrap).
    count: u32,
    n_lights: u32,
    scheme: u32,
    // Threads in the dispatch: thread t takes samples t, t + stride, t + 2·stride, ...
    stride: u32,
}

@group(0) @binding(0) var<uniform> params: HistogramParams;
fn alias_entry(column: u32) -> vec2<u32> {
    return alias_table_at(column);
}

// Few lights: count in workgroup memory first, then add each non-zero bin once per
// workgroup, instead of every thread contending for the same few global counters.
const SHARED_BINS: u32 = 2048u;
var<workgroup> shared_counts: array<atomic<u32>, SHARED_BINS>;

fn sample_light(local: u32) -> u32 {
    // 64-bit stream index base + local, with the carry into the high word.
    let stream_lo = params.base_lo + local;
    let stream_hi = params.base_hi + select(0u, 1u, stream_lo < params.base_lo);
    var state = rng_new(params.seed_lo, params.seed_hi, stream_lo, stream_hi);
    return pick_light(params.scheme, params.n_lights, &state);
}

@compute @workgroup_size(256)
fn histogram(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    // params are uniform, so this branch (and the barriers inside) is workgroup-uniform.
    if params.n_lights <= SHARED_BINS {
        for (var b = lid; b < params.n_lights; b += 256u) {
            atomicStore(&shared_counts[b], 0u);
        }
        workgroupBarrier();
        for (var k = gid.x; k < params.count; k += params.stride) {
            atomicAdd(&shared_counts[sample_light(k)], 1u);
        }
        workgroupBarrier();
        for (var b = lid; b < params.n_lights; b += 256u) {
            let c = atomicLoad(&shared_counts[b]);
            if c != 0u {
                counts_add(b, c);
            }
        }
    } else {
        for (var k = gid.x; k < params.count; k += params.stride) {
            counts_add(sample_light(k), 1u);
        }
    }
}
