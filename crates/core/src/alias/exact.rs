//! Walker's alias method, built with Vose's algorithm.
//!
//! # The table
//! For `N` lights with pmf `p_i`, scale to `q_i = N·p_i` (mean 1). Column `i` keeps light `i`
//! with probability `threshold_i` and otherwise yields `alias_i`. Sampling picks a column
//! uniformly (probability `1/N`), then keeps or aliases, so the pmf the table realizes is
//!
//! `P(i) = ( threshold_i + Σ_{j : alias_j = i} (1 − threshold_j) ) / N`,
//!
//! which equals `p_i` ([`AliasTable::implied_pmf`] recomputes it from the table).
//!
//! # Construction (Vose 1991, "A linear algorithm for generating random numbers with a
//! given distribution", IEEE TSE 17(9))
//! Repeatedly pair a *small* column (`q < 1`) with a *large* one (`q ≥ 1`): the small one's
//! threshold is its `q` and its alias the large one, which gives away `1 − q_small`:
//! `q_large ← (q_large + q_small) − 1`. Written this way the update adds first and
//! subtracts 1 last, which is exact for `1 ≤ sum < 2^53`; the naive
//! `q_large − (1 − q_small)` rounds `1 − q_small` and loses the small column's low bits.
//! Columns left over when one kind runs out have `q = 1` up to rounding: their threshold is
//! exactly 1 and their alias themselves. A zero power gets threshold 0, and since only large
//! columns ever serve as aliases, a zero-power light is never sampled.
//!
//! ## Where the rounding goes
//! Pairing conserves `Σ q` exactly in real arithmetic, so every rounding error that is not
//! itself conserved ends up on the last leftover column, whose relative error then grows
//! like `N·ε` (measured with the textbook build: 2·10⁻¹² at `N = 2^20`, 10⁻⁸ at `10^6` for
//! random real powers). Three measures conserve the total instead:
//! * the residue `Σ q_i − N` left by rounding `q_i = N·w_i/S` is summed exactly and diffused
//!   back over the large columns as whole-ulp nudges (`spread_residue`);
//! * the active large column's `q` is carried as a double-double (`TwoSum`), so a chain of
//!   donations rounds once, when the column turns small, not once per donation;
//! * that one rounding error is handed on to the next large column instead of dropped.
//!
//! The implied pmf then matches `p_i` to a few ulps for every light: measured worst relative
//! error 2.8·10⁻¹⁵ at `N = 1.6·10⁷` over integer, exponential and log-uniform powers.
//!
//! Instead of Vose's two work lists, two cursors sweep the array for the next small and the
//! next large column (no allocation beyond the outputs, sequential memory access).
//!
//! # The packed GPU form and the realized pmf
//! [`PackedAliasEntry`] holds the threshold as a `u32` `T_c` (`round(threshold·2^32)`,
//! saturating at `2^32 − 1`, and at least 1 for a positive threshold so every positive power
//! stays reachable) and the alias as a `u32`. Sampling ([`AliasTable::sample`], the default)
//! picks the column **exactly uniformly** with Lemire's nearly divisionless rejection
//! ([`crate::Uniform::sample`]: draw `r`, `m = r·N`, redraw while `m mod 2^32 < 2^32 mod N`,
//! column `⌊m/2^32⌋`; a multiply-high, exact for every `N < 2^32`, unlike `f32(u)·N` which
//! cannot reach every index past `2^24`), then keeps the column if the **next** draw
//! `r2 < T_c`, else yields its alias. Every column is accepted for exactly `⌊2^32/N⌋` draws,
//! and `r2` is a fresh draw, so the realized pmf is exactly the packed pmf
//!
//! `P(i) = ( T_i + Σ_{j : alias_j = i} (2^32 − T_j) ) / (N·2^32)`
//!
//! ([`AliasTable::implied_pmf_packed`]). Both the CPU and the GPU sample this way from the
//! same draws, so their picks agree bit for bit. The quantization moves each column's split
//! by at most `2^-32`, so `|P(i) − p_i| ≤ (1 + a_i)·2^-32 / N` (plus the `f64` table's own
//! error, ~10⁻¹⁵ relative), where `a_i` counts the columns aliasing to `i`.
//!
//! The raw column map [`AliasTable::column`] (`⌊r·N/2^32⌋` of one draw, no rejection) and
//! the two-draw [`AliasTable::sample_u32`] built on it stay available for the precision lab:
//! there `2^32 mod N` columns get one draw more than the others, which adds up to `2^-32`
//! absolute per column weight (`N·2^-32` relative, `2.3·10⁻⁴` at `N = 10^6`).

