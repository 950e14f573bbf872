//! Vose's construction of the alias table, recorded step by step for teaching.
//!
//! # What is recorded
//! Scale the powers to column masses `q_i = N·Φ_i / ΣΦ` (mean 1). A column is *small* when
//! `q < 1` and *large* when `q ≥ 1`. Each step pairs the next small column `s` with the
//! current large column `l`:
//!
//! * `threshold_s = q_s`, `alias_s = l` (column `s` is now full: its own light up to `q_s`,
//!   light `l` above it, height 1);
//! * `l` gave away `1 − q_s`, so `q_l ← (q_l + q_s) − 1`; if that drops below 1, `l` moves
//!   from the large list to the small list.
//!
//! When one list runs out, every column left has `q = 1` up to rounding: its threshold
//! becomes exactly 1 and its alias itself (a zero-power column left over keeps threshold 0
//! and takes the last large column as alias). [`ConstructionTrace::build`] records the state
//! after each of these events: the start, each pairing, each leftover.
//!
//! # Same order, same numbers as [`AliasTable::build_exact`]
//! The trace replays [`AliasTable::build_exact`] operation for operation: the same scaling
//! (an exact power-of-two rescale, then `q_i = (w_i·N)/S`), the same residue spreading, the
//! same two cursors that find the next small and the next large column (so the work lists
//! are *conceptual*: the small list is the active small column followed by the unvisited
//! columns with `q < 1` in index order, likewise for the large list), and the same
//! double-double carry of the active large column. Its final thresholds and aliases are
//! therefore bit-identical to the table's (tested). Two consequences for display:
//! * the mass shown for the active large column is `hi + lo` rounded to one `f64` (the build
//!   carries it as two numbers until the column turns small);
//! * a large column that ends at exactly 1 may be found by the small cursor (a rounding
//!   remnant a hair below 1): it is then a *leftover from the small list*, still set to 1.
//!
//! [`AliasTable::build_exact`]: crate::AliasTable::build_exact

use crate::alias::{double_double_sum, next_large, next_small, spread_residue, two_sum};
use crate::powers::{LightPowers, pow2_scale_to_unit};

/// What one step of the construction did.
#[derive(Clone, Debug, PartialEq)]
pub enum ConstructionEvent {
    /// The start: every column's mass `q_i = N·p_i`, sorted into the two lists.
    Scaled,
    /// Small column `small` was filled up to height 1 by large column `large`:
    /// `threshold_small = q_small`, `alias_small = large`,
    /// `q_large ← (q_large + q_small) − 1`.
    Pair {
        /// The small column (0-based).
        small: usize,
        /// The large column that filled it (0-based).
        large: usize,
        /// `q_small`, now the small column's threshold.
        threshold: f64,
        /// The remainder `1 − q_small` that moved from `large` onto `small`.
        moved: f64,
        /// `q_large` before the pairing.
        large_before: f64,
        /// `q_large` after the pairing, `(q_large + q_small) − 1`.
        large_after: f64,
        /// Whether `large` dropped below 1 and moved to the small list.
        large_became_small: bool,
    },
    /// A column left when one list ran out: threshold exactly 1 and alias itself, or, for a
    /// zero-power column, threshold 0 and the last large column as alias.
    Leftover {
        /// The column (0-based).
        column: usize,
        /// Its threshold (1, or 0 for a zero power).
        threshold: f64,
        /// Its alias (itself when the threshold is 1).
        alias: u32,
    },
}

/// The construction after one event.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstructionState {
    /// What happened in this step.
    pub event: ConstructionEvent,
    /// Each column's mass `q_i` now: for an assigned column its threshold, for the others the
    /// mass still to be placed.
    pub mass: Vec<f64>,
    /// The small work list (`q < 1`), in the order the columns will be taken.
    pub small: Vec<usize>,
    /// The large work list (`q ≥ 1`), the active large column first.
    pub large: Vec<usize>,
    /// Thresholds assigned so far (`None`: not yet).
    pub threshold: Vec<Option<f64>>,
    /// Aliases assigned so far (`None`: not yet).
    pub alias: Vec<Option<u32>>,
}

impl ConstructionState {
    /// Number of columns with both a threshold and an alias.
    pub fn assigned_count(&self) -> usize {
        self.threshold.iter().filter(|t| t.is_some()).count()
    }
}

/// The whole construction: [`ConstructionTrace::states`]`()[0]` is the start, each later
/// state the result of one event, the last the finished table.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstructionTrace {
    states: Vec<ConstructionState>,
}

