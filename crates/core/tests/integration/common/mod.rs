//! Shared by the integration tests: the GPU context of the `gpu_*` modules, a tiny
//! generator of test inputs ([`SplitMix`]), the fit of pick counts ([`fit`]) and the
//! scenes several modules build ([`scenes`]). Each module uses a different subset.

#![allow(dead_code)] // Each test module uses a different subset of the helpers.

pub mod fit;
#[cfg(feature = "gpu")]
mod gpu;
mod mix;
pub mod scenes;

#[cfg(feature = "gpu")]
pub use gpu::context;
pub use mix::SplitMix;
