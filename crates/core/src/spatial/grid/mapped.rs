//! A node's four lanes over spots and ranges as the descent reads them ([`MappedLanes`]):
//! their footprints, maps, peak intensities and unbounded lights side by side.

use glam::{DVec2, DVec3};

use super::{GRID_CELLS, GRID_SIDE, LaneGrid, decode};
use crate::scene::geometry_term;
use crate::spatial::{LaneBounds, LaneReach};

/// A node's four lanes over spots and ranges as the descent reads them: each lane's
/// footprint, map and peak intensity side by side (by field, so the four lanes evaluate
/// together, [`MappedLanes::weights`]), the codes of the lanes that hold lights, and for a
/// node with a lane whose footprint is unbounded what such lanes need besides
/// ([`UnboundedLanes`]).
#[derive(Clone, Debug, PartialEq)]
pub struct MappedLanes {
    /// Each lane's footprint box ([`LaneBounds::footprint`]) as `lo.x, lo.y, hi.x,
    /// hi.y` (infinite when some light of the lane reaches arbitrarily far).
    pub footprint: [[f64; 4]; 4],
    /// Each lane's map: `lo.x, lo.y`, cells per unit `x, y` and scale ([`LaneGrid`]).
    pub map: [[f64; 4]; 5],
    /// Each lane's `Σ p_i·g_i`, its share of the mixture.
    pub intensity: [f64; 4],
    /// Lanes (bits) with intensity whose footprint is unbounded: their range and cone tests
    /// ([`LaneReach::reach`]) run beside the footprint's, and their unbounded lights add
    /// their representative light.
    pub unbounded_lanes: u8,
    /// What lanes whose footprint is unbounded need, kept only where some lane's is (a
    /// bounded footprint holds every point its lights light, and holds no unbounded light).
    pub unbounded: Option<Box<UnboundedLanes>>,
    /// Where each lane's map is in `codes`, [`NO_MAP`] for a lane that keeps none.
    map_of: [u8; 4],
    /// The cell codes of the lanes that keep a map, in lane order
    /// ([`MappedLanes::keep_maps`]): a lane without lights would keep 256 zeros (a quarter
    /// of the lanes of `lightpick bench`'s 10^5 spots).
    codes: Vec<[u8; GRID_CELLS]>,
    /// Each lane's map scale in the weights it was mapped with ([`LaneGrid::of_weighted`]):
    /// `map[4]` is this over the weights' sum ([`MappedLanes::normalize`]).
    pub weighted: [f64; 4],
}

/// What the lanes of a node need where some lane's footprint is unbounded (a spot reaching
/// the horizon without a range, a point light among spots), beside [`MappedLanes`].
#[derive(Clone, Debug, PartialEq)]
pub struct UnboundedLanes {
    /// Each lane's box, cones and ranges ([`LaneBounds::geometry`]).
    pub reach: [LaneReach; 4],
    /// Each lane's unbounded lights (mapped without a region): `Σ p_i·g_i` and their
    /// centroid `x, y, z`.
    pub lights: [[f64; 4]; 4],
    /// Each lane's unbounded lights' `Σ w_i·g_i` in the weights it was mapped with:
    /// `lights[0]` is this over the weights' sum.
    pub weighted: [f64; 4],
}

impl UnboundedLanes {
    /// What a node without an unbounded lane stands for: reaches that cull nothing and no
    /// unbounded lights (what the GPU reads for such a node, and where a node with one
    /// starts before its maps).
    pub const NONE: UnboundedLanes = UnboundedLanes {
        reach: [LaneReach::EVERYWHERE; 4],
        lights: [[0.0; 4], [0.0; 4], [0.0; 4], [1.0; 4]],
        weighted: [0.0; 4],
    };
}

/// [`MappedLanes`]' mark of a lane that keeps no map.
const NO_MAP: u8 = u8::MAX;

impl MappedLanes {
    /// Lanes that give nothing anywhere.
    pub const EMPTY: MappedLanes = MappedLanes {
        footprint: [
            [f64::INFINITY; 4],
            [f64::INFINITY; 4],
            [f64::NEG_INFINITY; 4],
            [f64::NEG_INFINITY; 4],
        ],
        map: [[0.0; 4]; 5],
        intensity: [0.0; 4],
        unbounded_lanes: 0,
        unbounded: None,
        map_of: [NO_MAP; 4],
        codes: Vec::new(),
        weighted: [0.0; 4],
    };

