//! The scheme word the kernels switch on, one per GPU scheme (the inverse-CDF peer has
//! none).

use super::GpuError;
use crate::Scheme;

/// Scheme word of the exact contribution pick (`N ≤` [`crate::spatial::EXACT_MAX_LIGHTS`]).
pub(crate) const SCHEME_SPATIAL_EXACT: u32 = 3;
/// Scheme word of the light-tree descent.
pub(crate) const SCHEME_SPATIAL_TREE: u32 = 4;
/// The scheme word the kernels switch on: 0 uniform, 1 alias, 2 alias with one random,
/// 3 spatial (the renderer uses 4 instead when its spatial sampler is a light tree).
pub(crate) fn scheme_code(scheme: Scheme) -> Result<u32, GpuError> {
    match scheme {
        Scheme::Uniform => Ok(0),
        Scheme::Alias => Ok(1),
        Scheme::AliasOneRandom => Ok(2),
        Scheme::Spatial => Ok(SCHEME_SPATIAL_EXACT),
        Scheme::Cdf => Err(GpuError::UnsupportedScheme {
            scheme,
            reason: "the inverse-CDF binary search is a CPU-only peer; \
                     use alias (power) or uniform on the GPU, or the CPU device",
        }),
    }
}
