//! The large lights as a bitmap, and the per-chunk sums that place any state of the sweep.
//!
//! Bit `i mod 64` of word `i / 64` is set when light `i` is large (`m_i ≥ C`). The small
//! lights (clear bits) and the large ones (set bits), each in ascending order, are the two
//! sequences the sweep merges: a [`BitCursor`] walks one of them, finding the next index of
//! its kind with one trailing-zero count, so the sweep needs no index lists (an eighth of a
//! byte per light instead of four) and both cursors read the bitmap and the masses as
//! forward streams. Per chunk of [`CHUNK`] lights (`CHUNK / 64` whole words) the census
//! counts the small lights and sums the masses; prefix sums over the chunks locate any
//! ordinal of either sequence and its running deficit or excess.

use super::units::{CAPACITY, CHUNK, REACH_FLAG};

/// Bitmap words per chunk.
pub(super) const WORDS_PER_CHUNK: usize = CHUNK / 64;

/// One chunk's census: how many small lights, their masses' sum and every mass's sum
/// (flags removed). The deficit `Σ (C − m)` of the small lights and the excess `Σ (m − C)`
/// of the large ones follow from these and the chunk's length.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ChunkCensus {
    pub(super) small: u64,
    pub(super) small_mass: u64,
    pub(super) mass: u64,
}

impl ChunkCensus {
    /// Counts mass `m` (without its flag), branch-free; returns whether it is large.
    #[inline]
    pub(super) fn add(&mut self, m: u64) -> bool {
        let large = m >= CAPACITY;
        let small_mask = u64::from(large).wrapping_sub(1);
        self.small += small_mask & 1;
        self.small_mass += m & small_mask;
        self.mass += m;
        large
    }

    /// Counts mass `after` instead of `before` (flags removed); returns whether `after` is
    /// large.
    pub(super) fn replace(&mut self, before: u64, after: u64) -> bool {
        if before < CAPACITY {
            self.small -= 1;
            self.small_mass -= before;
        }
        self.mass -= before;
        self.add(after)
    }
}

/// Every chunk's counts as exclusive prefix sums over the chunks (each `chunks + 1` long):
/// small and large counts (ordinals), deficits `D` and excesses `E`.
#[derive(Debug)]
pub(super) struct Census {
    n: usize,
    pub(super) small_before: Vec<u64>,
    pub(super) large_before: Vec<u64>,
    pub(super) deficit_before: Vec<u64>,
    pub(super) excess_before: Vec<u64>,
}

impl Census {
    /// The prefix sums of the chunks' censuses (`n` lights in all).
    pub(super) fn new(chunks: &[ChunkCensus], n: usize) -> Self {
        let len = |c: usize| CHUNK.min(n - c * CHUNK) as u64;
        let small: Vec<u64> = chunks.iter().map(|c| c.small).collect();
        let large: Vec<u64> = (0..chunks.len()).map(|c| len(c) - small[c]).collect();
        let deficit: Vec<u64> = chunks
            .iter()
            .map(|c| c.small * CAPACITY - c.small_mass)
            .collect();
        let excess: Vec<u64> = chunks
            .iter()
            .zip(&large)
            .map(|(c, &l)| (c.mass - c.small_mass) - l * CAPACITY)
            .collect();
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

    /// The chunk holding ordinal `k` of a sequence whose prefix is `before` (`k` < total).
    fn chunk_of(before: &[u64], k: u64) -> usize {
        before.partition_point(|&b| b <= k) - 1
    }

    /// Chunk `c`'s bitmap words.
    fn words_of(c: usize, heavy: &[u64]) -> std::ops::Range<usize> {
        c * WORDS_PER_CHUNK..((c + 1) * WORDS_PER_CHUNK).min(heavy.len())
    }

    /// How many large ordinals `t ≤ L − 2` have `E(t+1) < v`, at most `L − 1`: with
    /// `v = D(s)`, the large columns that turn before small column `s` is filled. Returns
    /// `t` with its light `h_t` and `E(t)` ([`Census::large_at`]), from one scan of the
    /// chunk where the crossing lies.
    pub(super) fn large_below(&self, v: u64, heavy: &[u64], masses: &[u64]) -> (u64, usize, u64) {
        let last = self.large() - 1;
        if v == 0 {
            let (h, opened) = self.large_at(0, heavy, masses);
            return (0, h, opened);
        }
        // The last chunk whose excess prefix at its start is below v: the crossing is in it.
        let c = (self.excess_before.partition_point(|&e| e < v) - 1).min(self.chunks() - 1);
        let mut t = self.large_before[c];
        let mut opened = self.excess_before[c];
        for w in Self::words_of(c, heavy) {
            let mut bits = heavy[w];
            while bits != 0 {
                let i = w * 64 + bits.trailing_zeros() as usize;
                let next = opened + (masses[i] & !REACH_FLAG) - CAPACITY;
                if next >= v && t <= last {
                    return (t, i, opened);
                }
                opened = next;
                t += 1;
                bits &= bits - 1;
            }
        }
        let t = t.min(last);
        let (h, opened) = self.large_at(t, heavy, masses);
        (t, h, opened)
    }

    /// Large ordinal `t`: its light and `E(t) = Σ_{j<t} (m_{h_j} − C)`.
    pub(super) fn large_at(&self, t: u64, heavy: &[u64], masses: &[u64]) -> (usize, u64) {
        let c = Self::chunk_of(&self.large_before, t);
        let mut opened = self.excess_before[c];
        let mut skip = t - self.large_before[c];
        for w in Self::words_of(c, heavy) {
            let mut bits = heavy[w];
            while bits != 0 {
                let i = w * 64 + bits.trailing_zeros() as usize;
                if skip == 0 {
                    return (i, opened);
                }
                opened += (masses[i] & !REACH_FLAG) - CAPACITY;
                skip -= 1;
                bits &= bits - 1;
            }
        }
        unreachable!("large ordinal {t} lies in chunk {c}")
    }

    /// The walk over the small lights and a cursor at small ordinal `s` (`s == S`: past the
    /// end).
    pub(super) fn small_cursor<'a>(&self, s: u64, heavy: &'a [u64]) -> (Walk<'a>, BitCursor) {
        let walk = Walk::new(heavy, !0, self.n);
        let cursor = if s < self.small() {
            let c = Self::chunk_of(&self.small_before, s);
            walk.seek(Self::words_of(c, heavy), s - self.small_before[c])
        } else {
            walk.end()
        };
        (walk, cursor)
    }