    /// The lanes of `grids` (mapped in normalized powers, each keeping its map), with their
    /// bounds `bounds`.
    pub fn new(bounds: &[LaneBounds; 4], grids: &[LaneGrid; 4]) -> Self {
        let mut m = MappedLanes::EMPTY;
        m.keep_maps([true; 4]);
        m.set_bounds(bounds);
        for (k, g) in grids.iter().enumerate() {
            m.set_map(k, g);
        }
        m.normalize(1.0);
        m
    }

    /// Which lanes keep a map (`true`: a lane holding lights), each's codes zero until
    /// [`MappedLanes::set_map`]; the others read as code 0 everywhere.
    pub fn keep_maps(&mut self, lanes: [bool; 4]) {
        let mut kept = 0;
        for (map_of, keeps) in self.map_of.iter_mut().zip(lanes) {
            *map_of = if keeps { kept } else { NO_MAP };
            kept += u8::from(keeps);
        }
        self.codes = vec![[0; GRID_CELLS]; usize::from(kept)];
    }

    /// Lane `k`'s cell codes (all 0 for a lane without a map).
    pub fn codes(&self, k: usize) -> &[u8; GRID_CELLS] {
        self.codes
            .get(usize::from(self.map_of[k]))
            .unwrap_or(&[0; GRID_CELLS])
    }

    /// Heap bytes of the maps kept, by capacity.
    pub fn heap_bytes(&self) -> usize {
        self.codes.capacity() * GRID_CELLS
            + self
                .unbounded
                .as_ref()
                .map_or(0, |_| std::mem::size_of::<UnboundedLanes>())
    }

    /// Lane `k`'s map `grid`, in the weights it was mapped with (until
    /// [`MappedLanes::normalize`]); a lane that keeps no map ([`MappedLanes::keep_maps`])
    /// takes only an empty grid, and a node without unbounded lanes
    /// ([`MappedLanes::set_bounds`], called first) only a grid without unbounded lights.
    pub fn set_map(&mut self, k: usize, grid: &LaneGrid) {
        self.map[0][k] = grid.lo.x;
        self.map[1][k] = grid.lo.y;
        self.map[2][k] = grid.cells_per_unit.x;
        self.map[3][k] = grid.cells_per_unit.y;
        self.weighted[k] = grid.scale;
        match &mut self.unbounded {
            Some(u) => {
                u.weighted[k] = grid.unbounded_intensity;
                let c = grid.unbounded_centroid;
                u.lights[1][k] = c.x;
                u.lights[2][k] = c.y;
                u.lights[3][k] = c.z;
            }
            None => debug_assert!(
                grid.unbounded_intensity == 0.0,
                "lane {k}: unbounded lights in a node of bounded lanes"
            ),
        }
        match self.codes.get_mut(usize::from(self.map_of[k])) {
            Some(codes) => *codes = grid.codes,
            None => debug_assert!(grid.codes == [0; GRID_CELLS], "lane {k} keeps no map"),
        }
    }

    /// The lanes' footprints, peak intensities and unbounded lanes from their bounds, with
    /// their geometry where some lane's footprint is unbounded. Before the maps
    /// ([`MappedLanes::set_map`]): it starts the unbounded lanes' lights afresh.
    pub fn set_bounds(&mut self, bounds: &[LaneBounds; 4]) {
        for (k, b) in bounds.iter().enumerate() {
            let [lo, hi] = b.footprint;
            self.footprint[0][k] = lo.x;
            self.footprint[1][k] = lo.y;
            self.footprint[2][k] = hi.x;
            self.footprint[3][k] = hi.y;
        }
        let unbounded = (0..4).any(|k| self.is_unbounded(k));
        self.unbounded = unbounded.then(|| {
            Box::new(UnboundedLanes {
                reach: bounds.map(|b| b.geometry),
                ..UnboundedLanes::NONE
            })
        });
        for (k, b) in bounds.iter().enumerate() {
            self.set_intensity(k, b.intensity);
        }
    }

    /// Lane `k`'s peak intensity `Σ p_i·g_i` (new powers), and with it whether its range
    /// and cone tests run.
    pub fn set_intensity(&mut self, k: usize, intensity: f64) {
        self.intensity[k] = intensity;
        let bit = 1 << k;
        if intensity > 0.0 && self.is_unbounded(k) {
            self.unbounded_lanes |= bit;
        } else {
            self.unbounded_lanes &= !bit;
        }
    }

    /// Lane `k`'s footprint box `[lo, hi]` ([`LaneBounds::footprint`]).
    pub fn footprint_of(&self, k: usize) -> [DVec2; 2] {
        let [lo_x, lo_y, hi_x, hi_y] = &self.footprint;
        [DVec2::new(lo_x[k], lo_y[k]), DVec2::new(hi_x[k], hi_y[k])]
    }

