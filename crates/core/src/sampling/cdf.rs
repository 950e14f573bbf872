//! The inverse-CDF peer: prefix sums and a binary search, `O(log N)` per sample.

use crate::powers::LightPowers;
use crate::rng::unit_f64;

/// Cumulative distribution `c_i = Σ_{j ≤ i} p_j` over the lights; a uniform `u ∈ [0, 1)`
/// picks the first `i` with `u < c_i`, so light `i` is chosen with probability
/// `c_i − c_{i−1} = p_i` (up to the `2^-32` resolution of `u`). A zero-power light has
/// `c_i = c_{i−1}` and is never chosen. The last positive entry's `c` is set to exactly 1.
#[derive(Clone, Debug, PartialEq)]
pub struct CdfTable {
    cdf: Vec<f64>,
    pmf: Vec<f64>,
}

impl CdfTable {
    /// Builds the prefix sums in `O(N)`.
    pub fn build(powers: &LightPowers) -> Self {
        let (weights, sum) = powers.normalized();
        let mut cdf = Vec::with_capacity(weights.len());
        let mut running = 0.0;
        for &w in &weights {
            running += w;
            cdf.push(running / sum);
        }
        // Rounding may leave the total a few ulps from 1: pin the tail (from the last
        // positive light on) to exactly 1 so every u < 1 finds a light.
        if let Some(last) = weights.iter().rposition(|&w| w > 0.0) {
            for c in &mut cdf[last..] {
                *c = 1.0;
            }
        }
        let pmf = weights.into_iter().map(|w| w / sum).collect();
        Self { cdf, pmf }
    }

    /// Number of lights `N`.
    pub fn len(&self) -> usize {
        self.cdf.len()
    }

    /// Always `false`: a table has at least one light.
    pub fn is_empty(&self) -> bool {
        self.cdf.is_empty()
    }

    /// The normalized power `p_i`.
    pub fn pmf(&self, i: usize) -> f64 {
        self.pmf[i]
    }

    /// The cumulative sums `c_i`.
    pub fn cdf(&self) -> &[f64] {
        &self.cdf
    }

    /// The light whose CDF interval `[c_{i−1}, c_i)` holds `u = r·2^-32`.
    #[inline]
    pub fn sample_u32(&self, r: u32) -> u32 {
        let u = unit_f64(r);
        self.cdf.partition_point(|&c| c <= u) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_power_lights_own_empty_intervals() {
        let powers = LightPowers::new(vec![0.0, 1.0, 0.0, 1.0, 0.0]).unwrap();
        let t = CdfTable::build(&powers);
        assert_eq!(t.cdf(), &[0.0, 0.5, 0.5, 1.0, 1.0]);
        assert_eq!(t.sample_u32(0), 1);
        assert_eq!(t.sample_u32((1 << 31) - 1), 1);
        assert_eq!(t.sample_u32(1 << 31), 3);
        assert_eq!(t.sample_u32(u32::MAX), 3);
    }
}
