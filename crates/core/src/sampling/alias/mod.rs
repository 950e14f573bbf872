//! Walker's alias method: two constructions of one table, and its sampling paths.
//!
//! # The table
//! For `N` lights with pmf `p_i`, column `i` keeps light `i` with probability
//! `threshold_i` and otherwise yields `alias_i`. Sampling picks a column uniformly
//! (probability `1/N`), then keeps or aliases, so the pmf the table realizes is
//!
//! `P(i) = ( threshold_i + Σ_{j : alias_j = i} (1 − threshold_j) ) / N`.
//!
//! # Two constructions: the speed/accuracy trade, made explicit ([`Construction`])
//! * [`Construction::Integer`] (the default, [`AliasTable::build`]): the powers are
//!   quantized to integer masses `m_i` that sum to exactly `N·2^32`, then an exact integer
//!   sweep builds the packed table (`integer/`). The table realizes **exactly** the pmf
//!   `m_i/(N·2^32)`, with `|m_i/(N·2^32) − p_i| ≤ (1 + a_i)·2^-32/N` (`a_i` columns alias to
//!   `i`) and `< 2^-32/N` for every light unless some `p_i < 2^-32/N` (whose columns take
//!   one unit from their alias to stay reachable), for every `N` up to `2^31 − 1` and every
//!   valid power set (checked against exact big-integer arithmetic in
//!   `integer/exactness.rs`). 8 bytes per light; no `f64` table is
//!   stored: [`AliasTable::thresholds`] and [`AliasTable::pmf_slice`] are derived from the
//!   packed table on first use, so what they show is what is sampled.
//! * [`Construction::Exact`] ([`AliasTable::build_exact`]): Vose's pairing in `f64` with
//!   double-double carries (`exact.rs`). Its `f64` table implies `p_i` within `10^-12`
//!   relative (a few ulps in practice) — the worked example's powers `2, 5, 20` give thresholds
//!   `6/27, 15/27, 1` and aliases `2, 2, 2` exactly, which the classroom views show — and
//!   its packed form is that table quantized (within `(1 + a_i)·2^-32/N`). Several times
//!   slower to build (docs/numbers.md) and 28 bytes per light.
//!
//! Both sample through the same packed form, on the CPU and in WGSL.
//!
//! # The packed form and the realized pmf
//! [`PackedAliasEntry`] holds the threshold as a `u32` `T_c` and the alias as a `u32`.
//! Sampling ([`AliasTable::sample`], the default) picks the column **exactly uniformly**
//! with Lemire's nearly divisionless rejection ([`crate::Uniform::sample`]: draw `r`,
//! `m = r·N`, redraw while `m mod 2^32 < 2^32 mod N`, column `⌊m/2^32⌋`; a multiply-high,
//! exact for every `N < 2^32`, unlike `f32(u)·N` which cannot reach every index past
//! `2^24`), then keeps the column if the **next** draw `r2 < T_c`, else yields its alias.
//! Every column is accepted for exactly `⌊2^32/N⌋` draws and `r2` is a fresh draw, so the
//! realized pmf is exactly the packed pmf
//!
//! `P(i) = ( T_i + Σ_{j : alias_j = i} (2^32 − T_j) ) / (N·2^32)`
//!
//! ([`AliasTable::implied_pmf_packed`]). Both the CPU and the GPU sample this way from the
//! same draws, so their picks agree bit for bit; [`AliasTable::sample_into`] fills a batch
//! with exactly the picks of repeated [`AliasTable::sample`] calls on the same stream.
//!
//! The raw column map [`AliasTable::column`] (`⌊r·N/2^32⌋` of one draw, no rejection) and
//! the two-draw [`AliasTable::sample_u32`] built on it stay available for the precision lab:
//! there `2^32 mod N` columns get one draw more than the others, which adds up to `2^-32`
//! absolute per column weight (`N·2^-32` relative, `2.3·10⁻⁴` at `N = 10^6`).

mod batch;
mod exact;
mod integer;
mod packed;
mod pages;

use std::sync::OnceLock;

use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::uniform::Uniform;

pub(crate) use exact::{double_double_sum, next_large, next_small, spread_residue, two_sum};
pub use packed::PackedAliasEntry;

/// How an [`AliasTable`] is built: the trade between build speed and how closely the table
/// realizes `p_i` (module docs).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Construction {
    /// Exact integer masses summing to `N·2^32` and an exact integer sweep: the fastest
    /// build, realizing `p_i` within `(1 + a_i)·2^-32/N` (`2^-32/N` unless some
    /// `p_i < 2^-32/N`). The default.
    #[default]
    Integer,
    /// Vose in `f64` with double-double carries: an `f64` table within `10^-12` relative
    /// of `p_i` (exact fractions such as 6/27), quantized for sampling.
    Exact,
}

