//! Per-tile cuts of the light tree: the top of the descent decided once per tile of pixels
//! instead of at every sample.
//!
//! # What a cut is
//! The receiver is one plane with a known pixel grid ([`ReceiverPlane`]). It is split into
//! square tiles of [`TileCuts::tile_side`] pixels, about [`CUT_TILES_PER_SIDE`]` ²` of them
//! whatever the receiver's aspect ([`tile_side_for`]). Each tile keeps a **cut** of the tree: at most [`CUT_MAX_ENTRIES`] subtrees
//! (internal nodes, leaf clusters, or single lights of a leaf cluster: a cluster of one)
//! whose leaf-order ranges hold, between them, every light
//! that can light the tile, each with a mass `m_e` on the `2^24` grid (`Σ_e m_e = 2^24`). A
//! pick at `x` in the tile takes entry `e` by one draw from the tile's alias columns (below),
//! then descends below `e` at `x` exactly as the tree does from its root
//! ([`super::LightTree::sample`]). Its probability is
//!
//! `P(i | x) = m_e / 2^24 · Π_{nodes below e} m_lane(x) / 2^24 · m_j(x) / 2^24`,
//!
//! the product of realized grid probabilities: exact, and `Σ_i P(i | x) = 1` wherever the
//! entries' lights reach `x` and every level's masses sum to `2^24`.
//!
//! # How a tile cuts and weighs
//! Let `x_1 … x_9` be the centres of the tile's ninths. Each entry `e` of a cut carries an
//! **estimate** `Ê_e(x_k)` of what its lights give each weighing point: for a single
//! light or a leaf cluster its exact contribution `Σ_j p_j·G_j(x_k)·S_j(x_k)`; for a lane
//! of point lights its representative light `Φ_c·G(c, x_k)` (the tree's own importance,
//! [`crate::spatial::importance`]); for a lane of spots or ranges its map's value there
//! plus its unbounded lights' representative light ([`crate::spatial::grid`]). Against the
//! cut's total `Ê(x_k) = Σ_f Ê_f(x_k)` each entry has the **share** `s_e(x_k) =
//! Ê_e(x_k)/Ê(x_k)`. A cut starts as the root's lanes and splits, while it can, its most
//! urgent entry: the one of largest `q̄_e = max_k s_e(x_k)`, unless a group of point lights
//! may hold far more than its estimate says. A representative light judges a group just
//! above the tile badly (the nearest few of its lights give a point beneath most of its
//! light, and the centroid hangs elsewhere), so each node also keeps its **reach**, the
//! radius `r` of a sphere about its lights' centroid `c` that holds them all and the height
//! `z_min` of the lowest (8 bytes a node), and with it a lane of point lights over a
//! subtree has a **bound** of what it gives any point of the tile,
//! `B_e = Φ_e·min(1, (c_z + r)/d) / (4π·d²)` with `d = max(|c − tile| − r, z_min)`
//! ([`super::TreeNode::lane_bound`]). A group whose bound, as a share of the cut's
//! largest total (`B_e / max_k Ê(x_k)`), is more than 64 times its `q̄_e` is split first,
//! in the order of those bound shares. A node splits into its lanes, leaving out a lane
//! whose footprint box misses the tile (none of its lights gives the tile anything); a leaf
//! cluster into its lights, leaving out a light whose footprint misses the tile or whose
//! cone or range provably misses all of it, when each other light's contribution at every
//! weighing point is positive and at least a tenth of its largest. Otherwise the cluster's
//! **core**, its lights from the first that is not that flat to the last, stays whole
//! (weighed by their summed estimates) and the flat lights before and after it enter alone,
//! where the core is lit at a weighing point; else the whole cluster stays whole, narrowed
//! to its lights from the first that can light the tile to the last. A pick that takes a
//! single light evaluates that light alone, one that takes a core or a cluster each of its
//! lights. A spot dark at every weighing point but lit between them (its cone's edge
//! crossing the tile) keeps its cluster whole, whose pick weighs it at the pixel; one lit
//! at every point enters alone even where an edge crosses a corner of the tile (see "Which
//! clusters split" and "A cluster's flat ends" in `cut_growth.rs`). Its entries are weighed
//!
//! `w_e = (1 − ε)·((1 − β)·q̃_e / Σ q̃ + β·t̃_e / Σ t̃) + ε·Φ_e / Σ Φ`,  `ε =` [`POWER_SHARE`],
//! `β =` [`CUT_TREE_SHARE`] `= 0`,
//!
//! `q̃_e = √(q̄_e · q_e)` with `q_e = (Σ_k s_e(x_k)²/9)^½`, the root mean square of the
//! entry's shares at the weighing points, and `t̃_e` the same of its probabilities under the
//! tree from its root, `P_tree(e | x_k)`: every entry holding power keeps `m_e ≥ 1`, so a
//! light that contributes anywhere in the tile keeps `P(i | x) > 0`, and the estimate stays
//! unbiased. On 24 clusters of 400 lights 5–30 cm above the plane, one point beneath a
//! group of 600 lights held 95 % of the cut's variance: the group gave it two thirds of its
//! light and was weighed 0.7 %. Before the bounds, a quarter of each weight given by the
//! tree's probabilities (`β = ¼`) held that set to 1.3× the tree's variance (2.4× without);
//! with the bounds the set has 0.04× (`β = 0`) and 0.05× (`β = ¼`), and the quarter only
//! costs the others their gain (`equal` 0.14× against 0.07×, `heavy-tail` 0.21× against
//! 0.16×). Where the bound leads a split at a ratio of 1 (its share instead of 64 times
//! it; measured with `β = ¼`), `chandeliers` gains more (0.12× against 0.17×) and
//! `heavy-tail` and `million` lose (0.22× and 0.17× against 0.21× and 0.14×): groups above
//! the tile are split that the estimates judge well; at 16, `million` still has 0.17×.
//!
//! **Why estimates, not the tree's probabilities.** A descent from the root multiplies one
//! branch probability per level, each a ratio of representative lights with a share of
//! power mixed in: the errors of every level compound, and each level gives `ε` of its
//! probability to power. A cut weighed by the tree's probabilities `P_tree(e | x_k)` (as it
//! was first built) inherits all of that and at best keeps the tree's variance. Weighed by
//! estimates, the cut replaces the levels above its entries by one comparison of
//! estimates that get better as the cut gets finer, exact where it reaches single lights or
//! whole leaf clusters; below an entry the descent at `x` is the tree's as before. Exact
//! variances over the tree's (the module docs of [`crate::spatial`]): 0.14× on `equal`,
//! 0.21× on `heavy-tail`, 0.61× on `grid`, 0.66× on `stage`, 0.83–1.22× on the other spot
//! scenes, 0.07–1.34× on clustered point lights near the plane.
//!
//! **What fixing the top costs.** Where the shares estimate the entries' parts of the
//! irradiance well, a cut of weights `w` has at `x_k` the variance `E²·(Σ_e s_e(x_k)²/w_e −
//! 1)` at the entry level: least on average over the weighing points for `w_e ∝ q_e`, the
//! root mean square. The largest, `q̄_e`, guards a point between them where the share peaks;
//! `q̃_e` takes both. At a weighing point the cut's probability of any entry is at least
//! `(1 − ε)/(√3·S)` times its share, where `S = Σ_e q̄_e ≥ 1` is the cut's **spread**
//! (`q_e ≥ q̄_e/3`, so `q̃_e ≥ q̄_e/√3 ≥ s_e(x_k)/√3`, and `Σ q̃ ≤ S`). A split is made only
//! while `S` stays at most the cut's limit and the cut at most [`CUT_MAX_ENTRIES`] entries
//! ([`CUT_MAX_ENTRIES_LARGE`] in a tree of more than [`CUT_LARGE_TREE`] lights): the limit
//! is [`CUT_MAX_SPREAD`] (4) over point lights, whose shares change smoothly across a tile,
//! and [`CUT_MAX_SPREAD_PROFILES`] (1.6) over spots and ranges, whose maps are cell means a
//! cone's edge makes a poor guide between the points (at 2, `gallery` has 2.8× the tree's
//! variance, at 1.6 1.8×, at 1.25 1.2×, where `arena` has 0.46×, 0.48× and 0.83× and its
//! picks cost 5.7, 5.7 and 7.8 alias picks). The first split that would pass either limit
//! ends the cut (trying the smaller entries costs more build time than it saves).
//!
//! **Which clusters split** was measured rule by rule (exact variances and times per pick
//! on five scenes): the table is in `cut_growth.rs`'s module docs.
//!
//! # The draw: Walker's alias columns on the grid, exact
//! A tile of `n` entries keeps `K = n` rounded up to a power of two columns of `C = 2^24/K`
//! grid cells each (column `c ≥ n` is empty). Column `c` keeps a threshold `t_c ≤ C` and an
//! alias `a_c`, built in integers (Vose's two stacks: a column below `C` is filled from one
//! above it), so that entry `e` owns `t_e` cells of its own column and `C − t_c` of every
//! column `c` whose alias it is: `m_e` cells in all, exactly. The draw's top 24 bits `u`
//! give the column `u / C` and the cell `u mod C` in it; the cell takes the column's entry
//! below `t_c` and its alias from there on. One word and one entry are read, where a
//! binary search over the cumulative masses read six (measured: 10–20 ns a pick less).
//! Cold picks in lockstep over point lights (the first sample a pass gives a pixel) take
//! all their draws first and ask for those two lines ahead (`prefetch`): a cut of 256
//! entries is 3 kB, the tiles' cuts megabytes.
//!
//! Points off the plane's rectangle (the inspector or a test may ask there) descend from
//! the root as before: the pdf at a point is defined by the rule that point falls under.
//!
//! A tile is cut the first time a pick, a pdf or the GPU's upload needs it, on that
//! thread: new powers ([`super::LightTree::refit`]) only drop the cuts, and a drag of a
//! slider does not wait for 4096 tiles it may not draw before the next frame.
//!

