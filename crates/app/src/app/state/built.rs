//! The last valid scene and what is built from it once per scene generation.

use std::borrow::Cow;
use std::ops::Range;
use std::sync::{Arc, Mutex};

use lightpick_core::scene::Scene;
use lightpick_core::{AliasTable, Construction, SceneSamplers};

use super::sampling::HistogramPmf;

/// The last valid state: the scene, its alias table and display helpers.
#[derive(Debug)]
pub struct Built {
    /// Bumped on every rebuild; the engine and histograms restart when it changes.
    pub generation: u64,
    /// The validated scene.
    pub scene: Arc<Scene>,
    /// Its alias table, shared with whatever samples by power (histograms, the renderers,
    /// the estimator view).
    pub table: Arc<AliasTable>,
    /// The scene, its table and its spatial sampler, built once here and shared with the
    /// renderers (CPU or GPU), the pixel inspector and the estimator view.
    pub samplers: SceneSamplers,
    /// `Σ Φ` when every power is a small integer (exact fractions), else `None`.
    pub denominator: Option<u64>,
    /// `Σ Φ` (for display).
    pub total_power: f64,
    /// The last two windows of an integer-built table's pmf computed for display
    /// ([`Built::pmf_of`]); the exact construction stores its own pmf.
    pmf_windows: Mutex<[Option<PmfWindow>; 2]>,
    /// What the histograms expect of the table, computed with it.
    pub histogram_pmf: HistogramPmf,
}

/// Lights of a table and their probabilities, as [`Built::pmf_of`] computed them.
type PmfWindow = (Range<usize>, Vec<f64>);

/// Up to this many lights the app shows the exact `f64` construction (exact seed
/// fractions, replayed step by step by the stepper); beyond, the integer one, whose rebuild
/// fits a frame at `10^6` lights. Either way every panel and the histograms use this table.
pub const EXACT_TABLE_MAX_LIGHTS: usize = 1 << 16;

/// The construction the app uses for `n` lights ([`EXACT_TABLE_MAX_LIGHTS`]).
pub fn construction_for(n: usize) -> Construction {
    if n <= EXACT_TABLE_MAX_LIGHTS {
        Construction::Exact
    } else {
        Construction::Integer
    }
}

impl Built {
    /// Builds the table (`O(N)`) and the spatial sampler (`O(N log N)`) of a validated
    /// scene: on the UI thread up to `SYNC_BUILD_LIMIT` lights, on a worker beyond.
    pub fn new(generation: u64, scene: Scene) -> Self {
        let table = Arc::new(AliasTable::build_with(
            &scene.powers,
            construction_for(scene.powers.len()),
        ));
        Self::with_samplers(
            generation,
            SceneSamplers::with_table(Arc::new(scene), table),
        )
    }

    /// [`Built::new`] for a scene whose lights stand where `previous`'s do
    /// ([`Scene::same_geometry`]) with new powers (a power edit): the table is rebuilt and
    /// the light tree refitted in `O(N)` ([`SceneSamplers::repowered`]) instead of the tree
    /// being rebuilt in `O(N log N)` (0.2 s at 10^6 lights). The same tables and tree, bit
    /// for bit.
    ///
    /// `earlier`, an older generation of the same scene's samplers (the one two edits back,
    /// [`super::AppState`] keeps it a second), is rebuilt into where nothing else holds it
    /// any more ([`SceneSamplers::repowered_then`]): no copy of the table and the tree, and
    /// none of the page faults of fresh buffers.
    pub fn repowered(
        generation: u64,
        scene: Scene,
        previous: &SceneSamplers,
        earlier: Option<SceneSamplers>,
    ) -> Self {
        // The histograms' groups need only the table: computed while the tree is refitted.
        let (samplers, groups) =
            previous.repowered_then(Arc::new(scene), earlier, HistogramPmf::of);
        Self::with_parts(generation, samplers, groups)
    }

    /// The state around samplers whose table is built: the spatial sampler built now (off
    /// the UI thread for large scenes), the display helpers derived from the scene.
    fn with_samplers(generation: u64, samplers: SceneSamplers) -> Self {
        samplers.spatial();
        let groups = HistogramPmf::of(samplers.table());
        Self::with_parts(generation, samplers, groups)
    }

