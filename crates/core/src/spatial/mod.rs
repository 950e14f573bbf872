//! Contribution-aware light selection ("beyond power"): pick light `i` at a shading point
//! `x` of the receiver in proportion to (a bound on) what it contributes there, not just to
//! its power.
//!
//! # The target
//! The irradiance at `x` is `E(x) = Φ_total · Σ_i p_i·G_i(x)` with `p_i = Φ_i/Φ_total` and
//! `G_i(x) = max(0, cos θ)/(4π r²)` ([`crate::scene::geometry_term`]). A pick with pmf
//! `P(i | x)` gives the normalized estimate (see [`crate::render`])
//!
//! `ê = p_i·G_i(x) / P(i | x)`,  `E[ê] = Σ_{i: P(i|x) > 0} p_i·G_i(x)`,
//!
//! unbiased as long as `P(i | x) > 0` wherever `p_i·G_i(x) > 0`.
//!
//! * [`ExactSampler`] (for `N ≤` [`EXACT_MAX_LIGHTS`]): `P(i | x) = p_i·G_i(x) / Σ_j p_j·G_j(x)`,
//!   so `ê = Σ_j p_j·G_j(x)` for every pick: a **zero-variance** estimator for this
//!   unoccluded model (with shadows it would no longer be). It costs `O(N)` per shading
//!   point: all `N` contributions are evaluated, which is the exact answer already; the pick
//!   matters only once visibility enters.
//! * [`LightTree`] (larger `N`): a 4-wide tree over the lights with leaf clusters of up to
//!   [`LEAF_SIZE`] lights, descended stochastically from the root choosing a child in
//!   proportion to the importance of its representative light ([`importance`]: the child's
//!   power at its power-weighted centroid, mixed with a share of plain power), then a light
//!   of the leaf cluster in proportion to its exact contribution; `P(i | x)` is the product
//!   of the realized branch probabilities. About `log4(N/8) + 1` draws per pick.
//!
//! [`SpatialSampler`] chooses between the two by `N`. Only lights that can contribute at all
//! enter either sampler: power `> 0`, height `z > 0` (a light on or below the plane has
//! `G ≡ 0`) and, for a spot or a light with a range, an emission that reaches the plane
//! ([`Emission::reaches_plane`]). So zero-power lights are never picked, and a scene whose
//! every light is below the plane gives `ê = 0` without a pick ([`SpatialSampler::sample`]
//! returns `None`).
//!
//! # Spots and ranges
//! With emission profiles the contribution is `c_i(x) = p_i·G_i(x)·S_i(x)`
//! ([`crate::scene::light_term`]): the exact pick and the leaf clusters evaluate it as it is.
//! A tree over such lights splits them by where they shine, weighs each lane by a map of
//! what it gives the plane ([`grid`], where the choice is measured against pbrt-v4's and
//! Cycles' bounds) and culls a lane whose bounds (pbrt-v4's `LightBounds`, see
//! [`LightTree`]'s docs) cannot reach `x`.
//!
//! # Per-tile cuts: the top of the descent decided once per tile
//! A descent from the root costs 10–22 alias picks: one importance per lane and level, then
//! every light of a leaf. The receiver is one plane with a known pixel grid, so
//! [`SpatialSampler::for_scene`] cuts the tree once per tile of pixels (lightcuts and
//! stochastic lightcuts cut a tree once per region): [`TileCuts`] keeps, per tile, up to 256
//! entries (subtrees, and single lights taken out of their leaf clusters: a spot only where
//! its cone's edge does not cross the tile) weighed once for the whole tile by what each is
//! estimated to give the tile's nine weighing points (a single light or a leaf cluster
//! exactly, a lane by its representative light or its map); a group of point lights whose
//! bound ([`TreeNode::lane_bound`]) says it may give the tile far more than its
//! representative light does is split first. A pick draws one entry by the tile's alias
//! columns (one
//! word and one entry read) and descends below it at `x` as before; a single light costs no
//! descent at all. The pdf stays exact (the entry's grid probability times the descent's)
//! and positive wherever a light contributes. Weighed so, a cut replaces the tree's top
//! levels, whose errors compound from level to level, by one comparison of estimates that
//! get better as the cut gets finer: its variance falls well below the tree's on point
//! lights. Exact variances over 24 × 24 points off the pixel centres (× below power
//! sampling; in brackets, over the tree without cuts) and time per pixel sample (one
//! thread, every tile cut beforehand, over the alias table's) at 128 × 128 pixels, from
//! `cargo run --release -p lightpick-core --example tile_cuts -- equal heavy-tail grid stage
//! gallery random.json arena.json clusters-low.json chandeliers.json strips.json million`
//! (one run; the files written by `cargo run --release -p lightpick-core --example
//! tree_variance -- --write .`; `clusters-low`: 24 clusters of 400 lights 5–30 cm above the
//! plane, `chandeliers`: 100 of 100 lights 0.5–1 m up, `strips`: 40 lines of 250 lights
//! 10 cm up, sets no preset resembles):
//!
//! | pick | `equal` | `heavy-tail` | `grid` | `stage` | `gallery` | `random` | `arena` | `clusters-low` | `chandeliers` | `strips` |
//! | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |
//! | the tree from its root | 60× (1.00), 8.4× | 177× (1.00), 17.1× | 251× (1.00), 13.5× | 151× (1.00), 12.6× | 4366× (1.00), 9.0× | 156× (1.00), 18.9× | 195× (1.00), 19.2× | 11× (1.00), 17.1× | 46× (1.00), 17.0× | 16× (1.00), 17.0× |
//! | cuts as first built: ≤ 64 entries, spread ≤ 1.25, weighed by the tree's probabilities alone | 60× (1.00), 2.0× | 173× (1.02), 9.1× | 236× (1.06), 6.0× | 158× (0.96), 3.3× | 3048× (1.43), 4.6× | 151× (1.03), 6.8× | 198× (0.98), 6.6× | 11× (0.97), 9.8× | 45× (1.01), 8.7× | 13× (1.25), 10.3× |
//! | **built: ≤ 256 entries, the rest as the row below** | **891× (0.07), 1.2×** | **1233× (0.14), 6.9×** | **1317× (0.19), 2.0×** | **416× (0.36), 2.7×** | **2551× (1.71), 2.9×** | **288× (0.54), 3.4×** | **512× (0.38), 4.8×** | **291× (0.04), 6.1×** | **610× (0.08), 6.2×** | **298× (0.05), 5.4×** |
//! | the same, ≤ 128 entries (in the same run) | 891× (0.07), 1.2× | 1139× (0.16), 7.6× | 1323× (0.19), 1.9× | 416× (0.36), 2.7× | 2551× (1.71), 2.9× | 263× (0.59), 4.6× | 465× (0.42), 4.3× | 291× (0.04), 7.2× | 411× (0.11), 7.6× | 232× (0.07), 6.0× |
//! | built before, the rows below its variants: ≤ 128 entries, spread ≤ 4 (point lights) or 1.6 (spots), weighed by estimates, groups above the tile split by their bounds, a leaf cluster split where each of its lights that reaches the tile lights its nine weighing points within a tenth of its brightest | 891× (0.07), 2.0× | 1139× (0.16), 7.6× | 1323× (0.19), 2.6× | 406× (0.37), 3.2× | 2548× (1.71), 3.3× | 262× (0.59), 4.9× | 463× (0.42), 4.6× | 291× (0.04), 7.3× | 411× (0.11), 7.0× | 232× (0.07), 6.0× |
//! | the same, ≤ 64 entries | 891× (0.07), 2.0× | 1042× (0.17), 8.9× | 860× (0.29), 2.9× | 401× (0.38), 3.2× | 2548× (1.71), 3.3× | 213× (0.73), 6.5× | 445× (0.44), 5.4× | 347× (0.03), 9.0× | 221× (0.21), 8.3× | 31× (0.53), 7.8× |
//! | the same, spread ≤ 1.25 | 891× (0.07), 2.0× | 1139× (0.16), 7.7× | 382× (0.66), 6.2× | 276× (0.55), 3.6× | 3762× (1.16), 5.0× | 206× (0.76), 5.0× | 238× (0.82), 6.9× | 9× (1.20), 9.3× | 409× (0.11), 6.9× | 9× (1.90), 10.1× |
//! | the same, spread ≤ 1.6 | 891× (0.07), 2.1× | 1139× (0.16), 7.8× | 1317× (0.19), 2.5× | 406× (0.37), 3.2× | 2548× (1.71), 3.3× | 262× (0.59), 5.0× | 463× (0.42), 4.5× | 43× (0.25), 7.8× | 411× (0.11), 6.9× | 9× (1.80), 7.7× |
//! | the same, spread ≤ 4 | 891× (0.07), 2.0× | 1139× (0.16), 7.6× | 1323× (0.19), 2.5× | 408× (0.37), 3.1× | 1476× (2.96), 2.5× | 262× (0.59), 5.1× | 483× (0.40), 4.4× | 291× (0.04), 7.2× | 411× (0.11), 6.9× | 232× (0.07), 6.0× |
//! | the same, the tree's share 0.1 | 701× (0.09), 2.0× | 1079× (0.16), 7.7× | 1185× (0.21), 2.6× | 395× (0.38), 3.2× | 2519× (1.73), 3.4× | 260× (0.60), 5.0× | 456× (0.43), 4.5× | 269× (0.04), 7.4× | 368× (0.12), 7.1× | 236× (0.07), 6.2× |
//! | the same, the tree's share ¼ | 425× (0.14), 2.0× | 868× (0.20), 7.7× | 925× (0.27), 2.7× | 364× (0.42), 3.2× | 2466× (1.77), 3.3× | 254× (0.61), 5.0× | 428× (0.46), 4.6× | 229× (0.05), 7.5× | 277× (0.17), 7.2× | 225× (0.07), 6.4× |
//! | the same, the tree's share 0.5 | 198× (0.30), 2.0× | 509× (0.35), 7.7× | 583× (0.43), 2.9× | 294× (0.51), 3.2× | 2365× (1.85), 3.4× | 234× (0.66), 5.1× | 359× (0.54), 4.6× | 162× (0.07), 7.7× | 158× (0.29), 7.4× | 187× (0.09), 6.8× |
//! | the same, leaf clusters kept whole | 54× (1.11), 4.8× | 1069× (0.17), 7.8× | 402× (0.62), 4.7× | 259× (0.58), 4.5× | 2548× (1.71), 3.8× | 166× (0.94), 5.5× | 449× (0.43), 6.0× | 296× (0.04), 7.1× | 484× (0.09), 6.8× | 231× (0.07), 6.1× |
//!
//! The first two rows are this version's, from one run of the command without `million`
//! (whose cuts keep 64 entries); the rows below them come from earlier runs of earlier
//! versions, whose single-light picks cost more. Where a tile's lights reach past 128
//! entries the cut now grows to 256, and its picks (every tile cut beforehand) cost less
//! with less variance: `random` 4.6 → 3.4 alias picks (0.39 → 0.59 of its cuts' mass on
//! single lights, 0.59× → 0.54× the tree's variance), `chandeliers` 7.6 → 6.2 (0.11× →
//! 0.08×), `clusters-low` 7.2 → 6.1, `heavy-tail` 7.6 → 6.9, `strips` 6.0 → 5.4; `stage`
//! and `gallery`, whose spread ends their cuts at 41 and 6 entries a tile, do not change.
//! Cutting costs more, once per tree and receiver: every tile of those sets in 92–280 ms
//! on two threads against 40–99 ms (`random` 280 against 99); at `lightpick bench`'s 1024
//! samples a pixel the picks' saving outweighs it (`docs/numbers.md`). At 512 entries
//! `random` reached 2.8 alias picks, but its cuts took 1.2 s: each split looks for the next
//! among all the entries. An alias column keeps its threshold in the low `log2 C` bits and
//! its alias above them (`C = 2^24/K` cells a column), so a word holds any count.
//!
//! On `million` (10^6 lights, cuts of at most 64 entries above 2^18 lights, 6 × 6 points)
//! the built cuts give 1443× below power (0.11× the tree's variance) at 3.6× alias's time
//! (an alias pick there waits on a cache miss per light, 201 ns a pixel sample in this
//! run), against 186× (0.87) for the cuts weighed by the tree's probabilities alone and
//! 1118× (0.14) with the tree's share ¼. The spread limits: point lights' shares change
//! smoothly across a tile, and a spread of 4 lets the cut reach the lights of a strip or a
//! cluster near the plane (`strips` 231× against 9× at 1.25 and 1.6, `clusters-low` 296×
//! against 43× at 1.6); spots' maps are cell means that a cone's edge crossing the tile
//! makes a poor guide, and `gallery`'s variance grows with the spread (1.16×, 1.71×,
//! 2.96× the tree's at 1.25, 1.6, 4) where `arena`'s falls (0.82×, 0.44×, 0.42×, its picks
//! 8.1, 5.8, 5.8 alias picks): 1.6 keeps `gallery` within 1.25× of the variance of the
//! cuts as first built and doubles `arena`'s efficiency. Until the cut split the groups
//! hanging over a tile by their bounds, a quarter of each weight came from the tree's own
//! probabilities: without it `clusters-low` had 2.4× the tree's variance, with it 1.3×,
//! one point beneath a group of 600 lights holding 95 % of it. With the bounds that set has
//! 0.04×, and the quarter only costs the others their gain (`equal` 0.14× against 0.07×,
//! `heavy-tail` 0.21× against 0.16×, `chandeliers` 0.17× against 0.11×); `grid` alone
//! keeps a little more (0.61× against 0.64×). Another draw of the `clusters-low` recipe
//! (made outside the repository, with Python's `random` instead of `SplitMix`) gave 164×
//! below power (0.12×) before the bounds. What the
//! cut does not change is the work below an entry: a pick there still descends (a node's
//! importances, a leaf's contributions), so a pick costs 2.0 alias picks where the cut
//! reaches single lights (`equal`), 2.6 on `grid`, whose cuts hold 92 % of their mass on
//! single lights, and 3.2–7.6 elsewhere. A leaf cluster splits into its lights where each
//! of them that reaches the tile lights its nine weighing points within a tenth of its
//! brightest there, a spot whose cone or range misses the whole tile being left out (the
//! module docs of `tile_cut` give the rules measured, each in one run): under the rule
//! before it (within half, and no cone's edge across the tile) `grid` had 0.64× the tree's
//! variance at 4.6 alias picks, now 0.19× at 2.5; `stage` 0.58× at 4.2, now 0.37× at 3.2;
//! `random` 0.93× at 6.8, now 0.59× at 4.9; `arena` 0.44× at 5.7, now 0.42× at 4.6;
//! `gallery` 1.71× at 3.8, now 1.71× at 3.3; every point-light scene but `grid` kept its
//! variance and its time. Since then a cluster that does not split keeps only its core
//! whole (its lights from the first that is not that flat to the last, lit at a weighing
//! point), its flat lights before and after the core entering alone: `stage` 477× → 535×
//! below power, `random` 281× → 389×, `arena` 537× → 519×, `gallery` 2510× → 2398×
//! (`tree_variance` example), a pick evaluating 1.6–1.8 lights of the cut's clusters
//! where it evaluated 3.1 on `stage` and `arena` ("A cluster's flat ends" in
//! `cut_growth.rs`). A pick that takes a single light then evaluates that light
//! alone, without a leaf cluster's arrays of masses and contributions (the same draws and
//! bits): `equal` from 36 ns a pixel sample in the table's run to 27–28 in two later runs
//! (1.5 alias picks), `grid` from 48 ns to 39–40 (2.1). A leaf's spots are then tested
//! by squares before they are evaluated (a spot whose cone or range leaves the point dark
//! gives 0 without a square root or a division, the same bits), and a pick finds its tile
//! by multiplying by scales computed once: in `lightpick bench`, a spatial sample 6–8 %
//! cheaper on `stage`, `gallery` and `arena`, 13 % on `equal`, the same picks.
//!
//! The rest of this section was measured with the cuts as first built (weighed by the
//! tree's probabilities alone, at most 64 entries, spread ≤ 1.25).
//! Splitting leaf clusters puts all of `equal`'s mass on single lights (64 a tile), 14 % of
//! `heavy-tail`'s, 20 % of `grid`'s (59 % at one pixel a tile) and 17 % of `stage`'s (1–10 %
//! on the other spot scenes); the rest stays in subtrees, where a pick still costs a
//! descent. On `million` the built cuts give 186× (0.87 of the tree's variance) at 901 ns
//! against the tree's 1057; no cut reaches its single lights. Weighing the entries
//! by the root mean square alone (the least variance on average at the weighing points where
//! the tree picks nearly by contribution) gave `gallery` 1.34×, `stage` 0.97× and `arena`
//! 0.96× the tree's variance but `grid` 1.11× and `heavy-tail` 1.05×: a peak between the
//! points went unguarded. A binary search over a tile's
//! cumulative masses, the draw before the alias columns, cost 10–20 ns a pick (against a
//! lookup of no cost, on one pixel's samples: `equal` 28 → 18 ns, `grid` 110 → 91, `stage`
//! 130 → 111). Measured on the way (with entries weighed by their largest): splitting
//! spots' clusters on the weighing points' shares alone (each light's share at every
//! weighing point at least half its largest, the rule for point lights), `stage` 4.6× alias at 1.00× the tree's variance but `gallery`
//! 1.97× (its spots light patches about a tile wide: a cone's edge crosses a tile between
//! weighing points); without that rule, `stage` 3.7× at 1.24× and `gallery` 1.91×; 5 × 5
//! weighing points a tile instead of 3 × 3 (`gallery` 1.62×, no pick cheaper); a leaf
//! cluster whose split would pass the cut's limits kept whole while the cut goes on, instead
//! of ending it (no change beyond the timing noise); the spots of a leaf evaluated over all
//! eight lanes without a branch, as point lights' are (a leaf's masses 42 → 63 ns on
//! `gallery`, 57 → 69 on `stage`: its clusters hold 5.4 lights on average, and the spots'
//! branches predict well); a lower spread bound, 1.15, 1.1 or 1.05 (`gallery` at 1.42×,
//! 1.33× and 1.23× the tree's variance, but its picks 17–21 % dearer, and `stage`'s and
//! `arena`'s variance 1.07–1.11×: where `gallery`'s cut loses most, the tree's pdf lies
//! within a few percent of `c_i/E`, its variance near 0, and the spread bounds the second
//! moment, not the variance); at 32 × 32 tiles, weighing a cut's entries by their mean over the tile
//! instead of their largest, without the spread bound (1.0–1.3× the tree's variance on the
//! point presets and `stage`, 9.2× on `gallery`); weighing the entries by their maps'
//! largest cell over the tile (`stage` at 1.74×); and, in a prototype, descending below
//! an entry by power alone where the entry's lights are far from the tile. With a bound
//! that guarantees the loss (`G`'s largest over its smallest across the entry's box and the
//! tile at most 1.5, 2 or 3) almost no entry of `heavy-tail` or `grid` qualifies and
//! nothing changes; with every entry descended by power, no importance evaluated below the
//! cut, a pick still costs 8.5 (`heavy-tail`) and 5.9 (`grid`) alias picks, at 3.96× and
//! 5.62× the tree's variance. So the levels themselves cost (a node's loads, a draw and a
//! grid pick per level, a branch that cannot be predicted), not the importances: a pick
//! below a subtree entry costs 5–11 alias picks beyond `equal`, not the 3 hoped for, and
//! only entries that are single lights reach it.

