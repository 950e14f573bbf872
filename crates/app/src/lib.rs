//! # lightpick
//!
//! The lightpick desktop app (egui/eframe on wgpu) and its headless subcommands, as a
//! library so that tests can drive both; `main.rs` only dispatches.

pub mod app;
pub mod cli;
