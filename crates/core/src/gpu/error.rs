//! Why a GPU operation could not be carried out.

use crate::Scheme;

/// Everything the GPU module can refuse or fail at; each message names the problem.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GpuError {
    /// No adapter (GPU or software rasterizer) matched the request.
    #[error(
        "no GPU adapter found ({reason}); install a Vulkan, Metal, DX12 or GL driver \
         (Mesa's lavapipe works without a GPU) or select one with WGPU_BACKEND"
    )]
    NoAdapter {
        /// What wgpu reported.
        reason: String,
    },
    /// `WGPU_ADAPTER_NAME` is set but no adapter's name contains it.
    #[error("WGPU_ADAPTER_NAME is '{name}' but no adapter's name contains it (found: {found})")]
    AdapterNameNotFound {
        /// The requested name (lower-cased).
        name: String,
        /// The names of the adapters that were found, comma separated.
        found: String,
    },
    /// The adapter refused to create a logical device.
    #[error("the GPU adapter '{adapter}' refused to create a device: {reason}")]
    RequestDevice {
        /// The adapter's name.
        adapter: String,
        /// What wgpu reported.
        reason: String,
    },
    /// The scheme has no GPU implementation.
    #[error("scheme '{scheme}' is not supported on the GPU: {reason}")]
    UnsupportedScheme {
        /// The refused scheme.
        scheme: Scheme,
        /// Why, and what to use instead.
        reason: &'static str,
    },
    /// A buffer would exceed the device's limits.
    #[error("GPU buffer for {what} needs {bytes} bytes but the device allows at most {limit}")]
    BufferTooLarge {
        /// What the buffer holds.
        what: &'static str,
        /// The bytes it needs.
        bytes: u64,
        /// The device's limit.
        limit: u64,
    },
    /// A kernel would need more storage bindings than the device offers per shader stage
    /// (arrays beyond one binding are split over several, [`crate::gpu`] § Limits).
    #[error(
        "{what} needs {needed} storage bindings but the device allows at most {limit} per \
         shader stage"
    )]
    TooManyBindings {
        /// What the kernel computes.
        what: &'static str,
        /// The storage bindings it needs.
        needed: u32,
        /// The device's `max_storage_buffers_per_shader_stage`.
        limit: u32,
    },
    /// The image is empty or larger than a texture (or a dispatch) may be.
    #[error("image of {width}×{height} pixels is not supported: each side must be in 1..={max}")]
    ImageSize {
        /// Requested columns.
        width: u32,
        /// Requested rows.
        height: u32,
        /// The device's largest 2D texture side.
        max: u32,
    },
    /// The per-pixel sample index would pass `u32::MAX` (the high word of the stream).
    #[error(
        "cannot add {requested} samples per pixel to {accumulated}: the total would exceed {max}"
    )]
    TooManySamples {
        /// Samples already accumulated per pixel.
        accumulated: u32,
        /// Samples asked for.
        requested: u32,
        /// The largest total, `u32::MAX`.
        max: u32,
    },
    /// The sums were asked for while a sample pass was only partly done.
    #[error(
        "the sample pass in progress has reached {rows_done} of {height} rows; finish it \
         (finish_pass) before reading the sums back"
    )]
    PassInProgress {
        /// Rows of the pass done.
        rows_done: u32,
        /// Rows of the image.
        height: u32,
    },
    /// New powers do not match the renderer's light positions.
    #[error("{got} powers given for a scene of {expected} lights")]
    LightCountMismatch {
        /// Lights in the scene.
        expected: usize,
        /// Powers given.
        got: usize,
    },
    /// A scene coordinate (a light position or the receiver plane) is a finite `f64` but
    /// rounds to infinity as the `f32` the GPU stores: `|v|` beyond `f32::MAX ≈ 3.4·10^38`
    /// would turn the image into NaN.
    #[error(
        "{field} = {value} is beyond the f32 range of the GPU (|v| ≤ {max:e}); render on the \
         CPU, which works in f64, or scale the scene down",
        max = f32::MAX
    )]
    BeyondF32 {
        /// The scene field, as the scene file names it: `lights[3].position[2]`,
        /// `plane.max[0]`, or the plane's extent `plane.max[0] − plane.min[0]`.
        field: String,
        /// The value found, in scientific notation.
        value: String,
    },
    /// Waiting for the device or mapping a buffer for reading failed.
    #[error("GPU readback of {what} failed: {reason}")]
    Readback {
        /// What was being read.
        what: &'static str,
        /// What wgpu reported.
        reason: String,
    },
    /// wgpu reported a validation, out-of-memory or internal error.
    #[error("GPU error while {during}: {reason}")]
    Wgpu {
        /// The operation in progress.
        during: &'static str,
        /// What wgpu reported.
        reason: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_message_names_its_problem() {
        let cases = [
            (
                GpuError::NoAdapter {
                    reason: "none".into(),
                },
                "no GPU adapter found (none)",
            ),
            (
                GpuError::AdapterNameNotFound {
                    name: "nvidia".into(),
                    found: "llvmpipe".into(),
                },
                "WGPU_ADAPTER_NAME is 'nvidia' but no adapter's name contains it (found: llvmpipe)",
            ),
            (
                GpuError::RequestDevice {
                    adapter: "gpu0".into(),
                    reason: "lost".into(),
                },
                "the GPU adapter 'gpu0' refused to create a device: lost",
            ),
            (
                GpuError::UnsupportedScheme {
                    scheme: Scheme::Cdf,
                    reason: "why",
                },
                "scheme 'cdf' is not supported on the GPU: why",
            ),
            (
                GpuError::PassInProgress {
                    rows_done: 3,
                    height: 8,
                },
                "the sample pass in progress has reached 3 of 8 rows; finish it (finish_pass) \
                 before reading the sums back",
            ),
            (
                GpuError::BufferTooLarge {
                    what: "pixel sums",
                    bytes: 10,
                    limit: 8,
                },
                "GPU buffer for pixel sums needs 10 bytes but the device allows at most 8",
            ),
            (
                GpuError::ImageSize {
                    width: 0,
                    height: 4,
                    max: 16384,
                },
                "image of 0×4 pixels is not supported: each side must be in 1..=16384",
            ),
            (
                GpuError::TooManySamples {
                    accumulated: 1,
                    requested: u32::MAX,
                    max: u32::MAX,
                },
                "cannot add 4294967295 samples per pixel to 1: the total would exceed 4294967295",
            ),
            (
                GpuError::LightCountMismatch {
                    expected: 3,
                    got: 2,
                },
                "2 powers given for a scene of 3 lights",
            ),
            (
                GpuError::BeyondF32 {
                    field: "lights[3].position[2]".into(),
                    value: "1e39".into(),
                },
                "lights[3].position[2] = 1e39 is beyond the f32 range of the GPU \
                 (|v| ≤ 3.4028235e38); render on the CPU",
            ),
            (
                GpuError::Readback {
                    what: "pixel sums",
                    reason: "unmapped".into(),
                },
                "GPU readback of pixel sums failed: unmapped",
            ),
            (
                GpuError::Wgpu {
                    during: "histogram",
                    reason: "bad shader".into(),
                },
                "GPU error while histogram: bad shader",
            ),
        ];
        for (error, start) in cases {
            assert!(error.to_string().starts_with(start), "{error}");
        }
    }
}
