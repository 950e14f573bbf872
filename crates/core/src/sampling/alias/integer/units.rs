//! The integer construction's units: a column's capacity `C = 2^32`, the reachability
//! flag, the chunk every pass works on, and the packed words it writes.

use crate::alias::packed::packed_word;

/// One column's capacity, `C = 2^32`.
pub(super) const CAPACITY: u64 = 1 << 32;
/// Marks the mass word of a positive light whose mass rounded to 0.
pub(super) const REACH_FLAG: u64 = 1 << 63;
/// The largest `N` the integer construction takes: `N·C` and the flag must fit in a `u64`.
pub(crate) const MAX_LEN: usize = (1 << 31) - 1;
/// Lights per chunk of every pass. Fixed, so no result depends on the thread count; large
/// enough that a chunk's masses (128 KiB) and lists stay in L2 while it is listed.
pub(crate) const CHUNK: usize = 1 << 14;

/// The "keep always" entry of column `i`.
#[inline]
pub(super) fn full(i: usize) -> u64 {
    packed_word(u32::MAX, i as u32)
}