/// The cursors and values of the construction, from which a state is read off.
struct Work {
    q: Vec<f64>,
    alias: Vec<u32>,
    assigned: Vec<bool>,
    small: Option<usize>,
    small_scan: usize,
    large: Option<usize>,
    large_scan: usize,
    large_lo: f64,
}

impl Work {
    fn state(&self, event: ConstructionEvent) -> ConstructionState {
        let n = self.q.len();
        let mut mass = self.q.clone();
        if let Some(l) = self.large
            && !self.assigned[l]
        {
            mass[l] = self.q[l] + self.large_lo;
        }
        let open = |i: &usize| !self.assigned[*i];
        let small = self
            .small
            .into_iter()
            .chain((self.small_scan..n).filter(|&i| self.q[i] < 1.0))
            .filter(open)
            .collect();
        let large = self
            .large
            .into_iter()
            .chain((self.large_scan..n).filter(|&i| self.q[i] >= 1.0))
            .filter(open)
            .collect();
        let threshold = (0..n)
            .map(|i| self.assigned[i].then_some(self.q[i]))
            .collect();
        let alias = (0..n)
            .map(|i| self.assigned[i].then_some(self.alias[i]))
            .collect();
        ConstructionState {
            event,
            mass,
            small,
            large,
            threshold,
            alias,
        }
    }
}

impl ConstructionTrace {
    /// Runs Vose's construction on `powers`, recording a state after every event
    /// (`1 + pairings + leftovers` states, at most `2N`). `O(N²)` memory: meant for the
    /// small tables a lesson shows.
    pub fn build(powers: &LightPowers) -> Self {
        let values = powers.as_slice();
        let n = values.len();
        let n_f = n as f64;
        let scale = pow2_scale_to_unit(powers.max());
        let sum = double_double_sum(values.iter().map(|&p| scale.apply(p))).0;
        let mut q: Vec<f64> = values
            .iter()
            .map(|&p| (scale.apply(p) * n_f) / sum)
            .collect();
        spread_residue(&mut q, n_f);
        let mut w = Work {
            q,
            alias: (0..n as u32).collect(),
            assigned: vec![false; n],
            small: None,
            small_scan: 0,
            large: None,
            large_scan: 0,
            large_lo: 0.0,
        };
        w.small = next_small(&w.q, &mut w.small_scan);
        w.large = next_large(&w.q, &mut w.large_scan);
        let mut states = vec![w.state(ConstructionEvent::Scaled)];
        while let (Some(s), Some(l)) = (w.small, w.large) {
            let large_before = w.q[l] + w.large_lo;
            w.alias[s] = l as u32;
            w.assigned[s] = true;
            // The build's update, verbatim (see `alias::pair_columns`).
            let (sum, err) = two_sum(w.q[l], w.q[s]);
            let hi = sum - 1.0;
            w.large_lo += err;
            let (value, rounding) = two_sum(hi, w.large_lo);
            let became_small = value < 1.0;
            if became_small {
                w.q[l] = value.max(0.0);
                w.large_lo = rounding + value.min(0.0);
                w.small = if l < w.small_scan {
                    Some(l)
                } else {
                    next_small(&w.q, &mut w.small_scan)
                };
                w.large = next_large(&w.q, &mut w.large_scan);
            } else {
                if hi < 1.0 {
                    w.large_lo += hi - 1.0;
                    w.q[l] = 1.0;
                } else {
                    w.q[l] = hi;
                }
                w.small = next_small(&w.q, &mut w.small_scan);
            }
            let large_after = if became_small {
                w.q[l]
            } else {
                w.q[l] + w.large_lo
            };
            let event = ConstructionEvent::Pair {
                small: s,
                large: l,
                threshold: w.q[s],
                moved: 1.0 - w.q[s],
                large_before,
                large_after,
                large_became_small: became_small,
            };
            states.push(w.state(event));
        }
        // Leftovers, in the build's order: the large list, then the small list.
        let mut last_large = w.large.unwrap_or(0);
        let mut leftover = |w: &mut Work, i: usize, states: &mut Vec<ConstructionState>| {
            if w.q[i] > 0.0 {
                w.q[i] = 1.0;
                w.alias[i] = i as u32;
                last_large = i;
            } else {
                w.alias[i] = last_large as u32;
            }
            w.assigned[i] = true;
            let event = ConstructionEvent::Leftover {
                column: i,
                threshold: w.q[i],
                alias: w.alias[i],
            };
            states.push(w.state(event));
        };
        while let Some(l) = w.large {
            w.large = next_large(&w.q, &mut w.large_scan);
            leftover(&mut w, l, &mut states);
        }
        while let Some(s) = w.small {
            w.small = next_small(&w.q, &mut w.small_scan);
            leftover(&mut w, s, &mut states);
        }
        Self { states }
    }