    /// The walk over the large lights and a cursor at large ordinal `t` (`t == L`: past the
    /// end).
    pub(super) fn large_cursor<'a>(&self, t: u64, heavy: &'a [u64]) -> (Walk<'a>, BitCursor) {
        let walk = Walk::new(heavy, 0, self.n);
        let cursor = if t < self.large() {
            let c = Self::chunk_of(&self.large_before, t);
            walk.seek(Self::words_of(c, heavy), t - self.large_before[c])
        } else {
            walk.end()
        };
        (walk, cursor)
    }
}

/// Which lights a [`BitCursor`] walks: the set bits of the bitmap (large) or its clear bits
/// below `N` (small).
#[derive(Clone, Copy, Debug)]
pub(super) struct Walk<'a> {
    heavy: &'a [u64],
    /// `0` to walk set bits, all ones to walk clear ones.
    flip: u64,
    /// The lights of the last word (its bits at and above `N mod 64` are not lights).
    tail: u64,
}

/// A position in a [`Walk`], two registers: the first light of its word and the lights of
/// the kind still ahead in that word (never 0). Past the end it rests on the last light,
/// a valid index whose reads are never used, and stays there.
#[derive(Clone, Copy, Debug)]
pub(super) struct BitCursor {
    /// `64·word`.
    base: usize,
    bits: u64,
}

impl<'a> Walk<'a> {
    /// The walk over `n` lights.
    fn new(heavy: &'a [u64], flip: u64, n: usize) -> Self {
        let tail = match n % 64 {
            0 => !0,
            r => (1u64 << r) - 1,
        };
        Self { heavy, flip, tail }
    }

    /// Word `w`'s lights of the walk's kind.
    #[inline]
    fn bits_of(self, w: usize) -> u64 {
        let bits = self.heavy[w] ^ self.flip;
        if w + 1 == self.heavy.len() {
            bits & self.tail
        } else {
            bits
        }
    }

    /// The cursor past the end: on the last light (bit `(N − 1) mod 64` of the last word).
    fn end(self) -> BitCursor {
        let last = self.heavy.len() - 1;
        BitCursor {
            base: 64 * last,
            bits: 1 << self.tail.ilog2(),
        }
    }

    /// The cursor on the `k`-th light of the kind within `words` (there is one).
    fn seek(self, words: std::ops::Range<usize>, mut k: u64) -> BitCursor {
        for w in words {
            let mut bits = self.bits_of(w);
            let count = u64::from(bits.count_ones());
            if k < count {
                for _ in 0..k {
                    bits &= bits - 1;
                }
                return BitCursor { base: 64 * w, bits };
            }
            k -= count;
        }
        unreachable!("the ordinal lies in its chunk");
    }

    /// The first light of the kind in a word after `cursor`'s (or past the end).
    #[cold]
    #[inline(never)]
    fn next_word(self, cursor: BitCursor) -> BitCursor {
        for w in cursor.base / 64 + 1..self.heavy.len() {
            let bits = self.bits_of(w);
            if bits != 0 {
                return BitCursor { base: 64 * w, bits };
            }
        }
        self.end()
    }

    /// `cursor` moved `step` (0 or 1) lights on, without a branch on `step`.
    #[inline]
    pub(super) fn advance(self, cursor: BitCursor, step: u64) -> BitCursor {
        let bits = cursor.bits & cursor.bits.wrapping_sub(step);
        if bits == 0 {
            self.next_word(cursor)
        } else {
            BitCursor { bits, ..cursor }
        }
    }
}

impl BitCursor {
    /// The current light.
    #[inline]
    pub(super) fn pos(self) -> usize {
        self.base + self.bits.trailing_zeros() as usize
    }
}

/// The exclusive prefix sums of `values` (length `values.len() + 1`).
fn exclusive_prefix(values: &[u64]) -> Vec<u64> {
    let mut prefix = Vec::with_capacity(values.len() + 1);
    let mut sum = 0u64;
    prefix.push(0);
    for &v in values {
        sum += v;
        prefix.push(sum);
    }
    prefix
}