use std::sync::OnceLock;

use glam::DVec2;

use super::LightTree;
use super::cut_candidate::{Candidate, WEIGHING_POINTS, Weighing};
use super::cut_columns::{AliasWork, MOST_ENTRIES, alias_columns_into};
use super::cut_growth::{Growth, Rules, grow};
use super::cut_words::pick_in;
use super::node::{Child, ChildRef, TREE_WIDTH};
use crate::scene::ReceiverPlane;
use crate::spatial::importance::{POWER_SHARE, grid_masses_into};

/// Tiles along each side of a square receiver (64 × 64); a receiver of another aspect gets
/// about as many tiles ([`tile_side_for`]).
pub const CUT_TILES_PER_SIDE: u32 = 64;

/// The side, in pixels, of square tiles that split a receiver of `width × height` pixels into
/// about `tiles_per_side²` tiles: `s = √(width·height) / tiles_per_side` rounded to the
/// integer whose tile count `width·height / s²` lies nearest `tiles_per_side²` on a log scale
/// (`⌊s⌋` when `s² < ⌊s⌋·⌈s⌉`), so between half and twice as many tiles (before the partial
/// tiles at the edges); at least 1.
///
/// A tile's cut is weighed over its area, so its shape and size on the plane decide how
/// well the cut fits every pixel of it: by pixel count, a `256 × 160` receiver gets tiles of
/// 3 pixels (86 × 54 tiles), about the size a `128 × 128` rendering of the same floor gets
/// (2 pixels, 64 × 64), where 64 along the longer side would give it 4 (64 × 40 tiles, a
/// sixth larger each way: `gallery`'s exact variance 1.21× the 128 × 128 rendering's).
pub fn tile_side_for(width: u32, height: u32, tiles_per_side: u32) -> u32 {
    let s = (f64::from(width) * f64::from(height)).sqrt() / f64::from(tiles_per_side.max(1));
    if s <= 1.0 {
        return 1;
    }
    let (below, above) = (s.floor(), s.ceil());
    // Both sides are `u32`: `s < 2^32`, an exact conversion.
    if s * s < below * above {
        below as u32
    } else {
        above as u32
    }
}