mod bounds;
mod exact;
pub mod grid;
pub mod importance;
mod tree;

pub use bounds::{LaneBounds, LaneReach};
pub use exact::ExactSampler;
pub use grid::{LaneGrid, MappedLanes, UnboundedLanes};
pub use tree::{
    CUT_LARGE_TREE, CUT_MAX_ENTRIES, CUT_MAX_ENTRIES_LARGE, CUT_MAX_SPREAD,
    CUT_MAX_SPREAD_PROFILES, CUT_TILES_PER_SIDE, CUT_TREE_SHARE, Child, ChildRef, LEAF_SIZE,
    LightTree, TREE_WIDTH, TileCuts, TreeNode, tile_side_for,
};

use glam::{DVec2, DVec3};

use crate::light_sampler::{LightSampler, Pick, ShadingContext};
use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::scene::{Emission, EmissionShape, Scene, geometry_term, light_term, light_term_culled};

/// Up to this many lights [`SpatialSampler::build`] uses the exact sampler, beyond it the
/// tree. The exact pick evaluates all `N` contributions; the tree evaluates two importances
/// per level (`2·⌈log2 N⌉`) plus its branch logic, which costs about as much as `N` plain
/// contributions near `N = 16`. Below that the exact scan is no slower and has zero variance.
pub const EXACT_MAX_LIGHTS: usize = 16;