use crate::powers::{LightPowers, pow2_scale_to_unit};
use crate::rng::Rng;
use crate::uniform::Uniform;

/// One column of the packed alias table, as the GPU stores it (8 bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[repr(C)]
pub struct PackedAliasEntry {
    /// Keep probability of the column's own light, times `2^32` (saturating).
    pub threshold: u32,
    /// The light taken when the column is not kept.
    pub alias: u32,
}

/// Walker's alias table over a set of validated powers, with its exact `f64` form (for
/// reporting and analysis) and its packed `u32` form (for sampling on CPU and GPU).
#[derive(Clone, Debug, PartialEq)]
pub struct AliasTable {
    pmf: Vec<f64>,
    threshold: Vec<f64>,
    alias: Vec<u32>,
    packed: Vec<PackedAliasEntry>,
    /// The exact uniform column pick over `0..N` (holds Lemire's threshold `2^32 mod N`).
    columns: Uniform,
}

impl AliasTable {
    /// Builds the table in `O(N)` with Vose's algorithm in `f64`.
    ///
    /// The seed powers `2, 5, 20` give thresholds `6/27, 15/27, 1` and aliases `2, 2, 2`,
    /// each threshold the correctly rounded `f64` of its fraction.
    pub fn build(powers: &LightPowers) -> Self {
        let values = powers.as_slice();
        let n = values.len();
        let n_f = n as f64;
        let scale = pow2_scale_to_unit(powers.max());
        let sum = double_double_sum(values.iter().map(|&p| scale.apply(p))).0;
        let mut pmf = Vec::with_capacity(n);
        let mut q = Vec::with_capacity(n);
        for &p in values {
            let w = scale.apply(p);
            pmf.push(w / sum);
            // (w·N)/S rather than p·N: for integer powers w·N is exact, so q is correctly
            // rounded (2·3/27 is exactly the f64 nearest 6/27).
            q.push((w * n_f) / sum);
        }
        spread_residue(&mut q, n_f);
        let mut alias: Vec<u32> = (0..n as u32).collect();
        pair_columns(&mut q, &mut alias);
        let packed = q
            .iter()
            .zip(&alias)
            .map(|(&t, &a)| PackedAliasEntry {
                threshold: quantize_threshold(t),
                alias: a,
            })
            .collect();
        Self {
            pmf,
            threshold: q,
            alias,
            packed,
            columns: Uniform::new(n as u32),
        }
    }

    /// Number of lights (columns) `N`.
    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    /// Always `false`: a table has at least one column.
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// The normalized power `p_i = Φ_i / Σ Φ` of light `i`.
    pub fn pmf(&self, i: usize) -> f64 {
        self.pmf[i]
    }

    /// All normalized powers `p_i`.
    pub fn pmf_slice(&self) -> &[f64] {
        &self.pmf
    }

    /// Keep probability of each column, in `[0, 1]`.
    pub fn thresholds(&self) -> &[f64] {
        &self.threshold
    }

    /// Alias of each column: the light taken when the column is not kept.
    pub fn aliases(&self) -> &[u32] {
        &self.alias
    }

    /// The packed form the GPU uploads and both devices sample from.
    pub fn packed(&self) -> &[PackedAliasEntry] {
        &self.packed
    }

    /// The pmf the `f64` table realizes:
    /// `P(i) = (threshold_i + Σ_{alias_j = i} (1 − threshold_j)) / N`.
    pub fn implied_pmf(&self) -> Vec<f64> {
        let n = self.len() as f64;
        let mut mass = self.threshold.clone();
        for (&t, &a) in self.threshold.iter().zip(&self.alias) {
            mass[a as usize] += 1.0 - t;
        }
        mass.into_iter().map(|m| m / n).collect()
    }

    /// The pmf the packed `u32` table realizes, exactly as a rational `count / (N·2^32)`
    /// evaluated in `f64`: `P(i) = (t_i + Σ_{alias_j = i} (2^32 − t_j)) / (N·2^32)`.
    pub fn implied_pmf_packed(&self) -> Vec<f64> {
        let n = self.len();
        let mut mass = vec![0u64; n];
        for (i, e) in self.packed.iter().enumerate() {
            // The keep test is `r2 < t`, true for exactly t of the 2^32 values of r2.
            mass[i] += u64::from(e.threshold);
            mass[e.alias as usize] += (1u64 << 32) - u64::from(e.threshold);
        }
        let denom = n as f64 * 4_294_967_296.0;
        mass.into_iter().map(|m| m as f64 / denom).collect()
    }