/// The most entries of one tile's cut (measured against 128 in the module docs of
/// [`crate::spatial`]).
///
/// 512 and 1024 were measured too (`tile_cuts` example's rows `cut ≤ 512`, `cut ≤ 1024`):
/// over point lights no gain (`heavy-tail` 1233× → 1302× and 1342× below power sampling at
/// 7.1, 7.2 and 7.7 alias picks, `clusters-low` 6.2 → 7.0 and 8.4 alias picks at the same
/// variance), and cutting every tile took twice and four times as long. Over spots only
/// `random` grows past 256 entries (369 a tile, where its spread ends the cut; `stage`,
/// `gallery` and `arena` stop at 41, 6 and 133): in the example 289× → 328× at 3.2 → 2.6
/// alias picks, but under `lightpick bench` (`--no-gpu --presets stage,gallery --scene
/// random.json --scene arena.json`, two runs alternating with 256) its spatial sample took
/// 84 and 88 ns against 61 and 62 (cutting its 4096 tiles took three times as long, 830 ms
/// against 283), its efficiency over the alias table's 52× against 64×; the app's passes
/// gained a tenth (143 and 126 ns against 160 and 137). Not kept, for spots either.
pub const CUT_MAX_ENTRIES: usize = 256;

/// The most a cut may spread its entries' shares, `Σ_e max_k s_e(x_k)` over the tile's
/// weighing points `x_k` (module docs), in a tree of point lights.
pub const CUT_MAX_SPREAD: f64 = 4.0;

