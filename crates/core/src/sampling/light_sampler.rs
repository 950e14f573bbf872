//! The one interface every light-selection scheme shares: given a shading context, pick a
//! light and say with what probability, `pick_at(ctx, rng) → (i, q_i(ctx))`, and give that
//! probability for any light, `pmf_at(ctx, i) = q_i(ctx)`. It is all an estimator needs:
//! one sample of `F(ctx) = Σ_i f_i(ctx)` is `f_I / q_I(ctx)`, unbiased wherever
//! `q_i(ctx) > 0` for every `f_i(ctx) > 0`.
//!
//! As in pbrt-v4's `LightSampler` (`Sample(ctx, u)`, `PMF(ctx, light)`), the context is
//! given to every scheme and the point-free ones ignore it: uniform (`q_i = 1/N`) and the
//! power schemes (`q_i = Φ_i/ΣΦ`: alias table, CDF) implement [`PointFreeSampler`] and get
//! [`LightSampler`] from it; the spatial scheme ([`crate::spatial::SpatialSampler`],
//! `q_i(x) ∝` a bound on `p_i·G_i(x)`) reads the shading point. A caller holding any of them
//! ([`crate::SchemeSampler`], or `&dyn LightSampler`) treats them alike.

use glam::DVec2;

use crate::rng::Rng;

/// Where a light is picked for: the shading point on the receiver plane `z = 0`.
///
/// The receiver is one known plane with its normal `+z`, so the point is the whole context
/// the scenes need (pbrt-v4's `LightSampleContext` adds the normal and the time).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadingContext {
    /// The shading point `x`, in plane coordinates.
    pub point_on_plane: DVec2,
}

impl ShadingContext {
    /// The context of the shading point `point_on_plane`.
    pub const fn at(point_on_plane: DVec2) -> Self {
        Self { point_on_plane }
    }
}

/// A picked light and the probability `q_i` of that pick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// The light's index.
    pub light: u32,
    /// The probability the scheme assigns to it (`1/N`, `Φ_i / ΣΦ`, or `P(i | x)`).
    pub probability: f64,
}

/// A scheme that picks lights without looking at the shading point: uniform and the power
/// schemes. Each is a [`LightSampler`] that ignores the context.
pub trait PointFreeSampler {
    /// Number of lights.
    fn light_count(&self) -> usize;
    /// The probability `q_i` that a pick returns light `i`.
    fn probability(&self, i: usize) -> f64;
    /// Picks a light from `rng` (consuming at least [`PointFreeSampler::draws_per_pick`]
    /// draws).
    fn pick(&self, rng: &mut Rng) -> Pick;
    /// The fewest 32-bit draws one pick consumes. Uniform and alias picks take one more per
    /// draw rejected by Lemire's exact column pick (probability `(2^32 mod N)/2^32 < N·2^-32`
    /// per draw, none when `N` is a power of two); the one-random alias and the CDF always
    /// take exactly this many.
    fn draws_per_pick(&self) -> u32;
}

/// A way of picking one light at random at a shading context: the interface of every
/// scheme (see the module docs).
pub trait LightSampler {
    /// Number of lights of the scene (the indices a pick can return are `0..light_count`).
    fn light_count(&self) -> usize;

    /// `q_i(ctx)`: the probability that [`LightSampler::pick_at`] returns light `i` at `ctx`.
    fn pmf_at(&self, ctx: &ShadingContext, i: usize) -> f64;

    /// Picks a light for `ctx` from the next draws of `rng`, with its probability; `None`
    /// where the scheme picks nothing because no light contributes at `ctx` (the estimate is
    /// then 0).
    fn pick_at(&self, ctx: &ShadingContext, rng: &mut Rng) -> Option<Pick>;

    /// `q_i(ctx)` of every light, indexed by light (`O(N)`; the spatial scheme's in one
    /// traversal, where `N` calls of [`LightSampler::pmf_at`] would cost `O(N log N)` or more).
    fn pmfs_at(&self, ctx: &ShadingContext) -> Vec<f64> {
        (0..self.light_count())
            .map(|i| self.pmf_at(ctx, i))
            .collect()
    }
}

impl<S: PointFreeSampler + ?Sized> LightSampler for S {
    fn light_count(&self) -> usize {
        PointFreeSampler::light_count(self)
    }

    fn pmf_at(&self, _: &ShadingContext, i: usize) -> f64 {
        self.probability(i)
    }

    #[inline]
    fn pick_at(&self, _: &ShadingContext, rng: &mut Rng) -> Option<Pick> {
        Some(self.pick(rng))
    }
}
