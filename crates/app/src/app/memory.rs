//! Where the app's bytes go: [`AppState::memory_by_part`](super::state::AppState) and what
//! the renderers hold beside it, by part, from capacities and uploaded sizes (see the
//! table of bytes per light in docs/numbers.md).

use super::LightpickApp;
use super::images::{Engine, GpuImages, RendererBytes};

impl LightpickApp {
    /// The heap bytes each part of the app holds: the state's parts
    /// ([`super::state::AppState::memory_by_part`]), then the CPU engine's runs and the GPU
    /// runs, each split into what grows with the lights and what grows with the pixels. GPU
    /// runs count device bytes (in the process on a software device such as lavapipe).
    pub fn memory_by_part(&self) -> Vec<(&'static str, usize)> {
        let mut parts = self.state.memory_by_part();
        let cpu = self
            .engine
            .as_ref()
            .map_or_else(RendererBytes::default, Engine::bytes);
        let gpu = self
            .gpu
            .as_ref()
            .map_or_else(RendererBytes::default, GpuImages::bytes);
        parts.extend([
            (
                "CPU runs: light profiles (positions and powers are the scene's)",
                cpu.lights,
            ),
            ("CPU runs: pixel sums, reference", cpu.pixels),
            ("GPU runs: lights, tree", gpu.lights),
            ("GPU runs: pixel sums, outputs, reference", gpu.pixels),
        ]);
        parts
    }
}

/// Seconds after the scene or the renderer changed at which the allocator's free pages are
/// given back: once the new table, tree and runs are in place, and again as the slower
/// workers finish and free their scratch (the exact reference of a large scene takes a
/// minute or more on two cores).
const TRIM_AFTER_S: [f64; 4] = [3.0, 15.0, 60.0, 180.0];

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

/// Allocations of at least this many bytes get their own mappings ([`map_large_allocations`]).
const MMAP_THRESHOLD_BYTES: std::ffi::c_int = 128 << 10;

/// Makes glibc map every allocation of 128 KiB or more on its own, and unmap it when it is
/// freed (`mallopt(M_MMAP_THRESHOLD, 128 KiB)`: glibc's initial threshold, kept fixed);
/// elsewhere nothing.
///
/// glibc's default threshold is dynamic: after the first large block is freed (the light
/// tree's 32-byte-per-light build scratch at `10^6` lights) it rises to that block's size,
/// so the next per-light arrays are carved from the heap arenas, and whatever of them is
/// freed stays resident beside small live blocks that `malloc_trim` cannot return. Measured
/// on the running app (10^6 lights, CPU images): 115 bytes per light above the worked example
/// by RSS against 97 by the accounting with the default; 93 with the threshold kept at
/// 128 KiB (100 at 1 MiB). The cost is a `mmap`/`munmap` and fresh pages per such
/// allocation: a few per frame (the images' pixel buffers, 256 KiB at 256×256).
pub(crate) fn map_large_allocations() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[allow(unsafe_code)]
    {
        // SAFETY: `mallopt` only changes the allocator's policy for later allocations; it
        // takes the allocator's lock itself and touches no memory the program holds.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES);
        }
    }
}

/// Returns the allocator's free pages to the system (glibc's `malloc_trim(0)`, every arena);
/// elsewhere nothing.
fn release_free_memory() {
    // With `mallopt` above, the app's two foreign calls: glibc keeps freed pages otherwise.
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[allow(unsafe_code)]
    {
        // SAFETY: `malloc_trim` only returns pages of free chunks to the kernel; it takes
        // the arenas' locks itself and touches no memory the program holds.
        unsafe {
            libc::malloc_trim(0);
        }
    }
}