/// Whether [`SpatialSampler::build`] picks exactly for a scene of `light_count` lights
/// (`N ≤` [`EXACT_MAX_LIGHTS`]): then every estimate is the exact irradiance and the
/// scheme has zero variance; what a measurement shows is rounding (`~10^-16` relative in
/// `f64` sums, `~10^-6` in the GPU's `f32` ones).
pub fn uses_exact_pick(light_count: usize) -> bool {
    light_count <= EXACT_MAX_LIGHTS
}

/// One contribution-aware pick at a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialPick {
    /// The light's index in the scene.
    pub light: u32,
    /// `P(i | x)`, the probability of this pick at this shading point.
    pub pdf: f64,
    /// The normalized estimate `ê = p_i·G_i(x) / P(i | x)`.
    pub estimate: f64,
}

/// A contributing light as both samplers read it: its position and normalized power.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialLight {
    /// Where the light is, in the world (`z > 0`).
    pub position_in_world: DVec3,
    /// Its normalized power `p_i = Φ_i / Φ_total` (`> 0`).
    pub power: f64,
}

impl SpatialLight {
    /// `c_i(x) = p_i·G_i(x)`, its normalized contribution at `point_on_plane` as a point
    /// light.
    #[inline]
    pub fn contribution(&self, point_on_plane: DVec2) -> f64 {
        self.power * geometry_term(self.position_in_world, point_on_plane)
    }

