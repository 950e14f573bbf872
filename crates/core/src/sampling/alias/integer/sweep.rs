//! The exact integer sweep, cut into pieces that run in parallel (module docs of
//! `integer`): each piece starts from a state `(s, t, h, w)` of the sequential sweep,
//! computed from the chunks' prefix sums, and stops where the next piece starts. Its two
//! cursors walk the bitmap of large lights (`heavy`).
//!
//! The pieces share the table through [`Slot`]: `AtomicU64` words with relaxed loads and
//! stores when they run at once, or `Cell<u64>` words when they run one after the other
//! (where `AtomicU64` is missing or aligned more strictly than `u64`, as on 32-bit x86).
//! Both write the same bits: the pieces' columns are disjoint and each piece needs nothing
//! from the pieces after it.

use std::cell::Cell;
#[cfg(target_has_atomic = "64")]
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use rayon::prelude::*;

use super::heavy::Census;
use super::units::{CAPACITY, REACH_FLAG, full};
use crate::alias::packed::packed_word;

/// Pieces per thread: enough that uneven pieces balance out, and that a thread the system
/// takes off its core in the middle of a piece (a machine shared with other work) holds
/// up the others for a small part of the sweep only.
const PIECES_PER_THREAD: usize = 8;

/// A state of the sequential sweep: `s` small columns filled, `t` large ones turned, the
/// current large light `h` (ordinal `t`) holding the rest `w` of its mass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct State {
    s: u64,
    t: u64,
    h: usize,
    w: u64,
}

/// One piece: from `start` up to the state whose ordinals are `(end_s, end_t)`; the mass
/// of large ordinal `end_t` (the next piece's `h`, whose word that piece may overwrite at
/// any time) is handed over as `end_mass`.
#[derive(Clone, Copy, Debug)]
struct Piece {
    start: State,
    end_s: u64,
    end_t: u64,
    end_mass: u64,
}

/// In which order the pieces run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Order {
    /// At once, on the current rayon pool (one after the other, first first, where the
    /// table cannot be viewed as `AtomicU64` words).
    Parallel,
    /// One after the other, the first first, on plain words: the path of targets without
    /// a usable `AtomicU64`, run on any target by the tests.
    #[cfg(test)]
    Forward,
    /// One after the other, the last first: every piece then finds the words of the
    /// pieces after it already overwritten (what parallel runs may or may not show).
    #[cfg(test)]
    Reversed,
}

/// A table word the pieces read and write through a shared reference.
trait Slot {
    /// The word.
    fn get(&self) -> u64;
    /// Overwrites the word.
    fn set(&self, word: u64);
}

#[cfg(target_has_atomic = "64")]
impl Slot for AtomicU64 {
    #[inline]
    fn get(&self) -> u64 {
        self.load(Relaxed)
    }

    #[inline]
    fn set(&self, word: u64) {
        self.store(word, Relaxed);
    }
}

impl Slot for Cell<u64> {
    #[inline]
    fn get(&self) -> u64 {
        Cell::get(self)
    }

    #[inline]
    fn set(&self, word: u64) {
        Cell::set(self, word);
    }
}

/// Sweeps the masses in `table` into packed entries (large lights marked in `heavy`).
#[cfg_attr(
    not(any(test, target_has_atomic = "64")),
    allow(unused_variables, reason = "one order only without atomics")
)]
#[allow(
    clippy::needless_range_loop,
    reason = "the tests run the pieces by index, last first"
)]
pub(super) fn sweep(table: &mut [u64], heavy: &[u64], census: &Census, order: Order) {
    if census.large() == 0 {
        // Impossible when Σ m = N·C; keep the table valid regardless.
        for (i, slot) in table.iter_mut().enumerate() {
            *slot = full(i);
        }
        return;
    }
    let pieces = pieces(table, heavy, census);
    #[cfg(target_has_atomic = "64")]
    if order == Order::Parallel
        && let Some(shared) = atomic_view(table)
    {
        let last = pieces.len() - 1;
        let tail = pieces
            .par_iter()
            .enumerate()
            .map(|(k, piece)| {
                let end = run(shared, heavy, census, piece);
                (k == last).then_some(end)
            })
            .reduce(|| None, Option::or);
        let Some(end) = tail else {
            unreachable!("the last piece reports where the sweep ended");
        };
        finish(shared, heavy, census, end);
        return;
    }
    let words = Cell::from_mut(table).as_slice_of_cells();
    let count = pieces.len();
    let mut tail = None;
    for k in 0..count {
        #[cfg(test)]
        let k = if order == Order::Reversed {
            count - 1 - k
        } else {
            k
        };
        let end = run(words, heavy, census, &pieces[k]);
        if k == count - 1 {
            tail = Some(end);
        }
    }
    let Some(end) = tail else {
        unreachable!("the last piece reports where the sweep ended");
    };
    finish(words, heavy, census, end);
}

