//! # lightpick-core
//!
//! The numerics behind lightpick: picking one of many point lights at random in
//! proportion to its power, and measuring what that buys.
//!
//! * [`LightPowers`] validates a set of powers (finite, non-negative, not all zero).
//! * [`AliasTable`] is Walker's alias method, built with Vose's algorithm in `f64`, and its
//!   packed `u32` form shared bit for bit with the GPU. [`CdfTable`] and [`Uniform`] are the
//!   peers it is compared with; all three implement [`LightSampler`].
//! * [`Rng`] is the one counter-based random number generator (the PCG hash of Jarzynski &
//!   Olano 2020) that the CPU and the WGSL shaders both implement.
//! * [`Welford`], [`analytic_moments`] and [`chi_square`] measure estimators and samplers.
//! * [`precision`] measures what each numerical choice of the alias table costs.
//! * [`walkthrough`] and [`construction`] hold the classroom's material: the classic
//!   explanation's steps with live numbers, and Vose's construction recorded step by step.
//! * [`spatial`] picks lights by their contribution at a shading point (exact for few
//!   lights, a light tree for many): the render-only scheme [`Scheme::Spatial`].
//! * [`draw`] renders the diagrams, plots and image sheets headless (tiny-skia → PNG).
//!
//! Nothing here depends on a UI toolkit.

mod alias;
mod cdf;
mod chi_square;
pub mod construction;
pub mod draw;
pub mod fraction;
pub mod gpu;
pub mod inspect;
mod moments;
mod powers;
pub mod precision;
pub mod render;
mod rng;
mod sampler;
pub mod scene;
mod seed_example;
pub mod spatial;
mod uniform;
pub mod walkthrough;
mod welford;

pub use alias::{AliasTable, PackedAliasEntry};
pub use cdf::CdfTable;
pub use chi_square::{ChiSquare, chi_square};
pub use moments::{EstimatorMoments, analytic_moments};
pub use powers::{LightPowers, PowersError};
pub use rng::{Rng, pcg_hash, unit_f64};
pub use sampler::{LightSampler, NeedsShadingPoint, Pick, Sampler, Scheme, UnknownScheme};
pub use seed_example::SeedExample;
pub use uniform::{Uniform, rejection_threshold};
pub use welford::Welford;