    /// `c_i(x) = p_i·G_i(x)·S_i(x)` with the emission profile `emission` (`None`: a point
    /// light, [`SpatialLight::contribution`]).
    #[inline]
    pub fn contribution_with(
        &self,
        emission: Option<&EmissionShape>,
        point_on_plane: DVec2,
    ) -> f64 {
        self.power * light_term(self.position_in_world, emission, point_on_plane)
    }

    /// [`SpatialLight::contribution_with`] for a light with a profile, the same bits, without
    /// the square root and the divisions where its cone or range leaves the point dark
    /// (`crate::scene::light_term_culled`): what the tree's leaves and maps evaluate.
    #[inline]
    pub(crate) fn contribution_culled(
        &self,
        emission: &EmissionShape,
        point_on_plane: DVec2,
    ) -> f64 {
        self.power * light_term_culled(self.position_in_world, emission, point_on_plane)
    }
}

/// A contribution-aware sampler: [`ExactSampler`] for few lights, [`LightTree`] for many.
#[derive(Clone, Debug, PartialEq)]
pub enum SpatialSampler {
    /// `P(i | x) ∝ p_i·G_i(x)` exactly (zero variance, `O(N)` per point).
    Exact(ExactSampler),
    /// Stochastic descent of a light tree (`O(log N)` per point).
    Tree(LightTree),
}

