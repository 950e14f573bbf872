//! Shared by the integration tests: the GPU context of the `gpu_*` modules, a tiny
//! generator of test inputs ([`SplitMix`]), the fit of pick counts ([`fit`]), the
//! scenes several modules build ([`scenes`]) and what the per-tile cuts' tests share
//! ([`cuts`]). Each module uses a different subset.

#![allow(dead_code)] // Each test module uses a different subset of the helpers.

pub mod cuts;
pub mod fit;
#[cfg(feature = "gpu")]
mod gpu;
mod mix;
pub mod scenes;
/// The workspace's snapshot comparison (`tests/support`), shared with the root package's
/// `draw_snapshots` tests: the same goldens folder, tolerance and `UPDATE_SNAPSHOTS` switch.
#[cfg(feature = "draw")]
#[path = "../../../../../tests/support/lib.rs"]
pub mod snapshot_support;

#[cfg(feature = "gpu")]
pub use gpu::context;
pub use mix::SplitMix;
