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
use crate::cdf::CdfTable;
use crate::cpu_lights::CpuLights;
use crate::sampler::{Sampler, Scheme};
use crate::scene::Scene;
use crate::scheme_sampler::SchemeSampler;
use crate::spatial::SpatialSampler;
use crate::uniform::Uniform;

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

    /// The sampler of `scheme` over the scene, sharing what is built: the alias schemes
    /// take the table, the spatial scheme the spatial sampler (built now if no one has yet),
    /// uniform and CDF are built (`O(1)`, `O(N)`).
    pub fn sampler(&self, scheme: Scheme) -> SchemeSampler {
        match scheme {
            Scheme::Alias => Sampler::Alias(Arc::clone(&self.table)).into(),
            Scheme::AliasOneRandom => Sampler::AliasOneRandom(Arc::clone(&self.table)).into(),
            Scheme::Spatial => SchemeSampler::Spatial(Arc::clone(self.spatial())),
            Scheme::Uniform => {
                Sampler::Uniform(Uniform::new(self.scene.light_count() as u32)).into()
            }
            Scheme::Cdf => Sampler::Cdf(CdfTable::build(&self.scene.powers)).into(),
        }
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
        self.repowered_then(scene, None, |_| ()).0
    }

    /// [`SceneSamplers::repowered`], rebuilding into `earlier`'s table and tree where
    /// nothing else holds them any more, and applying `with_table` to the new table.
    ///
    /// * `earlier`: an older generation of these samplers (same lights, same places, other
    ///   powers), say the one two edits back. Its table is rebuilt and its tree refitted in
    ///   place instead of copying this generation's: the same bits (a refit recomputes
    ///   every node from the powers), without the copies and the page faults of fresh
    ///   buffers (the tree is about 49 bytes per light). Whatever of it is still shared (a
    ///   renderer not yet restarted) or does not match is copied from `self` as usual.
    /// * `with_table` runs right after the table's rebuild, beside the tree's refit
    ///   (`rayon::join`), so work that needs only the table (a pmf for display, say) takes
    ///   no time of its own while the tree, the longer part, is refitted.
    ///
    /// # Panics
    /// If `scene` holds a different number of lights.
    pub fn repowered_then<R: Send>(
        &self,
        scene: Arc<Scene>,
        earlier: Option<SceneSamplers>,
        with_table: impl FnOnce(&AliasTable) -> R + Send,
    ) -> (Self, R) {
        assert_eq!(
            scene.light_count(),
            self.scene.light_count(),
            "one power per light"
        );
        let (earlier_table, earlier_tree) = earlier
            .filter(|e| e.scene.same_geometry(&scene))
            .map_or((None, None), SceneSamplers::into_unshared);
        let ((table, result), spatial) = rayon::join(
            || {
                let mut table = earlier_table
                    .filter(|t| t.construction() == self.table.construction())
                    .unwrap_or_else(|| AliasTable::clone(&self.table));
                table.rebuild(&scene.powers);
                let result = with_table(&table);
                (table, result)
            },
            || {
                let spatial = OnceLock::new();
                if let Some(built) = self.spatial.get() {
                    let mut refitted = earlier_tree
                        .filter(|t| std::mem::discriminant(t) == std::mem::discriminant(&**built))
                        .unwrap_or_else(|| SpatialSampler::clone(built));
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

    /// This generation's table and built tree, each where nothing else holds it.
    fn into_unshared(self) -> (Option<AliasTable>, Option<SpatialSampler>) {
        let table = Arc::try_unwrap(self.table).ok();
        let tree = Arc::try_unwrap(self.spatial)
            .ok()
            .and_then(OnceLock::into_inner)
            .and_then(|tree| Arc::try_unwrap(tree).ok());
        (table, tree)
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

    /// The scene with every power `p` replaced by `p·factor + 1` (same lights, same places).
    fn repowered_scene(scene: &Arc<Scene>, factor: f64) -> Arc<Scene> {
        let mut edited = Scene::clone(scene);
        let powers = scene.powers.as_slice().iter().map(|p| p * factor + 1.0);
        edited.powers = crate::LightPowers::new(powers.collect()).expect("valid powers");
        Arc::new(edited)
    }

    #[test]
    fn repowering_into_an_earlier_generation_reuses_it_and_equals_a_fresh_build() {
        let scene = Arc::new(Scene::preset("heavy-tail").expect("preset"));
        let first = SceneSamplers::new(Arc::clone(&scene), Construction::Integer);
        first.spatial();
        let second = first.repowered(repowered_scene(&scene, 2.0));
        let third_scene = repowered_scene(&scene, 3.0);
        let fresh = SceneSamplers::new(Arc::clone(&third_scene), Construction::Integer);
        fresh.spatial();
        // Still shared (a renderer holding the first generation): copied, the same result.
        let holder = first.clone();
        let (copied, ()) = second.repowered_then(Arc::clone(&third_scene), Some(first), |_| ());
        assert_eq!(**copied.table(), **fresh.table());
        assert_eq!(copied.spatial_if_built(), fresh.spatial_if_built());
        // Unshared: rebuilt in place, the same result again.
        let table_words = holder.table().packed().as_ptr();
        let (reused, pmf_len) = second.repowered_then(third_scene, Some(holder), AliasTable::len);
        assert_eq!(pmf_len, fresh.table().len());
        assert_eq!(
            reused.table().packed().as_ptr(),
            table_words,
            "table copied"
        );
        assert_eq!(**reused.table(), **fresh.table());
        assert_eq!(reused.spatial_if_built(), fresh.spatial_if_built());
    }
}
