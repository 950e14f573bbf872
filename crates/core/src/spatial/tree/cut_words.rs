//! Reading one tile's cut in the words it is kept in (`TileCuts`' module docs): the entry a
//! draw takes, and the lines that pick will read, asked for ahead.
//!
//! A tile's words are its column count `K` (0 when no entry has power), the `K` alias
//! columns (threshold `t_c` in the low `log2 C` bits, alias `a_c` above them, `C = 2^24/K`),
//! then per entry its mass `m_e` and its child word.

use super::cut_columns::alias_pick;
use super::node::ChildRef;
use super::prefetch::prefetch;

/// The fewest alias columns of a tile's cut whose picks ask for their lines ahead
/// ([`prefetch_pick`]): 64 columns and their entries are 1.5 kB. At 128 the cuts of
/// `million` (64 entries) took no hints, and its passes of one sample a pixel were 8 %
/// slower a sample than at 64.
const PREFETCH_MIN_COLUMNS: u32 = 64;

/// The entry of a tile's cut `words` that the 24-bit draw `u` takes through its alias
/// columns, with its mass (`m_e / 2^24` is the probability of taking it, exactly); `None`
/// when no entry of the tile has power.
#[inline]
pub(super) fn pick_in(words: &[u32], u: u32) -> Option<(ChildRef, u32)> {
    let k = words[0];
    if k == 0 {
        return None;
    }
    let shift = 24 - k.trailing_zeros();
    let e = alias_pick(&words[1..], shift, u);
    let pair = 1 + k as usize + 2 * e;
    Some((ChildRef::from_bits(words[pair + 1]), words[pair]))
}

/// Asks for the cache lines [`pick_in`] reads for the draw `u` in a tile's cut `words` of at
/// least [`PREFETCH_MIN_COLUMNS`] columns: the draw's alias column and the pair of the
/// column's own entry (its alias's pair is known only once the column is read). The cut's
/// first word, which every pick of the tile reads, is read here.
#[inline]
pub(super) fn prefetch_pick(words: &[u32], u: u32) {
    let k = words[0];
    if k < PREFETCH_MIN_COLUMNS {
        return;
    }
    let column = (u >> (24 - k.trailing_zeros())) as usize;
    if let Some(word) = words.get(1 + column) {
        prefetch(word);
    }
    if let Some(pair) = words.get(1 + k as usize + 2 * column) {
        prefetch(pair);
    }
}
