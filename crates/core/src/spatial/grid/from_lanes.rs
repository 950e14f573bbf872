//! A lane's map from its child node's four maps ([`LaneGrid::of_lanes`]): what a lane over a
//! node gives the plane is what that node's lanes give it, so its map is theirs, resampled.

use glam::{DVec2, DVec3};

use super::{GRID_CELLS, GRID_SIDE, LaneGrid, MappedLanes, decode};
use crate::avx2::avx2_dispatch;

impl LaneGrid {
    avx2_dispatch! {
        /// The map of a lane over a node, from that node's four lanes `lanes` as mapped (in the
        /// weights their maps were integrated in, [`MappedLanes::weighted`]; the normalization
        /// is not read).
        ///
        /// The map spans the box of the four maps' boxes. A child map is a mean value `v_c` on
        /// each of its cells `c`, so its integral over this map's cell `C` is
        /// `Σ_c v_c·|c ∩ C|`, and `C`'s mean is the four maps' sum of those over `|C|`:
        ///
        /// `M(C) = (1/|C|) Σ_lanes Σ_c v_c·|c ∩ C|`,
        ///
        /// each overlap a product of its `x` and `y` lengths. Every child cell's integral lands
        /// in the cells it overlaps, so the map's integral is the children's (up to rounding),
        /// and it is as fine as they are wherever a cell here holds several of theirs. The
        /// lanes' unbounded lights add up: their `Σ w_i·g_i` summed, their centroids weighed by
        /// it. `O(cells)` a lane, whatever its number of lights.
        ///
        /// Compiled for AVX2 where the processor has it (checked at run time; the same bits:
        /// every operation is an IEEE one rounded once, none fused).
        pub fn of_lanes(lanes: &MappedLanes) -> LaneGrid => of_lanes_in;
    }
}

/// [`LaneGrid::of_lanes`]' body, inlined into each of its compilations.
#[allow(
    clippy::inline_always,
    reason = "compiled into the AVX2 instance too, where its rows widen"
)]
#[inline(always)]
fn of_lanes_in(lanes: &MappedLanes) -> LaneGrid {
    let mut grid = LaneGrid::EMPTY;
    if let Some(u) = &lanes.unbounded {
        let [_, c_x, c_y, c_z] = &u.lights;
        let (mut intensity, mut weighted) = (0.0, DVec3::ZERO);
        for (k, &w) in u.weighted.iter().enumerate() {
            if w > 0.0 {
                intensity += w;
                weighted += w * DVec3::new(c_x[k], c_y[k], c_z[k]);
            }
        }
        grid.unbounded_intensity = intensity;
        if intensity > 0.0 {
            grid.unbounded_centroid = weighted / intensity;
        }
    }
    let side = GRID_SIDE as f64;
    // The lanes with a map (no allocation: a refit maps every lane this way).
    let mapped = || (0..4).filter(|&k| lanes.weighted[k] > 0.0);
    let child_box = |k: usize| {
        let lo = DVec2::new(lanes.map[0][k], lanes.map[1][k]);
        let per = DVec2::new(lanes.map[2][k], lanes.map[3][k]);
        (lo, lo + DVec2::splat(side) / per)
    };
    let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for k in mapped() {
        let (a, b) = child_box(k);
        lo = lo.min(a);
        hi = hi.max(b);
    }
    let size = hi - lo;
    if !(size.x > 0.0 && size.y > 0.0 && size.is_finite()) {
        return grid;
    }
    let cell = size / side;
    let per = DVec2::splat(side) / size;
    let mut integral = [0.0f64; GRID_CELLS];
    for k in mapped() {
        let (child_lo, child_hi) = child_box(k);
        let child_cell = (child_hi - child_lo) / side;
        let scale = lanes.weighted[k];
        let columns = Overlaps::along(child_lo.x, child_cell.x, lo.x, cell.x, per.x);
        let mut spread = [[0.0f64; GRID_SIDE]; GRID_SIDE];
        for (i, lengths) in spread.iter_mut().enumerate() {
            for &(column, length) in columns.of(i) {
                lengths[column] = length;
            }
        }
        let rows = Overlaps::along(child_lo.y, child_cell.y, lo.y, cell.y, per.y);
        for (j, row_codes) in lanes.codes(k).chunks_exact(GRID_SIDE).enumerate() {
            // This child row's integral per column of this map, then split over rows.
            // Every child cell adds its value times its overlap with every column (0
            // but for the one to three it overlaps), a row of vectors with no branch:
            // the same sums in the same order as adding only the overlaps, +0 leaving
            // each (non-negative) sum as it is.
            let mut row = [0.0f64; GRID_SIDE];
            let mut any = false;
            for (&code, lengths) in row_codes.iter().zip(&spread) {
                any |= code != 0;
                let v = scale * decode(code);
                for (sum, &length) in row.iter_mut().zip(lengths) {
                    *sum += v * length;
                }
            }
            if !any {
                continue;
            }
            for &(r, height) in rows.of(j) {
                let cells = &mut integral[r * GRID_SIDE..(r + 1) * GRID_SIDE];
                for (cell, &v) in cells.iter_mut().zip(&row) {
                    *cell += v * height;
                }
            }
        }
    }
    grid.set_integral(lo, size, &integral);
    grid
}

/// The most cells of the coarser map one child cell overlaps along an axis.
const MOST_OVERLAPS: usize = 4;

/// Along one axis, each child cell's overlaps with this map's cells: `(cell, length)` pairs.
struct Overlaps {
    pairs: [[(usize, f64); MOST_OVERLAPS]; GRID_SIDE],
    counts: [usize; GRID_SIDE],
}

