//! The order a tile's cut splits its entries in ([`super::cut_growth`]): the most urgent
//! entry first, found in `O(log n)` a change by a tournament over the entries' keys.

/// The key of an entry the cut cannot split (below every urgency's [`ordered_key`] but a
/// negative NaN's, which no urgency is).
pub(super) const NOT_SPLIT: i64 = i64::MIN;

/// `x` as an integer in the order of [`f64::total_cmp`].
pub(super) fn ordered_key(x: f64) -> i64 {
    let bits = x.to_bits() as i64;
    bits ^ (((bits >> 63) as u64) >> 1) as i64
}

/// A max-tournament over the keys of a cut's entries, by position: its winner is the
/// entry of largest key, the last of equal ones (as [`Iterator::max_by`] takes them), so
/// the cut splits in the order a scan of every entry gives, reading `log2 n` keys a change
/// instead of `n`.
#[derive(Default)]
pub(super) struct Tournament {
    /// Each position's key ([`NOT_SPLIT`] past the cut's end), a power of two of them.
    key: Vec<i64>,
    /// The winning position of each match: `winner[1]` of all, `winner[m]` of
    /// `winner[2m]` against `winner[2m + 1]`, the positions themselves from `key.len()` on.
    winner: Vec<u32>,
}

impl Tournament {
    /// The tournament over `keys` (positions past them [`NOT_SPLIT`]), `O(n)`.
    pub(super) fn reset(&mut self, keys: impl Iterator<Item = i64>) {
        self.key.clear();
        self.key.extend(keys);
        self.replay_all();
    }

    /// Every match played again over `key`, extended to a power of two of at least 2.
    fn replay_all(&mut self) {
        let leaves = self.key.len().next_power_of_two().max(2);
        self.key.resize(leaves, NOT_SPLIT);
        self.winner.clear();
        self.winner.resize(leaves, 0);
        self.winner.extend(0..leaves as u32);
        for m in (1..leaves).rev() {
            self.winner[m] = self.play(m);
        }
    }

    /// The winner of match `m`: the right one (the later position) on equal keys.
    #[inline]
    fn play(&self, m: usize) -> u32 {
        let (left, right) = (self.winner[2 * m], self.winner[2 * m + 1]);
        if self.key[right as usize] >= self.key[left as usize] {
            right
        } else {
            left
        }
    }

    /// Sets position `at`'s key, replaying the matches above it (`O(log n)`; doubling the
    /// positions, `O(n)`, where `at` lies past them).
    pub(super) fn set(&mut self, at: usize, key: i64) {
        while at >= self.key.len() {
            // The new positions hold no split; the matches are played again over them.
            let doubled = (2 * self.key.len()).max(2);
            self.key.resize(doubled, NOT_SPLIT);
            self.replay_all();
        }
        self.key[at] = key;
        // The match above leaf `key.len() + at`.
        let mut m = (self.key.len() + at) >> 1;
        while m >= 1 {
            self.winner[m] = self.play(m);
            m /= 2;
        }
    }

    /// Position `at`'s key.
    pub(super) fn key(&self, at: usize) -> i64 {
        self.key[at]
    }

    /// The position of the largest key (the last of equal ones), `None` when every key is
    /// [`NOT_SPLIT`] (or none was set).
    pub(super) fn top(&self) -> Option<usize> {
        let best = *self.winner.get(1)? as usize;
        (self.key[best] != NOT_SPLIT).then_some(best)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scan the tournament stands for.
    fn scanned(keys: &[i64]) -> Option<usize> {
        keys.iter()
            .enumerate()
            .filter(|(_, k)| **k != NOT_SPLIT)
            .max_by(|a, b| a.1.cmp(b.1))
            .map(|(at, _)| at)
    }

    #[test]
    fn ordered_keys_order_as_total_cmp() {
        let values = [
            f64::NEG_INFINITY,
            -2.0,
            -0.0,
            0.0,
            1e-300,
            0.5,
            0.500_000_000_000_000_1,
            3.0,
            f64::INFINITY,
            f64::NAN,
        ];
        for a in values {
            for b in values {
                assert_eq!(
                    ordered_key(a).cmp(&ordered_key(b)),
                    a.total_cmp(&b),
                    "{a} {b}"
                );
            }
        }
    }

    #[test]
    fn the_winner_is_the_scans_through_any_changes() {
        // Keys from a small set, so that ties are common; changes as a cut makes them:
        // an entry kept whole, every key taken again, a split (the last entry moves into
        // the split one's place, its children are appended).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |m: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % m
        };
        for most in [1, 2, 3, 7, 64, 130] {
            let mut keys: Vec<i64> = vec![5];
            let mut t = Tournament::default();
            t.reset(keys.iter().copied());
            for _ in 0..2000 {
                assert_eq!(t.top(), scanned(&keys), "{keys:?}");
                let Some(k) = t.top() else {
                    keys = vec![next(4) as i64];
                    t.reset(keys.iter().copied());
                    continue;
                };
                match next(4) {
                    0 => {
                        keys[k] = NOT_SPLIT;
                        t.set(k, NOT_SPLIT);
                    }
                    1 => {
                        for key in &mut keys {
                            *key = next(5) as i64 - 1;
                        }
                        t.reset(keys.iter().copied());
                    }
                    _ => {
                        let last = keys.len() - 1;
                        keys.swap_remove(k);
                        t.set(k, t.key(last));
                        t.set(last, NOT_SPLIT);
                        let children = next(4) as usize;
                        for _ in 0..children.min(most - keys.len()) {
                            let key = next(6) as i64;
                            t.set(keys.len(), key);
                            keys.push(key);
                        }
                    }
                }
            }
        }
    }
}
