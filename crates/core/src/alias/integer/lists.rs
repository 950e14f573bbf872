//! The small and large index lists, kept per chunk: chunk `c` (lights `c·CHUNK..`) lists
//! its small indices ascending from its front and its large ones ascending from its back
//! (the `k`-th large at `end − 1 − k`). The global lists are the chunks' lists in order;
//! cursors walk them across chunks, and prefix sums over the chunks locate any ordinal.

use super::quantize::exclusive_prefix;
use super::{CAPACITY, CHUNK, REACH_FLAG};

/// One chunk's lists: how many small and large lights, the deficit `Σ (C − m)` of its
/// small ones, the excess `Σ (m − C)` of its large ones, and `Σ m`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ChunkLists {
    pub(super) small: usize,
    pub(super) deficit: u64,
    pub(super) excess: u64,
    pub(super) mass: u64,
}

impl ChunkLists {
    /// Counts mass `m` (without its flag) into the sums.
    #[inline]
    pub(super) fn add(&mut self, m: u64) {
        let small = m < CAPACITY;
        self.mass += m;
        self.deficit += if small { CAPACITY - m } else { 0 };
        self.excess += if small { 0 } else { m - CAPACITY };
    }
}

/// The small indices ascending from the front of one buffer, the large ones from the back.
pub(super) struct IndexLists<'a> {
    scratch: &'a mut [u32],
    pub(super) small: usize,
    large: usize,
}

impl<'a> IndexLists<'a> {
    pub(super) fn new(scratch: &'a mut [u32]) -> Self {
        Self {
            scratch,
            small: 0,
            large: 0,
        }
    }

    /// Lists index `i`: written to both ends, and the end it does not belong to is
    /// overwritten by a later index (the two ends never meet before the last one), so
    /// there is no branch.
    #[inline]
    pub(super) fn push(&mut self, i: usize, is_small: bool) {
        let n = self.scratch.len();
        self.scratch[self.small] = i as u32;
        self.scratch[n - 1 - self.large] = i as u32;
        self.small += usize::from(is_small);
        self.large += usize::from(!is_small);
    }
}

/// Every chunk's counts and the exclusive prefix sums over chunks (each `chunks + 1` long):
/// small and large counts (ordinals), deficits `D` and excesses `E`.
#[derive(Debug)]
pub(super) struct Lists {
    n: usize,
    pub(super) small_before: Vec<u64>,
    pub(super) large_before: Vec<u64>,
    pub(super) deficit_before: Vec<u64>,
    pub(super) excess_before: Vec<u64>,
}

impl Lists {
    pub(super) fn new(chunks: &[ChunkLists], n: usize) -> Self {
        let len = |c: usize| CHUNK.min(n - c * CHUNK) as u64;
        let small: Vec<u64> = chunks.iter().map(|c| c.small as u64).collect();
        let large: Vec<u64> = chunks
            .iter()
            .enumerate()
            .map(|(i, c)| len(i) - c.small as u64)
            .collect();
        let deficit: Vec<u64> = chunks.iter().map(|c| c.deficit).collect();
        let excess: Vec<u64> = chunks.iter().map(|c| c.excess).collect();
        Self {
            n,
            small_before: exclusive_prefix(&small),
            large_before: exclusive_prefix(&large),
            deficit_before: exclusive_prefix(&deficit),
            excess_before: exclusive_prefix(&excess),
        }
    }

    /// Number of chunks.
    pub(super) fn chunks(&self) -> usize {
        self.small_before.len() - 1
    }

    /// How many small lights `S`.
    pub(super) fn small(&self) -> u64 {
        self.small_before[self.chunks()]
    }

    /// How many large lights `L`.
    pub(super) fn large(&self) -> u64 {
        self.large_before[self.chunks()]
    }

    /// Start and end of chunk `c`'s lights.
    fn bounds(&self, c: usize) -> (usize, usize) {
        (c * CHUNK, ((c + 1) * CHUNK).min(self.n))
    }

    /// The chunk holding ordinal `k` of a list whose prefix is `before` (`k` < the total).
    fn chunk_of(before: &[u64], k: u64) -> usize {
        before.partition_point(|&b| b <= k) - 1
    }

    /// Chunk `c`'s large indices in ascending order (their positions in the buffer).
    fn large_positions(&self, c: usize) -> impl Iterator<Item = usize> {
        let (_, end) = self.bounds(c);
        let count = (self.large_before[c + 1] - self.large_before[c]) as usize;
        (end - count..end).rev()
    }

    /// How many large ordinals `t ≤ L − 2` have `E(t+1) < v`, at most `L − 1`: with
    /// `v = D(s)`, the large columns that turn before small column `s` is filled.
    pub(super) fn large_below(&self, v: u64, scratch: &[u32], masses: &[u64]) -> u64 {
        let last = self.large() - 1;
        if v == 0 {
            return 0;
        }
        // The last chunk whose excess prefix at its start is below v: the crossing is in it.
        let c = (self.excess_before.partition_point(|&e| e < v) - 1).min(self.chunks() - 1);
        let mut t = self.large_before[c];
        let mut opened = self.excess_before[c];
        for pos in self.large_positions(c) {
            opened += (masses[scratch[pos] as usize] & !REACH_FLAG) - CAPACITY;
            if opened >= v {
                break;
            }
            t += 1;
        }
        t.min(last)
    }

