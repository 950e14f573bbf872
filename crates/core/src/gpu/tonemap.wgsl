// tonemap.wgsl: the WGSL twin of crates/core/src/render/tonemap.rs. The irradiance of a
// pixel is Φ_total·Σê/spp, so L = exposure·E = factor·Σê with factor = exposure·Φ_total/spp
// computed in f64 on the CPU (no f32 overflow of Φ_total). Display d = L/(1 + L)
// (Reinhard), then sRGB, then round(255·v); negative or NaN values map to black.

struct TonemapParams {
    // exposure·Φ_total/spp, and /(spp + 1) for the rows 0..band_row that a sample pass in
    // progress has reached (they hold one sample more).
    factor: f32,
    width: u32,
    height: u32,
    band_row: u32,
    factor_band: f32,
    // The first row of this dispatch (the grid covers rows from here to height).
    row_begin: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> params: TonemapParams;
@group(0) @binding(1) var<storage, read> sums: array<vec2<f32>>;
@group(0) @binding(2) var output: texture_storage_2d<rgba8unorm, write>;

fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        return 12.92 * v;
    }
    return 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

fn tonemap_value(l: f32) -> f32 {
    if !(l > 0.0) {
        return 0.0;
    }
    // L/(1 + L) written as 1/(1 + 1/L): equal for finite L, and 1 for L = +inf.
    return clamp(linear_to_srgb(1.0 / (1.0 + 1.0 / l)), 0.0, 1.0);
}

@compute @workgroup_size(16, 16)
fn tonemap(@builtin(global_invocation_id) gid: vec3<u32>) {
    let py = params.row_begin + gid.y;
    if gid.x >= params.width || py >= params.height {
        return;
    }
    let p = py * params.width + gid.x;
    // Quantize here, so the unorm store receives an exact k/255.
    let factor = select(params.factor, params.factor_band, py < params.band_row);
    let v = round(255.0 * tonemap_value(factor * sums[p].x)) / 255.0;
    textureStore(output, vec2<i32>(i32(gid.x), i32(py)), vec4<f32>(v, v, v, 1.0));
}
