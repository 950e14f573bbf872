//! What a lane of spots gives the plane: a coarse map of its irradiance, which the light tree
//! weighs the lane by over spots and ranges.
//!
//! # Why a map
//! A spot's power says little about what it gives a point: its cone lights a patch of the
//! plane and nothing beyond. A lane of spots therefore gives a point the sum of the few
//! spots whose patches hold it. A bound over the lane (its box, the cone holding its axes,
//! pbrt-v4's `LightBounds::Importance`) weighs every spot of the lane as if it shone on the
//! point, so it cannot tell a lane with one spot on the point from a lane with twenty aimed
//! elsewhere. The receiver here is one known plane, so each lane keeps what its lights give
//! that plane instead: over the box of the lane's footprints, a [`GRID_SIDE`]` × `[`GRID_SIDE`]
//! map of the lane's **mean irradiance per cell**,
//!
//! `M(cell) = (1/|cell|) ∫_cell Σ_i p_i·G_i(y)·S_i(y) dy`,
//!
//! and a lane's importance at `x` is `M` of the cell holding `x` (0 outside the box). Lights
//! whose footprint is unbounded (point lights, spots reaching the horizon) add the
//! representative light of [`super::importance`] instead: their intensity `Σ p_i·g_i` at
//! their intensity-weighted centroid `c`, `Σ p_i·g_i · G(c, x)`.
//!
//! The integral over a cell is a midpoint rule over the part of each light's footprint that
//! falls in the cell, with up to 4 × 4 points scaled to that part: a narrow spot in a large
//! cell is sampled where it shines (never missed between the cell's points), a wide one over
//! small cells by one point per cell. A light's points form a separable lattice (each column
//! of cells takes its points along `x`, each row along `y`), evaluated a row at a time in
//! the light's own units, eight points a vector (`integrate`'s docs). The map is an
//! estimate, not a bound; what keeps the descent unbiased is that every lane the lane bounds
//! do not cull ([`super::LaneBounds`]) keeps a share of the probability
//! ([`super::importance`]'s mixture).
//!
//! # Storage
//! Cell values are stored as 8-bit codes on a logarithmic scale below the map's largest
//! value `s`: code `c > 0` stands for `s·2^((c − 255)/8)` (8 codes an octave, 31 octaves),
//! code 0 for nothing. 256 bytes a lane (none for a lane without lights, a quarter of the
//! lanes of 10^5 spots); the GPU reads the same codes (256 bytes for every lane).
//!
//! # A lane over a node: its child's maps, resampled
//! A lane over a leaf cluster integrates its lights ([`LaneGrid::of_weighted`]). A lane over
//! an internal node gives the plane what that node's four lanes give it, so its map is
//! theirs, resampled onto its own cells ([`LaneGrid::of_lanes`]: each child cell's integral
//! split over the cells it overlaps). The tree maps its lanes bottom up, so each light is
//! integrated once, into its leaf cluster's lane, and a lane above costs `O(cells)` however
//! many lights it holds. The child maps are finer than the lane's (their boxes lie in its
//! box), so its cells are resolved as well as by integrating its lights into them, up to
//! the children's 8-bit codes. The exact variances (`tile_cuts` example) moved within ±3 %
//! against integrating every light into every lane above it: the tree from its root
//! `stage` 151× → 155× below power sampling, `gallery` 4366× → 4227×, `random` 156× →
//! 158×, `arena` 195× → 196×; with the tiles' cuts 416× → 415×, 2551× → 2620×, 288× →
//! 289×, 512× → 526×. Leaf lanes integrated on coarser cells (8 × 8, each spread over its
//! four) cost the whole tree that coarseness, since every map above is built from them:
//! `tree_variance` read `stage` 477× → 236× and `random` 271× → 115×, and 4 × 4 quartered
//! the gains, for a refit a quarter and two fifths faster.
//!
//! # New powers
//! A map is linear in its lights' powers, and the light tree integrates it in their
//! weights `w_i = Φ_i·2^-e` ([`crate::PmfScale::weight`], exact), keeping the scale and the
//! unbounded lights' intensity in those weights beside the codes
//! ([`MappedLanes::weighted`]), and divides by the weights' sum `S` (`p_i = w_i/S`) for the
//! descent. New powers change the sum but leave a light's weight alone unless its own power
//! (or the largest power's binary exponent `e`) changes, so a refit maps again only the
//! lanes over a light whose weight changed (its leaf cluster's lane from its lights, the
//! lanes above from their children) and divides every other lane's by the new sum: the same
//! bits as a fresh build.
//!
//! A light costs about 200 midpoints in its leaf cluster's lane at `lightpick bench`'s 10^5
//! spots (a footprint over some 140 of the lane's cells, most cell parts taking one point);
//! when every lane integrated all of its lights, it paid that at every depth (fourteen
//! there). Measured at those 10^5 spots on two threads, a refit keeping the bounds'
//! geometry and summing only their intensities again took 241–243 ms for every power
//! (`tree-refit-spots`; 1.25 s with every lane integrating its lights) and 3.0–3.1 ms for
//! one light's (`tree-refit-spots-one`; 145 ms), three quarters of it the leaf lanes'
//! integration, each point's `p·G·S` in `f64` one after another behind a test of squares
//! for dark points, each cell part sizing its points with a square root and a division.
//! With the separable lattice evaluated eight points a vector in `f32`, the codes taken
//! from the ratios' bits rather than a logarithm and the lanes above resampled a row of
//! vectors at a time: 80–96 ms (277–330 ms for the version before in the same runs; 0.9–1.2
//! ms at 10^3, 3.1–3.8 before), the exact variances within 4 % (`tree_variance`: `stage`,
//! `gallery` and `arena` the same to three digits, `random` 271× → 281×). What is left, on
//! one thread (`perf` over twenty refits): the lanes above resampled 18 %, each light's
//! lattice laid out 18 % and summed into its cells 19 %, the points' shapes 16 %, the codes
//! 10 %.
//!
//! # Measured: importances and splits for spots
//! Exact variances `Σ c_i²/P_i − E²` (mean over 37 × 37 shading points, over power
//! sampling's mean: how many times fewer samples the tree needs for the same noise), 4-wide
//! nodes, leaf clusters of 8, on `stage` (300 spots), `gallery` (1356) and two spot sets
//! this was not tuned to: `random` (2000 spots 2–8 m up aimed at random marks, a third with
//! ranges) and `arena` (1500 spots on a ring aimed into it, every fifth wide). "Cull": a lane
//! whose bounds exclude the point gets probability 0 and the defensive share goes by peak
//! intensity `Σ p_i·g_i`. The alternatives were measured with maps of exact cell means (4 × 4
//! points a cell) in a lab before this module was written; the last row is this module
//! (`cargo run --release -p lightpick-core --example tree_variance -- stage gallery random
//! arena`).
//!
//! | split | lane importance | `stage` | `gallery` | `random` | `arena` |
//! | --- | --- | ---: | ---: | ---: | ---: |
//! | position median | representative light × reach (the tree before) | 4.8× | 172× | 6.4× | 5.5× |
//! | position median | pbrt-v4 `Φ·cos θ′/d²` × receiver cosine, cull | 4.1× | 142× | 7.1× | 6.2× |
//! | SAOH (count · `M_Ω` · `K_r` · area) | pbrt-v4, cull | 3.7× | 95× | 5.6× | 6.2× |
//! | SAOH, with the axis's `x`, `y` as keys too | pbrt-v4, cull | 4.0× | 96× | 5.5× | 6.7× |
//! | any of the above | the best bound, with an oracle culling exactly | ≤ 9.6× | — | — | ≤ 9.3× |
//! | position median | map 16 × 16, cull | 33× | 1025× | 137× | 61× |
//! | SAOH, axis keys | map 16 × 16, cull | 86× | 2486× | 153× | 67× |
//! | footprint SAH | map 8 × 8, cull | 62× | 1576× | 57× | 64× |
//! | footprint SAH | map 16 × 16, cull | 163× | 3587× | 179× | 212× |
//! | **footprint SAH** | **map 16 × 16 (this module's midpoints, 8-bit codes), cull** | **158×** | **3576×** | **176×** | **207×** |
//!
//! The bounds fail twice on spots: they cull too little (40–65 % of picks land on lights
//! that give the point nothing) and, more, they weigh what they keep badly: with an oracle
//! that culls every lane giving nothing the best of them still gains less than 10×. Maps
//! need lanes whose lights shine on one region: split by position, the lanes of spots hung
//! together but aimed apart have maps spread over the whole plane.

