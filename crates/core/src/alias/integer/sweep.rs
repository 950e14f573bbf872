//! The exact integer sweep, cut into pieces that run in parallel (module docs of
//! `integer`): each piece starts from a state `(s, t, h, w)` of the sequential sweep,
//! computed from the chunks' prefix sums, and stops where the next piece starts. Its two
//! cursors walk the bitmap of large lights (`heavy`).

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use rayon::prelude::*;

use super::heavy::Census;
use super::{CAPACITY, REACH_FLAG, full, word};

/// Pieces per thread: enough that uneven pieces balance out.
const PIECES_PER_THREAD: usize = 4;

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
#[derive(Clone, Copy, Debug)]
pub(super) enum Order {
    /// At once, on the current rayon pool.
    Parallel,
    /// One after the other, the last first: every piece then finds the words of the
    /// pieces after it already overwritten (what parallel runs may or may not show).
    #[cfg(test)]
    Reversed,
}

/// Sweeps the masses in `table` into packed entries (large lights marked in `heavy`).
pub(super) fn sweep(table: &mut [u64], heavy: &[u64], census: &Census, order: Order) {
    let (small, large) = (census.small(), census.large());
    if large == 0 {
        // Impossible when Σ m = N·C; keep the table valid regardless.
        for (i, slot) in table.iter_mut().enumerate() {
            *slot = full(i);
        }
        return;
    }
    let pieces = pieces(table, heavy, census);
    let table = atomic_view(table);
    let last = pieces.len() - 1;
    let run_piece = |(k, piece): (usize, &Piece)| {
        let end = run(table, heavy, census, piece);
        (k == last).then_some(end)
    };
    let tail = match order {
        Order::Parallel => pieces
            .par_iter()
            .enumerate()
            .map(run_piece)
            .reduce(|| None, Option::or),
        #[cfg(test)]
        Order::Reversed => pieces
            .iter()
            .enumerate()
            .rev()
            .map(run_piece)
            .fold(None, Option::or),
    };
    let Some(end) = tail else {
        unreachable!("the last piece reports where the sweep ended");
    };
    // Once the small columns have run out with `w ≥ C`, the current large column and every
    // one not yet opened hold exactly C (integer arithmetic conserves the total).
    debug_assert!(
        end.s == small && end.w == CAPACITY,
        "integer sweep ran short"
    );
    table[end.h].store(full(end.h), Relaxed);
    let mut cursor = census.large_cursor(end.t + 1, heavy);
    for _ in end.t + 1..large {
        let j = cursor.pos();
        table[j].store(full(j), Relaxed);
        cursor.advance(1);
    }
}

/// The pieces: cut where the merge reaches `V = D(s)` at the first small ordinal `s` of
/// evenly spaced chunks (the same table for any cuts; their number follows the pool).
fn pieces(masses: &[u64], heavy: &[u64], census: &Census) -> Vec<Piece> {
    let chunks = census.chunks();
    let wanted = (rayon::current_num_threads() * PIECES_PER_THREAD).clamp(1, chunks);
    let mut starts: Vec<State> = (0..wanted)
        .map(|k| {
            let c = k * chunks / wanted;
            let (s, v) = (census.small_before[c], census.deficit_before[c]);
            let t = census.large_below(v, heavy, masses);
            let (h, opened) = census.large_at(t, heavy, masses);
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
/// and both candidates are computed and one selected, so the step has no data-dependent
/// branch to mispredict (about half the steps would, with powers in random order). The
/// piece stops before a fill when its small columns are done, and before a turn when its
/// large ones are.
fn run(table: &[AtomicU64], heavy: &[u64], census: &Census, piece: &Piece) -> State {
    let State {
        mut s,
        mut t,
        mut h,
        mut w,
    } = piece.start;
    let mut small = census.small_cursor(s, heavy);
    let mut large = census.large_cursor(t + 1, heavy);
    loop {
        // All ones when `h` fills the next small column, zero when `h` itself turns. The
        // step selects with this mask (bit operations, no branch on `fill`, which the
        // compiler otherwise turns back into a mispredicted jump).
        let fill = u64::from(w >= CAPACITY).wrapping_neg();
        let filling = fill & 1;
        let done = (u64::from(s == piece.end_s) & fill) | (u64::from(t == piece.end_t) & !fill);
        if done != 0 {
            return State { s, t, h, w };
        }
        // The next small column and the next large one (past either sequence's end a
        // valid index whose values go unused).
        let l = small.pos() as u64;
        let h_next = large.pos() as u64;
        let raw = table[l as usize].load(Relaxed);
        let m_l = raw & !REACH_FLAG;
        let loaded_next = table[h_next as usize].load(Relaxed) & !REACH_FLAG;
        // The piece's last turn opens the next piece's first large light: its word may be
        // gone already, its mass was handed over.
        let m_next = if t + 1 == piece.end_t {
            piece.end_mass
        } else {
            loaded_next
        };
        let h64 = h as u64;
        let column = (l & fill) | (h64 & !fill);
        let threshold = ((m_l | raw >> 63) & fill) | (w & !fill);
        let alias = (h64 & fill) | (h_next & !fill);
        table[column as usize].store(word(threshold as u32, alias as u32), Relaxed);
        // Filled: h gives C − m_l. Turned: h_next gives C − w to h's column.
        let w_fill = w.wrapping_add(m_l).wrapping_sub(CAPACITY);
        let w_turn = m_next.wrapping_add(w).wrapping_sub(CAPACITY);
        w = (w_fill & fill) | (w_turn & !fill);
        h = ((h64 & fill) | (h_next & !fill)) as usize;
        s += filling;
        t += filling ^ 1;
        small.advance(filling);
        large.advance(filling ^ 1);
    }
}

/// The table's words as atomics, so that pieces running at once can write their (disjoint)
/// columns anywhere in it. Relaxed loads and stores compile to plain moves; the one word a
/// piece may read while its neighbour writes it (a speculative read whose value the select
/// drops) is then well defined.
#[allow(unsafe_code)]
fn atomic_view(words: &mut [u64]) -> &[AtomicU64] {
    const _: () = assert!(
        std::mem::size_of::<AtomicU64>() == std::mem::size_of::<u64>()
            && std::mem::align_of::<AtomicU64>() == std::mem::align_of::<u64>()
    );
    // SAFETY: `AtomicU64` has the size, alignment (asserted above) and bit validity of
    // `u64`, and the exclusive borrow guarantees no other access for the view's lifetime
    // (what the unstable `AtomicU64::from_mut_slice` does).
    unsafe { &*(std::ptr::from_mut::<[u64]>(words) as *const [AtomicU64]) }
}
