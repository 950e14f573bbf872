//! One GPU context per test binary, for the `gpu_*` tests.
//!
//! A GPU test FAILS when no adapter is found, unless `LIGHTPICK_SKIP_GPU_TESTS=1` is set, in
//! which case it prints that it was skipped and passes. On a machine without a GPU, Mesa's
//! lavapipe (package `mesa-vulkan-drivers`) provides a Vulkan adapter on the CPU.

use std::sync::OnceLock;

use lightpick_core::gpu::GpuContext;

/// The shared context, or `None` when GPU tests are skipped on purpose; panics (fails the
/// test) when no adapter can be had.
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