use glam::{DVec2, DVec3};

mod codes;
mod from_lanes;
mod integrate;
mod mapped;

pub use codes::{decode, encode};
use codes::{encode_cells, encode_ratio};
use integrate::add_light;
pub use mapped::{MappedLanes, UnboundedLanes};

use super::SpatialLight;
use crate::scene::{EmissionShape, geometry_term};

/// Cells along each side of a lane's map.
pub const GRID_SIDE: usize = 16;

/// Cells of a lane's map.
pub const GRID_CELLS: usize = GRID_SIDE * GRID_SIDE;

/// A lane's map of what its lights give the plane (module docs), and the representative
/// light of its lights whose footprint is unbounded.
#[derive(Clone, Debug, PartialEq)]
pub struct LaneGrid {
    /// The map's lower-left corner on the plane.
    pub lo: DVec2,
    /// Cells per unit length along `x` and `y`: `GRID_SIDE / (hi − lo)`.
    pub cells_per_unit: DVec2,
    /// The largest cell value (0: no map).
    pub scale: f64,
    /// Each cell's code, row by row from `lo` (`y` rows, `x` within a row).
    pub codes: [u8; GRID_CELLS],
    /// `Σ p_i·g_i` of the lane's lights with unbounded footprints.
    pub unbounded_intensity: f64,
    /// Their intensity-weighted centroid, in the world.
    pub unbounded_centroid: DVec3,
}

