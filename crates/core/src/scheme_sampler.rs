//! A built sampler of any [`Scheme`], spatial included: what renderers, the pixel inspector
//! and the point estimator hold, so that none of them treats one scheme apart.

use std::sync::Arc;

use crate::light_sampler::{LightSampler, Pick, ShadingContext};
use crate::rng::Rng;
use crate::sampler::{Sampler, Scheme};
use crate::scene::Scene;
use crate::spatial::SpatialSampler;

/// A sampler of one [`Scheme`]: a point-free [`Sampler`] (uniform, alias, alias-one-random,
/// CDF) or the contribution-aware [`SpatialSampler`]. Both halves share what they were built
/// from (`Arc`s), so cloning is cheap.
#[derive(Clone, Debug, PartialEq)]
pub enum SchemeSampler {
    /// A scheme that ignores the shading point: `q_i = 1/N` or `Φ_i/ΣΦ`.
    PointFree(Sampler),
    /// [`Scheme::Spatial`]: `q_i(x) = P(i | x)`.
    Spatial(Arc<SpatialSampler>),
}

impl SchemeSampler {
    /// Builds the sampler of `scheme` over `scene` (`O(N)`; the spatial light tree
    /// `O(N log N)`). To share one table and one tree between several users, build through
    /// [`crate::SceneSamplers::sampler`] instead.
    pub fn for_scene(scene: &Scene, scheme: Scheme) -> Self {
        match Sampler::try_build(scheme, &scene.powers) {
            Ok(sampler) => SchemeSampler::PointFree(sampler),
            Err(_) => SchemeSampler::Spatial(Arc::new(SpatialSampler::for_scene(scene))),
        }
    }

    /// The scheme this sampler realizes.
    pub fn scheme(&self) -> Scheme {
        match self {
            SchemeSampler::PointFree(sampler) => sampler.scheme(),
            SchemeSampler::Spatial(_) => Scheme::Spatial,
        }
    }
}

impl From<Sampler> for SchemeSampler {
    fn from(sampler: Sampler) -> Self {
        SchemeSampler::PointFree(sampler)
    }
}

impl From<Arc<SpatialSampler>> for SchemeSampler {
    fn from(sampler: Arc<SpatialSampler>) -> Self {
        SchemeSampler::Spatial(sampler)
    }
}

impl LightSampler for SchemeSampler {
    fn light_count(&self) -> usize {
        match self {
            SchemeSampler::PointFree(s) => LightSampler::light_count(s),
            SchemeSampler::Spatial(s) => LightSampler::light_count(&**s),
        }
    }

    fn pmf_at(&self, ctx: &ShadingContext, i: usize) -> f64 {
        match self {
            SchemeSampler::PointFree(s) => s.pmf_at(ctx, i),
            SchemeSampler::Spatial(s) => s.pmf_at(ctx, i),
        }
    }

    #[inline]
    fn pick_at(&self, ctx: &ShadingContext, rng: &mut Rng) -> Option<Pick> {
        match self {
            SchemeSampler::PointFree(s) => s.pick_at(ctx, rng),
            SchemeSampler::Spatial(s) => s.pick_at(ctx, rng),
        }
    }

    fn pmfs_at(&self, ctx: &ShadingContext) -> Vec<f64> {
        match self {
            SchemeSampler::PointFree(s) => s.pmfs_at(ctx),
            SchemeSampler::Spatial(s) => s.pmfs_at(ctx),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::scene::{ReceiverPlane, Scene};

    fn scene(n: usize) -> Scene {
        let positions: Vec<DVec3> = (0..n)
            .map(|i| {
                let i = i as f64;
                DVec3::new(i * 0.7 - 3.0, (i % 5.0) * 0.4 - 1.0, 0.5 + i % 3.0)
            })
            .collect();
        let powers = (0..n).map(|i| 1.0 + (i * 7 % 11) as f64).collect();
        let plane = ReceiverPlane {
            min: glam::dvec2(-4.0, -4.0),
            max: glam::dvec2(4.0, 4.0),
            width: 8,
            height: 8,
        };
        let powers = crate::LightPowers::new(powers).expect("valid powers");
        Scene::new("test", plane, positions, powers)
    }

    /// Every scheme, spatial included, through the one interface: the pmf sums to 1 at a
    /// point, each pick's probability is its pmf there, and the spatial picks are the spatial
    /// sampler's own (same draws).
    #[test]
    fn every_scheme_picks_through_the_one_interface() {
        for n in [3, 40] {
            let scene = scene(n);
            let ctx = ShadingContext::at(glam::DVec2::new(0.3, -0.2));
            for scheme in [Scheme::ALL.as_slice(), &[Scheme::Spatial]].concat() {
                let sampler = SchemeSampler::for_scene(&scene, scheme);
                assert_eq!(sampler.scheme(), scheme);
                assert_eq!(LightSampler::light_count(&sampler), n);
                let pmf = sampler.pmfs_at(&ctx);
                let total: f64 = pmf.iter().sum();
                assert!(
                    (total - 1.0).abs() < 1e-12,
                    "{scheme} at n = {n}: Σq = {total}"
                );
                let mut rng = Rng::new(9, 1);
                for _ in 0..200 {
                    let pick = sampler
                        .pick_at(&ctx, &mut rng)
                        .expect("lights reach the point");
                    assert_eq!(pick.probability, sampler.pmf_at(&ctx, pick.light as usize));
                    assert_eq!(pick.probability, pmf[pick.light as usize]);
                }
                if let SchemeSampler::Spatial(spatial) = &sampler {
                    let (mut a, mut b) = (Rng::new(4, 2), Rng::new(4, 2));
                    for _ in 0..200 {
                        let ours = sampler.pick_at(&ctx, &mut a).map(|p| p.light);
                        let its = spatial.sample(ctx.point_on_plane, &mut b).map(|p| p.light);
                        assert_eq!(ours, its);
                    }
                }
            }
        }
    }
}
