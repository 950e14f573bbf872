//! One light's integral over the cells of a lane's map, `∫_cell p·G·S dy`: a midpoint rule
//! over the part of the light's footprint in each cell (the rule of [`super`]'s docs), its
//! points evaluated eight at a time, in the light's own units and in `f32`.
//!
//! # In the light's own units
//! A light at height `z` above the foot `f` gives a point `y` of the plane, with
//! `(u, v) = (y − f)/z` and `n² = 1 + u² + v²`,
//!
//! `p·G·S = p·g/(4π z²) · n⁻³ · t(α)² · w`, `w = clamp(1 − (k·n²)², 0, 1)`, `k = (z/r)²`,
//!
//! so everything that carries the light's scale (its power, gain and height) is one factor
//! `K = p·g/(4π z²)`, taken in `f64` once a row of points, and what is left, the light's
//! **shape** `n⁻³·t²·w`, lies in `[0, 1]` at offsets of a few heights: `f32` holds it to
//! `2^-24` where the map's codes round to half an eighth of an octave (`2^(1/16)`, 4.4 %). The cone
//! is tested on `1 − cos α = |a × d|²/(n·(n + a·d))` (`d = (u, v, −1)`, `a` the unit axis),
//! which keeps its relative precision next to the axis, where `cos α` itself rounds to 1
//! in `f32` within `3.5·10^-4` rad: a spot of a milliradian keeps its falloff. A point more
//! than 90° off the axis (`a·d ≤ 0`, where that quotient nears `0/0` straight behind the
//! spot) is dark, as for every cone (`θo ≤ 90°`).
//!
//! A light whose factor or offsets leave that range (a height below the least normal
//! `f64`, offsets over `2^20` heights, a cone whose `1/(cos θi − cos θo)` is no `f32`)
//! takes the `f64` evaluation of [`SpatialLight::contribution_culled`] point by point.
//!
//! # A separable lattice, a row at a time
//! Each column of cells the footprint overlaps takes its points along `x` (1 to 4, by the
//! rule of [`Axis::along`]), each row its points along `y`, and a cell part takes every pair
//! of its column's and its row's: a light's points are one lattice, evaluated a row at a
//! time ([`shape_row`]) and summed into their cells. Sizing the points per axis (a column's
//! distance from the foot along `x` alone, where it was the distance in the plane) gives a
//! part at least the points it had; the exact variances moved by at most 4 %.
//!
//! # Measured
//! The `f64` evaluation point by point, with each cell part sizing its points by a square
//! root and a division, took three quarters of a spot tree's refit: at `lightpick bench`'s
//! 10^5 spots a light's footprint covers some 140 cells of its lane's map, 83 % of them
//! with a single point, and the cell parts' own work (latency, mispredicted branches) was
//! most of it. This lattice, the `f32` shapes eight to a vector (AVX2 where the processor has
//! it; four on the baseline, the same bits) and the codes' thresholds made the refit 3–4×
//! faster (`docs/numbers.md`).

use glam::DVec2;

use super::{GRID_CELLS, GRID_SIDE};
use crate::avx2::avx2_dispatch;
use crate::scene::EmissionShape;
use crate::spatial::SpatialLight;

/// Midpoints along each side of a light's part of a cell, at most.
const SAMPLES_PER_SIDE: usize = 4;

/// Midpoints per length on which a light's irradiance changes ([`add_light`]): 8 measured
/// within 4 % of 16 on `stage`, `gallery`, `random` and `arena`, 4 up to 27 % below.
const POINTS_PER_SCALE: f64 = 8.0;

/// The farthest offset from a light's foot, in its heights, that its shape is evaluated
/// at in `f32` (`n² ≤ 2^41`, `n⁻³ ≥ 2^-62`).
const MOST_HEIGHTS: f64 = (1u64 << 20) as f64;

