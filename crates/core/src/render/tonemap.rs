//! The one tonemap from irradiance to display values (its WGSL twin is in the GPU module).
//!
//! `L = exposure · E`, display `d = L / (1 + L)` (Reinhard), then the sRGB transfer
//! function, then `round(255 · v)`. Negative or NaN inputs map to black.

/// The sRGB encoding of a linear value in `[0, 1]` (IEC 61966-2-1).
#[inline]
pub fn linear_to_srgb(v: f64) -> f64 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The display value in `[0, 1]` of irradiance `e` at `exposure`.
#[inline]
pub fn tonemap_value(e: f64, exposure: f64) -> f64 {
    let l = e * exposure;
    if l.is_nan() || l <= 0.0 {
        return 0.0;
    }
    if l.is_infinite() {
        return 1.0;
    }
    linear_to_srgb(l / (1.0 + l))
}

/// Tonemaps a row-major image of irradiance to grey `RGBA8` pixels (alpha 255).
pub fn tonemap_rgba8(image: &[f64], exposure: f64) -> Vec<u8> {
    image
        .iter()
        .flat_map(|&e| {
            let v = (tonemap_value(e, exposure) * 255.0).round() as u8;
            [v, v, v, 255]
        })
        .collect()
}
