// pick.wgsl: Sampler::pick_light on the GPU for the schemes it supports. Requires the
// kernel to define `fn alias_entry(column: u32) -> vec2<u32>`, the packed
// (threshold, alias) of a column (never called by the uniform scheme).

const SCHEME_UNIFORM: u32 = 0u;
const SCHEME_ALIAS: u32 = 1u;
const SCHEME_ALIAS_ONE_RANDOM: u32 = 2u;

// The light that the scheme picks from the next draws of `state`, consuming exactly the
// draws of the CPU sampler, in the same order: uniform takes the exact pick (pick_uniform:
// one draw, plus one per draw rejected by Lemire's test); alias takes the same exact column
// pick, then the next draw for the keep test; the one-random alias takes one draw, its column
// the raw high word of r·N and its keep test the low word.
fn pick_light(scheme: u32, n: u32, state: ptr<function, u32>) -> u32 {
    var light: u32;
    switch scheme {
        case SCHEME_UNIFORM: {
            light = pick_uniform(n, state);
        }
        case SCHEME_ALIAS: {
            let column = pick_uniform(n, state);
            let r2 = rng_next(state);
            light = alias_resolve(column, alias_entry(column), r2);
        }
        default: {
            let r = rng_next(state);
            let column = sample_uniform(r, n);
            light = alias_resolve(column, alias_entry(column), r * n);
        }
    }
    return light;
}