/// [`CUT_MAX_SPREAD`] in a tree of spots or lights with a range, whose maps are cell means
/// that a cone's edge crossing the tile makes a poor guide between the weighing points.
pub const CUT_MAX_SPREAD_PROFILES: f64 = 1.6;

/// The share of a cut's weights given by the tree's probabilities `P_tree(e | x_k)`, the
/// rest by the entries' estimates (module docs): none. A quarter was a floor under the
/// groups a representative light misjudges until the cut split those by their bounds; it
/// now only costs variance (measured in the module docs of [`crate::spatial`]).
/// [`TileCuts::with_tree_share`] measures other shares.
pub const CUT_TREE_SHARE: f64 = 0.0;

/// Trees of more lights than this cut at most [`CUT_MAX_ENTRIES_LARGE`] entries a tile:
/// their cuts reach no single light either way, and the app's 100 bytes per light at
/// `10^6` lights hold half the cut.
pub const CUT_LARGE_TREE: usize = 1 << 18;

/// The most entries of a tile's cut in a tree of more than [`CUT_LARGE_TREE`] lights.
pub const CUT_MAX_ENTRIES_LARGE: usize = 64;

/// The cuts of every tile of one receiver's pixel grid; see the module docs. A tile is cut
/// the first time something needs it (a pick, a pdf, the GPU's upload: [`TileCuts::cut_all`]),
/// on whichever thread asks, so that new powers cost no more than clearing them; a tile's
/// cut is a function of the tree and the tile alone, so which thread cuts it, and when,
/// changes nothing.
#[derive(Clone, Debug)]
pub struct TileCuts {
    /// The receiver (its rectangle and pixel grid) the tiles split.
    plane: ReceiverPlane,
    /// Pixels along a tile's side.
    tile_side: u32,
    /// How each tile's cut grows: its limits and what it weighs its entries by.
    rules: Rules,
    /// Tiles along `x` (columns).
    tiles_x: u32,
    /// Tiles along `y` (rows, from the plane's top row of pixels).
    tiles_y: u32,
    /// Tiles per unit length of the plane along `x` and `y`, `w / ((max.x − min.x)·s)` and
    /// `h / ((max.y − min.y)·s)` for a receiver of `w × h` pixels and tiles of side `s`
    /// ([`TileCuts::tile_at`]).
    tiles_per_unit: DVec2,
    /// Each tile's cut once made, as [`TileCut`]'s words.
    cuts: Vec<OnceLock<TileCut>>,
}

