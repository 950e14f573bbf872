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

impl PackedAliasEntry {
    /// How the column's `2^32` values of the keep draw `r2` split: `t` keep its own light
    /// (`r2 < t`), `2^32 − t` go to its alias.
    #[inline]
    pub(crate) fn masses(self) -> (u64, u64) {
        let kept = u64::from(self.threshold);
        (kept, (1u64 << 32) - kept)
    }
}

/// `entry` as one `u64` word: its 8 bytes, as the table stores them.
#[inline]
pub(crate) fn packed_word(threshold: u32, alias: u32) -> u64 {
    bytemuck::cast(PackedAliasEntry { threshold, alias })
}
