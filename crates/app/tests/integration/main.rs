//! The integration tests of the `lightpick` binary and app library, one module per concern,
//! linked into one test binary (one link of eframe, wgpu and the core instead of one per
//! file). Run one module with `cargo test -p lightpick --test integration MODULE::`.

mod common;

mod app_classroom;
mod app_classroom_screens;
mod app_classroom_windows;
mod app_classroom_words;
mod app_estimator;
mod app_export_animation;
mod app_figure_export;
mod app_gpu_images;
mod app_inspector;
mod app_interaction;
mod app_light_tree;
mod app_lights;
mod app_memory;
mod app_near_light;
mod app_scale;
mod app_scene_files;
mod app_session;
mod app_snapshots;
mod app_spatial;
mod app_trade_precision;
mod app_undo;
mod app_variance_maps;
mod cli_animation;
mod cli_bench_precision;
mod cli_device;
mod cli_e2e;
mod cli_gpu_scale;
mod cli_plot_tree_variance;
mod cli_render_plot;
mod cli_scene;
mod cli_spatial;
mod docs_architecture;