    /// Large ordinal `t`: its light and `E(t) = Σ_{j<t} (m_{h_j} − C)`.
    pub(super) fn large_at(&self, t: u64, scratch: &[u32], masses: &[u64]) -> (usize, u64) {
        let c = Self::chunk_of(&self.large_before, t);
        let mut opened = self.excess_before[c];
        let skip = (t - self.large_before[c]) as usize;
        let mut positions = self.large_positions(c);
        for pos in positions.by_ref().take(skip) {
            opened += (masses[scratch[pos] as usize] & !REACH_FLAG) - CAPACITY;
        }
        let pos = positions.next().expect("ordinal t lies in its chunk");
        (scratch[pos] as usize, opened)
    }

    /// A cursor at small ordinal `s` (`s == S`: past the end).
    pub(super) fn small_cursor(&self, s: u64) -> SmallCursor<'_> {
        let mut cursor = SmallCursor {
            lists: self,
            pos: 0,
            end: usize::MAX,
            chunk: self.chunks(),
        };
        if s < self.small() {
            let c = Self::chunk_of(&self.small_before, s);
            let (start, _) = self.bounds(c);
            cursor.chunk = c;
            cursor.pos = start + (s - self.small_before[c]) as usize;
            cursor.end = start + (self.small_before[c + 1] - self.small_before[c]) as usize;
        }
        cursor
    }

    /// A cursor at large ordinal `t` (`t == L`: past the end).
    pub(super) fn large_cursor(&self, t: u64) -> LargeCursor<'_> {
        let mut cursor = LargeCursor {
            lists: self,
            pos: 0,
            lowest: 0,
            chunk: self.chunks(),
        };
        if t < self.large() {
            let c = Self::chunk_of(&self.large_before, t);
            cursor.enter(c);
            cursor.pos -= (t - self.large_before[c]) as usize;
        }
        cursor
    }
}

/// Walks the small list across chunks. Past the end it rests on position 0, a valid index
/// whose reads are never used.
pub(super) struct SmallCursor<'a> {
    lists: &'a Lists,
    /// The buffer position of the current small ordinal.
    pub(super) pos: usize,
    end: usize,
    chunk: usize,
}

impl SmallCursor<'_> {
    /// Moves `step` (0 or 1) ordinals on.
    #[inline]
    pub(super) fn advance(&mut self, step: usize) {
        self.pos += step;
        if self.pos == self.end {
            self.next_chunk();
        }
    }

    #[cold]
    fn next_chunk(&mut self) {
        let lists = self.lists;
        self.pos = 0;
        self.end = usize::MAX;
        for c in self.chunk + 1..lists.chunks() {
            let count = (lists.small_before[c + 1] - lists.small_before[c]) as usize;
            if count > 0 {
                let (start, _) = lists.bounds(c);
                self.chunk = c;
                self.pos = start;
                self.end = start + count;
                return;
            }
        }
        self.chunk = lists.chunks();
    }
}

/// Walks the large list across chunks (downwards in each chunk's back). Past the end it
/// rests on position 0, a valid index whose reads are never used.
pub(super) struct LargeCursor<'a> {
    lists: &'a Lists,
    /// The buffer position of the current large ordinal.
    pub(super) pos: usize,
    lowest: usize,
    chunk: usize,
}

impl LargeCursor<'_> {
    /// Points at chunk `c`'s first large index (it has at least one).
    fn enter(&mut self, c: usize) {
        let (_, end) = self.lists.bounds(c);
        let count = (self.lists.large_before[c + 1] - self.lists.large_before[c]) as usize;
        self.chunk = c;
        self.pos = end - 1;
        self.lowest = end - count;
    }

    /// Moves `step` (0 or 1) ordinals on.
    #[inline]
    #[allow(
        clippy::needless_bitwise_bool,
        reason = "no branch on the fill-or-turn step"
    )]
    pub(super) fn advance(&mut self, step: usize) {
        // `&`, not `&&`: no branch on `step` (a fill or a turn, unpredictable), only on the
        // chunk's end (rare).
        if (step == 1) & (self.pos == self.lowest) {
            self.next_chunk();
        } else {
            self.pos -= step;
        }
    }

    #[cold]
    fn next_chunk(&mut self) {
        let lists = self.lists;
        for c in self.chunk + 1..lists.chunks() {
            if lists.large_before[c + 1] > lists.large_before[c] {
                self.enter(c);
                return;
            }
        }
        self.chunk = lists.chunks();
        self.pos = 0;
        self.lowest = 0;
    }
}
