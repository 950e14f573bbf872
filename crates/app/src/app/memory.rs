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
            (
                "CPU lanes: light profiles (positions and powers are the scene's)",
                cpu.lights,
            ),
            ("CPU lanes: pixel sums, reference", cpu.pixels),
            ("GPU lanes: lights, tree", gpu.lights),
            ("GPU lanes: pixel sums, outputs, reference", gpu.pixels),
        ]);
        parts
    }
}

/// Seconds after the scene or the renderer changed at which the allocator's free pages are
/// given back: once the new table, tree and lanes are in place, and again once the
/// slower workers (the exact reference of a large scene) have finished and freed theirs.
const TRIM_AFTER_S: [f64; 2] = [3.0, 15.0];

/// Gives the memory freed after a scene or renderer change back to the system.
///
/// Loading a large scene allocates far more than it keeps: the light tree's build, the
/// uploads and the reference each hold `O(N)` scratch for a moment, on worker threads whose
/// allocator arenas keep the freed pages (about 30 bytes per light at `10^6` lights on
/// glibc). [`Trim::frame`] asks the allocator to return them a few seconds after the
/// scene generation or the renderer changed, twice ([`TRIM_AFTER_S`]); nothing else.
#[derive(Debug, Default)]
pub(crate) struct Trim {
    /// The scene generation and renderer last seen, and when they changed.
    seen: Option<((u64, bool), std::time::Instant)>,
    /// How many of the trims after that change are done.
    done: usize,
}

impl Trim {
    /// Called once per frame with the scene generation, whether the GPU renders, and whether
    /// a table is still being built (then the trim waits).
    pub(crate) fn frame(&mut self, generation: u64, gpu: bool, building: bool) {
        let now = std::time::Instant::now();
        let key = (generation, gpu);
        match self.seen {
            Some((seen, _)) if seen == key => {}
            _ => {
                self.seen = Some((key, now));
                self.done = 0;
            }
        }
        let Some((_, since)) = self.seen else {
            return;
        };
        let due = TRIM_AFTER_S
            .get(self.done)
            .is_some_and(|&s| (now - since).as_secs_f64() >= s);
        if due && !building {
            self.done += 1;
            release_free_memory();
        }
    }
}

/// Returns the allocator's free pages to the system (glibc's `malloc_trim(0)`, every arena);
/// elsewhere nothing.
fn release_free_memory() {
    // The one foreign call of the app: glibc keeps freed pages otherwise.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[allow(unsafe_code)]
    {
        unsafe extern "C" {
            /// glibc: releases free memory at the top of the heap and, since 2.8, free
            /// pages inside every arena; returns 1 when some memory was released.
            fn malloc_trim(pad: usize) -> std::ffi::c_int;
        }
        // SAFETY: `malloc_trim` only returns pages of free chunks to the kernel; it takes
        // the arenas' locks itself and touches no memory the program holds.
        unsafe {
            malloc_trim(0);
        }
    }
}
