//! What light picking does at one shading point: each light's pick probability beside its
//! true share of the irradiance there, and the variance that follows.
//!
//! At a point `x` of the receiver plane light `i` contributes `f_i = Φ_i·G_i(x)` of the
//! irradiance `E(x) = Σ_j f_j`; its **share** is `s_i = f_i / E(x)`. A scheme that picks
//! light `i` with probability `q_i` (and estimates `f_i/q_i`) has the per-sample variance
//!
//! ```text
//! Var = Σ_{q_i > 0} f_i²/q_i − E² = E² · (Σ_{q_i > 0} s_i²/q_i − 1),
//! ```
//!
//! so its **relative variance** `Var/E² = Σ s_i²/q_i − 1` is the χ²-divergence of the shares
//! from the pick probabilities: zero exactly when `q = s` (picking in proportion to the
//! contribution), and large where a light with a big share is rarely picked. Power sampling
//! (`q_i = p_i = Φ_i/ΣΦ`) is ideal only where every light's geometry term is the same.
//! The spatial scheme ([`crate::spatial`], [`PointInspection::at_with_spatial`]) picks with
//! `q_i = P(i | x)`: exactly `s_i` for few lights (no variance), a light tree's
//! approximation of it beyond.
//!
//! Everything is computed in normalized units (`p_i·G_i` instead of `Φ_i·G_i`), so powers
//! near `f64::MAX` or 1e-300 neither overflow nor underflow where their shares matter.

use glam::DVec2;

use crate::light_sampler::{LightSampler, ShadingContext};
use crate::scene::Scene;

/// Lights listed individually per ranking (largest share, largest pmf) in an inspection.
pub const LISTED_PER_RANKING: usize = 8;

/// One light at the inspected point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LightShare {
    /// The light's index in the scene.
    pub index: usize,
    /// Its power `Φ_i`.
    pub power: f64,
    /// Its pick probability under power sampling, `p_i = Φ_i / ΣΦ`.
    pub pmf: f64,
    /// Its share of the irradiance at the point, `s_i = Φ_i·G_i(x) / E(x)` (0 when `E = 0`).
    pub share: f64,
    /// Its pick probability under the spatial scheme at the point, `P(i | x)`
    /// ([`crate::spatial`]), when the inspection was given the spatial sampler.
    pub spatial: Option<f64>,
    /// For a spot, its cone term `t²` toward the point
    /// ([`crate::scene::EmissionShape::cone_term`]: 1 inside the inner cone, 0 beyond the
    /// outer); `None` for a light without a spot.
    pub cone: Option<f64>,
}

/// The lights an inspection does not list one by one, summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct OtherLights {
    /// How many lights.
    pub count: usize,
    /// Their total pick probability `Σ p_i`.
    pub pmf: f64,
    /// Their total share `Σ s_i`.
    pub share: f64,
    /// Their total spatial pick probability `Σ P(i | x)`, when known.
    pub spatial: Option<f64>,
}

/// Light picking at one point `x` of the receiver plane (see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PointInspection {
    /// The point `(x, y)` on `z = 0`.
    pub x: DVec2,
    /// The exact irradiance `E(x) = Σ Φ_i·G_i(x)`.
    pub irradiance: f64,
    /// Every light when there are at most `2·LISTED_PER_RANKING`, else the
    /// [`LISTED_PER_RANKING`] largest shares and the [`LISTED_PER_RANKING`] largest pmfs;
    /// sorted by share (largest first), ties by index.
    pub lights: Vec<LightShare>,
    /// The lights not in `lights`.
    pub others: OtherLights,
    /// `Var/E²` of uniform picking (`q_i = 1/N`): `N·Σ s_i² − 1`.
    pub uniform_relative_variance: f64,
    /// `Var/E²` of power picking (`q_i = p_i`): `Σ_{p_i>0} s_i²/p_i − 1`.
    pub power_relative_variance: f64,
    /// `Var/E²` of the spatial scheme (`q_i = P(i | x)`): `Σ_{q_i>0} s_i²/q_i − 1`, 0 for
    /// the exact pick (`q = s`) up to rounding; when the inspection was given the sampler.
    pub spatial_relative_variance: Option<f64>,
    /// `½·Σ |s_i − p_i|`: how far power sampling is from the ideal pmf here.
    pub total_variation: f64,
}

