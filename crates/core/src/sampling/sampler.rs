//! The selection schemes by name ([`Scheme`]) and the point-free ones built ([`Sampler`]):
//! each returns a light and the probability with which it was picked, which is all an
//! estimator `f/p` needs ([`crate::light_sampler`]).

use std::sync::Arc;

use crate::alias::{AliasTable, Construction};
use crate::cdf::CdfTable;
use crate::light_sampler::{Pick, PointFreeSampler};
use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::uniform::Uniform;

/// The selection schemes lightpick compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// Every light with probability exactly `1/N` (Lemire's rejection, [`Uniform::sample`]).
    Uniform,
    /// Power-proportional, alias table (the default): exactly uniform column, keep test on
    /// the next draw; realized pmf exactly [`AliasTable::implied_pmf_packed`].
    Alias,
    /// Power-proportional, alias table, one random whose fraction is reused (speed option):
    /// raw multiply-high column, no rejection, bias of order `N·2^-32` relative.
    AliasOneRandom,
    /// Power-proportional, inverse CDF by binary search.
    Cdf,
    /// Contribution-aware, render only: at each shading point `x`, `P(i | x) ∝ p_i·G_i(x)`
    /// exactly for few lights, or a light-tree descent for many ([`crate::spatial`]). It needs
    /// a shading point, so it has no [`Sampler`] and is not in [`Scheme::ALL`]; `sample` and
    /// `estimate` refuse it ([`Scheme::needs_shading_point`]).
    Spatial,
}

/// A scheme name that is not one of [`Scheme::ALL`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown scheme '{0}' (expected uniform, alias (or power), alias-one-random, cdf, spatial)"
)]
pub struct UnknownScheme(pub String);

impl Scheme {
    /// Every scheme that picks lights without a shading point (all but [`Scheme::Spatial`]),
    /// in display order: the schemes a [`Sampler`] realizes.
    pub const ALL: [Scheme; 4] = [
        Scheme::Uniform,
        Scheme::Alias,
        Scheme::AliasOneRandom,
        Scheme::Cdf,
    ];

    /// The scheme's command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Uniform => "uniform",
            Scheme::Alias => "alias",
            Scheme::AliasOneRandom => "alias-one-random",
            Scheme::Cdf => "cdf",
            Scheme::Spatial => "spatial",
        }
    }

    /// Whether the scheme picks by contribution at a shading point ([`Scheme::Spatial`]):
    /// renderers support it, the point-free `sample`/`estimate` and [`Sampler`] do not.
    pub fn needs_shading_point(self) -> bool {
        matches!(self, Scheme::Spatial)
    }

    /// Whether the scheme picks lights in proportion to their power.
    pub fn is_power_proportional(self) -> bool {
        !matches!(self, Scheme::Uniform | Scheme::Spatial)
    }
}

impl std::fmt::Display for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Scheme {
    type Err = UnknownScheme;

    /// Parses a scheme name; `power` is accepted for `alias` (the renderer's word).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "uniform" => Ok(Scheme::Uniform),
            "alias" | "power" => Ok(Scheme::Alias),
            "alias-one-random" | "alias1" => Ok(Scheme::AliasOneRandom),
            "cdf" => Ok(Scheme::Cdf),
            "spatial" => Ok(Scheme::Spatial),
            other => Err(UnknownScheme(other.to_owned())),
        }
    }
}

/// A scheme that picks by contribution at a shading point, asked for where there is none.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "scheme '{0}' picks lights by their contribution at a shading point; it renders \
     (render, bench, the app) but cannot sample or estimate without a point \
     (use uniform, alias, alias-one-random or cdf)"
)]
pub struct NeedsShadingPoint(pub Scheme);

/// A built sampler of one [`Scheme`].
#[derive(Clone, Debug, PartialEq)]
pub enum Sampler {
    /// See [`Scheme::Uniform`].
    Uniform(Uniform),
    /// See [`Scheme::Alias`]. The table is shared (`Arc`): the app hands one table to the
    /// table panel, the histograms and every renderer.
    Alias(Arc<AliasTable>),
    /// See [`Scheme::AliasOneRandom`].
    AliasOneRandom(Arc<AliasTable>),
    /// See [`Scheme::Cdf`].
    Cdf(CdfTable),
}