impl LaneGrid {
    /// A lane that gives nothing.
    pub const EMPTY: LaneGrid = LaneGrid {
        lo: DVec2::ZERO,
        cells_per_unit: DVec2::ZERO,
        scale: 0.0,
        codes: [0; GRID_CELLS],
        unbounded_intensity: 0.0,
        unbounded_centroid: DVec3::Z,
    };

    /// The map of `lights` with their profiles `emission` and the parts of the plane they
    /// are mapped over, `footprints` (their footprints within the region of interest;
    /// `None`: unbounded, weighed as a representative light instead; an empty box: not
    /// mapped), one each.
    pub fn of_lights(
        lights: &[SpatialLight],
        emission: &[EmissionShape],
        footprints: &[Option<[DVec2; 2]>],
    ) -> Self {
        Self::of_weighted(lights, |j| lights[j].power, emission, footprints)
    }

    /// [`LaneGrid::of_lights`] with light `j` weighed by `weight(j)` instead of its
    /// normalized power (the tree maps its lanes in the unnormalized weights of
    /// [`crate::PmfScale::weight`], so that a lane whose lights keep their weights keeps its
    /// map when other lights' powers change: [`MappedLanes::normalize`] divides by the sum).
    pub fn of_weighted(
        lights: &[SpatialLight],
        weight: impl Fn(usize) -> f64,
        emission: &[EmissionShape],
        footprints: &[Option<[DVec2; 2]>],
    ) -> Self {
        let mut grid = LaneGrid::EMPTY;
        let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        let (mut intensity, mut weighted) = (0.0, DVec3::ZERO);
        for (j, ((l, e), f)) in lights.iter().zip(emission).zip(footprints).enumerate() {
            match f {
                Some([a, b]) if a.cmplt(*b).all() => {
                    lo = lo.min(*a);
                    hi = hi.max(*b);
                }
                Some(_) => {}
                None => {
                    let w = weight(j) * e.gain();
                    intensity += w;
                    weighted += w * l.position_in_world;
                }
            }
        }
        grid.unbounded_intensity = intensity;
        if intensity > 0.0 {
            grid.unbounded_centroid = weighted / intensity;
        }
        let size = hi - lo;
        if !(size.x > 0.0 && size.y > 0.0 && size.is_finite()) {
            return grid;
        }
        let cell = size / GRID_SIDE as f64;
        let mut integral = [0.0f64; GRID_CELLS];
        for (j, ((l, e), f)) in lights.iter().zip(emission).zip(footprints).enumerate() {
            let Some([a, b]) = *f else { continue };
            let weighted = SpatialLight {
                power: weight(j),
                ..*l
            };
            if weighted.power <= 0.0 || !a.cmplt(b).all() {
                continue;
            }
            add_light(&mut integral, lo, cell, &weighted, e, [a, b]);
        }
        grid.set_integral(lo, size, &integral);
        grid
    }

