//! `--device cpu|gpu` and the choice made when it is left out.

use anyhow::anyhow;
use clap::ValueEnum;
use lightpick_core::gpu::GpuContext;

/// Where samples are drawn or images rendered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Device {
    /// The CPU (rayon).
    Cpu,
    /// The GPU (wgpu compute), bit-identical picks to the CPU.
    Gpu,
}

impl Device {
    /// The device's command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Device::Cpu => "cpu",
            Device::Gpu => "gpu",
        }
    }
}

/// Resolves `--device`: an explicit `gpu` without an adapter is an error (no silent
/// fallback); an explicit `cpu` opens nothing; no choice takes the GPU when an adapter exists
/// and otherwise falls back to the CPU with a one-line notice on stderr.
pub fn choose(
    requested: Option<Device>,
    gpu_supported: bool,
) -> anyhow::Result<Option<GpuContext>> {
    match requested {
        Some(Device::Cpu) => Ok(None),
        Some(Device::Gpu) => GpuContext::new()
            .map(Some)
            .map_err(|e| anyhow!("--device gpu: {e}")),
        None if !gpu_supported => Ok(None),
        None => match GpuContext::new() {
            Ok(ctx) => Ok(Some(ctx)),
            Err(e) => {
                eprintln!("notice: no GPU adapter ({e}); using the CPU");
                Ok(None)
            }
        },
    }
}
