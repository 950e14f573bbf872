//! The integration tests of `lightpick-core`, one module per concern, linked into one test
//! binary (one link of wgpu and the core instead of one per file). Run one module with
//! `cargo test -p lightpick-core --test integration MODULE::`.

mod gpu_common;

mod gpu_emission;

mod alias_guarantees;
mod alias_properties;
mod extremes;
mod gpu_extremes;
mod gpu_histogram;
mod gpu_render;
mod gpu_rng;
mod gpu_spatial;
mod gpu_split;
mod inspect;
mod point_estimate;
mod precision_lab;
mod render_cpu;
mod render_metrics;
mod render_speed;
mod scene_files;
mod scene_import;
mod spatial;
mod spatial_emission;
mod statistics;