impl Sampler {
    /// Builds the sampler for `scheme` over `powers` (`O(N)`).
    ///
    /// # Panics
    /// For [`Scheme::Spatial`], which needs a shading point and the light positions (see
    /// [`crate::spatial::SpatialSampler`]); check [`Scheme::needs_shading_point`] first, or use
    /// [`Sampler::try_build`].
    pub fn build(scheme: Scheme, powers: &LightPowers) -> Self {
        match Self::try_build(scheme, powers) {
            Ok(sampler) => sampler,
            Err(e) => panic!("{e}"),
        }
    }

    /// [`Sampler::build`], refusing [`Scheme::Spatial`] with [`NeedsShadingPoint`].
    pub fn try_build(scheme: Scheme, powers: &LightPowers) -> Result<Self, NeedsShadingPoint> {
        Self::try_build_with(scheme, powers, Construction::default())
    }

    /// [`Sampler::try_build`] with the alias tables built by `construction` (the other
    /// schemes ignore it).
    pub fn try_build_with(
        scheme: Scheme,
        powers: &LightPowers,
        construction: Construction,
    ) -> Result<Self, NeedsShadingPoint> {
        let table = || Arc::new(AliasTable::build_with(powers, construction));
        Ok(match scheme {
            Scheme::Uniform => Sampler::Uniform(Uniform::new(powers.len() as u32)),
            Scheme::Alias => Sampler::Alias(table()),
            Scheme::AliasOneRandom => Sampler::AliasOneRandom(table()),
            Scheme::Cdf => Sampler::Cdf(CdfTable::build(powers)),
            Scheme::Spatial => return Err(NeedsShadingPoint(scheme)),
        })
    }

    /// The scheme this sampler realizes.
    pub fn scheme(&self) -> Scheme {
        match self {
            Sampler::Uniform(_) => Scheme::Uniform,
            Sampler::Alias(_) => Scheme::Alias,
            Sampler::AliasOneRandom(_) => Scheme::AliasOneRandom,
            Sampler::Cdf(_) => Scheme::Cdf,
        }
    }

    /// The light picked by the scheme from the next draws of `rng`, without its probability.
    ///
    /// Uniform: [`Uniform::sample`] (exactly `1/N`). Alias: [`AliasTable::sample`] (exact
    /// column pick by Lemire's rejection, then the keep test on the next draw). Both consume
    /// one extra draw per rejected draw, in stream order, exactly as the GPU's `pick.wgsl`.
    /// Alias-one-random: [`AliasTable::sample_one_random`] (one draw, raw column). CDF: one
    /// draw.
    #[inline]
    pub fn pick_light(&self, rng: &mut Rng) -> u32 {
        match self {
            Sampler::Uniform(u) => u.sample(rng),
            Sampler::Alias(t) => t.sample(rng),
            Sampler::AliasOneRandom(t) => t.sample_one_random(rng.next_u32()),
            Sampler::Cdf(c) => c.sample_u32(rng.next_u32()),
        }
    }
}

impl PointFreeSampler for Sampler {
    fn light_count(&self) -> usize {
        match self {
            Sampler::Uniform(u) => u.len(),
            Sampler::Alias(t) | Sampler::AliasOneRandom(t) => t.len(),
            Sampler::Cdf(c) => c.len(),
        }
    }

    fn probability(&self, i: usize) -> f64 {
        match self {
            Sampler::Uniform(u) => 1.0 / u.len() as f64,
            Sampler::Alias(t) | Sampler::AliasOneRandom(t) => t.pmf(i),
            Sampler::Cdf(c) => c.pmf(i),
        }
    }

    #[inline]
    fn pick(&self, rng: &mut Rng) -> Pick {
        let light = self.pick_light(rng);
        Pick {
            light,
            probability: self.probability(light as usize),
        }
    }

    fn draws_per_pick(&self) -> u32 {
        match self {
            Sampler::Alias(_) => 2,
            Sampler::Uniform(_) | Sampler::AliasOneRandom(_) | Sampler::Cdf(_) => 1,
        }
    }
}
