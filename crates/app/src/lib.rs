//! # lightpick
//!
//! The lightpick desktop app (egui/eframe on wgpu) and its headless subcommands, as a
//! library so that tests can drive both; `main.rs` only dispatches.
//!
//! Below both sit what they share: [`recording`] (the convergence animation, recorded by
//! `lightpick plot animation` and by the app's File → "Export animation…") and [`numbers`]
//! (number labels). [`app`] imports neither `cli` nor anything above it; [`cli`] opens the
//! app and measures its state.

pub mod app;
pub mod cli;
pub mod numbers;
pub mod recording;
