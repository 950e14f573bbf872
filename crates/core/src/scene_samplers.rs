//! What a scene's renderers and views sample with, built once per scene and shared.
//!
//! A scene models only what it requires (a point light is a position and a power), and what
//! is built from it — the alias table (`O(N)`), the spatial sampler's light tree
//! (`O(N log N)`) — is built once and handed out through `Arc`s: to the table panel and
//! the histograms, to every CPU and GPU renderer of the scene, to the pixel inspector and to
//! the estimator view. Before this, the app built the table for its panels, each renderer
//! built its own again, the inspector built a second light tree, and each GPU renderer kept
//! its own `f64` copy of the positions and powers (about 96 MB for 10^6 lights over three).

use std::sync::{Arc, OnceLock};

use crate::alias::{AliasTable, Construction};
use crate::render::CpuLights;
use crate::scene::Scene;
use crate::spatial::SpatialSampler;

/// A scene with its alias table and (built on first use, once) its spatial sampler and the
/// CPU renderers' view of its lights. Cloning shares everything.
#[derive(Clone, Debug)]
pub struct SceneSamplers {
    scene: Arc<Scene>,
    table: Arc<AliasTable>,
    spatial: Arc<OnceLock<Arc<SpatialSampler>>>,
    cpu_lights: Arc<OnceLock<CpuLights>>,
}

impl SceneSamplers {
    /// The scene's alias table built by `construction` (`O(N)`); the spatial sampler waits
    /// for its first use ([`SceneSamplers::spatial`]).
    pub fn new(scene: Arc<Scene>, construction: Construction) -> Self {
        let table = Arc::new(AliasTable::build_with(&scene.powers, construction));
        Self::with_table(scene, table)
    }

    /// The scene with a table already built over its powers.
    ///
    /// # Panics
    /// If the table's length differs from the scene's light count.
    pub fn with_table(scene: Arc<Scene>, table: Arc<AliasTable>) -> Self {
        assert_eq!(
            table.len(),
            scene.light_count(),
            "table built for another scene"
        );
        Self {
            scene,
            table,
            spatial: Arc::new(OnceLock::new()),
            cpu_lights: Arc::new(OnceLock::new()),
        }
    }

    /// The scene.
    pub fn scene(&self) -> &Arc<Scene> {
        &self.scene
    }

    /// The alias table over the scene's powers.
    pub fn table(&self) -> &Arc<AliasTable> {
        &self.table
    }

    /// The spatial sampler ([`SpatialSampler::for_scene`]: the exact pick for few lights, the
    /// light tree beyond), built by the first caller, once for every clone.
    pub fn spatial(&self) -> &Arc<SpatialSampler> {
        self.spatial
            .get_or_init(|| Arc::new(SpatialSampler::for_scene(&self.scene)))
    }

    /// The samplers of `scene`, a scene with the same lights in the same places
    /// ([`Scene::same_geometry`]) and new powers: the table is rebuilt (`O(N)`, into a copy,
    /// since renderers may still hold this one), the light tree refitted
    /// ([`SpatialSampler::refit`], `O(N)`) if it was built, where a fresh
    /// [`SceneSamplers::new`] would rebuild the tree in `O(N log N)`. Equal bit for bit to
    /// a fresh build with the same construction.
    ///
    /// # Panics
    /// If `scene` holds a different number of lights.
    #[must_use]
    pub fn repowered(&self, scene: Arc<Scene>) -> Self {
        self.repowered_then(scene, |_| ()).0
    }

    /// [`SceneSamplers::repowered`], and `with_table` applied to the new table: the table's
    /// rebuild and then `with_table` run beside the tree's copy and refit (`rayon::join`),
    /// so work that needs only the table (a pmf for display, say) takes no time of its own
    /// while the tree, the longer part, is refitted.
    ///
    /// # Panics
    /// If `scene` holds a different number of lights.
    pub fn repowered_then<R: Send>(
        &self,
        scene: Arc<Scene>,
        with_table: impl FnOnce(&AliasTable) -> R + Send,
    ) -> (Self, R) {
        assert_eq!(
            scene.light_count(),
            self.scene.light_count(),
            "one power per light"
        );
        let ((table, result), spatial) = rayon::join(
            || {
                let mut table = AliasTable::clone(&self.table);
                table.rebuild(&scene.powers);
                let result = with_table(&table);
                (table, result)
            },
            || {
                let spatial = OnceLock::new();
                if let Some(built) = self.spatial.get() {
                    let mut refitted = SpatialSampler::clone(built);
                    refitted.refit(&scene);
                    let _ = spatial.set(Arc::new(refitted));
                }
                spatial
            },
        );
        let samplers = Self {
            scene,
            table: Arc::new(table),
            spatial: Arc::new(spatial),
            cpu_lights: Arc::new(OnceLock::new()),
        };
        (samplers, result)
    }

    /// The lights every power-picking CPU renderer of the scene reads (the scene's arrays
    /// and the pmf's scale), made by the first of them, once for every clone.
    pub(crate) fn cpu_lights(&self) -> &CpuLights {
        self.cpu_lights.get_or_init(|| CpuLights::of(&self.scene))
    }

    /// The spatial sampler if some caller has built it already.
    pub fn spatial_if_built(&self) -> Option<&Arc<SpatialSampler>> {
        self.spatial.get()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_one_table_and_one_tree() {
        let scene = Arc::new(Scene::preset("heavy-tail").expect("preset"));
        let a = SceneSamplers::new(scene, Construction::Integer);
        let b = a.clone();
        assert!(Arc::ptr_eq(a.table(), b.table()));
        assert!(b.spatial_if_built().is_none());
        let tree = Arc::clone(a.spatial());
        assert!(Arc::ptr_eq(&tree, b.spatial()));
        assert!(b.spatial_if_built().is_some());
    }
}