    /// Sets the map over the box from `lo` of size `size` from each cell's integral (its
    /// mean value times its area), row by row: the scale is the largest mean, each code the
    /// nearest to its cell's mean ([`encode`]). No map where the largest is 0 or not finite.
    fn set_integral(&mut self, lo: DVec2, size: DVec2, integral: &[f64; GRID_CELLS]) {
        let cell = size / GRID_SIDE as f64;
        let area = cell.x * cell.y;
        let largest = largest_of(integral);
        let scale = largest / area;
        if !(scale > 0.0 && scale.is_finite()) {
            return;
        }
        self.lo = lo;
        self.cells_per_unit = DVec2::splat(GRID_SIDE as f64) / size;
        self.scale = scale;
        // Each cell's mean over the largest, `(v/area)/(largest/area)`, as `v·(1/largest)`
        // where that reciprocal is finite (a largest integral below `2^-1024` divides).
        let inverse = 1.0 / largest;
        if inverse.is_finite() {
            encode_cells(&mut self.codes, integral, inverse);
        } else {
            for (code, &v) in self.codes.iter_mut().zip(integral) {
                *code = encode_ratio(v / largest);
            }
        }
    }

    /// The cell of `point_on_plane`, if the map holds it.
    #[inline]
    pub fn cell(&self, point_on_plane: DVec2) -> Option<usize> {
        let c = (point_on_plane - self.lo) * self.cells_per_unit;
        let side = GRID_SIDE as f64;
        (c.x >= 0.0 && c.y >= 0.0 && c.x < side && c.y < side)
            .then(|| c.y as usize * GRID_SIDE + c.x as usize)
    }

    /// The lane's importance at `point_on_plane`: the map's value in the cell holding it
    /// (0 outside the map) plus the unbounded lights' representative light there.
    #[inline]
    pub fn importance(&self, point_on_plane: DVec2) -> f64 {
        let mapped = self
            .cell(point_on_plane)
            .map_or(0.0, |c| self.scale * decode(self.codes[c]));
        let unbounded = if self.unbounded_intensity > 0.0 {
            self.unbounded_intensity * geometry_term(self.unbounded_centroid, point_on_plane)
        } else {
            0.0
        };
        mapped + unbounded
    }
}

