//! Picking a light: the validated powers, the alias table and its peers (inverse CDF,
//! uniform), the one interface they share, and the random numbers they draw, bit for bit
//! the WGSL shaders' ([`rng`]).

pub mod alias;
pub mod cdf;
pub mod light_sampler;
pub mod powers;
pub mod rng;
pub mod sampler;
pub mod uniform;
