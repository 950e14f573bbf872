//! The packed alias table's column: the threshold and alias as two `u32` (8 bytes), the
//! form the GPU reads and both constructions write.

/// One column of the packed alias table, as the GPU stores it (8 bytes).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
pub struct PackedAliasEntry {
    /// Keep probability of the column's own light, times `2^32` (saturating).
    pub threshold: u32,
    /// The light taken when the column is not kept.
    pub alias: u32,
}

/// `entry` as one `u64` word: its 8 bytes, as the table stores them.
#[inline]
pub(crate) fn packed_word(threshold: u32, alias: u32) -> u64 {
    bytemuck::cast(PackedAliasEntry { threshold, alias })
}