impl Overlaps {
    /// The overlaps of the child cells `[a + i·h, a + (i+1)·h]` with this map's cells
    /// `[lo + j·H, lo + (j+1)·H]` (`per = 1/H`). A child cell never spans more than
    /// [`MOST_OVERLAPS`] cells here: the child's box lies in this map's, so its cells are no
    /// wider than these (up to rounding, which may add a sliver at each end).
    fn along(a: f64, h: f64, lo: f64, big: f64, per: f64) -> Self {
        let mut out = Overlaps {
            pairs: [[(0, 0.0); MOST_OVERLAPS]; GRID_SIDE],
            counts: [0; GRID_SIDE],
        };
        let last = GRID_SIDE - 1;
        for i in 0..GRID_SIDE {
            let x0 = a + i as f64 * h;
            let x1 = x0 + h;
            let first = (((x0 - lo) * per).max(0.0) as usize).min(last);
            let end = (((x1 - lo) * per).max(0.0) as usize).min(last);
            for j in first..=end.min(first + MOST_OVERLAPS - 1) {
                let cell_lo = lo + j as f64 * big;
                let length = x1.min(cell_lo + big) - x0.max(cell_lo);
                if length > 0.0 {
                    out.pairs[i][out.counts[i]] = (j, length);
                    out.counts[i] += 1;
                }
            }
        }
        out
    }

    /// Child cell `i`'s overlaps.
    fn of(&self, i: usize) -> &[(usize, f64)] {
        &self.pairs[i][..self.counts[i]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::EmissionShape;
    use crate::spatial::{LaneBounds, SpatialLight};

    /// Four lanes of point lights mapped over boxes of their own: the map over them keeps
    /// their integral (each child cell's mean times its area, summed) within the rounding of
    /// its codes, half an eighth of an octave either way, and is the same where the four
    /// share one box; and outside their boxes it is 0.
    #[test]
    fn a_lanes_map_keeps_its_childrens_integral() {
        let light = |x: f64, y: f64, z: f64, p: f64| SpatialLight {
            position_in_world: DVec3::new(x, y, z),
            power: p,
        };
        let boxes = [
            [DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0)],
            [DVec2::new(0.7, -0.3), DVec2::new(2.5, 0.4)],
            [DVec2::new(-1.0, 0.5), DVec2::new(-0.2, 3.0)],
            [DVec2::new(0.3, 0.3), DVec2::new(0.31, 0.305)],
        ];
        let lights = [
            light(0.5, 0.5, 0.3, 1.0),
            light(1.6, 0.0, 0.2, 2.0),
            light(-0.6, 1.7, 1.0, 0.5),
            light(0.305, 0.302, 0.01, 1e-3),
        ];
        let grids: [LaneGrid; 4] = std::array::from_fn(|k| {
            LaneGrid::of_lights(&lights[k..=k], &[EmissionShape::POINT], &[Some(boxes[k])])
        });
        let lanes = MappedLanes::new(&[LaneBounds::EMPTY; 4], &grids);
        let total = |g: &LaneGrid| {
            let size = DVec2::splat(GRID_SIDE as f64) / g.cells_per_unit;
            let area = size.x * size.y / GRID_CELLS as f64;
            g.codes
                .iter()
                .map(|&c| g.scale * decode(c) * area)
                .sum::<f64>()
        };
        let children: f64 = grids.iter().map(total).sum();
        let parent = LaneGrid::of_lanes(&lanes);
        // Both compilations (AVX2 where the processor has it, and the baseline) agree.
        assert_eq!(parent, of_lanes_in(&lanes));
        let half = 2f64.powf(1.0 / 16.0);
        let ratio = total(&parent) / children;
        assert!(ratio <= half && ratio >= 1.0 / half, "{ratio}");
        assert_eq!(parent.importance(DVec2::new(3.0, 3.0)), 0.0);
        assert_eq!(parent.importance(DVec2::new(-1.5, -0.5)), 0.0);
        // One child alone, resampled onto its own box: every cell its own code.
        let mut alone = MappedLanes::EMPTY;
        alone.keep_maps([true, false, false, false]);
        alone.set_map(0, &grids[0]);
        let same = LaneGrid::of_lanes(&alone);
        assert_eq!(same.codes, grids[0].codes);
        assert_eq!(same.lo, grids[0].lo);
    }

    /// The lanes' unbounded lights add up: their weights summed, their centroid weighed.
    #[test]
    fn unbounded_lights_add_up() {
        let mut lanes = MappedLanes::EMPTY;
        let mut everywhere = LaneBounds::EMPTY;
        everywhere.footprint = [DVec2::NEG_INFINITY, DVec2::INFINITY];
        lanes.set_bounds(&[everywhere; 4]);
        for (k, (w, c)) in [
            (1.0, DVec3::new(0.0, 0.0, 1.0)),
            (3.0, DVec3::new(4.0, 0.0, 1.0)),
        ]
        .into_iter()
        .enumerate()
        {
            let mut g = LaneGrid::EMPTY;
            g.unbounded_intensity = w;
            g.unbounded_centroid = c;
            lanes.set_map(k, &g);
        }
        let grid = LaneGrid::of_lanes(&lanes);
        assert_eq!(grid.unbounded_intensity, 4.0);
        assert_eq!(grid.unbounded_centroid, DVec3::new(3.0, 0.0, 1.0));
        assert_eq!(grid.scale, 0.0);
    }
}