    /// The state around built samplers and what the histograms expect of their table.
    fn with_parts(generation: u64, samplers: SceneSamplers, histogram_pmf: HistogramPmf) -> Self {
        let scene = Arc::clone(samplers.scene());
        let table = Arc::clone(samplers.table());
        let denominator = lightpick_core::draw::fraction_denominator(&scene.powers);
        let total_power = scene.powers.as_slice().iter().sum();
        Self {
            generation,
            scene,
            table,
            samplers,
            denominator,
            total_power,
            pmf_windows: Mutex::new([None, None]),
            histogram_pmf,
        }
    }

    /// The pmf the table realizes for the lights in `range`, each `p_i`
    /// ([`AliasTable::pmf_slice`] bit for bit). The exact construction stores its pmf; for an
    /// integer-built table (beyond [`EXACT_TABLE_MAX_LIGHTS`] lights) the window is computed
    /// from the packed columns ([`AliasTable::implied_pmf_packed_of`]: one pass, `O(N)`)
    /// and the last two windows kept, so the app holds no pmf of `N` (8 bytes per light)
    /// for the few hundred lights a panel shows.
    ///
    /// # Panics
    /// If `range` reaches past the last light.
    pub fn pmf_of(&self, range: Range<usize>) -> Cow<'_, [f64]> {
        if self.table.construction() == Construction::Exact {
            return Cow::Borrowed(&self.table.pmf_slice()[range]);
        }
        let mut windows = self
            .pmf_windows
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((_, pmf)) = windows.iter().flatten().find(|(r, _)| *r == range) {
            return Cow::Owned(pmf.clone());
        }
        let pmf = self.table.implied_pmf_packed_of(range.clone());
        // The newer window first; the older one goes.
        windows.swap(0, 1);
        windows[0] = Some((range, pmf.clone()));
        Cow::Owned(pmf)
    }

    /// Heap bytes of the pmf windows kept ([`Built::pmf_of`]).
    pub fn pmf_window_bytes(&self) -> usize {
        self.pmf_windows
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .iter()
            .flatten()
            .map(|(_, pmf)| pmf.capacity() * std::mem::size_of::<f64>())
            .sum()
    }

    /// [`Built::repowered`] when `scene` keeps `previous`'s geometry, else [`Built::new`].
    pub fn from_edit(
        generation: u64,
        scene: Scene,
        previous: &SceneSamplers,
        earlier: Option<SceneSamplers>,
    ) -> Self {
        if previous.scene().same_geometry(&scene) {
            Self::repowered(generation, scene, previous, earlier)
        } else {
            Self::new(generation, scene)
        }
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.table.len()
    }

    /// Always `false` (a valid scene has a light).
    pub fn is_empty(&self) -> bool {
        self.table.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lightpick_core::LightPowers;

    /// An integer-built table (beyond the exact construction's limit): every window the
    /// panels ask for, new or kept, is the table's realized pmf there bit for bit, in any
    /// order of asking (two windows kept, a third evicts the older), and the groups are
    /// their lights' exact masses.
    #[test]
    fn a_large_tables_pmf_windows_are_its_realized_pmf() {
        let n = EXACT_TABLE_MAX_LIGHTS + 1000;
        let powers: Vec<f64> = (0..n).map(|i| 1.0 + (i * 7919 % 1013) as f64).collect();
        let positions = vec![glam::dvec3(0.0, 0.0, 1.0); n];
        let plane = crate::app::scene_io::worked_example_scene().plane;
        let scene = Scene::new("large", plane, positions, LightPowers::new(powers).unwrap());
        let built = Built::new(1, scene);
        assert_eq!(built.table.construction(), Construction::Integer);
        let whole = built.table.implied_pmf_packed();
        let windows = [0..30, 500..900, 0..30, n - 10..n, 500..900, 7..8, n - 10..n];
        for w in windows {
            assert_eq!(&*built.pmf_of(w.clone()), &whole[w.clone()], "{w:?}");
        }
        assert!(built.pmf_window_bytes() <= 2 * 400 * 8);
        let masses = built.table.packed_masses();
        let denom = n as f64 * 4_294_967_296.0;
        let groups = &built.histogram_pmf;
        assert!(groups.per_bar > 1 && groups.per_cell > 1);
        for (per, pmf) in [
            (groups.per_bar, &groups.bars),
            (groups.per_cell, &groups.cells),
        ] {
            assert_eq!(pmf.len(), n.div_ceil(per));
            for (g, &p) in pmf.iter().enumerate() {
                let m: u64 = masses[g * per..((g + 1) * per).min(n)].iter().sum();
                assert_eq!(p, m as f64 / denom, "groups of {per}: {g}");
            }
        }
    }
}