    /// Whether lane `k` has a footprint and it is not a finite box (an empty lane's is the
    /// empty box `[∞, −∞]`).
    fn is_unbounded(&self, k: usize) -> bool {
        self.footprint[0][k] <= self.footprint[2][k]
            && !self.footprint.iter().all(|side| side[k].is_finite())
    }

    /// Lane `k`'s box, cones and ranges where its footprint is unbounded (`None` where it is
    /// bounded: it then holds every point they reach).
    pub fn reach_of(&self, k: usize) -> Option<&LaneReach> {
        self.unbounded
            .as_deref()
            .filter(|_| self.is_unbounded(k))
            .map(|u| &u.reach[k])
    }

    /// 0 where no light of lane `k` can light `point_on_plane`, else 1: outside its
    /// footprint, or, where that is unbounded, beyond its ranges or outside its cones
    /// ([`LaneBounds::reach`] from what the node keeps).
    pub fn reaches(&self, k: usize, point_on_plane: DVec2) -> f64 {
        let [lo, hi] = self.footprint_of(k);
        if !(point_on_plane.cmpge(lo).all() && point_on_plane.cmple(hi).all()) {
            return 0.0;
        }
        self.reach_of(k).map_or(1.0, |r| r.reach(point_on_plane))
    }

    /// The maps' scales and unbounded intensities as the descent reads them: the weighted
    /// ones over `sum`, the weights' sum (`p_i = w_i / S`, so a map of `Σ w_i·…` over `S` is
    /// the map of `Σ p_i·…` up to rounding).
    pub fn normalize(&mut self, sum: f64) {
        for k in 0..4 {
            self.map[4][k] = self.weighted[k] / sum;
        }
        if let Some(u) = &mut self.unbounded {
            for k in 0..4 {
                u.lights[0][k] = u.weighted[k] / sum;
            }
        }
    }