    /// The exact column pick: draws from `rng` until one is accepted by Lemire's test and
    /// returns its column, each with probability exactly `1/N` ([`crate::Uniform::sample`]).
    #[inline]
    pub fn pick_column(&self, rng: &mut Rng) -> usize {
        self.columns.sample(rng) as usize
    }

    /// Lemire's rejection threshold `2^32 mod N` of the column pick.
    pub fn rejection_threshold(&self) -> u32 {
        self.columns.rejection_threshold()
    }

    /// Samples a light (the default, GPU-identical path): the exact column pick
    /// ([`AliasTable::pick_column`]), then the keep test on the next draw. Realized pmf:
    /// exactly [`AliasTable::implied_pmf_packed`] (see the module docs).
    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> u32 {
        let column = self.pick_column(rng);
        self.resolve(column, rng.next_u32())
    }

    /// The keep-or-alias step: column `column` yields its own light if `r2 < T_c`, else its
    /// alias.
    #[inline]
    pub fn resolve(&self, column: usize, r2: u32) -> u32 {
        let entry = self.packed[column];
        if r2 < entry.threshold {
            column as u32
        } else {
            entry.alias
        }
    }

    /// The raw column map `⌊r·N / 2^32⌋` of one draw (multiply-high, no rejection): uniform
    /// over `0..N` only up to one draw per column (`2^32 mod N` columns receive
    /// `⌊2^32/N⌋ + 1` draws, the rest `⌊2^32/N⌋`), a bias of up to `2^-32` absolute per column
    /// weight. Measured by the precision lab; [`AliasTable::pick_column`] is the exact pick.
    #[inline]
    pub fn column(&self, r: u32) -> usize {
        ((u64::from(r) * self.packed.len() as u64) >> 32) as usize
    }

    /// Samples a light from two 32-bit randoms with the raw column map
    /// ([`AliasTable::column`]`(r1)`, keep if `r2 < T_c`): the slightly biased mapping the
    /// precision lab measures (column weights `m_c/2^32`, `m_c ∈ {⌊2^32/N⌋, ⌈2^32/N⌉}`).
    /// Equal to [`AliasTable::sample`] whenever `r1` is accepted by Lemire's test (always
    /// when `N` is a power of two); the samplers use [`AliasTable::sample`].
    #[inline]
    pub fn sample_u32(&self, r1: u32, r2: u32) -> u32 {
        self.resolve(self.column(r1), r2)
    }

    /// Samples a light from one 32-bit random: the column is the high word of `r·N` and the
    /// keep test reuses the low word (the fraction of `u·N`) as the second random.
    ///
    /// A speed option, not the default. Its column is the **raw** multiply-high
    /// ([`AliasTable::column`], no rejection: columns differ by one in how many `r` values
    /// they receive), and within a column the low word only takes `⌊2^32/N⌋` or `⌈2^32/N⌉`
    /// values spaced `N` apart, so the realized pmf carries a bias of order `N·2^-32`
    /// relative (measured exactly by the precision lab) that the default
    /// [`AliasTable::sample`] does not have.
    #[inline]
    pub fn sample_one_random(&self, r: u32) -> u32 {
        let product = u64::from(r) * self.packed.len() as u64;
        let column = (product >> 32) as usize;
        let fraction = product as u32;
        let entry = self.packed[column];
        if fraction < entry.threshold {
            column as u32
        } else {
            entry.alias
        }
    }
}

/// Makes `Σ q_i = N` to a few ulps before pairing.
///
/// Pairing conserves `Σ q` exactly in real arithmetic, so whatever `Σ q_i − N` the rounding
/// of `q_i = N·w_i/S` leaves lands on the last leftover column, whose relative error would
/// grow like `N·ε`: the rounding of `S` scales every `q_i` alike, and repeated powers repeat
/// the same rounding error (measured before this step: 10⁻¹¹ at `N = 1.6·10⁷`). The residue
/// `R` is summed exactly ([`double_double_sum`]) and taken back from the large columns in
/// proportion to their size, `−R·q_i/Σ_{q_j ≥ 1} q_j`. Each such share is below an ulp, so
/// it is diffused: eight lanes carry what is not yet applied and release it as whole-ulp
/// nudges once it passes half an ulp (`q + carry` rounds to a neighbour of `q`). What stays
/// is at most about four ulps of 1 in total. Small columns (`q < 1`) are never touched, so
/// the carry can never swamp a small value.
pub(crate) fn spread_residue(q: &mut [f64], n: f64) {
    let mut large_mass = 0.0;
    let (total_hi, total_lo) = double_double_sum(q.iter().map(|&x| {
        large_mass += if x >= 1.0 { x } else { 0.0 };
        x
    }));
    let residue = (total_hi - n) + total_lo;
    if residue == 0.0 || large_mass == 0.0 {
        return;
    }
    let t = -residue / large_mass;
    let mut carry = [0.0f64; 8];
    for (i, x) in q.iter_mut().enumerate() {
        let q0 = *x;
        let large = q0 >= 1.0;
        let c = &mut carry[i & 7];
        *c += if large { q0 * t } else { 0.0 };
        let q1 = if large { q0 + *c } else { q0 };
        *c -= q1 - q0; // exact: 0 or one ulp of q0
        *x = q1;
    }
}