impl PointInspection {
    /// Inspects `scene` at the point `x` in `O(N)` (power and uniform picking).
    pub fn at(scene: &Scene, x: DVec2) -> Self {
        Self::compute(scene, x, None)
    }

    /// [`PointInspection::at`] with a contribution-aware scheme too, through the one
    /// interface: `spatial` is a sampler of `scene` (usually
    /// [`SpatialSampler::for_scene`](crate::spatial::SpatialSampler::for_scene)),
    /// whose `q_i(x)` ([`LightSampler::pmfs_at`], one traversal) fills the spatial column;
    /// `O(N)` for the spatial sampler.
    ///
    /// # Panics
    /// If `spatial` was built for a different number of lights.
    pub fn at_with_spatial(
        scene: &Scene,
        x: DVec2,
        spatial: &(impl LightSampler + ?Sized),
    ) -> Self {
        assert_eq!(
            spatial.light_count(),
            scene.light_count(),
            "sampler built for another scene"
        );
        Self::compute(scene, x, Some(&spatial.pmfs_at(&ShadingContext::at(x))))
    }

    fn compute(scene: &Scene, x: DVec2, spatial: Option<&[f64]>) -> Self {
        let pmf = scene.powers.pmf();
        let n = pmf.len();
        // Normalized contributions p_i·G_i(x)·S_i(x): E(x)/ΣΦ.
        let contribution = scene.weighted_terms(&pmf, x);
        let normalized_irradiance: f64 = contribution.iter().sum();
        let share = |i: usize| {
            if normalized_irradiance > 0.0 {
                contribution[i] / normalized_irradiance
            } else {
                0.0
            }
        };
        let (mut uniform_second, mut power_second, mut variation) = (0.0, 0.0, 0.0);
        let mut spatial_second = 0.0;
        for (i, &p) in pmf.iter().enumerate() {
            let s = share(i);
            uniform_second += s * s;
            if p > 0.0 {
                power_second += s * s / p;
            }
            if let Some(q) = spatial.map(|q| q[i])
                && q > 0.0
            {
                spatial_second += s * s / q;
            }
            variation += (s - p).abs();
        }
        let relative = |second: f64| {
            if normalized_irradiance > 0.0 {
                (second - 1.0).max(0.0)
            } else {
                0.0
            }
        };
        let listed = listed_lights(&pmf, &contribution);
        let mut others = OtherLights {
            count: n - listed.len(),
            pmf: 1.0,
            share: if normalized_irradiance > 0.0 {
                1.0
            } else {
                0.0
            },
            spatial: spatial.map(|_| 1.0),
        };
        let lights: Vec<LightShare> = listed
            .into_iter()
            .map(|i| {
                let light = LightShare {
                    index: i,
                    power: scene.powers.as_slice()[i],
                    pmf: pmf[i],
                    share: share(i),
                    spatial: spatial.map(|q| q[i]),
                    cone: scene
                        .emission_of(i)
                        .and_then(|e| e.cone_term(scene.positions[i], x)),
                };
                others.pmf -= light.pmf;
                others.share -= light.share;
                if let (Some(rest), Some(q)) = (others.spatial.as_mut(), light.spatial) {
                    *rest -= q;
                }
                light
            })
            .collect();
        if others.count == 0 {
            others = OtherLights::default();
        } else {
            others.pmf = others.pmf.max(0.0);
            others.share = others.share.max(0.0);
            others.spatial = others.spatial.map(|q| q.max(0.0));
        }
        Self {
            x,
            irradiance: scene.exact_irradiance(x),
            lights,
            others,
            uniform_relative_variance: relative(n as f64 * uniform_second),
            power_relative_variance: relative(power_second),
            spatial_relative_variance: spatial.map(|_| relative(spatial_second)),
            total_variation: 0.5 * variation,
        }
    }