    /// Each lane's importance and share at `point_on_plane`: 0 and 0 for a lane whose
    /// footprint (and, where it is unbounded, range and cones: [`MappedLanes::reaches`])
    /// excludes the point; else its map's value plus its unbounded lights' representative
    /// light ([`LaneGrid::importance`]), and its `Σ p_i·g_i`.
    #[inline]
    pub fn weights(&self, point_on_plane: DVec2) -> ([f64; 4], [f64; 4]) {
        let (x, y) = (point_on_plane.x, point_on_plane.y);
        let [lo_x, lo_y, hi_x, hi_y] = &self.footprint;
        let [map_x, map_y, per_x, per_y, scale] = &self.map;
        let side = GRID_SIDE as f64;
        let mut importance = [0.0; 4];
        let mut share = [0.0; 4];
        let last = side - 1.0;
        for k in 0..4 {
            // Every index clamped into the map, so nothing below depends on a branch.
            let inside = x >= lo_x[k] && x <= hi_x[k] && y >= lo_y[k] && y <= hi_y[k];
            let cx = (x - map_x[k]) * per_x[k];
            let cy = (y - map_y[k]) * per_y[k];
            let in_map = cx >= 0.0 && cy >= 0.0 && cx < side && cy < side;
            // Within 0..16 after the clamp (NaN gives 0): a 32-bit conversion is exact.
            let cell = (cy.clamp(0.0, last) as i32 * GRID_SIDE as i32 + cx.clamp(0.0, last) as i32)
                as usize;
            let mapped = scale[k] * decode(self.codes(k)[cell & (GRID_CELLS - 1)]);
            importance[k] = if inside & in_map { mapped } else { 0.0 };
            share[k] = if inside { self.intensity[k] } else { 0.0 };
        }
        if self.unbounded_lanes != 0
            && let Some(u) = &self.unbounded
        {
            let [w, c_x, c_y, c_z] = &u.lights;
            for k in 0..4 {
                if w[k] > 0.0 && share[k] > 0.0 {
                    importance[k] +=
                        w[k] * geometry_term(DVec3::new(c_x[k], c_y[k], c_z[k]), point_on_plane);
                }
                if self.unbounded_lanes & (1 << k) != 0 && u.reach[k].reach(point_on_plane) == 0.0 {
                    importance[k] = 0.0;
                    share[k] = 0.0;
                }
            }
        }
        (importance, share)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The descent's own cell lookup ([`MappedLanes::weights`], the production path) reads
    /// the cell a point lies in, by an index computed here apart from the code: four lanes
    /// whose maps differ in origin and cell size, every cell a different code, probed at cell
    /// centres and a hair inside every cell edge, where an off-by-one cell would show.
    #[test]
    fn the_descent_reads_the_cell_each_point_lies_in() {
        let origins = [(-3.0, -2.0), (0.5, -1.25), (-1.0, 0.75), (-4.0, -4.0)];
        let sizes = [(6.0, 4.0), (2.0, 3.5), (1.0, 1.0), (8.0, 5.0)];
        let grids: [LaneGrid; 4] = std::array::from_fn(|k| {
            let mut grid = LaneGrid::EMPTY;
            grid.lo = DVec2::new(origins[k].0, origins[k].1);
            grid.cells_per_unit =
                DVec2::splat(GRID_SIDE as f64) / DVec2::new(sizes[k].0, sizes[k].1);
            grid.scale = 1.0 + k as f64;
            for (c, code) in grid.codes.iter_mut().enumerate() {
                // 255 different codes, none 0; cell 255 shares cell 0's, far away.
                *code = 1 + ((c + 37 * k) % 255) as u8;
            }
            grid
        });
        let mut bounds = [super::LaneBounds::EMPTY; 4];
        for (k, b) in bounds.iter_mut().enumerate() {
            // Footprints holding the whole map, so only the map decides.
            b.footprint = [DVec2::splat(-1e3), DVec2::splat(1e3)];
            b.intensity = 1.0 + k as f64;
        }
        let lanes = MappedLanes::new(&bounds, &grids);
        let side = GRID_SIDE as f64;
        let mut probes = 0;
        for k in 0..4 {
            let (w, h) = (sizes[k].0 / side, sizes[k].1 / side);
            for cy in 0..GRID_SIDE {
                for cx in 0..GRID_SIDE {
                    let x0 = origins[k].0 + cx as f64 * w;
                    let y0 = origins[k].1 + cy as f64 * h;
                    let hair = 1e-9;
                    for (fx, fy) in [
                        (0.5, 0.5),
                        (hair, hair),
                        (1.0 - hair, 1.0 - hair),
                        (hair, 1.0 - hair),
                    ] {
                        let x = DVec2::new(x0 + fx * w, y0 + fy * h);
                        let expected = grids[k].scale * decode(grids[k].codes[cy * GRID_SIDE + cx]);
                        let (importance, share) = lanes.weights(x);
                        assert_eq!(
                            importance[k], expected,
                            "lane {k}, cell ({cx}, {cy}), point {x}"
                        );
                        assert_eq!(share[k], bounds[k].intensity);
                        probes += 1;
                    }
                }
            }
        }
        assert_eq!(probes, 4 * GRID_CELLS * 4);
        // Outside a map: nothing from it, though the footprint holds the point.
        let (importance, _) = lanes.weights(DVec2::new(-3.5, 0.0));
        assert_eq!(importance[0], 0.0);
    }

    /// Lanes without lights keep no map: their codes read 0 and cost no memory, and the
    /// lanes that keep one read their own, whichever lanes before them keep none.
    #[test]
    fn only_the_lanes_that_keep_a_map_hold_codes() {
        let mut lanes = MappedLanes::EMPTY;
        lanes.keep_maps([false, true, false, true]);
        assert_eq!(lanes.heap_bytes(), 2 * GRID_CELLS);
        let mut grid = LaneGrid::EMPTY;
        grid.lo = DVec2::ZERO;
        grid.cells_per_unit = DVec2::splat(GRID_SIDE as f64);
        grid.scale = 2.0;
        for (c, code) in grid.codes.iter_mut().enumerate() {
            *code = 1 + (c % 200) as u8;
        }
        lanes.set_map(3, &grid);
        lanes.set_map(0, &LaneGrid::EMPTY);
        assert_eq!(lanes.codes(3), &grid.codes);
        assert_eq!(lanes.codes(1), &[0; GRID_CELLS]);
        assert_eq!(lanes.codes(0), &[0; GRID_CELLS]);
        let mut bounds = [LaneBounds::EMPTY; 4];
        bounds[3].footprint = [DVec2::ZERO, DVec2::ONE];
        bounds[3].intensity = 1.0;
        lanes.set_bounds(&bounds);
        lanes.normalize(1.0);
        let x = DVec2::new(0.53, 0.21);
        let cell = 3 * GRID_SIDE + 8;
        let (importance, share) = lanes.weights(x);
        assert_eq!(importance, [0.0, 0.0, 0.0, 2.0 * decode(grid.codes[cell])]);
        assert_eq!(share, [0.0, 0.0, 0.0, 1.0]);
    }

    /// What every node of a spot tree holds beside its maps, as `heap_bytes` documents
    /// it: 392 bytes, and 544 more only where a lane's footprint is unbounded.
    #[test]
    fn a_nodes_lanes_hold_what_the_docs_say() {
        assert_eq!(std::mem::size_of::<MappedLanes>(), 392);
        assert_eq!(std::mem::size_of::<UnboundedLanes>(), 544);
    }
}