/// One tile's cut in the words the GPU reads too: the column count `K` (0 when no entry of
/// the tile has power), the `K` alias columns (module docs: threshold `t_c < C` in the low
/// `log2 C` bits, alias `a_c` above them), then per entry, in leaf order, its mass `m_e`
/// and its child word.
type TileCut = Box<[u32]>;

/// Two cuts are equal when they cut the same grid with the same limits: over equal trees
/// their tiles' cuts are then equal, made or not.
impl PartialEq for TileCuts {
    fn eq(&self, other: &Self) -> bool {
        self.plane == other.plane && self.tile_side == other.tile_side && self.rules == other.rules
    }
}

impl TileCuts {
    /// The cuts of `tree` over `plane`'s pixel grid (`None` when the tree's root is not an
    /// internal node, or the plane has no pixels), each tile cut when first needed.
    pub fn build(tree: &LightTree, plane: &ReceiverPlane) -> Option<Self> {
        let max_entries = if tree.lights.len() > CUT_LARGE_TREE {
            CUT_MAX_ENTRIES_LARGE
        } else {
            CUT_MAX_ENTRIES
        };
        let max_spread = if tree.emission.is_empty() {
            CUT_MAX_SPREAD
        } else {
            CUT_MAX_SPREAD_PROFILES
        };
        Self::build_sized(tree, plane, CUT_TILES_PER_SIDE, max_entries, max_spread)
    }

    /// [`TileCuts::build`] with about `tiles_per_side²` tiles ([`tile_side_for`]), at most `max_entries` entries a cut (4 to 1024) and a spread of at most
    /// `max_spread` (at least 1): for measuring alternatives (the `tile_cuts` example).
    pub fn build_sized(
        tree: &LightTree,
        plane: &ReceiverPlane,
        tiles_per_side: u32,
        max_entries: usize,
        max_spread: f64,
    ) -> Option<Self> {
        let tile_side = tile_side_for(plane.width, plane.height, tiles_per_side);
        Self::build_with_side(tree, plane, tile_side, (max_entries, max_spread))
    }

    /// The cuts of tiles of `tile_side` pixels (at least 1), none made yet.
    fn build_with_side(
        tree: &LightTree,
        plane: &ReceiverPlane,
        tile_side: u32,
        (max_entries, max_spread): (usize, f64),
    ) -> Option<Self> {
        let Child::Node(_) = tree.root().get() else {
            return None;
        };
        if plane.width == 0 || plane.height == 0 {
            return None;
        }
        let tile_side = tile_side.max(1);
        let (tiles_x, tiles_y) = (
            plane.width.div_ceil(tile_side),
            plane.height.div_ceil(tile_side),
        );
        Some(Self {
            plane: plane.clone(),
            tile_side,
            rules: Rules {
                max_entries: max_entries.clamp(TREE_WIDTH, MOST_ENTRIES),
                max_spread: max_spread.max(1.0),
                split_leaves: true,
                weighing: Weighing::Estimates,
                tree_share: CUT_TREE_SHARE,
            },
            tiles_x,
            tiles_y,
            tiles_per_unit: DVec2::new(f64::from(plane.width), f64::from(plane.height))
                / ((plane.max - plane.min) * f64::from(tile_side)),
            cuts: (0..tiles_x * tiles_y).map(|_| OnceLock::new()).collect(),
        })
    }

