//! Where the progressive images are made: the CPU [`engine`] (a render thread in the app,
//! inline in tests) and the [`gpu`] runs on eframe's own wgpu device, both publishing the
//! same [`Published`] frame; the [`renderer_choice`] that picks one of them, and the
//! [`frame_budget`] that keeps the GPU's share of a UI frame small enough for the window.
//!
//! This layer reads the state's settings and scene samplers; it knows no panel.

pub mod engine;
pub mod frame_budget;
pub mod gpu;
pub mod published;
pub mod reference;
pub mod renderer_choice;

pub use engine::Engine;
pub use gpu::GpuImages;
pub use published::{ConvergencePoint, EngineConfig, Published, RendererBytes, SchemeImage};
