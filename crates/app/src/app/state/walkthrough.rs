//! The classroom walkthrough's state: the current step, the user's scene kept while the
//! classic one is shown, and the lesson of the current table (cached per generation).

use std::sync::Arc;

use lightpick_core::scene::Scene;
use lightpick_core::walkthrough::{CLASSIC_GEOMETRY, WalkStep, Walkthrough};

use super::built::Built;
use super::{AppState, MessageKind};
use crate::app::scene_io;

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

impl AppState {
    /// Once per frame, before the panels: restores the user's scene when the walkthrough
    /// was just closed, and sets the table highlight of the current step (or clears it).
    pub fn prepare_walkthrough(&mut self) {
        let open = self.settings.show_walkthrough;
        if self.walkthrough.was_open && !open {
            self.restore_scene();
        }
        self.walkthrough.was_open = open;
        self.table_highlight = None;
        if let Some(walk) = self.walkthrough_lesson() {
            let k = self.walkthrough.step.min(walk.1.len() - 1);
            self.walkthrough.step = k;
            self.table_highlight = Some(walk.1[k].highlight.clone());
        }
    }

    /// The walkthrough of the current powers, `None` when its window is closed or the scene
    /// does not have three lights.
    pub fn walkthrough_lesson(&mut self) -> Option<Lesson> {
        if !self.settings.show_walkthrough {
            return None;
        }
        let built = Arc::clone(&self.built);
        self.walkthrough.lesson(&built)
    }

    /// Loads the worked example (2, 5, 20), keeping the user's scene for later and the
    /// walkthrough at its step.
    pub fn load_classic(&mut self) {
        if self.walkthrough.saved_scene.is_none() {
            self.walkthrough.saved_scene = Some((*self.built.scene).clone());
        }
        // The step stays: the class goes on where it was, now on the classic powers.
        self.load_scene(scene_io::worked_example_scene());
        self.message(
            "classic scene loaded (powers 2, 5, 20); your scene comes back when the \
             walkthrough closes",
            MessageKind::Info,
        );
    }

    /// Puts the scene kept by the walkthrough back, if any.
    pub fn restore_scene(&mut self) {
        if let Some(scene) = self.walkthrough.saved_scene.take() {
            let text = format!(
                "restored your scene \"{}\" ({} lights)",
                scene.name,
                scene.light_count()
            );
            self.load_scene(scene);
            self.message(text, MessageKind::Success);
        }
    }
}
