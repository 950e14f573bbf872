//! The construction stepper's state: the event shown, playback, and the recorded
//! construction of the current table (cached per generation).

use std::sync::Arc;

use lightpick_core::construction::ConstructionTrace;

use super::AppState;
use super::built::Built;

/// The stepper animates tables of at most this many lights.
pub const STEPPER_MAX_LIGHTS: usize = 64;

/// The stepper's own state (in `AppState::stepper`).
pub struct StepperState {
    /// The state shown: 0 is the start, the last is the finished table.
    pub index: usize,
    /// Whether Play advances one event per [`StepperState::seconds_per_step`].
    pub playing: bool,
    /// Seconds per event while playing.
    pub seconds_per_step: f32,
    /// When (egui's clock, seconds) the shown event was last advanced.
    pub last_advance: f64,
    cache: Option<(u64, Arc<ConstructionTrace>)>,
}

impl Default for StepperState {
    fn default() -> Self {
        Self {
            index: 0,
            playing: false,
            seconds_per_step: 1.5,
            last_advance: 0.0,
            cache: None,
        }
    }
}

impl StepperState {
    /// The construction of `built`'s table (cached per table generation; a new table starts
    /// the stepper over). `None` when the scene has more than [`STEPPER_MAX_LIGHTS`] lights.
    pub fn trace(&mut self, built: &Built) -> Option<Arc<ConstructionTrace>> {
        if built.len() > STEPPER_MAX_LIGHTS {
            return None;
        }
        if let Some((g, trace)) = &self.cache
            && *g == built.generation
        {
            return Some(Arc::clone(trace));
        }
        let trace = Arc::new(ConstructionTrace::build(&built.scene.powers));
        self.cache = Some((built.generation, Arc::clone(&trace)));
        self.index = 0;
        self.playing = false;
        Some(trace)
    }

    /// Heap bytes of the cached construction (only tables of at most
    /// [`STEPPER_MAX_LIGHTS`] lights have one).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.cache.as_ref().map_or(0, |(_, trace)| {
            trace
                .states()
                .iter()
                .map(|s| {
                    size_of::<lightpick_core::construction::ConstructionState>()
                        + s.mass.capacity() * size_of::<f64>()
                        + (s.small.capacity() + s.large.capacity()) * size_of::<usize>()
                        + s.threshold.capacity() * size_of::<Option<f64>>()
                        + s.alias.capacity() * size_of::<Option<u32>>()
                })
                .sum()
        })
    }
}

impl AppState {
    /// The construction of the current table for the stepper (`None` beyond
    /// [`STEPPER_MAX_LIGHTS`] lights).
    pub fn stepper_trace(&mut self) -> Option<Arc<ConstructionTrace>> {
        let built = Arc::clone(&self.built);
        self.stepper.trace(&built)
    }
}