impl Construction {
    /// Both constructions, fastest first.
    pub const ALL: [Construction; 2] = [Construction::Integer, Construction::Exact];

    /// The name used by the CLI and the JSON output (`integer`, `exact`).
    pub fn name(self) -> &'static str {
        match self {
            Construction::Integer => "integer",
            Construction::Exact => "exact",
        }
    }
}

impl std::str::FromStr for Construction {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "integer" => Ok(Construction::Integer),
            "exact" => Ok(Construction::Exact),
            other => Err(format!(
                "unknown construction '{other}' (expected integer or exact)"
            )),
        }
    }
}

impl std::fmt::Display for Construction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The `f64` views of an integer-built table, derived from its packed form on first use.
#[derive(Clone, Debug)]
struct DerivedViews {
    threshold: Vec<f64>,
    alias: Vec<u32>,
    pmf: Vec<f64>,
}

/// Walker's alias table over a set of validated powers: the packed `u32` form both devices
/// sample from, and its `f64` views (stored by the exact construction, derived on demand
/// for the integer one).
#[derive(Clone, Debug)]
pub struct AliasTable {
    /// One [`PackedAliasEntry`] per column, stored as its 8 bytes.
    words: Vec<u64>,
    /// The exact uniform column pick over `0..N` (holds Lemire's threshold `2^32 mod N`).
    columns: Uniform,
    construction: Construction,
    /// The `f64` table of the exact construction (empty for the integer one).
    exact: exact::ExactParts,
    /// The integer construction's `f64` views, computed when first asked for.
    derived: OnceLock<DerivedViews>,
    /// The integer sweep's bitmap of large lights (one bit per light), kept after a
    /// rebuild so the next one allocates nothing (empty after a fresh build).
    heavy: Vec<u64>,
}

impl PartialEq for AliasTable {
    /// Two tables are equal when they sample alike and report the same `f64` table.
    fn eq(&self, other: &Self) -> bool {
        self.construction == other.construction
            && self.words == other.words
            && self.exact == other.exact
    }
}

impl AliasTable {
    /// Builds the table with the default, fastest construction
    /// ([`Construction::Integer`]; the exact one beyond `2^31 − 1` lights). `O(N)`, on the
    /// current rayon pool: the passes work on fixed chunks of 16384 lights and the sweep is
    /// cut at states of the sequential sweep, so the table is bit for bit the one a single
    /// thread builds, whatever the pool's size.
    pub fn build(powers: &LightPowers) -> Self {
        Self::build_with(powers, Construction::Integer)
    }

    /// Builds the table with the exact `f64` construction ([`Construction::Exact`]): the
    /// seed powers `2, 5, 20` give thresholds `6/27, 15/27, 1` and aliases `2, 2, 2`, each
    /// threshold the correctly rounded `f64` of its fraction.
    pub fn build_exact(powers: &LightPowers) -> Self {
        Self::build_with(powers, Construction::Exact)
    }

    /// Builds the table with the given construction.
    pub fn build_with(powers: &LightPowers, construction: Construction) -> Self {
        let mut table = Self {
            words: Vec::new(),
            columns: Uniform::new(1),
            construction,
            exact: exact::ExactParts::default(),
            derived: OnceLock::new(),
            heavy: Vec::new(),
        };
        table.rebuild(powers);
        // A one-off table keeps only what it samples with (8 bytes per light); the sweep's
        // bitmap comes back on the first rebuild and stays for the next.
        table.heavy = Vec::new();
        table
    }

    /// Rebuilds the table in place for new `powers`, with the same construction, reusing
    /// every buffer: when `N` is unchanged nothing is allocated (what the app does while a
    /// power is dragged), except the integer sweep's bitmap (one bit per light) on the first
    /// rebuild of a freshly built table.
    pub fn rebuild(&mut self, powers: &LightPowers) {
        let n = powers.len();
        self.columns = Uniform::new(n as u32);
        self.derived = OnceLock::new();
        if self.construction == Construction::Integer && n <= integer::MAX_LEN {
            self.exact = exact::ExactParts::default();
            integer::build(powers.as_slice(), &mut self.words, &mut self.heavy);
        } else {
            exact::build(powers, &mut self.exact, &mut self.words);
        }
    }

    /// The construction this table was built with.
    pub fn construction(&self) -> Construction {
        self.construction
    }

    /// Number of lights (columns) `N`.
    pub fn len(&self) -> usize {
        self.words.len()
    }