    /// Per-sample variance of uniform picking here, in irradiance units: `E²·(N·Σs² − 1)`.
    pub fn uniform_variance(&self) -> f64 {
        self.irradiance * self.irradiance * self.uniform_relative_variance
    }

    /// Per-sample variance of power picking here, in irradiance units: `E²·(Σ s²/p − 1)`.
    pub fn power_variance(&self) -> f64 {
        self.irradiance * self.irradiance * self.power_relative_variance
    }

    /// Per-sample variance of the spatial scheme here, in irradiance units:
    /// `E²·(Σ s²/q − 1)`, when the inspection was given the sampler.
    pub fn spatial_variance(&self) -> Option<f64> {
        self.spatial_relative_variance
            .map(|r| self.irradiance * self.irradiance * r)
    }
}

/// The indices to list: all of them for small scenes, else the largest shares and the
/// largest pmfs; sorted by share (largest first), ties by index.
fn listed_lights(pmf: &[f64], contribution: &[f64]) -> Vec<usize> {
    let n = pmf.len();
    let mut listed: Vec<usize> = if n <= 2 * LISTED_PER_RANKING {
        (0..n).collect()
    } else {
        let mut picked = largest(contribution, LISTED_PER_RANKING);
        picked.extend(largest(pmf, LISTED_PER_RANKING));
        picked.sort_unstable();
        picked.dedup();
        picked
    };
    listed.sort_by(|&a, &b| contribution[b].total_cmp(&contribution[a]).then(a.cmp(&b)));
    listed
}