/// `Σ x_i` as a double-double `(hi, lo)`: eight independent `TwoSum` lanes (branch-free)
/// whose compensations are summed plainly; the error is that of adding the compensations,
/// negligible against one ulp of the total for any `N < 2^32`.
pub(crate) fn double_double_sum(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut hi = [0.0f64; 8];
    let mut lo = [0.0f64; 8];
    for (i, x) in values.enumerate() {
        let lane = i & 7;
        let (s, e) = two_sum(hi[lane], x);
        hi[lane] = s;
        lo[lane] += e;
    }
    let (mut total, mut comp) = (0.0, 0.0);
    for &x in hi.iter().chain(&lo) {
        let (s, e) = two_sum(total, x);
        total = s;
        comp += e;
    }
    two_sum(total, comp)
}

/// Vose's pairing on `q` (mean 1) in place: on return `q` holds the thresholds and `alias`
/// the aliases (`alias` must enter as the identity).
fn pair_columns(q: &mut [f64], alias: &mut [u32]) {
    let mut small_scan = 0;
    let mut large_scan = 0;
    let mut small = next_small(q, &mut small_scan);
    let mut large = next_large(q, &mut large_scan);
    // The active large column's q is carried as hi + lo (hi = q[l]) so that a long chain of
    // donations rounds once, when the column turns small, instead of once per donation. Only
    // `hi` is on the dependency chain; the exact error of each step goes into `lo`.
    let mut large_lo = 0.0f64;
    while let (Some(s), Some(l)) = (small, large) {
        alias[s] = l as u32;
        // (q_l + q_s) − 1 exactly: TwoSum gives q_l + q_s = sum + err, and sum − 1 is exact
        // for 1 ≤ sum < 2^53 (1 is a multiple of ulp(sum) and the result is representable).
        let (sum, err) = two_sum(q[l], q[s]);
        let hi = sum - 1.0;
        large_lo += err;
        let (value, rounding) = two_sum(hi, large_lo);
        if value < 1.0 {
            // The large column became small, its threshold the rounded hi + lo. The rounding
            // error goes on to the next large column rather than being dropped: dropped, the
            // errors of all columns would add up on the last leftover (systematically so when
            // powers repeat). If the small cursor already passed this column, handle it now;
            // otherwise the cursor finds it. A column that gave away all its mass can come
            // out a hair below 0 (the carried error of an earlier column): its threshold is
            // then 0 and the deficit is carried on like the rounding.
            q[l] = value.max(0.0);
            large_lo = rounding + value.min(0.0);
            small = if l < small_scan {
                Some(l)
            } else {
                next_small(q, &mut small_scan)
            };
            large = next_large(q, &mut large_scan);
        } else {
            // Still large. Keep the stored q ≥ 1 so the small cursor can never pick it up;
            // a hi just below 1 moves its (exact, by Sterbenz) excess into lo.
            if hi < 1.0 {
                large_lo += hi - 1.0;
                q[l] = 1.0;
            } else {
                q[l] = hi;
            }
            small = next_small(q, &mut small_scan);
        }
    }
    // Leftovers hold q = 1 up to rounding. Their threshold becomes exactly 1, alias self. A
    // small column left without a donor can only be a rounding remnant near 1; a zero one
    // cannot be (its deficit of 1 is far beyond rounding), but it is kept at 0 regardless.
    let mut last_large = large.unwrap_or(0);
    let mut tail = |i: usize, q: &mut [f64], alias: &mut [u32]| {
        if q[i] > 0.0 {
            q[i] = 1.0;
            alias[i] = i as u32;
            last_large = i;
        } else {
            alias[i] = last_large as u32;
        }
    };
    if let Some(l) = large {
        tail(l, q, alias);
        while let Some(l) = next_large(q, &mut large_scan) {
            tail(l, q, alias);
        }
    }
    if let Some(s) = small {
        tail(s, q, alias);
        while let Some(s) = next_small(q, &mut small_scan) {
            tail(s, q, alias);
        }
    }
}

