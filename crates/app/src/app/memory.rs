//! Where the app's bytes go: [`AppState::memory_by_part`](super::state::AppState) and what
//! the renderers hold beside it, by part, from capacities and uploaded sizes (see the
//! README's table of bytes per light).

use super::LightpickApp;
use super::engine::RendererBytes;

impl LightpickApp {
    /// The heap bytes each part of the app holds: the state's parts
    /// ([`super::state::AppState::memory_by_part`]), then the CPU engine's lanes and the GPU
    /// lanes, each split into what grows with the lights and what grows with the pixels. GPU
    /// lanes count device bytes (in the process on a software device such as lavapipe).
    pub fn memory_by_part(&self) -> Vec<(&'static str, usize)> {
        let mut parts = self.state.memory_by_part();
        let cpu = self
            .engine
            .as_ref()
            .map_or_else(RendererBytes::default, super::engine::Engine::bytes);
        let gpu = self
            .gpu
            .as_ref()
            .map_or_else(RendererBytes::default, super::gpu_images::GpuImages::bytes);
        parts.extend([
            ("CPU lanes: light records", cpu.lights),
            ("CPU lanes: pixel sums, reference", cpu.pixels),
            ("GPU lanes: lights, tree", gpu.lights),
            ("GPU lanes: pixel sums, outputs, reference", gpu.pixels),
        ]);
        parts
    }
}
