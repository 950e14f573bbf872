//! Batched sampling: many picks into a caller's slice, the same picks as one at a time.
//!
//! A block of picks first draws all its randoms ([`Rng::fill`], whose lanes break the
//! generator's dependency chain), then maps the column draws with the multiply-high, and
//! only then reads the table: the reads are independent, so the processor overlaps their
//! cache misses instead of waiting for each (memory-level parallelism), and the keep test
//! is a select, not a branch. Lemire's rejection (probability `(2^32 mod N)/2^32` per
//! column draw) shifts the stream by one draw: the block stops at the first rejected draw,
//! that pick is made one at a time, and the next block starts from there, so the picks and
//! the generator's final position are exactly those of repeated [`AliasTable::sample`].

use super::{AliasTable, PackedAliasEntry};
use crate::rng::Rng;

/// Picks per block: the draws (8 KiB) and columns stay in L1.
const BLOCK: usize = 512;

impl AliasTable {
    /// Fills `out` with `out.len()` picks: exactly the lights, in order, that as many calls
    /// of [`AliasTable::sample`] would return on `rng`, leaving `rng` where they would (so
    /// CPU == GPU still holds pick for pick). Faster per pick than the one-at-a-time path
    /// on large tables, where each pick's table read misses the cache.
    pub fn sample_into(&self, out: &mut [u32], rng: &mut Rng) {
        let n = self.words.len() as u64;
        let reject_below = self.columns.rejection_threshold();
        let mut draws = [0u32; 2 * BLOCK];
        let mut columns = [0u32; BLOCK];
        let mut rest = out;
        while !rest.is_empty() {
            let block = rest.len().min(BLOCK);
            let mut ahead = rng.clone();
            ahead.fill(&mut draws[..2 * block]);
            // Columns up to the first rejected column draw (the block's end if none).
            let mut accepted = block;
            for (k, column) in columns[..block].iter_mut().enumerate() {
                let m = u64::from(draws[2 * k]) * n;
                *column = (m >> 32) as u32;
                if (m as u32) < reject_below {
                    accepted = k;
                    break;
                }
            }
            let (done, later) = rest.split_at_mut(accepted);
            for ((pick, &column), keep) in done
                .iter_mut()
                .zip(&columns[..accepted])
                .zip(draws[1..].iter().step_by(2))
            {
                let entry: PackedAliasEntry = bytemuck::cast(self.words[column as usize]);
                *pick = if *keep < entry.threshold {
                    column
                } else {
                    entry.alias
                };
            }
            if accepted == block {
                *rng = ahead;
                rest = later;
            } else {
                rng.advance(2 * accepted as u64);
                // The rejected pick, one at a time (it redraws its column).
                later[0] = self.sample(rng);
                rest = &mut later[1..];
            }
        }
    }
}