/// Completes the table after the pieces: the column the sweep ended on and every large
/// column not yet opened are full.
fn finish<S: Slot>(table: &[S], heavy: &[u64], census: &Census, end: State) {
    // Once the small columns have run out with `w ≥ C`, the current large column and every
    // one not yet opened hold exactly C (integer arithmetic conserves the total, which the
    // quantization checked). Checked in release too: a table past this would be wrong.
    assert!(
        end.s == census.small() && end.w == CAPACITY,
        "integer sweep ran short"
    );
    table[end.h].set(full(end.h));
    let (walk, mut cursor) = census.large_cursor(end.t + 1, heavy);
    for _ in end.t + 1..census.large() {
        let j = cursor.pos();
        table[j].set(full(j));
        cursor = walk.advance(cursor, 1);
    }
}

/// The pieces: cut where the merge reaches `V = D(s)` at the first small ordinal `s` of
/// evenly spaced chunks (the same table for any cuts; their number follows the pool).
fn pieces(masses: &[u64], heavy: &[u64], census: &Census) -> Vec<Piece> {
    let chunks = census.chunks();
    let wanted = (rayon::current_num_threads() * PIECES_PER_THREAD).clamp(1, chunks);
    let mut starts: Vec<State> = (0..wanted)
        .into_par_iter()
        .map(|k| {
            let c = k * chunks / wanted;
            let (s, v) = (census.small_before[c], census.deficit_before[c]);
            let (t, h, opened) = census.large_below(v, heavy, masses);
            let m_h = masses[h] & !REACH_FLAG;
            // w = E(t+1) − D(s) + C = E(t) + m_h − D(s) ≥ C (the cut comes before a fill).
            State {
                s,
                t,
                h,
                w: opened + m_h - v,
            }
        })
        .collect();
    starts.dedup_by_key(|state| (state.s, state.t));
    let mut pieces: Vec<Piece> = starts
        .windows(2)
        .map(|pair| Piece {
            start: pair[0],
            end_s: pair[1].s,
            end_t: pair[1].t,
            end_mass: masses[pair[1].h] & !REACH_FLAG,
        })
        .collect();
    let last = *starts.last().expect("at least one cut");
    // No other piece touches the last large light; its mass goes through the same hand-over.
    let (h_last, _) = census.large_at(census.large() - 1, heavy, masses);
    pieces.push(Piece {
        start: last,
        end_s: census.small(),
        end_t: census.large() - 1,
        end_mass: masses[h_last] & !REACH_FLAG,
    });
    pieces
}