/// The midpoints a side of a cell part takes: `⌈8·overlap/scale⌉` ([`POINTS_PER_SCALE`])
/// clamped to `1 ..=` [`SAMPLES_PER_SIDE`] (1 for NaN), by comparing `8·overlap` with
/// multiples of `scale` (no division, no call to `ceil`, no branch: this runs once a cell
/// a side of every light).
#[inline]
fn points_per_side(overlap: f64, scale: f64) -> usize {
    const _: () = assert!(SAMPLES_PER_SIDE == 4);
    let eighths = POINTS_PER_SCALE * overlap;
    1 + usize::from(eighths > scale)
        + usize::from(eighths > 2.0 * scale)
        + usize::from(eighths > 3.0 * scale)
}

/// A light's shape `n⁻³·t²·w` in its own units (module docs), in `f32`.
#[derive(Clone, Copy, Debug)]
struct UnitShape {
    /// The spot's unit axis `a` (zero without a spot).
    axis: [f32; 3],
    /// `1 − cos θi`.
    inner: f32,
    /// `1 − cos θo`.
    outer: f32,
    /// `1/(cos θi − cos θo)`, 0 without a spot.
    cone_scale: f32,
    /// `k = (z/r)²`, 0 without a range.
    range: f32,
}

impl UnitShape {
    /// The shape of a light `z` above the plane with profile `e`, where `f32` holds it.
    fn of(e: &EmissionShape, z: f64) -> Option<Self> {
        let axis = e.axis();
        let zr = z * e.inv_range();
        let shape = UnitShape {
            axis: [axis.x as f32, axis.y as f32, axis.z as f32],
            inner: (1.0 - e.cos_inner()) as f32,
            outer: (1.0 - e.cos_outer()) as f32,
            cone_scale: e.cone_scale() as f32,
            range: (zr * zr) as f32,
        };
        (shape.cone_scale.is_finite() && shape.range.is_finite()).then_some(shape)
    }

    /// `n⁻³·t²·w` at `(u, v)`, every factor a selection rather than a branch (lanes).
    #[inline(always)]
    #[allow(
        clippy::inline_always,
        reason = "inlined into each compilation of the row's loop, where it widens"
    )]
    fn at(&self, u: f32, v: f32) -> f32 {
        let [ax, ay, az] = self.axis;
        let n2 = 1.0 + (u * u + v * v);
        let n = n2.sqrt();
        let inverse_cube = 1.0 / (n2 * n);
        // d = (u, v, −1): a·d and a × d.
        let dot = ax * u + ay * v - az;
        let (cx, cy, cz) = (-ay - az * v, az * u + ax, ax * v - ay * u);
        let cross2 = cx * cx + cy * cy + cz * cz;
        // 1 − cos α = |a × d|² / (n·(n + a·d)) where the point lies within 90° of the axis
        // (`a·d > 0`: no cancellation); beyond, 2, dark for every cone (θo ≤ 90°).
        let off_axis = if dot > 0.0 {
            cross2 / (n2 + n * dot)
        } else {
            2.0
        };
        let t = (self.outer - off_axis) * self.cone_scale;
        let partial = if off_axis < self.outer { t * t } else { 0.0 };
        let cone = if off_axis <= self.inner { 1.0 } else { partial };
        let cone = if self.cone_scale == 0.0 { 1.0 } else { cone };
        let kn2 = self.range * n2;
        let window = (1.0 - kn2 * kn2).clamp(0.0, 1.0);
        inverse_cube * cone * window
    }
}

avx2_dispatch! {
    /// `out[i] =` the shape at `(u[i], v)`, for lengths a multiple of 8; compiled for AVX2
    /// where the processor has it (checked at run time; eight lanes a vector where the
    /// baseline packs four; the same bits: every operation is an IEEE one rounded once, none
    /// fused).
    fn shape_row(shape: &UnitShape, u: &[f32], v: f32, out: &mut [f32]) => shape_row_in;
}

/// [`shape_row`]'s body, inlined into each of its compilations.
#[allow(
    clippy::inline_always,
    reason = "compiled into the AVX2 instance too, where its loop widens"
)]
#[inline(always)]
fn shape_row_in(shape: &UnitShape, u: &[f32], v: f32, out: &mut [f32]) {
    for (o, u) in out.chunks_exact_mut(8).zip(u.chunks_exact(8)) {
        for i in 0..8 {
            o[i] = shape.at(u[i], v);
        }
    }
}