/// Knuth's `TwoSum`: `a + b = s + e` exactly, `s = fl(a + b)`.
#[inline]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The next column at or after `*cursor` with `q < 1`; the cursor moves past it.
#[inline]
pub(crate) fn next_small(q: &[f64], cursor: &mut usize) -> Option<usize> {
    let found = q[*cursor..].iter().position(|&x| x < 1.0)? + *cursor;
    *cursor = found + 1;
    Some(found)
}

/// The next column at or after `*cursor` with `q ≥ 1`; the cursor moves past it.
#[inline]
pub(crate) fn next_large(q: &[f64], cursor: &mut usize) -> Option<usize> {
    let found = q[*cursor..].iter().position(|&x| x >= 1.0)? + *cursor;
    *cursor = found + 1;
    Some(found)
}

/// `round(t·2^32)` clamped to `[1, 2^32 − 1]` for `t > 0`, and 0 for `t = 0`.
fn quantize_threshold(t: f64) -> u32 {
    if t <= 0.0 {
        return 0;
    }
    let scaled = (t * 4_294_967_296.0).round();
    if scaled >= 4_294_967_295.0 {
        u32::MAX
    } else {
        (scaled as u32).max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(powers: &[f64]) -> AliasTable {
        AliasTable::build(&LightPowers::new(powers.to_vec()).unwrap())
    }

    #[test]
    fn seed_table_is_exact() {
        let t = table(&[2.0, 5.0, 20.0]);
        assert_eq!(t.thresholds(), &[6.0 / 27.0, 15.0 / 27.0, 1.0]);
        assert_eq!(t.aliases(), &[2, 2, 2]);
        assert_eq!(t.pmf_slice(), &[2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]);
    }

    #[test]
    fn seed_implied_pmf_matches() {
        let t = table(&[2.0, 5.0, 20.0]);
        for (implied, exact) in t.implied_pmf().iter().zip([2.0, 5.0, 20.0]) {
            assert!((implied - exact / 27.0).abs() <= 1e-15, "{implied}");
        }
    }

    #[test]
    fn exhausted_large_column_never_gets_a_negative_threshold() {
        // Found by proptest in CI: a large column left with exactly 0 of its own mass
        // received a negative carried rounding error (threshold −4.5e-17 before the fix).
        let tiny = f64::from_bits(1);
        let mut powers = vec![0.0; 95];
        for i in [9, 21, 39] {
            powers[i] = tiny;
        }
        powers[25] = 1.000_000_000_000_000_6e293;
        for i in [40, 41, 43, 44, 48, 53, 57, 67, 75, 78] {
            powers[i] = f64::MAX;
        }
        let t = table(&powers);
        assert!(t.thresholds().iter().all(|&x| (0.0..=1.0).contains(&x)));
        let implied = t.implied_pmf();
        for (i, (&got, &want)) in implied.iter().zip(t.pmf_slice()).enumerate() {
            assert!(
                (got - want).abs() <= 1e-12 * want + 1e-15 / 95.0,
                "light {i}"
            );
        }
    }

    #[test]
    fn one_light_is_always_picked() {
        let t = table(&[3.5]);
        assert_eq!(t.thresholds(), &[1.0]);
        assert_eq!(t.aliases(), &[0]);
        for r in [0, 1, u32::MAX / 2, u32::MAX] {
            assert_eq!(t.sample_u32(r, u32::MAX), 0);
            assert_eq!(t.sample_one_random(r), 0);
        }
    }

    #[test]
    fn zero_power_columns_always_alias_to_a_positive_light() {
        let t = table(&[0.0, 1.0, 0.0, 3.0]);
        for (i, e) in t.packed().iter().enumerate() {
            if i % 2 == 0 {
                assert_eq!(e.threshold, 0);
                assert_ne!(e.alias as usize % 2, 0);
            }
        }
    }

    #[test]
    fn quantization_rounds_and_keeps_positive_thresholds_reachable() {
        assert_eq!(quantize_threshold(0.0), 0);
        assert_eq!(quantize_threshold(1e-300), 1);
        assert_eq!(quantize_threshold(0.5), 1 << 31);
        assert_eq!(quantize_threshold(1.0), u32::MAX);
        assert_eq!(quantize_threshold(1.0 - 1e-12), u32::MAX);
    }

    #[test]
    fn multiply_high_reaches_every_column() {
        let t = table(&[1.0; 5]);
        let first_r = |c: u64| (c << 32).div_ceil(5) as u32;
        for c in 0..5 {
            assert_eq!(t.column(first_r(c)), c as usize);
        }
        assert_eq!(t.column(u32::MAX), 4);
    }
}
