//! Spots and ranges on the GPU: each light's emission profile as a 24-byte `Shape`
//! (`emission.wgsl`, the twin of [`crate::scene::EmissionShape::factor`]), uploaded only
//! for scenes that have profiles, and the WGSL function `light_emission(i, light, x)` the
//! kernels call: the factor `S_i(x)` of light `i` read from a split array, or a stub
//! returning 1 for a scene of point lights (so those kernels read and compute exactly what
//! they did before).

use super::split::{Access, ArrayLayout, SplitShape, declarations};
use crate::scene::EmissionShape;

pub(crate) const EMISSION_WGSL: &str = include_str!("emission.wgsl");

/// GPU bytes per emission profile.
pub(crate) const BYTES_PER_SHAPE: u64 = 24;

/// One light's profile as `emission.wgsl` reads it (`Shape`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuShape {
    axis: [f32; 2],
    cos_outer: f32,
    cone_scale: f32,
    gain: f32,
    inv_range: f32,
}

impl GpuShape {
    /// The `f32` form of `e` (octahedral axis; the cone scale 0 without a spot, as the shape
    /// keeps it).
    pub(crate) fn of(e: &EmissionShape) -> Self {
        GpuShape {
            axis: octahedral_encode(e.axis()),
            cos_outer: e.cos_outer() as f32,
            cone_scale: e.cone_scale() as f32,
            gain: e.gain() as f32,
            inv_range: e.inv_range() as f32,
        }
    }
}

/// The octahedral coordinates `(u, v) ∈ [−1, 1]²` of a unit vector (Cigolle et al. 2014),
/// computed in `f64` and rounded once; `(0, 0)` for the zero vector.
pub(crate) fn octahedral_encode(n: glam::DVec3) -> [f32; 2] {
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    if l1 == 0.0 {
        return [0.0, 0.0];
    }
    let (mut u, mut v) = (n.x / l1, n.y / l1);
    if n.z < 0.0 {
        let (ou, ov) = (u, v);
        u = (1.0 - ov.abs()) * if ou >= 0.0 { 1.0 } else { -1.0 };
        v = (1.0 - ou.abs()) * if ov >= 0.0 { 1.0 } else { -1.0 };
    }
    [u as f32, v as f32]
}

/// The split-array layout of the profiles, named `name` (`shapes` in leaf or scene order).
pub(crate) const fn shapes_layout(name: &'static str) -> ArrayLayout {
    ArrayLayout {
        name,
        element: "Shape",
        bytes: BYTES_PER_SHAPE,
    }
}

/// The WGSL of `fn light_emission(i: u32, light: vec3<f32>, x: vec2<f32>) -> f32`: with
/// `shapes` (the profiles' split shape and first binding) the factor of profile `i` of the
/// array `name`, else 1.
pub(crate) fn emission_source(name: &'static str, shapes: Option<(SplitShape, u32)>) -> String {
    match shapes {
        None => {
            "fn light_emission(i: u32, light: vec3<f32>, x: vec2<f32>) -> f32 { return 1.0; }\n"
                .to_owned()
        }
        Some((shape, binding)) => format!(
            "{EMISSION_WGSL}\n{}\nfn light_emission(i: u32, light: vec3<f32>, x: vec2<f32>) -> f32 {{ return emission_factor({name}_at(i), light, x); }}\n",
            declarations(shapes_layout(name), shape, binding, Access::Read)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// The WGSL decode, mirrored in f64 for the test.
    fn decode([u, v]: [f32; 2]) -> DVec3 {
        let (u, v) = (f64::from(u), f64::from(v));
        let mut n = DVec3::new(u, v, 1.0 - u.abs() - v.abs());
        if n.z < 0.0 {
            let x = (1.0 - n.y.abs()) * if n.x >= 0.0 { 1.0 } else { -1.0 };
            let y = (1.0 - n.x.abs()) * if n.y >= 0.0 { 1.0 } else { -1.0 };
            n = DVec3::new(x, y, n.z);
        }
        n.normalize()
    }

    #[test]
    fn octahedral_axes_round_trip_within_f32_rounding() {
        for d in [
            DVec3::X,
            DVec3::NEG_Z,
            DVec3::new(0.3, -0.4, -0.866),
            DVec3::new(-0.01, 0.02, 0.9997),
            DVec3::new(1.0, 1.0, -1e-7),
        ] {
            let n = d.normalize();
            let back = decode(octahedral_encode(n));
            // Each coordinate rounds by at most 2^-24; the map's derivative is at most ~2
            // in norm, and the normalization adds a few ulps.
            assert!(
                back.angle_between(n) < 4.0 * f64::from(f32::EPSILON),
                "{n} → {back}"
            );
        }
    }
}