impl SpatialSampler {
    /// The exact sampler for `N ≤` [`EXACT_MAX_LIGHTS`], else the light tree
    /// (`O(N log N)` build).
    ///
    /// # Panics
    /// If `positions` and `powers` have different lengths.
    pub fn build(positions: &[DVec3], powers: &LightPowers) -> Self {
        Self::build_with_emission(positions, powers, None)
    }

    /// [`SpatialSampler::build`] for lights with emission profiles (one per light;
    /// `None`: point lights).
    ///
    /// # Panics
    /// If the lengths differ.
    pub fn build_with_emission(
        positions: &[DVec3],
        powers: &LightPowers,
        emission: Option<&[Emission]>,
    ) -> Self {
        if uses_exact_pick(positions.len()) {
            SpatialSampler::Exact(ExactSampler::build_with_emission(
                positions, powers, emission,
            ))
        } else {
            SpatialSampler::Tree(LightTree::build_with_emission(positions, powers, emission))
        }
    }

    /// The sampler of a scene: its positions, powers and emission profiles; a tree over
    /// spots or ranges maps its lanes over the scene's receiver rectangle
    /// ([`LightTree::build_over`]), and a tree is cut per tile of the receiver's pixels
    /// ([`TileCuts`], [`LightTree::with_tile_cuts`]).
    pub fn for_scene(scene: &Scene) -> Self {
        let (positions, powers) = (&scene.positions, &scene.powers);
        let emission = scene.emission.as_deref();
        if uses_exact_pick(positions.len()) {
            Self::build_with_emission(positions, powers, emission)
        } else {
            let region = [scene.plane.min, scene.plane.max];
            SpatialSampler::Tree(
                LightTree::build_over(positions, powers, emission, Some(region))
                    .with_tile_cuts(&scene.plane),
            )
        }
    }

