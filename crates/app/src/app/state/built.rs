//! The last valid scene and what is built from it once per scene generation.

use std::sync::Arc;

use lightpick_core::scene::Scene;
use lightpick_core::{AliasTable, Construction, SceneSamplers};

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
    /// The integer-built table's pmf, kept here ([`Built::pmf`]); `None` for the exact
    /// construction, which stores its own.
    pmf: Option<Vec<f64>>,
}

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

/// The pmf the app keeps beside an integer-built table ([`Built::pmf`]); `None` for the
/// exact construction, which stores its own.
fn pmf_kept(table: &AliasTable) -> Option<Vec<f64>> {
    (table.construction() == Construction::Integer).then(|| table.implied_pmf_packed())
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
        // The pmf needs only the table: it is computed while the tree is refitted.
        let (samplers, pmf) = previous.repowered_then(Arc::new(scene), earlier, pmf_kept);
        Self::with_parts(generation, samplers, pmf)
    }

    /// The state around samplers whose table is built: the spatial sampler built now (off
    /// the UI thread for large scenes), the display helpers derived from the scene.
    fn with_samplers(generation: u64, samplers: SceneSamplers) -> Self {
        samplers.spatial();
        let pmf = pmf_kept(samplers.table());
        Self::with_parts(generation, samplers, pmf)
    }

    /// The state around built samplers and the pmf kept for them ([`pmf_kept`]).
    fn with_parts(generation: u64, samplers: SceneSamplers, pmf: Option<Vec<f64>>) -> Self {
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
            pmf,
        }
    }

    /// The pmf the table realizes, every light's `p_i`: [`AliasTable::pmf_slice`] bit for
    /// bit. An integer-built table would derive it with its thresholds and aliases (20 bytes
    /// per light, [`AliasTable::heap_bytes`]); the app keeps the pmf alone (8 bytes), which
    /// the histograms and the table panel need for every light, and reads thresholds and
    /// aliases per shown column ([`AliasTable::threshold`], [`AliasTable::alias`]).
    pub fn pmf(&self) -> &[f64] {
        self.pmf
            .as_deref()
            .unwrap_or_else(|| self.table.pmf_slice())
    }

    /// Heap bytes of the pmf kept here ([`Built::pmf`]; 0 for the exact construction).
    pub fn pmf_heap_bytes(&self) -> usize {
        self.pmf
            .as_ref()
            .map_or(0, |p| p.capacity() * std::mem::size_of::<f64>())
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