    /// Always `false`: a table has at least one column.
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
    }

    /// Whether the `f64` table is stored (exact construction) rather than derived.
    fn has_exact_parts(&self) -> bool {
        !self.exact.threshold.is_empty()
    }

    fn derived(&self) -> &DerivedViews {
        self.derived.get_or_init(|| {
            let (threshold, alias) = self
                .packed()
                .iter()
                .enumerate()
                .map(|(i, e)| {
                    let full = e.threshold == u32::MAX && e.alias as usize == i;
                    let t = if full {
                        1.0
                    } else {
                        f64::from(e.threshold) * (1.0 / 4_294_967_296.0)
                    };
                    (t, e.alias)
                })
                .unzip();
            DerivedViews {
                threshold,
                alias,
                pmf: self.implied_pmf_packed(),
            }
        })
    }

    /// The probability of light `i`: the normalized power `p_i = Φ_i / Σ Φ` for the exact
    /// construction; for the integer one the pmf its packed table realizes exactly,
    /// `m_i/(N·2^32)` (within `(1 + a_i)·2^-32/N` of `p_i`), so an estimator dividing by it
    /// is unbiased for the picks it gets.
    pub fn pmf(&self, i: usize) -> f64 {
        self.pmf_slice()[i]
    }

    /// All probabilities [`AliasTable::pmf`].
    pub fn pmf_slice(&self) -> &[f64] {
        if self.has_exact_parts() {
            &self.exact.pmf
        } else {
            &self.derived().pmf
        }
    }

    /// Keep probability of each column, in `[0, 1]` (the integer construction's `T/2^32`,
    /// and exactly 1 for its full columns).
    pub fn thresholds(&self) -> &[f64] {
        if self.has_exact_parts() {
            &self.exact.threshold
        } else {
            &self.derived().threshold
        }
    }

    /// Alias of each column: the light taken when the column is not kept.
    pub fn aliases(&self) -> &[u32] {
        if self.has_exact_parts() {
            &self.exact.alias
        } else {
            &self.derived().alias
        }
    }

    /// The packed form the GPU uploads and both devices sample from.
    pub fn packed(&self) -> &[PackedAliasEntry] {
        bytemuck::cast_slice(&self.words)
    }

    /// The pmf the `f64` table realizes:
    /// `P(i) = (threshold_i + Σ_{alias_j = i} (1 − threshold_j)) / N`.
    ///
    /// Each light's sum is accumulated as a double-double (`TwoSum`), so what is measured is
    /// the table, not the rounding of the measurement: a light that `10^4` columns alias to
    /// would otherwise gain `10^4` roundings of its running sum (`4·10⁻¹²` relative, seen on
    /// log-normal powers), more than the table's own error.
    pub fn implied_pmf(&self) -> Vec<f64> {
        let n = self.len() as f64;
        let threshold = self.thresholds();
        let mut hi = threshold.to_vec();
        let mut lo = vec![0.0f64; hi.len()];
        for (&t, &a) in threshold.iter().zip(self.aliases()) {
            // 1 − t exactly as d + de, then added to the light's running double-double.
            let (d, de) = two_sum(1.0, -t);
            let (s, e) = two_sum(hi[a as usize], d);
            hi[a as usize] = s;
            lo[a as usize] += e + de;
        }
        hi.into_iter().zip(lo).map(|(h, l)| (h + l) / n).collect()
    }

    /// The pmf the packed `u32` table realizes, exactly as a rational `count / (N·2^32)`
    /// evaluated in `f64`: `P(i) = (t_i + Σ_{alias_j = i} (2^32 − t_j)) / (N·2^32)`.
    pub fn implied_pmf_packed(&self) -> Vec<f64> {
        self.packed_probabilities(self.packed_masses())
    }

    /// Masses out of `N·2^32` as probabilities, each rounded once.
    fn packed_probabilities(&self, masses: Vec<u64>) -> Vec<f64> {
        let denom = self.len() as f64 * 4_294_967_296.0;
        masses.into_iter().map(|m| m as f64 / denom).collect()
    }

    /// The exact integer mass each light receives from the packed table, out of `N·2^32`:
    /// `t_i + Σ_{alias_j = i} (2^32 − t_j)` (the keep test `r2 < t` is true for exactly `t`
    /// of the `2^32` values of `r2`).
    pub fn packed_masses(&self) -> Vec<u64> {
        let mut mass = vec![0u64; self.len()];
        for (i, e) in self.packed().iter().enumerate() {
            let (kept, given) = e.masses();
            mass[i] += kept;
            mass[e.alias as usize] += given;
        }
        mass
    }

    /// [`AliasTable::implied_pmf_packed`] of the lights in `range` alone, bit for bit, with
    /// memory for those lights only: one pass over every column, `O(N)` time (a view of a
    /// few hundred lights of a large table need not hold a pmf of `N`).
    ///
    /// # Panics
    /// If `range` reaches past the last light.
    pub fn implied_pmf_packed_of(&self, range: std::ops::Range<usize>) -> Vec<f64> {
        assert!(
            range.end <= self.len(),
            "lights {range:?} of {}",
            self.len()
        );
        let mut mass = vec![0u64; range.len()];
        for (j, e) in self.packed().iter().enumerate() {
            let (kept, given) = e.masses();
            if range.contains(&j) {
                mass[j - range.start] += kept;
            }
            let alias = e.alias as usize;
            if range.contains(&alias) {
                mass[alias - range.start] += given;
            }
        }
        self.packed_probabilities(mass)
    }

    /// The packed table's probability of each group of `per` consecutive lights (the last
    /// group may hold fewer): the exact integer mass of the group, `Σ` of
    /// [`AliasTable::packed_masses`] over its lights (at most `N·2^32 ≤ 2^56`, exact in
    /// `u64`), over `N·2^32`, rounded once; one pass, memory per group only.
    ///
    /// # Panics
    /// If `per` is 0.
    pub fn packed_group_pmf(&self, per: usize) -> Vec<f64> {
        assert!(per > 0, "groups of at least one light");
        let mut mass = vec![0u64; self.len().div_ceil(per)];
        // A column's own light is in the group being walked; its alias's group takes a
        // division, by multiplication (a hardware division per column cost as much as the
        // rest of the pass).
        let group_of = GroupOf::new(per);
        for (g, columns) in self.packed().chunks(per).enumerate() {
            for e in columns {
                let (kept, given) = e.masses();
                mass[g] += kept;
                mass[group_of.index(e.alias)] += given;
            }
        }
        self.packed_probabilities(mass)
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
        let entry: PackedAliasEntry = bytemuck::cast(self.words[column]);
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
        ((u64::from(r) * self.words.len() as u64) >> 32) as usize
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
        let product = u64::from(r) * self.words.len() as u64;
        let column = (product >> 32) as usize;
        self.resolve(column, product as u32)
    }
}