    /// New powers for the same lights: `scene` has the positions, cones and ranges this
    /// sampler was built over ([`Scene::same_geometry`]) and new powers. The light tree is
    /// refitted bottom up ([`LightTree::refit`]: `O(N)` and no allocation for point lights;
    /// spot and range maps recomputed as a build does) and then equals a fresh
    /// [`SpatialSampler::for_scene`] bit for bit; the exact pick (`N ≤ 16`) is rebuilt.
    ///
    /// # Panics
    /// If `scene` holds a different number of lights.
    pub fn refit(&mut self, scene: &Scene) {
        match self {
            SpatialSampler::Exact(_) => *self = Self::for_scene(scene),
            SpatialSampler::Tree(tree) => tree.refit(&scene.powers),
        }
    }

    /// Picks a light for shading point `x` from the next draws of `rng`, or `None` when no
    /// light contributes at `x` (then `ê = 0`).
    #[inline]
    pub fn sample(&self, x: DVec2, rng: &mut Rng) -> Option<SpatialPick> {
        match self {
            SpatialSampler::Exact(s) => s.sample(x, rng),
            SpatialSampler::Tree(t) => t.sample(x, rng),
        }
    }

    /// The normalized estimate `ê` of one pick (0 when nothing contributes).
    #[inline]
    pub fn estimate(&self, x: DVec2, rng: &mut Rng) -> f64 {
        self.sample(x, rng).map_or(0.0, |pick| pick.estimate)
    }

