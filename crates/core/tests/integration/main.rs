//! The integration tests of `lightpick-core`, one module per concern, linked into one test
//! binary (one link of wgpu and the core instead of one per file). Run one module with
//! `cargo test -p lightpick-core --test integration MODULE::`. The `gpu_*` modules need
//! the `gpu` feature (on by default); `cargo test -p lightpick-core --no-default-features`
//! runs the rest, the lean configuration.

mod common;

#[cfg(feature = "gpu")]
mod gpu_emission;

mod alias_guarantees;
mod alias_properties;
mod cut_bounds;
mod cut_clusters;
mod determinism;
mod extremes;
#[cfg(feature = "gpu")]
mod gpu_extremes;
#[cfg(feature = "gpu")]
mod gpu_histogram;
#[cfg(feature = "gpu")]
mod gpu_render;
#[cfg(feature = "gpu")]
mod gpu_rng;
#[cfg(feature = "gpu")]
mod gpu_spatial;
#[cfg(feature = "gpu")]
mod gpu_split;
mod inspect;
mod near_light;
mod point_estimate;
mod precision_lab;
mod refit_allocations;
mod render_cpu;
mod render_metrics;
mod scale_property;
mod scene_files;
mod scene_import;
mod spatial;
mod spatial_emission;
mod spatial_rims;
mod statistics;
mod tile_cuts;
mod tree_pick;
#[cfg(feature = "draw")]
mod tree_view;
mod variance_map;