/// Runs one piece of the sweep and returns the state it stopped in.
///
/// Each step finishes one column, either the next small one (filled by `h`) or `h` itself,
/// and both candidates are computed and one selected (`cmov`), so the step has no
/// data-dependent branch to mispredict (about half the steps would, with powers in random
/// order). Steps run in blocks that cannot reach either end of the piece, with no test of
/// the ends inside (the block's length is the distance to the nearer one); at the ends a
/// step checks them. The piece stops before a fill when its small columns are done, and
/// before a turn when its large ones are.
fn run<S: Slot>(table: &[S], heavy: &[u64], census: &Census, piece: &Piece) -> State {
    let mut state = piece.start;
    let (small_walk, mut small) = census.small_cursor(state.s, heavy);
    let (large_walk, mut large) = census.large_cursor(state.t + 1, heavy);
    loop {
        // Neither `s` nor the next large ordinal `t + 1` reaches its end in `k` steps.
        let k = (piece.end_s - state.s).min((piece.end_t - state.t).saturating_sub(1));
        if k == 0 {
            // One step at an end: stop, or open the next piece's first large light, whose
            // word may be gone already (its mass was handed over).
            let fill = state.w >= CAPACITY;
            if (fill && state.s == piece.end_s) || (!fill && state.t == piece.end_t) {
                return state;
            }
            let m_next = if state.t + 1 == piece.end_t {
                piece.end_mass
            } else {
                table[large.pos()].get()
            };
            step(table, &mut state, small.pos(), large.pos(), m_next);
            let filling = u64::from(fill);
            state.t += filling ^ 1;
            small = small_walk.advance(small, filling);
            large = large_walk.advance(large, filling ^ 1);
            continue;
        }
        let s_before = state.s;
        for _ in 0..k {
            let (l, h_next) = (small.pos(), large.pos());
            let filling = step(table, &mut state, l, h_next, table[h_next].get());
            small = small_walk.advance(small, filling);
            large = large_walk.advance(large, filling ^ 1);
        }
        state.t += k - (state.s - s_before);
    }
}

/// One step of the sweep from `state` with the next small light `l` and the next large
/// light `h_next` of mass `m_next`: fills `l` from `h` (if `w ≥ C`) or turns `h` (threshold
/// `w`, alias `h_next`), selecting between the two without a branch. Counts a fill in
/// `state.s` (a turn's `t` is counted by the caller) and returns 1 for a fill, 0 for a turn.
#[inline]
fn step<S: Slot>(table: &[S], state: &mut State, l: usize, h_next: usize, m_next: u64) -> u64 {
    use std::hint::select_unpredictable as select;
    let State { s, t: _, h, w } = *state;
    let fill = w >= CAPACITY;
    let raw = table[l].get();
    let m_l = raw & !REACH_FLAG;
    let column = select(fill, l, h);
    let threshold = select(fill, m_l | raw >> 63, w);
    let alias = select(fill, h, h_next);
    table[column].set(packed_word(threshold as u32, alias as u32));
    // Filled: h gives C − m_l. Turned: h_next gives C − w to h's column.
    state.w = (select(fill, m_l, m_next) + w) - CAPACITY;
    state.h = select(fill, h, h_next);
    let filling = u64::from(fill);
    state.s = s + filling;
    filling
}

/// The table's words as atomics, so that pieces running at once can write their (disjoint)
/// columns anywhere in it; `None` where `AtomicU64` is aligned more strictly than these
/// words happen to be (32-bit x86 aligns `u64` to 4 bytes, `AtomicU64` to 8). Relaxed
/// loads and stores compile to plain moves; the one word a piece may read while its
/// neighbour writes it (a speculative read whose value the select drops) is then well
/// defined.
#[cfg(target_has_atomic = "64")]
#[allow(unsafe_code)]
#[allow(
    clippy::cast_ptr_alignment,
    reason = "the alignment is checked before the cast"
)]
fn atomic_view(words: &mut [u64]) -> Option<&[AtomicU64]> {
    const {
        assert!(std::mem::size_of::<AtomicU64>() == std::mem::size_of::<u64>());
    }
    if !words
        .as_ptr()
        .addr()
        .is_multiple_of(std::mem::align_of::<AtomicU64>())
    {
        return None;
    }
    // SAFETY: `AtomicU64` has the size (asserted above) and bit validity of `u64`, the
    // words are aligned for it (checked above), and the exclusive borrow guarantees no
    // other access for the view's lifetime (what the unstable `AtomicU64::from_mut_slice`
    // does).
    Some(unsafe { &*(std::ptr::from_mut::<[u64]>(words) as *const [AtomicU64]) })
}