    /// [`SpatialSampler::estimate`] at `B` points, each from its own stream, equal one for
    /// one to `estimate(points[b], rngs[b])`; the tree interleaves the `B` descents
    /// ([`LightTree::sample_many`]) so that their memory loads overlap.
    #[inline]
    pub fn estimate_many<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
    ) -> [f64; B] {
        self.estimate_many_with(points, rngs, false)
    }

    /// [`SpatialSampler::estimate_many`] for points whose tiles' cuts have likely left the
    /// caches since last read (the first sample a pass takes at each pixel: the app's passes
    /// of one sample a pixel); the same estimates, with the cuts' lines asked for ahead
    /// ([`LightTree::sample_many_cold`]).
    #[inline]
    pub fn estimate_many_cold<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
    ) -> [f64; B] {
        self.estimate_many_with(points, rngs, true)
    }

    /// [`SpatialSampler::estimate_many`], or [`SpatialSampler::estimate_many_cold`] when
    /// `cold`.
    #[inline]
    fn estimate_many_with<const B: usize>(
        &self,
        points: &[DVec2; B],
        rngs: &mut [Rng; B],
        cold: bool,
    ) -> [f64; B] {
        match self {
            SpatialSampler::Exact(_) => {
                std::array::from_fn(|b| self.estimate(points[b], &mut rngs[b]))
            }
            SpatialSampler::Tree(t) => t
                .sample_many_with(points, rngs, cold)
                .map(|p| p.map_or(0.0, |p| p.estimate)),
        }
    }

    /// `P(i | x)`, the probability that [`SpatialSampler::sample`] picks light `i` at `x`.
    pub fn pdf(&self, x: DVec2, light: usize) -> f64 {
        match self {
            SpatialSampler::Exact(s) => s.pdf(x, light),
            SpatialSampler::Tree(t) => t.pdf(x, light),
        }
    }

    /// `P(i | x)` of every light of the scene at once (indexed by scene index, 0 for a light
    /// that cannot contribute): `O(N)`, where calling [`SpatialSampler::pdf`] per light would
    /// cost `O(N²)` for the tree.
    pub fn pdfs(&self, x: DVec2) -> Vec<f64> {
        match self {
            SpatialSampler::Exact(s) => s.pdfs(x),
            SpatialSampler::Tree(t) => t.pdfs(x),
        }
    }

    /// Number of lights of the scene (contributing or not).
    pub fn light_count(&self) -> usize {
        match self {
            SpatialSampler::Exact(s) => s.light_count(),
            SpatialSampler::Tree(t) => t.light_count(),
        }
    }

    /// Heap bytes the sampler holds, by capacity ([`LightTree::heap_bytes`],
    /// [`ExactSampler::heap_bytes`]).
    pub fn heap_bytes(&self) -> usize {
        match self {
            SpatialSampler::Exact(s) => s.heap_bytes(),
            SpatialSampler::Tree(t) => t.heap_bytes(),
        }
    }
}