    /// The receiver whose pixel grid the tiles split.
    pub fn plane(&self) -> &ReceiverPlane {
        &self.plane
    }

    /// Pixels along a tile's side.
    pub fn tile_side(&self) -> u32 {
        self.tile_side
    }

    /// The most entries of a tile's cut.
    pub fn max_entries(&self) -> usize {
        self.rules.max_entries
    }

    /// The most spread `Σ_e max_k s_e(x_k)` of a tile's cut (module docs).
    pub fn max_spread(&self) -> f64 {
        self.rules.max_spread
    }

    /// The same cuts with the share `tree_share` (0 to 1) of their weights given by the
    /// tree's probabilities: for measuring alternatives (the `tile_cuts` example).
    #[must_use]
    pub fn with_tree_share(mut self, tree_share: f64) -> Self {
        self.rules.tree_share = tree_share.clamp(0.0, 1.0);
        self.clear();
        self
    }

    /// Every tile's cut dropped, to be cut again when next needed (the tree's new powers,
    /// same layout): no allocation.
    pub(super) fn clear(&mut self) {
        self.cuts.iter_mut().for_each(|cut| drop(cut.take()));
    }

    /// The same cuts with every leaf cluster kept whole: for measuring what splitting
    /// clusters gains (the `tile_cuts` example).
    #[must_use]
    pub fn keeping_leaf_clusters(mut self) -> Self {
        self.rules.split_leaves = false;
        self.clear();
        self
    }

    /// The same cuts with entries weighed by the tree's probabilities `P_tree(e | x_k)`
    /// instead of their estimated contributions (module docs): for measuring what weighing
    /// by estimates gains (the `tile_cuts` example).
    #[must_use]
    pub fn weighing_by_tree_probabilities(mut self) -> Self {
        self.rules.weighing = Weighing::TreeProbabilities;
        self.rules.tree_share = 1.0;
        self.clear();
        self
    }

    /// Tiles along `x` and along `y`.
    pub fn tiles(&self) -> [u32; 2] {
        [self.tiles_x, self.tiles_y]
    }

    /// The tile of pixel `(px, py)` (row-major from the plane's top row).
    #[inline]
    pub fn tile_of_pixel(&self, px: u32, py: u32) -> usize {
        ((py / self.tile_side) * self.tiles_x + px / self.tile_side) as usize
    }

    /// Tile `tile`'s pixels: its first column and row, and one past its last.
    pub fn tile_pixels(&self, tile: usize) -> [[u32; 2]; 2] {
        let (tx, ty) = (tile as u32 % self.tiles_x, tile as u32 / self.tiles_x);
        let side = self.tile_side;
        [
            [tx * side, ty * side],
            [
                ((tx + 1) * side).min(self.plane.width),
                ((ty + 1) * side).min(self.plane.height),
            ],
        ]
    }

    /// The tile holding `point_on_plane`, `None` off the plane's rectangle (then the
    /// descent starts at the root): `⌊(x − min.x)·w/((max.x − min.x)·s)⌋` across and
    /// `⌊(max.y − y)·h/((max.y − min.y)·s)⌋` down, each clamped to the last tile, with the
    /// scales computed once (no division a pick). At a pixel's centre that is the pixel's
    /// tile ([`TileCuts::tile_of_pixel`], what the GPU takes from the pixel's index): the
    /// centre lies half a pixel from any tile's edge, `1/(2s)` in tiles, and the few
    /// roundings move it by `~2^-50` of the receiver's width in tiles.
    #[inline]
    pub fn tile_at(&self, point_on_plane: DVec2) -> Option<usize> {
        let (lo, hi) = (self.plane.min, self.plane.max);
        let inside = point_on_plane.cmpge(lo).all() && point_on_plane.cmple(hi).all();
        inside.then(|| {
            // `as u32` truncates (the floor, for the offsets `≥ 0` inside) and saturates.
            let tx = ((point_on_plane.x - lo.x) * self.tiles_per_unit.x) as u32;
            let ty = ((hi.y - point_on_plane.y) * self.tiles_per_unit.y) as u32;
            (ty.min(self.tiles_y - 1) * self.tiles_x + tx.min(self.tiles_x - 1)) as usize
        })
    }

