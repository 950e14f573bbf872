//! What the machine's memory allows, beside the tables' figures: the copy bandwidth's floor
//! under a table build (`16·N` bytes at least, see [`super::bandwidth`]), and the
//! random-read floor under a batched pick (`alias-batch`) with the builds' page faults.

use std::fmt::Write as _;

use serde_json::json;

use super::bandwidth::{BUILD_BYTES_PER_LIGHT, Bandwidth};
use super::case::Case;

/// The memory figures of one run.
pub(super) struct MemoryFloors {
    /// The copy bandwidth of one thread.
    pub(super) bandwidth: Bandwidth,
    /// The table sizes timed.
    pub(super) sizes: Vec<usize>,
    /// Per size, nanoseconds per random read of the table's entries.
    pub(super) read_floors: Vec<(usize, f64)>,
}

impl MemoryFloors {
    /// Measures the copy bandwidth (256 MiB buffers, 64 MiB in `--quick`: far beyond the
    /// caches) beside the random-read floors measured with the tables.
    pub(super) fn measure(quick: bool, sizes: Vec<usize>, read_floors: Vec<(usize, f64)>) -> Self {
        Self {
            bandwidth: Bandwidth::measure(if quick { 64 << 20 } else { 256 << 20 }, 5),
            sizes,
            read_floors,
        }
    }

    /// `"memory_bandwidth"` of the JSON: the bandwidth, the build floors, and the
    /// random-read floors with `alias-batch`'s pick over them.
    pub(super) fn json(&self, cases: &[Case]) -> serde_json::Value {
        let bandwidth = &self.bandwidth;
        let floors: Vec<serde_json::Value> = self
            .sizes
            .iter()
            .map(|&n| json!({ "n": n, "build_floor_ns": bandwidth.build_floor_ns(n) }))
            .collect();
        let read_floors: Vec<serde_json::Value> = self
            .read_floors
            .iter()
            .map(|&(n, ns)| {
                let batch = batch_case(cases, n).map(|c| c.sample_ns / ns);
                json!({ "n": n, "random_read_ns": ns, "batch_over_random_read": batch })
            })
            .collect();
        json!({
            "copy_gb_per_s": bandwidth.copy_gb_per_s,
            "buffer_bytes": bandwidth.buffer_bytes,
            "build_bytes_per_light": BUILD_BYTES_PER_LIGHT,
            "build_floors": floors,
            "random_read_floors": read_floors,
        })
    }

    /// The bandwidth and the build floor per size, then [`MemoryFloors::read_floor_text`].
    pub(super) fn text(&self, cases: &[Case]) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "\nmemory: copy {:.1} GB/s (read + write, one thread); a table build moves at \
             least {BUILD_BYTES_PER_LIGHT} bytes per light, so no build is faster than:",
            self.bandwidth.copy_gb_per_s
        );
        for &n in &self.sizes {
            let _ = writeln!(
                out,
                "{n:>9}  {:.3} ms",
                self.bandwidth.build_floor_ns(n) / 1e6
            );
        }
        out.push_str(&self.read_floor_text(cases));
        out
    }

    /// The random-read floor beside the batched pick, and the page faults of the builds.
    fn read_floor_text(&self, cases: &[Case]) -> String {
        let mut out = String::from(
            "\nrandom reads of the table's entries (8 bytes at hashed positions, one thread), \
             beside alias-batch's pick:\n",
        );
        for &(n, ns) in &self.read_floors {
            let batch = batch_case(cases, n).map_or(f64::NAN, |c| c.sample_ns);
            let _ = writeln!(
                out,
                "{n:>9}  {ns:.2} ns per read; alias-batch {batch:.2} ns per pick ({:.2}× the floor)",
                batch / ns
            );
        }
        out.push_str("minor page faults per build / rebuild:\n");
        for c in cases.iter().filter(|c| c.build_faults.is_some()) {
            let rebuild = c
                .rebuild_faults
                .map_or_else(|| "-".to_owned(), |f| format!("{f:.0}"));
            let _ = writeln!(
                out,
                "{:>9}  {:<31} {:>9.0} / {rebuild}",
                c.n,
                c.method,
                c.build_faults.unwrap_or(f64::NAN)
            );
        }
        out.push_str("heap bytes per light of the light trees (without tile cuts):\n");
        for c in cases {
            if let Some(bytes) = c.bytes_per_light {
                let _ = writeln!(out, "{:>9}  {:<31} {bytes:>9.1}", c.n, c.method);
            }
        }
        out
    }
}

/// The `alias-batch` case at `n` lights.
fn batch_case(cases: &[Case], n: usize) -> Option<&Case> {
    cases.iter().find(|c| c.n == n && c.method == "alias-batch")
}