impl LightSampler for SpatialSampler {
    fn light_count(&self) -> usize {
        SpatialSampler::light_count(self)
    }

    /// `P(i | x)` at the context's point ([`SpatialSampler::pdf`]).
    fn pmf_at(&self, ctx: &ShadingContext, i: usize) -> f64 {
        self.pdf(ctx.point_on_plane, i)
    }

    /// [`SpatialSampler::sample`] at the context's point, with the same draws.
    #[inline]
    fn pick_at(&self, ctx: &ShadingContext, rng: &mut Rng) -> Option<Pick> {
        self.sample(ctx.point_on_plane, rng).map(|pick| Pick {
            light: pick.light,
            probability: pick.pdf,
        })
    }

    /// [`SpatialSampler::pdfs`] at the context's point (one traversal).
    fn pmfs_at(&self, ctx: &ShadingContext) -> Vec<f64> {
        self.pdfs(ctx.point_on_plane)
    }
}

/// The lights that can contribute somewhere on the plane (`z_i > 0`, an emission that
/// reaches the plane and, unless `keep_zero_power`, `p_i > 0`), with their scene index and
/// emission profile (all `None` without profiles).
///
/// # Panics
/// If the lengths differ.
fn contributing(
    positions: &[DVec3],
    powers: &LightPowers,
    emission: Option<&[Emission]>,
    keep_zero_power: bool,
) -> Vec<(u32, SpatialLight, Option<EmissionShape>)> {
    assert_eq!(positions.len(), powers.len(), "one position per power");
    if let Some(e) = emission {
        assert_eq!(e.len(), powers.len(), "one emission profile per power");
    }
    positions
        .iter()
        .zip(powers.pmf())
        .enumerate()
        .map(|(i, (&position_in_world, power))| {
            let e = emission.map(|e| e[i]);
            (
                i as u32,
                SpatialLight {
                    position_in_world,
                    power,
                },
                e,
            )
        })
        .filter(|(_, l, e)| {
            (keep_zero_power || l.power > 0.0)
                && l.position_in_world.z > 0.0
                && e.is_none_or(|e| e.reaches_plane(l.position_in_world))
        })
        .map(|(i, l, e)| (i, l, e.map(|e| *e.shape())))
        .collect()
}

/// `(r >> 8) · 2^-24`: a uniform in `[0, 1)` on the 24-bit grid, exact in `f32` and `f64`,
/// so the CPU and the GPU scan the same `u·S` in the exact pick (whose estimate `S` does not
/// depend on which light the grid lands on; the pick itself is within `2^-24` of `c_i/S`).
#[inline]
pub fn unit24(r: u32) -> f64 {
    f64::from(r >> 8) * (1.0 / 16_777_216.0)
}