    /// Every recorded state, the start first.
    pub fn states(&self) -> &[ConstructionState] {
        &self.states
    }

    /// Number of states (`1 +` the number of events).
    pub fn len(&self) -> usize {
        self.states.len()
    }

    /// Always `false`: the start state is always recorded.
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// The finished table's thresholds (every column is assigned in the last state).
    pub fn thresholds(&self) -> Vec<f64> {
        self.states
            .last()
            .map(|s| s.threshold.iter().map(|t| t.unwrap_or(f64::NAN)).collect())
            .unwrap_or_default()
    }

    /// The finished table's aliases.
    pub fn aliases(&self) -> Vec<u32> {
        self.states
            .last()
            .map(|s| s.alias.iter().map(|a| a.unwrap_or(u32::MAX)).collect())
            .unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AliasTable;
    use proptest::prelude::*;

    fn trace(powers: &[f64]) -> (ConstructionTrace, AliasTable) {
        let p = LightPowers::new(powers.to_vec()).unwrap();
        (ConstructionTrace::build(&p), AliasTable::build_exact(&p))
    }

    fn assert_same_as_build(powers: &[f64]) {
        let (t, table) = trace(powers);
        let got = t.thresholds();
        for (i, (a, b)) in got.iter().zip(table.thresholds()).enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "threshold {i} of {powers:?}");
        }
        assert_eq!(t.aliases(), table.aliases(), "aliases of {powers:?}");
        let last = &t.states()[t.len() - 1];
        assert!(last.small.is_empty() && last.large.is_empty());
        assert!(t.len() <= 2 * powers.len());
    }

    #[test]
    fn seed_construction_step_by_step() {
        let (t, _) = trace(&[2.0, 5.0, 20.0]);
        let s = t.states();
        assert_eq!(s.len(), 4);
        assert_eq!(s[0].event, ConstructionEvent::Scaled);
        assert_eq!(s[0].mass, vec![6.0 / 27.0, 15.0 / 27.0, 60.0 / 27.0]);
        assert_eq!(
            (s[0].small.clone(), s[0].large.clone()),
            (vec![0, 1], vec![2])
        );
        let ConstructionEvent::Pair {
            small,
            large,
            large_after,
            large_became_small,
            ..
        } = s[1].event
        else {
            panic!("{:?}", s[1].event)
        };
        assert_eq!((small, large, large_became_small), (0, 2, false));
        assert!((large_after - 39.0 / 27.0).abs() < 1e-15);
        assert_eq!((s[1].small.clone(), s[1].large.clone()), (vec![1], vec![2]));
        assert_eq!(s[1].threshold, vec![Some(6.0 / 27.0), None, None]);
        assert_eq!(s[1].alias, vec![Some(2), None, None]);
        let ConstructionEvent::Pair { small, large, .. } = s[2].event else {
            panic!("{:?}", s[2].event)
        };
        assert_eq!((small, large), (1, 2));
        assert_eq!(s[2].threshold[1], Some(15.0 / 27.0));
        assert!(matches!(
            s[3].event,
            ConstructionEvent::Leftover {
                column: 2,
                threshold: 1.0,
                alias: 2
            }
        ));
        assert_eq!(s[3].assigned_count(), 3);
    }

    #[test]
    fn final_state_is_the_built_table_for_small_integer_powers() {
        let lists: &[&[f64]] = &[
            &[2.0, 5.0, 20.0],
            &[7.0, 5.0, 20.0],
            &[1.0],
            &[1.0, 1.0, 1.0, 1.0],
            &[0.0, 1.0, 0.0, 3.0],
            &[3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0],
            &[100.0, 1.0, 1.0, 1.0, 1.0, 1.0],
            &[5.0, 5.0, 0.0, 0.0, 7.0],
        ];
        for powers in lists {
            assert_same_as_build(powers);
        }
    }

    proptest! {
        #[test]
        fn final_state_is_the_built_table(
            powers in prop::collection::vec(0u32..50, 1..40)
                .prop_filter("a positive power", |v| v.iter().any(|&p| p > 0))
        ) {
            let powers: Vec<f64> = powers.into_iter().map(f64::from).collect();
            assert_same_as_build(&powers);
        }

        #[test]
        fn final_state_is_the_built_table_for_real_powers(
            powers in prop::collection::vec(1e-3f64..1e3, 1..64)
        ) {
            assert_same_as_build(&powers);
        }
    }
}
