//! What the machine itself allows a table, measured beside it: the time of an independent
//! random read of a table-sized buffer (the floor under a batched pick), and the page
//! faults an operation takes (what a fresh buffer costs before it is written).

use std::hint::black_box;
use std::time::Instant;

use lightpick_core::PackedAliasEntry;

/// Nanoseconds per independent random read of `entries` on one thread: the median of
/// `repetitions` passes of `reads` loads at positions `⌊h·N/2^32⌋`, `h` a multiplicative
/// hash of the read's index (a multiply, a shift and a xor: what the positions cost is
/// small beside a cache miss). Each block of 256 positions is computed first and then read
/// into a small array in a loop of loads and nothing else, the way a batched pick gathers
/// its entries, so the reads overlap as far as the machine allows. A batched pick reads one
/// such entry at a random position, so it cannot be faster than this.
pub fn random_read_ns(entries: &[PackedAliasEntry], reads: u32, repetitions: usize) -> f64 {
    const BLOCK: u32 = 256;
    let n = entries.len() as u64;
    let mut at = [0u32; BLOCK as usize];
    let mut read = [PackedAliasEntry::default(); BLOCK as usize];
    let mut times: Vec<f64> = (0..repetitions.max(1))
        .map(|rep| {
            let salt = (rep as u32).wrapping_mul(0x85EB_CA6B);
            let start = Instant::now();
            for block in 0..reads.div_ceil(BLOCK) {
                for (k, a) in (block * BLOCK..).zip(at.iter_mut()) {
                    let h = (k ^ salt).wrapping_mul(0x9E37_79B9);
                    *a = ((u64::from(h ^ (h >> 15)) * n) >> 32) as u32;
                }
                for (r, &a) in read.iter_mut().zip(&at) {
                    *r = entries[a as usize];
                }
                black_box(&read);
            }
            start.elapsed().as_secs_f64() * 1e9 / f64::from(reads.div_ceil(BLOCK) * BLOCK)
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The process's minor page faults so far (`/proc/self/stat`, field 10), or `None` where
/// that file does not exist (not Linux).
pub fn minor_faults() -> Option<u64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it.
    let rest = &stat[stat.rfind(')')? + 1..];
    rest.split_whitespace().nth(7)?.parse().ok()
}

/// Minor page faults per call of `f`, over `calls` calls (`None` without `/proc`).
pub fn faults_per_call<T>(calls: usize, mut f: impl FnMut() -> T) -> Option<f64> {
    let before = minor_faults()?;
    for _ in 0..calls {
        black_box(f());
    }
    let after = minor_faults()?;
    Some((after - before) as f64 / calls.max(1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fresh_buffer_faults_and_reads_take_time() {
        let entries = vec![PackedAliasEntry::default(); 1 << 12];
        let ns = random_read_ns(&entries, 1 << 12, 3);
        assert!(ns > 0.0 && ns.is_finite(), "{ns}");
        if let Some(faults) = faults_per_call(1, || {
            // 64 MiB, written: its pages fault in as they are touched.
            let mut v = vec![0u8; 64 << 20];
            for page in v.chunks_mut(4096) {
                page[0] = 1;
            }
            v.len()
        }) {
            // 16 384 pages of 4 KiB (fewer if the kernel gives huge pages).
            assert!(faults >= 32.0, "{faults}");
        }
    }
}