/// The largest of `values` and 0 (NaN ignored, as `f64::max` does), over eight running
/// maxima rather than one chain of 256 dependent comparisons.
fn largest_of(values: &[f64; GRID_CELLS]) -> f64 {
    let mut largest = [0.0f64; 8];
    for chunk in values.chunks_exact(8) {
        for (m, &v) in largest.iter_mut().zip(chunk) {
            *m = m.max(v);
        }
    }
    largest.into_iter().fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Emission;

    /// A point light 10 above a 4 × 3 region, mapped over it: each cell's value is its mean
    /// of `p·G`, within the midpoint rule's error and half an eighth octave of rounding.
    /// `|∂²G/∂x²| = z/(4π)·|15x²/r⁷ − 3/r⁵| ≤ 12z/(4π r⁵) ≤ 3/(π z⁴)` (the same along `y`),
    /// so a cell of sides `h_x, h_y` split into `n × n` midpoints has a mean off by at most
    /// `(h_x² + h_y²)/(24 n²) · 3/(π z⁴)`; the reference mean uses 64 × 64 points a cell.
    #[test]
    fn a_smooth_light_maps_to_its_mean_per_cell() {
        let z = 10.0;
        let light = SpatialLight {
            position_in_world: DVec3::new(0.3, -0.2, z),
            power: 0.7,
        };
        let (lo, hi) = (DVec2::new(-2.0, -1.0), DVec2::new(2.0, 2.0));
        let grid = LaneGrid::of_lights(&[light], &[EmissionShape::POINT], &[Some([lo, hi])]);
        assert_eq!(grid.unbounded_intensity, 0.0);
        let cell = (hi - lo) / GRID_SIDE as f64;
        let curvature = 3.0 / (std::f64::consts::PI * z.powi(4));
        let midpoint =
            |n: f64| light.power * (cell.x * cell.x + cell.y * cell.y) / (24.0 * n * n) * curvature;
        let rounding = 2f64.powf(1.0 / 16.0);
        for cy in 0..GRID_SIDE {
            for cx in 0..GRID_SIDE {
                let corner = lo + cell * DVec2::new(cx as f64, cy as f64);
                let reference: f64 = (0..64 * 64)
                    .map(|k| {
                        let at = DVec2::new((k % 64) as f64 + 0.5, (k / 64) as f64 + 0.5) / 64.0;
                        light.contribution(corner + cell * at)
                    })
                    .sum::<f64>()
                    / 4096.0;
                let x = corner + 0.5 * cell;
                let mapped = grid.importance(x);
                // The map used at least one midpoint a cell.
                let slack = midpoint(1.0) + midpoint(64.0);
                assert!(
                    mapped <= (reference + slack) * rounding
                        && mapped >= (reference - slack) / rounding,
                    "cell ({cx}, {cy}): {mapped} vs {reference} ± {slack}"
                );
            }
        }
        // Outside the map: nothing.
        assert_eq!(grid.importance(DVec2::new(5.0, 0.0)), 0.0);
    }

    /// A narrow spot in a large map is sampled where it shines: its cell holds its flux.
    #[test]
    fn a_narrow_spot_is_never_missed_between_midpoints() {
        let spot = crate::scene::Spot {
            direction: DVec3::NEG_Z,
            inner_cone: 0.001,
            outer_cone: 0.002,
        };
        let e = Emission::new(Some(spot), None).expect("valid");
        let light = SpatialLight {
            position_in_world: DVec3::new(0.05, 0.05, 1.0),
            power: 1.0,
        };
        let footprint = e.footprint(light.position_in_world).expect("bounded");
        let (lo, hi) = (DVec2::new(-8.0, -8.0), DVec2::new(8.0, 8.0));
        // A second light spans the map, so cells are 1 × 1 and the spot's disc (radius
        // 0.002) lies inside one of them.
        let wide = SpatialLight {
            position_in_world: DVec3::new(0.0, 0.0, 50.0),
            power: 1e-12,
        };
        let grid = LaneGrid::of_lights(
            &[light, wide],
            &[*e.shape(), EmissionShape::POINT],
            &[Some(footprint), Some([lo, hi])],
        );
        let at = light.position_in_world.truncate();
        // Midpoints spread over the cell (1 apart at most) would all miss the disc; the
        // spot's own midpoints land on it. The wide light alone gives the cell ~1e-12·G.
        let value = grid.importance(at);
        let wide_only = 2.0 * wide.contribution(at);
        assert!(value > 1e3 * wide_only, "{value} vs {wide_only}");
    }
}
