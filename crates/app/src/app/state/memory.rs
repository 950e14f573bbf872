//! Where the state's bytes go: the heap bytes each part holds, from capacities (what is
//! allocated, not what is used), for the table of bytes per light in docs/numbers.md and
//! the test that holds it.

use std::mem::size_of;

use super::AppState;

/// Heap bytes of a vector's allocation.
pub(crate) fn vec_bytes<T>(v: &Vec<T>) -> usize {
    v.capacity() * size_of::<T>()
}

/// Heap bytes of the edit's array `edit`, or 0 while it is the scene's `scene` itself.
fn unshared_bytes<T>(edit: &std::sync::Arc<[T]>, scene: &std::sync::Arc<[T]>) -> usize {
    if std::sync::Arc::ptr_eq(edit, scene) {
        0
    } else {
        std::mem::size_of_val::<[T]>(edit)
    }
}

impl AppState {
    /// The heap bytes each part of the state holds, by capacity, in a fixed order: the scene
    /// (positions, powers, spot/range profiles, names), the scene as edited, the alias table
    /// (with whatever views of it were derived), the spatial sampler, the samplers a power
    /// edit replaced (kept a second, for the next edit to rebuild into), the histograms, the
    /// inspector, the estimator, the stepper and the walkthrough. What is shared (`Arc`) is
    /// counted once, under its first owner here; the renderers' parts are
    /// [`crate::app::LightpickApp::memory_by_part`]'s.
    pub fn memory_by_part(&self) -> Vec<(&'static str, usize)> {
        let built = &self.built;
        let [positions, powers, emission, names] = built.scene.heap_bytes_by_part();
        let edit = &self.edit;
        let edit_extras = edit.emission.as_ref().map_or(0, vec_bytes)
            + edit.names.as_ref().map_or(0, |n| {
                vec_bytes(n) + n.iter().map(String::capacity).sum::<usize>()
            });
        let sampling = &self.sampling;
        let histograms = sampling.uniform_counts.heap_bytes()
            + sampling.alias_counts.heap_bytes()
            + std::mem::size_of_val(&*sampling.alias_cell_pmf)
            + vec_bytes(&sampling.uniform_bins)
            + vec_bytes(&sampling.alias_bins)
            + std::mem::size_of_val(&*sampling.expected_bins)
            + vec_bytes(&sampling.flat_bins);
        let spatial = built
            .samplers
            .spatial_if_built()
            .map_or(0, |s| s.heap_bytes());
        let earlier = self.earlier.as_ref().map_or(0, |(_, samplers)| {
            samplers.table().heap_bytes()
                + samplers.spatial_if_built().map_or(0, |s| s.heap_bytes())
                + unshared_bytes(
                    samplers.scene().powers.shared(),
                    built.scene.powers.shared(),
                )
        });
        vec![
            ("scene: positions", positions.1),
            ("scene: powers", powers.1),
            ("scene: spot/range profiles", emission.1),
            ("scene: names", names.1),
            (
                "edit: positions",
                unshared_bytes(&edit.positions, &built.scene.positions),
            ),
            (
                "edit: powers",
                unshared_bytes(&edit.powers, built.scene.powers.shared()),
            ),
            ("edit: profiles and names", edit_extras),
            ("edit: powers text", self.powers_text.capacity()),
            ("alias table", built.table.heap_bytes()),
            (
                "alias table pmf (the windows shown)",
                built.pmf_window_bytes(),
            ),
            ("spatial sampler (light tree)", spatial),
            (
                "earlier table, tree and powers (kept a second for the next power edit)",
                earlier,
            ),
            ("histograms", histograms),
            ("inspector", self.inspector.heap_bytes()),
            ("estimator", self.estimator.heap_bytes()),
            ("stepper", self.stepper.heap_bytes()),
            ("walkthrough (saved scene)", self.walkthrough.heap_bytes()),
            (
                "undo history (changed powers, replaced scenes)",
                self.history.heap_bytes(),
            ),
        ]
    }
}