/// The midpoints along one axis of a light's footprint: for each cell the footprint
/// overlaps, [`points_per_side`] points spaced evenly over the overlap. A light's points
/// are every pair of an `x` and a `y` point (a separable lattice), each cell part taking the
/// points of its column and row.
struct Axis {
    /// The points, on the plane (and room for a part's four past the last).
    at: [f64; Axis::MOST + SAMPLES_PER_SIDE],
    /// The length each point stands for, on the plane.
    width: [f64; Axis::MOST + SAMPLES_PER_SIDE],
    /// Each point's cell along the axis.
    cell: [u8; Axis::MOST + SAMPLES_PER_SIDE],
    /// The points (the rest of the arrays unused).
    len: usize,
    /// The first and last cells the footprint overlaps.
    cells: std::ops::RangeInclusive<usize>,
}

impl Axis {
    /// The most points an axis holds.
    const MOST: usize = GRID_SIDE * SAMPLES_PER_SIDE;

    /// The midpoints over `[a, b]` (the footprint along the axis, of length `extent` across
    /// the whole footprint, a light of foot `foot` at `height`) in cells of length `cell`
    /// from `lo`. A cell part's points are spaced by at most an eighth of the length on
    /// which the light's irradiance changes there: the smaller of the footprint's extent and
    /// the light's distance (its height, or the distance along the axis from the foot to
    /// the part where that is larger).
    fn along(a: f64, b: f64, lo: f64, cell: f64, foot: f64, height: f64, extent: f64) -> Self {
        let last = GRID_SIDE as f64 - 1.0;
        let first_cell = ((a - lo) / cell).floor().clamp(0.0, last) as usize;
        let last_cell = ((b - lo) / cell).floor().clamp(0.0, last) as usize;
        let mut axis = Axis {
            at: [0.0; Axis::MOST + SAMPLES_PER_SIDE],
            width: [0.0; Axis::MOST + SAMPLES_PER_SIDE],
            cell: [0; Axis::MOST + SAMPLES_PER_SIDE],
            len: 0,
            cells: first_cell..=last_cell,
        };
        for c in first_cell..=last_cell {
            let cell_lo = lo + cell * c as f64;
            let o_lo = a.max(cell_lo);
            let o = b.min(cell_lo + cell) - o_lo;
            if o.is_nan() || o <= 0.0 {
                continue;
            }
            let near = foot.clamp(o_lo, o_lo + o);
            let reach = height.max((near - foot).abs());
            let scale = extent.min(reach).max(f64::MIN_POSITIVE);
            let n = points_per_side(o, scale);
            let step = o / n as f64;
            // All four written, the next part's overwriting those past `n`.
            let k = axis.len;
            for i in 0..SAMPLES_PER_SIDE {
                axis.at[k + i] = o_lo + step * (i as f64 + 0.5);
                axis.width[k + i] = step;
                axis.cell[k + i] = c as u8;
            }
            axis.len += n;
        }
        axis
    }
}

