//! The classroom walkthrough's state: the current step, the user's scene kept while the
//! classic one is shown, and the lesson of the current table (cached per generation).

use std::sync::Arc;

use lightpick_core::scene::Scene;
use lightpick_core::walkthrough::{CLASSIC_GEOMETRY, WalkStep, Walkthrough};

use super::built::Built;

/// The walkthrough retells the classic explanation, which has exactly this many lights.
pub const WALKTHROUGH_LIGHTS: usize = 3;

/// The walkthrough of the current powers and its steps.
pub type Lesson = Arc<(Walkthrough, Vec<WalkStep>)>;

/// The walkthrough's own state (in `AppState::walkthrough`).
#[derive(Default)]
pub struct WalkthroughState {
    /// The current step (0-based).
    pub step: usize,
    /// The user's scene, kept while the classic scene is shown; restored on close.
    pub saved_scene: Option<Scene>,
    cache: Option<(u64, Lesson)>,
    /// Whether the window was open last frame (closing it restores the user's scene).
    pub(crate) was_open: bool,
}

impl WalkthroughState {
    /// The walkthrough of `built`'s powers (cached per table generation), `None` when the
    /// scene does not have [`WALKTHROUGH_LIGHTS`] lights.
    pub fn lesson(&mut self, built: &Built) -> Option<Lesson> {
        if built.len() != WALKTHROUGH_LIGHTS {
            return None;
        }
        if let Some((g, walk)) = &self.cache
            && *g == built.generation
        {
            return Some(Arc::clone(walk));
        }
        let walk = Walkthrough::new(&built.scene.powers, &CLASSIC_GEOMETRY);
        let steps = walk.steps();
        let walk = Arc::new((walk, steps));
        self.cache = Some((built.generation, Arc::clone(&walk)));
        Some(walk)
    }

    /// Heap bytes of the user's scene kept while the classic one is shown (the lesson itself
    /// is of three lights and not counted).
    pub fn heap_bytes(&self) -> usize {
        self.saved_scene.as_ref().map_or(0, |s| {
            s.heap_bytes_by_part().iter().map(|(_, bytes)| bytes).sum()
        })
    }

    /// Whether the current step is the last one of `lesson`.
    pub fn at_last_step(&self, lesson: &Lesson) -> bool {
        self.step + 1 >= lesson.1.len()
    }
}