/// `⌊i / d⌋` for `i < 2^32` by one multiplication: `⌊c·i / 2^64⌋` with `c = ⌈2^64 / d⌉`,
/// exact for every `i < 2^32` when `2 ≤ d < 2^32` (Lemire, Kaser & Kurz, "Faster remainder by
/// direct computation", 2019, with `N = 32` and `F = 64`); `d = 1` is the identity.
#[derive(Clone, Copy, Debug)]
struct GroupOf {
    /// `⌈2^64 / d⌉`, or 0 for `d = 1`.
    c: u64,
}

impl GroupOf {
    /// The division by `d` (`1 ≤ d < 2^32`; a larger `d` is clamped to `2^32 − 1`, which
    /// puts every index below it in group 0).
    fn new(d: usize) -> Self {
        let d = d.min(u32::MAX as usize) as u64;
        Self {
            c: if d <= 1 { 0 } else { u64::MAX / d + 1 },
        }
    }

    /// `⌊i / d⌋`.
    #[inline]
    fn index(self, i: u32) -> usize {
        if self.c == 0 {
            i as usize
        } else {
            ((u128::from(self.c) * u128::from(i)) >> 64) as usize
        }
    }
}

#[cfg(test)]
mod tests;

impl AliasTable {
    /// Column `column`'s keep probability, [`AliasTable::thresholds`]`()[column]`, read from
    /// the stored `f64` table or the packed entry without deriving the `f64` views of an
    /// integer-built table (20 bytes per light) for a panel that shows a few columns.
    pub fn threshold(&self, column: usize) -> f64 {
        if self.has_exact_parts() {
            return self.exact.threshold[column];
        }
        let e = self.packed()[column];
        if e.threshold == u32::MAX && e.alias as usize == column {
            1.0
        } else {
            f64::from(e.threshold) * (1.0 / 4_294_967_296.0)
        }
    }

    /// Column `column`'s alias, [`AliasTable::aliases`]`()[column]`, without deriving the
    /// `f64` views ([`AliasTable::threshold`]).
    pub fn alias(&self, column: usize) -> u32 {
        if self.has_exact_parts() {
            self.exact.alias[column]
        } else {
            self.packed()[column].alias
        }
    }

    /// Heap bytes the table holds, by capacity: the packed words (8 bytes per light), the
    /// integer sweep's bitmap kept for the next rebuild, the exact construction's `f64`
    /// table, and the `f64` views of an integer-built table once something derived them
    /// ([`AliasTable::thresholds`], [`AliasTable::aliases`], [`AliasTable::pmf_slice`]: 20
    /// bytes per light).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        let exact = &self.exact;
        let derived = self.derived.get().map_or(0, |d| {
            (d.threshold.capacity() + d.pmf.capacity()) * size_of::<f64>()
                + d.alias.capacity() * size_of::<u32>()
        });
        self.words.capacity() * size_of::<u64>()
            + self.heavy.capacity() * size_of::<u64>()
            + (exact.threshold.capacity() + exact.pmf.capacity()) * size_of::<f64>()
            + exact.alias.capacity() * size_of::<u32>()
            + derived
    }
}