/// Adds light `l`'s integral over each cell of the map (from `lo`, cells of size `cell`)
/// that its mapped area `[a, b]` overlaps: a midpoint rule over the separable lattice of
/// [`Axis::along`] (up to [`SAMPLES_PER_SIDE`] points a side of a cell part, at most an
/// eighth, [`POINTS_PER_SCALE`], of the length on which the light's irradiance changes
/// there), the points' shapes evaluated in the light's units, a row of the lattice at a
/// time (module docs).
pub(super) fn add_light(
    integral: &mut [f64; GRID_CELLS],
    lo: DVec2,
    cell: DVec2,
    l: &SpatialLight,
    e: &EmissionShape,
    [a, b]: [DVec2; 2],
) {
    let foot = l.position_in_world.truncate();
    let height = l.position_in_world.z;
    let extent = b - a;
    let xs = Axis::along(a.x, b.x, lo.x, cell.x, foot.x, height, extent.x);
    let ys = Axis::along(a.y, b.y, lo.y, cell.y, foot.y, height, extent.y);
    // p·g/(4π z²), and what f32 holds of the offsets in heights.
    let factor = l.power * e.gain() / (4.0 * std::f64::consts::PI * height * height);
    let farthest = (a - foot).abs().max((b - foot).abs()).max_element();
    let shape = UnitShape::of(e, height).filter(|_| {
        height >= f64::MIN_POSITIVE
            && factor > 0.0
            && factor.is_finite()
            && farthest <= MOST_HEIGHTS * height
    });
    let Some(shape) = shape else {
        for j in 0..ys.len {
            let row = &mut integral[usize::from(ys.cell[j]) * GRID_SIDE..][..GRID_SIDE];
            for i in 0..xs.len {
                let y = DVec2::new(xs.at[i], ys.at[j]);
                row[usize::from(xs.cell[i])] +=
                    l.contribution_culled(e, y) * xs.width[i] * ys.width[j];
            }
        }
        return;
    };
    // The x points in heights from the foot, and their widths in heights; the padding
    // points lie 10^18 heights out, where the shape is exactly 0, with no width.
    let inv_height = 1.0 / height;
    let padded = xs.len.next_multiple_of(8);
    let mut u = [1e18f32; Axis::MOST];
    let mut width = [0.0f32; Axis::MOST];
    for i in 0..xs.len {
        u[i] = ((xs.at[i] - foot.x) * inv_height) as f32;
        width[i] = (xs.width[i] * inv_height) as f32;
    }
    // p·g/(4π): K times a point's area, in heights squared.
    let flux = factor * height * height;
    let mut value = [0.0f32; Axis::MOST];
    for j in 0..ys.len {
        let v = ((ys.at[j] - foot.y) * inv_height) as f32;
        shape_row(&shape, &u[..padded], v, &mut value[..padded]);
        let mut sums = [0.0f32; GRID_SIDE];
        for i in 0..xs.len {
            sums[usize::from(xs.cell[i])] += value[i] * width[i];
        }
        let weight = flux * ys.width[j] * inv_height;
        let row = &mut integral[usize::from(ys.cell[j]) * GRID_SIDE..][..GRID_SIDE];
        for c in xs.cells.clone() {
            row[c] += weight * f64::from(sums[c]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Emission, Spot, light_term};
    use glam::DVec3;

    /// A xorshift stream's next value in `[0, 1)`.
    fn next(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A light `z` above the origin: a spot (cones from a milliradian to the horizon, tilted
    /// up to 80°) in three of four, a range in one of three.
    fn random_emission(state: &mut u64, z: f64) -> Emission {
        let spot = (next(state) < 0.75).then(|| {
            let outer = 1e-3 * (1.57e3f64).powf(next(state));
            // One in five aimed anywhere, up to straight up (lighting the plane behind it
            // only through a wide cone, and mapped only with a range).
            let most_tilt = if next(state) < 0.2 { 3.1 } else { 1.4 };
            let (tilt, turn) = (most_tilt * next(state), std::f64::consts::TAU * next(state));
            Spot {
                direction: DVec3::new(
                    tilt.sin() * turn.cos(),
                    tilt.sin() * turn.sin(),
                    -tilt.cos(),
                ),
                inner_cone: outer * next(state) * 0.999,
                outer_cone: outer,
            }
        });
        let range = (next(state) < 0.34).then(|| z * (0.5 + 10.0 * next(state)));
        Emission::new(spot, range).expect("valid")
    }

    /// The shape in `f32` (module docs) against the `f64` light term it stands for,
    /// `G·S·4π z²/g`, at the same points (the `f32` offsets, widened): within its rounding,
    /// `n⁻³·2^-24·(40 + 2·s·16·(√δ + δ))` with `δ = 1 − cos α` and `s = 1/(cos θi − cos θo)`
    /// (each factor's few roundings; the cone's angle to a few `2^-24`, which the falloff
    /// scales by `s·α`). Both compilations give the same bits. Heights from 10^-3 to 10^3,
    /// points up to three heights and a footprint out; each case (lit, inside a falloff,
    /// dark, inside a range's window) is met more than 1000 times.
    #[test]
    fn the_shape_in_heights_is_the_light_term_within_its_rounding() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let (mut lit, mut falloff, mut dark, mut window, mut behind) = (0, 0, 0, 0, 0);
        for _ in 0..4000 {
            let z = 10f64.powf(6.0 * next(&mut state) - 3.0);
            let e = random_emission(&mut state, z);
            let shape = UnitShape::of(e.shape(), z).expect("in range");
            let light = DVec3::new(0.0, 0.0, z);
            let reach = e
                .shape()
                .footprint(light)
                .map_or(3.0, |[a, b]| a.abs().max(b.abs()).max_element() / z + 1.0);
            let mut u = [0.0f32; 16];
            for x in &mut u {
                *x = (reach * (2.0 * next(&mut state) - 1.0)) as f32;
            }
            let mut v = (reach * (2.0 * next(&mut state) - 1.0)) as f32;
            // A spot aimed up: the row through the point straight behind it, where
            // `1 − cos α` is `0/0` from the cross product, and its neighbours.
            let axis = e.shape().axis();
            if axis.z > 0.05 {
                v = (-axis.y / axis.z) as f32;
                u[0] = (-axis.x / axis.z) as f32;
                u[1] = u[0].next_up();
                u[2] = u[0].next_down();
                behind += 1;
            }
            let (mut values, mut baseline) = ([0.0f32; 16], [0.0f32; 16]);
            shape_row(&shape, &u, v, &mut values);
            shape_row_in(&shape, &u, v, &mut baseline);
            assert_eq!(values.map(f32::to_bits), baseline.map(f32::to_bits));
            let gain_4pi_z2 = 4.0 * std::f64::consts::PI * z * z / e.shape().gain();
            for (&ui, &value) in u.iter().zip(&values) {
                let (uf, vf) = (f64::from(ui), f64::from(v));
                let y = DVec2::new(uf * z, vf * z);
                let reference = light_term(light, Some(e.shape()), y) * gain_4pi_z2;
                let n2 = 1.0 + uf * uf + vf * vf;
                let inverse_cube = 1.0 / (n2 * n2.sqrt());
                let to_point = DVec3::new(uf, vf, -1.0) / n2.sqrt();
                let off_axis = 1.0 - e.shape().axis().dot(to_point);
                let angle = 16.0 * (off_axis.abs().sqrt() + off_axis.abs());
                let bound =
                    inverse_cube * 2f64.powi(-24) * (40.0 + 2.0 * e.shape().cone_scale() * angle);
                assert!(
                    (f64::from(value) - reference).abs() <= bound,
                    "z {z:e}, {e:?} at ({uf}, {vf}): {value} vs {reference} ± {bound:e}"
                );
                let cone = e.shape().cone_term(light, y);
                match cone {
                    Some(0.0) => dark += 1,
                    Some(t) if t < 1.0 => falloff += 1,
                    _ if reference > 0.0 => lit += 1,
                    _ => dark += 1,
                }
                let q = y.extend(-z).length() * e.shape().inv_range();
                if q > 0.0 && q < 1.0 && cone.is_none_or(|t| t > 0.0) {
                    window += 1;
                }
            }
        }
        for (case, count) in [
            ("lit", lit),
            ("falloff", falloff),
            ("dark", dark),
            ("window", window),
        ] {
            assert!(count > 1000, "{case}: {count}");
        }
        assert!(behind > 100, "spots aimed up: {behind}");
    }

    /// A light's map from the `f32` shapes against the same lattice evaluated in `f64`
    /// ([`SpatialLight::contribution_culled`], the path of a light outside `f32`'s range):
    /// each cell within the points' bound (the test above) summed over its points, relative
    /// to the light's largest cell.
    #[test]
    fn a_lights_cells_in_f32_are_its_cells_in_f64() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut mapped = 0;
        for _ in 0..300 {
            let z = 10f64.powf(4.0 * next(&mut state) - 2.0);
            let e = random_emission(&mut state, z);
            let l = SpatialLight {
                position_in_world: DVec3::new(next(&mut state), next(&mut state), z),
                power: 0.3 + next(&mut state),
            };
            let Some([a, b]) = e.shape().footprint(l.position_in_world) else {
                continue;
            };
            if !a.cmplt(b).all() {
                continue; // a range short of the plane: nothing to map
            }
            let (lo, cell) = (a, (b - a) / GRID_SIDE as f64);
            let mut fast = [0.0; GRID_CELLS];
            add_light(&mut fast, lo, cell, &l, e.shape(), [a, b]);
            // The same lattice, in f64 point by point.
            let foot = l.position_in_world.truncate();
            let extent = b - a;
            let xs = Axis::along(a.x, b.x, lo.x, cell.x, foot.x, z, extent.x);
            let ys = Axis::along(a.y, b.y, lo.y, cell.y, foot.y, z, extent.y);
            let mut exact = [0.0; GRID_CELLS];
            for j in 0..ys.len {
                for i in 0..xs.len {
                    let y = DVec2::new(xs.at[i], ys.at[j]);
                    exact[usize::from(ys.cell[j]) * GRID_SIDE + usize::from(xs.cell[i])] +=
                        l.contribution_culled(e.shape(), y) * xs.width[i] * ys.width[j];
                }
            }
            let largest = exact.iter().fold(0.0f64, |m, &v| m.max(v));
            // (A thin ellipse across its box may fall between every midpoint: no map.)
            if largest > 0.0 {
                mapped += 1;
            }
            for (k, (&f, &x)) in fast.iter().zip(&exact).enumerate() {
                // Each point's shape within 2^-24·(40 + 2·s·32) of its peak, n⁻³ ≤ 1,
                // over at most 16 points of the cell's area.
                let per_point = 2f64.powi(-24) * (40.0 + 64.0 * e.shape().cone_scale());
                let area = cell.x * cell.y;
                let bound = l.power * e.shape().gain() / (4.0 * std::f64::consts::PI * z * z)
                    * per_point
                    * area
                    + 1e-12 * largest;
                assert!((f - x).abs() <= bound, "cell {k}: {f} vs {x} ± {bound:e}");
            }
        }
        assert!(mapped > 200, "{mapped}");
    }

    /// The points a side takes are the written rule `⌈8·overlap/scale⌉` clamped to
    /// `1 ..= 4` (NaN to 1, as `as usize` saturates it to 0): at ratios next to every
    /// integer (where the quotient's rounding decides nothing), zeros, infinities and NaN.
    #[test]
    fn points_per_side_is_the_clamped_ceiling() {
        let written = |o: f64, s: f64| ((8.0 * o / s).ceil() as usize).clamp(1, SAMPLES_PER_SIDE);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..10_000 {
            let scale = 10f64.powf(12.0 * next(&mut state) - 6.0);
            let ratio = 6.0 * next(&mut state);
            if (ratio - ratio.round()).abs() < 1e-9 {
                continue;
            }
            let overlap = ratio * scale / 8.0;
            assert_eq!(
                points_per_side(overlap, scale),
                written(overlap, scale),
                "{ratio}"
            );
        }
        for k in 0..=6 {
            let at = f64::from(k) / 8.0;
            assert_eq!(points_per_side(at, 1.0), written(at, 1.0), "{at}");
        }
        for (o, s, n) in [
            (0.0, 1.0, 1),
            (1.0, f64::INFINITY, 1),
            (f64::INFINITY, 1.0, 4),
            (f64::NAN, 1.0, 1),
            (1.0, f64::NAN, 1),
            (1e300, f64::MIN_POSITIVE, 4),
        ] {
            assert_eq!(points_per_side(o, s), n, "{o} / {s}");
        }
    }
}