    /// Tile `tile`'s cut of `tree` (the tree these cuts were made for) as [`TileCut`]'s
    /// words, cut now if it was not yet.
    #[inline]
    pub(super) fn cut(&self, tree: &LightTree, tile: usize) -> &[u32] {
        self.cuts[tile].get_or_init(|| {
            SCRATCH.with_borrow_mut(|scratch| {
                self.cut_tile(tree, tile as u32, scratch);
                scratch.words.as_slice().into()
            })
        })
    }

    /// Every tile's cut of `tree`, made now where it was not yet, in parallel (what the
    /// GPU's upload needs, and what a first pass over every pixel costs).
    pub fn cut_all(&self, tree: &LightTree) {
        use rayon::prelude::*;
        (0..self.cuts.len()).into_par_iter().for_each(|tile| {
            self.cut(tree, tile);
        });
    }

    /// Tile `tile`'s entries in `tree` and their grid masses `m_e` (of `2^24`).
    pub fn entries<'a>(
        &'a self,
        tree: &LightTree,
        tile: usize,
    ) -> impl Iterator<Item = (ChildRef, u32)> + 'a {
        let words = self.cut(tree, tile);
        let k = words[0] as usize;
        words[1 + k..]
            .chunks_exact(2)
            .map(|pair| (ChildRef::from_bits(pair[1]), pair[0]))
    }

    /// The entry of tile `tile` in `tree` that the 24-bit draw `u` takes through the tile's
    /// alias columns (module docs), with its mass (`m_e / 2^24` is the probability of
    /// taking it, exactly); `None` when no entry of the tile has power.
    #[inline]
    pub fn pick(&self, tree: &LightTree, tile: usize, u: u32) -> Option<(ChildRef, u32)> {
        pick_in(self.cut(tree, tile), u)
    }

    /// The words the GPU reads, every tile of `tree` cut: per tile the offset of its words
    /// (and one past the last tile's), then every tile's words (its column count, columns,
    /// and per entry its mass and child word).
    pub fn gpu_words(&self, tree: &LightTree) -> (Vec<u32>, Vec<u32>) {
        self.cut_all(tree);
        let mut offsets = Vec::with_capacity(self.cuts.len() + 1);
        let mut words = Vec::new();
        for tile in 0..self.cuts.len() {
            offsets.push(words.len() as u32);
            words.extend_from_slice(self.cut(tree, tile));
        }
        offsets.push(words.len() as u32);
        (offsets, words)
    }

    /// Heap bytes held, by capacity: a cell per tile, and per tile cut 4 bytes, 4 per
    /// column and 8 per entry.
    pub fn heap_bytes(&self) -> usize {
        self.cuts.capacity() * std::mem::size_of::<OnceLock<TileCut>>()
            + self
                .cuts
                .iter()
                .filter_map(OnceLock::get)
                .map(|c| std::mem::size_of_val::<[u32]>(c))
                .sum::<usize>()
    }

    /// The weighing points of tile `tile` on the plane, and the box that holds every point
    /// of the tile with half a pixel to spare (for the tile's cull, whatever the rounding of
    /// [`ReceiverPlane::pixel_at`] at its edges).
    fn tile_geometry(&self, tile: u32) -> ([DVec2; WEIGHING_POINTS.len()], [DVec2; 2]) {
        let [first, end] = self
            .tile_pixels(tile as usize)
            .map(|[px, py]| DVec2::new(f64::from(px), f64::from(py)));
        let points =
            WEIGHING_POINTS.map(|f| self.plane.point_at(first + DVec2::from(f) * (end - first)));
        // Pixel rows run down from the top: the first pixel's corner is the box's top left.
        let (top_left, bottom_right) = (
            self.plane.point_at(first - 0.5),
            self.plane.point_at(end + 0.5),
        );
        let rect = [top_left.min(bottom_right), top_left.max(bottom_right)];
        (points, rect)
    }

    /// One tile's cut, written over `scratch`: its entries' grid masses and subtrees in leaf
    /// order with their alias columns, as [`TileCut`]'s words in `scratch.words`.
    fn cut_tile(&self, tree: &LightTree, tile: u32, scratch: &mut Scratch) {
        let tile = self.tile_geometry(tile);
        let Scratch { cut, growth, .. } = scratch;
        cut.clear();
        // The root alone: its estimate is a placeholder, replaced by its lanes' at once.
        cut.push(Candidate::new(
            tree.root(),
            [1.0; WEIGHING_POINTS.len()],
            [1.0; WEIGHING_POINTS.len()],
            1.0,
        ));
        grow(tree, tile, cut, growth, self.rules);
        Self::finish(scratch, self.rules.tree_share);
    }

    /// The grown cut's masses and alias columns, in `scratch.words`.
    fn finish(scratch: &mut Scratch, tree_share: f64) {
        let Scratch {
            cut,
            weights,
            masses,
            ..
        } = scratch;
        let (estimated, by_tree, power) = cut.iter().fold((0.0, 0.0, 0.0), |(e, t, p), c| {
            (e + c.weight, t + c.tree_weight, p + c.power)
        });
        let usable = |sum: f64| sum > 0.0 && sum.is_finite();
        // The tree's share of the weights: all of it where the estimates say nothing, none
        // where the tree's probabilities do (`None`: neither does, by power alone).
        let tree_share = match (usable(estimated), usable(by_tree)) {
            (true, true) => Some(tree_share),
            (false, true) => Some(1.0),
            (true, false) => Some(0.0),
            (false, false) => None,
        };
        weights.clear();
        weights.extend(cut.iter().map(|c| {
            let by_power = if power > 0.0 { c.power / power } else { 0.0 };
            let Some(share) = tree_share else {
                return by_power;
            };
            let mut w = 0.0;
            if share < 1.0 {
                w += (1.0 - share) * c.weight / estimated;
            }
            if share > 0.0 {
                w += share * c.tree_weight / by_tree;
            }
            (1.0 - POWER_SHARE) * w + POWER_SHARE * by_power
        }));
        masses.clear();
        masses.resize(cut.len(), 0);
        grid_masses_into(weights, masses);
        debug_assert!(matches!(
            masses.iter().map(|&m| u64::from(m)).sum::<u64>(),
            0 | 0x100_0000
        ));
        let words = &mut scratch.words;
        words.clear();
        if masses.iter().all(|&m| m == 0) {
            words.push(0);
        } else {
            words.push(masses.len().next_power_of_two() as u32);
            alias_columns_into(masses, &mut scratch.columns, words);
        }
        let pairs = masses.iter().zip(cut.iter());
        words.extend(pairs.flat_map(|(&m, c)| [m, c.at.bits()]));
    }
}

thread_local! {
    /// What cutting a tile works in, kept from tile to tile on each thread.
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// What cutting one tile works in, kept from tile to tile on a thread (no allocation but
/// the cut's own once warm).
#[derive(Default)]
struct Scratch {
    cut: Vec<Candidate>,
    growth: Growth,
    weights: Vec<f64>,
    masses: Vec<u32>,
    columns: AliasWork,
    words: Vec<u32>,
}