/// The indices of the `k` largest values (`O(N)` selection).
fn largest(values: &[f64], k: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    if k < order.len() {
        order.select_nth_unstable_by(k, |&a, &b| values[b].total_cmp(&values[a]));
        order.truncate(k);
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LightPowers;
    use crate::analytic_moments;
    use crate::scene::{ReceiverPlane, Scene, geometry_term};
    use glam::{DVec3, dvec2};

    fn scene(positions: Vec<[f64; 3]>, powers: &[f64]) -> Scene {
        Scene::new(
            "test",
            ReceiverPlane {
                min: dvec2(-1.0, -1.0),
                max: dvec2(1.0, 1.0),
                width: 8,
                height: 8,
            },
            positions.into_iter().map(DVec3::from).collect::<Vec<_>>(),
            LightPowers::new(powers.to_vec()).unwrap(),
        )
    }

    #[test]
    fn shares_sum_to_one_and_variances_match_the_moments() {
        let s = scene(
            vec![[-0.5, 0.2, 0.3], [0.4, -0.1, 0.8], [0.0, 0.9, 0.1]],
            &[2.0, 5.0, 20.0],
        );
        let x = dvec2(0.1, -0.3);
        let inspection = PointInspection::at(&s, x);
        let total_share: f64 = inspection.lights.iter().map(|l| l.share).sum();
        assert!((total_share - 1.0).abs() < 1e-15, "{total_share}");
        let normalized: f64 = inspection.irradiance / 27.0;
        let shares_from_sum: f64 = s
            .positions
            .iter()
            .zip(s.powers.pmf())
            .map(|(&l, p)| p * geometry_term(l, x))
            .sum();
        assert!((normalized - shares_from_sum).abs() <= 1e-14 * normalized);
        let f: Vec<f64> = s
            .positions
            .iter()
            .zip(s.powers.as_slice())
            .map(|(&l, &phi)| phi * geometry_term(l, x))
            .collect();
        let uniform = analytic_moments(&f, |_| 1.0 / 3.0);
        let power = analytic_moments(&f, |i| s.powers.as_slice()[i] / 27.0);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
        assert!(close(inspection.uniform_variance(), uniform.variance));
        assert!(close(inspection.power_variance(), power.variance));
        // Sorted by share, largest first.
        assert!(
            inspection
                .lights
                .windows(2)
                .all(|w| w[0].share >= w[1].share)
        );
        assert_eq!(inspection.others, OtherLights::default());
    }

    #[test]
    fn power_sampling_is_ideal_where_the_geometry_is_equal() {
        // Lights straight above x at the same height: equal G, so shares equal the pmf.
        let s = scene(vec![[0.0, 0.0, 1.0]; 3], &[2.0, 5.0, 20.0]);
        let inspection = PointInspection::at(&s, dvec2(0.0, 0.0));
        assert!(inspection.power_relative_variance < 1e-14);
        assert!(inspection.total_variation < 1e-15);
        // Uniform: N·Σp² − 1 = 3·(4 + 25 + 400)/729 − 1.
        let expected = 3.0 * 429.0 / 729.0 - 1.0;
        assert!((inspection.uniform_relative_variance - expected).abs() < 1e-14);
    }

    #[test]
    fn no_light_above_the_plane_means_zero_irradiance_and_no_variance() {
        let s = scene(vec![[0.0, 0.0, -1.0], [0.5, 0.5, 0.0]], &[1.0, 3.0]);
        let inspection = PointInspection::at(&s, dvec2(0.0, 0.0));
        assert_eq!(inspection.irradiance, 0.0);
        assert_eq!(inspection.uniform_relative_variance, 0.0);
        assert_eq!(inspection.power_relative_variance, 0.0);
        assert!(inspection.lights.iter().all(|l| l.share == 0.0));
    }

    #[test]
    fn large_scenes_list_the_largest_shares_and_pmfs_and_sum_the_rest() {
        let n = 1000;
        let positions: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let t = i as f64 / n as f64;
                [2.0 * t - 1.0, 1.0 - 2.0 * t, 0.05 + t]
            })
            .collect();
        let powers: Vec<f64> = (0..n).map(|i| 1.0 + (i % 17) as f64).collect();
        let s = scene(positions, &powers);
        let inspection = PointInspection::at(&s, dvec2(0.3, -0.2));
        assert!(inspection.lights.len() <= 2 * LISTED_PER_RANKING);
        assert!(inspection.lights.len() >= LISTED_PER_RANKING);
        assert_eq!(inspection.others.count, n - inspection.lights.len());
        let share: f64 =
            inspection.lights.iter().map(|l| l.share).sum::<f64>() + inspection.others.share;
        let pmf: f64 = inspection.lights.iter().map(|l| l.pmf).sum::<f64>() + inspection.others.pmf;
        assert!((share - 1.0).abs() < 1e-12 && (pmf - 1.0).abs() < 1e-12);
        // The largest share overall is listed first.
        let best = (0..n)
            .max_by(|&a, &b| {
                let g = |i: usize| powers[i] * geometry_term(s.positions[i], dvec2(0.3, -0.2));
                g(a).total_cmp(&g(b))
            })
            .unwrap();
        assert_eq!(inspection.lights[0].index, best);
    }

    #[test]
    fn extreme_powers_stay_finite() {
        let s = scene(
            vec![[0.0, 0.0, 1.0], [0.5, 0.0, 0.2], [0.0, 0.5, 0.5]],
            &[1e-300, f64::MAX, 1e300],
        );
        let inspection = PointInspection::at(&s, dvec2(0.2, 0.1));
        assert!(inspection.irradiance.is_finite() && inspection.irradiance > 0.0);
        assert!(inspection.power_relative_variance.is_finite());
        assert!(inspection.uniform_relative_variance.is_finite());
    }
}
