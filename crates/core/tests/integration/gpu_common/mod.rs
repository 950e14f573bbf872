//! Shared by the `gpu_*` tests: one GPU context per test binary, and small helpers.
//!
//! A GPU test FAILS when no adapter is found, unless `LIGHTPICK_SKIP_GPU_TESTS=1` is set, in
//! which case it prints that it was skipped and passes. On a machine without a GPU, Mesa's
//! lavapipe (package `mesa-vulkan-drivers`) provides a Vulkan adapter on the CPU.

#![allow(dead_code)] // Each test binary uses a different subset of the helpers.

#[cfg(feature = "gpu")]
use std::sync::OnceLock;

#[cfg(feature = "gpu")]
use lightpick_core::gpu::GpuContext;

/// The shared context, or `None` when GPU tests are skipped on purpose; panics (fails the
/// test) when no adapter can be had.
#[cfg(feature = "gpu")]
pub fn context() -> Option<&'static GpuContext> {
    static CONTEXT: OnceLock<Result<GpuContext, String>> = OnceLock::new();
    if std::env::var("LIGHTPICK_SKIP_GPU_TESTS").as_deref() == Ok("1") {
        eprintln!("GPU test skipped: LIGHTPICK_SKIP_GPU_TESTS=1");
        return None;
    }
    let context = CONTEXT.get_or_init(|| {
        let ctx = GpuContext::new().map_err(|e| e.to_string())?;
        eprintln!("GPU tests run on {}", ctx.description());
        Ok(ctx)
    });
    match context {
        Ok(ctx) => Some(ctx),
        Err(e) => panic!(
            "no GPU context for the GPU tests: {e}\n\
             (install mesa-vulkan-drivers for lavapipe, or set LIGHTPICK_SKIP_GPU_TESTS=1 to skip)"
        ),
    }
}

/// `SplitMix64`: a tiny deterministic generator for test inputs (not the code under test).
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform `f64` in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform `f64` in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}
