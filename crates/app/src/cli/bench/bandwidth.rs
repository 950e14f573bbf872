//! The bound this machine's memory bandwidth puts on building a table: a build must at
//! least read every power (8 bytes) and write every packed entry (8 bytes), so no build of
//! `N` lights beats `16·N` bytes over the copy bandwidth.

use std::hint::black_box;
use std::time::Instant;

use serde::Serialize;

/// Bytes a table build must move per light: read one `f64` power, write one 8-byte entry.
pub const BUILD_BYTES_PER_LIGHT: f64 = 16.0;

/// The measured bandwidth and what it allows.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Bandwidth {
    /// Bytes read plus bytes written per second by `copy_from_slice` of a buffer far larger
    /// than the caches (the fastest of several copies), in GB/s (`10^9`).
    pub copy_gb_per_s: f64,
    /// Bytes of each buffer.
    pub buffer_bytes: usize,
}

impl Bandwidth {
    /// Measures the copy bandwidth of one thread on buffers of `bytes` each (the fastest of
    /// `repetitions` copies, after one untimed copy that faults the pages in).
    pub fn measure(bytes: usize, repetitions: usize) -> Self {
        let len = bytes / 8;
        let source: Vec<u64> = (0..len as u64).collect();
        let mut target = vec![0u64; len];
        target.copy_from_slice(&source);
        let fastest = (0..repetitions.max(1))
            .map(|_| {
                let start = Instant::now();
                target.copy_from_slice(black_box(&source));
                black_box(&target);
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min);
        Self {
            copy_gb_per_s: (2 * len * 8) as f64 / fastest / 1e9,
            buffer_bytes: len * 8,
        }
    }

    /// The fewest nanoseconds a build of `n` lights can take at this bandwidth:
    /// `16·n` bytes over the copy rate.
    pub fn build_floor_ns(self, n: usize) -> f64 {
        BUILD_BYTES_PER_LIGHT * n as f64 / self.copy_gb_per_s
    }
}

#[cfg(test)]
mod tests {
    use super::Bandwidth;

    #[test]
    fn the_floor_scales_with_the_lights() {
        let b = Bandwidth {
            copy_gb_per_s: 16.0,
            buffer_bytes: 1,
        };
        // 16 bytes per light at 16 bytes per ns: one ns per light.
        assert_eq!(b.build_floor_ns(1_000_000), 1_000_000.0);
        let measured = Bandwidth::measure(1 << 20, 2);
        assert!(measured.copy_gb_per_s > 0.0 && measured.copy_gb_per_s.is_finite());
    }
}
