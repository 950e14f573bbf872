//! A tile's alias columns: Walker's alias method on the `2^24` grid of the tree's draws,
//! built in integers so that each entry of a cut is taken for exactly its mass (the module
//! docs of [`super::tile_cut`]).

use crate::spatial::importance::GRID;

/// The most entries a cut may have. A column word holds its threshold `t_c < C` in the
/// low `log2 C` bits and its alias `a_c < K` above them: `t_c | a_c·C < K·C = 2^24`, so
/// any `K` fits; a full column (`t_c = C`) is its own alias and keeps 0 there, every cell
/// taking the column's entry either way. The limit is what a tile's cut may cost, not the
/// word.
pub(super) const MOST_ENTRIES: usize = 1 << 10;

/// The entry column `column` of a cut whose columns are `C = 2^shift` cells wide takes for
/// the draw `u < 2^24`: its own below the threshold, its alias from there on.
#[inline]
pub(super) fn alias_pick(columns: &[u32], shift: u32, u: u32) -> usize {
    let column = (u >> shift) as usize;
    let word = columns[column];
    let cells = (1 << shift) - 1;
    if u & cells < word & cells {
        column
    } else {
        (word >> shift) as usize
    }
}

/// The alias columns of the masses `masses` (summing to `2^24`, at most [`MOST_ENTRIES`]):
/// `K = n.next_power_of_two()` words appended to `out` (module docs), built in integers so
/// that entry `e` owns exactly `m_e` cells.
pub(super) fn alias_columns_into(masses: &[u32], work: &mut AliasWork, out: &mut Vec<u32>) {
    let k = masses.len().next_power_of_two();
    let width = GRID / k as u32;
    let shift = width.trailing_zeros();
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
        out[start + s] = own | (l as u32) << shift;
        left[l] -= width - own;
        if left[l] < width {
            large.pop();
            small.push(l);
        }
    }
    // What is left holds exactly a column each (the masses sum to K·C).
    for &i in large.iter().chain(small.iter()) {
        debug_assert_eq!(left[i], width, "alias columns: a column left unfilled");
        out[start + i] = (i as u32) << shift;
    }
}

/// What building one tile's alias columns works in.
#[derive(Default)]
pub(super) struct AliasWork {
    left: Vec<u32>,
    small: Vec<usize>,
    large: Vec<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Masses of `n` entries summing to `2^24`, uneven (from a hash), each at least 1.
    fn masses(n: usize, salt: u32) -> Vec<u32> {
        let raw: Vec<u64> = (0..n as u32)
            .map(|i| u64::from(crate::pcg_hash(i ^ salt.rotate_left(16)) % 1000 + 1))
            .collect();
        let sum: u64 = raw.iter().sum();
        let mut m: Vec<u32> = raw
            .iter()
            .map(|&r| ((r * u64::from(GRID)) / sum).max(1) as u32)
            .collect();
        let placed: u32 = m.iter().sum();
        m[0] += GRID - placed;
        m
    }

    #[test]
    fn every_draw_counted_gives_each_entry_exactly_its_mass() {
        // Brute force over all 2^24 draws, at counts from one entry (its one column full,
        // `C = 2^24`) through empty columns (3, 129) to the most a cut may hold.
        let mut work = AliasWork::default();
        for (n, salt) in [(1, 1), (3, 2), (129, 3), (MOST_ENTRIES, 4)] {
            let m = masses(n, salt);
            let mut words = Vec::new();
            alias_columns_into(&m, &mut work, &mut words);
            let k = n.next_power_of_two();
            assert_eq!(words.len(), k);
            let shift = (GRID / k as u32).trailing_zeros();
            let mut counts = vec![0u32; k];
            for u in 0..GRID {
                counts[alias_pick(&words, shift, u)] += 1;
            }
            assert_eq!(&counts[..n], &m[..], "{n} entries");
            assert!(counts[n..].iter().all(|&c| c == 0), "{n} entries");
        }
    }
}
