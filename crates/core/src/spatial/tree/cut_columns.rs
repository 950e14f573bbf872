//! A tile's alias columns: Walker's alias method on the `2^24` grid of the tree's draws,
//! built in integers so that each entry of a cut is taken for exactly its mass (the module
//! docs of [`super::tile_cut`]).

use crate::spatial::importance::GRID;

/// Bits of a column word below its alias: the threshold `t_c ≤ 2^24`.
const THRESHOLD_BITS: u32 = 25;

/// The most entries a cut may have: an alias fits the 7 bits above the threshold.
pub(super) const MOST_ENTRIES: usize = 1 << (32 - THRESHOLD_BITS);

/// The entry column `column` of a cut whose columns are `C = 2^shift` cells wide takes for
/// the draw `u < 2^24`: its own below the threshold, its alias from there on.
#[inline]
pub(super) fn alias_pick(columns: &[u32], shift: u32, u: u32) -> usize {
    let column = (u >> shift) as usize;
    let word = columns[column];
    let cell = u & ((1 << shift) - 1);
    if cell < word & ((1 << THRESHOLD_BITS) - 1) {
        column
    } else {
        (word >> THRESHOLD_BITS) as usize
    }
}

/// The alias columns of the masses `masses` (summing to `2^24`, at most [`MOST_ENTRIES`]):
/// `K = n.next_power_of_two()` words appended to `out` (module docs), built in integers so
/// that entry `e` owns exactly `m_e` cells.
pub(super) fn alias_columns_into(masses: &[u32], work: &mut AliasWork, out: &mut Vec<u32>) {
    let k = masses.len().next_power_of_two();
    let width = GRID / k as u32;
    let start = out.len();
    out.resize(start + k, 0);
    let AliasWork { left, small, large } = work;
    // Cells each column still has to place; the empty columns past `n` are small.
    left.clear();
    left.extend((0..k).map(|i| masses.get(i).copied().unwrap_or(0)));
    small.clear();
    large.clear();
    for (i, &m) in left.iter().enumerate() {
        if m < width {
            small.push(i);
        } else {
            large.push(i);
        }
    }
    while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
        small.pop();
        let own = left[s];
        out[start + s] = own | (l as u32) << THRESHOLD_BITS;
        left[l] -= width - own;
        if left[l] < width {
            large.pop();
            small.push(l);
        }
    }
    // What is left holds exactly a column each (the masses sum to K·C).
    for &i in large.iter().chain(small.iter()) {
        debug_assert_eq!(left[i], width, "alias columns: a column left unfilled");
        out[start + i] = width | (i as u32) << THRESHOLD_BITS;
    }
}

/// What building one tile's alias columns works in.
#[derive(Default)]
pub(super) struct AliasWork {
    left: Vec<u32>,
    small: Vec<usize>,
    large: Vec<usize>,
}
