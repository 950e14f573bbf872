//! Batched sampling: many picks into a caller's slice, the same picks as one at a time.
//!
//! A block of picks runs in four branch-free passes over small arrays that stay in L1:
//! 1. **draws**: the block's column draws and keep draws at once ([`Rng::fill_pairs`]:
//!    sixteen independent hash lanes, the even draws in one array, the odd in another);
//! 2. **columns**: the multiply-high `⌊r·N/2^32⌋` of every column draw, and whether any
//!    draw falls in Lemire's rejection band;
//! 3. **gather**: the table entry of every column, a loop of independent loads and nothing
//!    else, so the processor keeps as many cache misses in flight as it can (what a
//!    software prefetch would buy);
//! 4. **select**: keep the column if its keep draw is below the threshold, else take the
//!    alias (a select, not a branch).
//!
//! The four passes are plain loops; on x86-64 processors with AVX2 (checked at run time)
//! the same code is compiled a second time for AVX2, where the hashes vectorize (eight
//! lanes, with per-lane shifts that SSE2 lacks): about ten times fewer cycles per draw.
//!
//! Lemire's rejection (probability `(2^32 mod N)/2^32` per column draw) shifts the stream
//! by one draw: the block stops at the first rejected draw, that pick is made one at a
//! time, and the next block starts from there, so the picks and the generator's final
//! position are exactly those of repeated [`AliasTable::sample`].

use super::AliasTable;
use super::packed::PackedAliasEntry;
use crate::rng::Rng;

/// Picks per block: its draws, columns and entries (16 bytes per pick) stay in L1.
const BLOCK: usize = 256;

/// One block's working arrays.
struct Block {
    column_draws: [u32; BLOCK],
    keep_draws: [u32; BLOCK],
    columns: [u32; BLOCK],
    entries: [u64; BLOCK],
}

impl AliasTable {
    /// Fills `out` with `out.len()` picks: exactly the lights, in order, that as many calls
    /// of [`AliasTable::sample`] would return on `rng`, leaving `rng` where they would (so
    /// CPU == GPU still holds pick for pick). Faster per pick than the one-at-a-time path:
    /// the randoms are drawn in lanes, the table reads overlap their cache misses, and no
    /// step branches on a random.
    pub fn sample_into(&self, out: &mut [u32], rng: &mut Rng) {
        self.sample_into_by(out, rng, Self::pick_block_fastest);
    }

    /// [`AliasTable::sample_into`] on the portable instance of the block passes, whatever
    /// the processor has: the tests compare it with the AVX2 one.
    #[cfg(test)]
    pub(crate) fn sample_into_portable(&self, out: &mut [u32], rng: &mut Rng) {
        self.sample_into_by(out, rng, Self::pick_block);
    }

    /// [`AliasTable::sample_into`] with `pick` filling each block.
    #[inline]
    fn sample_into_by(
        &self,
        out: &mut [u32],
        rng: &mut Rng,
        pick: impl Fn(&Self, &mut Block, &mut [u32], &mut Rng) -> usize,
    ) {
        let mut block = Block {
            column_draws: [0; BLOCK],
            keep_draws: [0; BLOCK],
            columns: [0; BLOCK],
            entries: [0; BLOCK],
        };
        let mut rest = out;
        while !rest.is_empty() {
            let len = rest.len().min(BLOCK);
            let mut ahead = rng.clone();
            let accepted = pick(self, &mut block, &mut rest[..len], &mut ahead);
            let later = &mut rest[accepted..];
            if accepted == len {
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

    /// [`AliasTable::pick_block`] compiled for AVX2 where the processor has it.
    #[allow(unsafe_code)]
    fn pick_block_fastest(&self, block: &mut Block, out: &mut [u32], ahead: &mut Rng) -> usize {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, checked just above.
            return unsafe { self.pick_block_avx2(block, out, ahead) };
        }
        self.pick_block(block, out, ahead)
    }

    /// [`AliasTable::pick_block`] with AVX2 enabled (the same picks, bit for bit: integer
    /// arithmetic only).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn pick_block_avx2(&self, block: &mut Block, out: &mut [u32], ahead: &mut Rng) -> usize {
        self.pick_block(block, out, ahead)
    }

    /// Fills `out` (at most [`BLOCK`] picks) up to the first pick whose column draw is
    /// rejected, drawing from `ahead`; returns how many picks were made (`out.len()` if no
    /// draw was rejected, and then `ahead` is after the block's draws).
    #[inline(always)]
    #[allow(
        clippy::inline_always,
        reason = "compiled into the AVX2 instance too, where its loops widen"
    )]
    fn pick_block(&self, block: &mut Block, out: &mut [u32], ahead: &mut Rng) -> usize {
        let len = out.len();
        let n = self.words.len() as u64;
        let reject_below = self.columns.rejection_threshold();
        let (draws, keeps) = (&mut block.column_draws[..len], &mut block.keep_draws[..len]);
        ahead.fill_pairs(draws, keeps);
        let mut rejected = false;
        for (column, &r) in block.columns[..len].iter_mut().zip(draws.iter()) {
            let m = u64::from(r) * n;
            *column = (m >> 32) as u32;
            rejected |= (m as u32) < reject_below;
        }
        let accepted = if rejected {
            draws
                .iter()
                .position(|&r| ((u64::from(r) * n) as u32) < reject_below)
                .unwrap_or(len)
        } else {
            len
        };
        let columns = &block.columns[..accepted];
        let entries = &mut block.entries[..accepted];
        for (entry, &column) in entries.iter_mut().zip(columns) {
            *entry = self.words[column as usize];
        }
        for (((pick, &column), &keep), &entry) in out[..accepted]
            .iter_mut()
            .zip(columns)
            .zip(keeps.iter())
            .zip(entries.iter())
        {
            let entry: PackedAliasEntry = bytemuck::cast(entry);
            *pick = std::hint::select_unpredictable(keep < entry.threshold, column, entry.alias);
        }
        accepted
    }
}
