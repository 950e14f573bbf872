//! What the CPU renderer's power-picking passes read of a scene's lights: its own arrays,
//! shared, and the scale from a power to its share. Kept per scene by [`crate::SceneSamplers`]
//! and read by [`crate::render::CpuRenderer`]; below both, so neither imports the other for
//! it.

use std::sync::Arc;

use glam::DVec3;

use crate::powers::PmfScale;
use crate::scene::{Emission, Scene};

/// What a power-picking pass reads of the lights: the scene's own positions and powers
/// (shared, not copied: no bytes per light beyond the scene's) and the scale that turns a
/// power into its normalized share, `p_i =` [`PmfScale::of`]`(Φ_i)` (bit for bit the
/// entries of [`crate::LightPowers::pmf`]); the estimate in the accumulation unit is then
/// `ê' = w_i · G_i(x)` with `w_i = N·p_i·2^-s` for uniform picking and `w_i = 2^-s` for
/// power-proportional picking (`s` the scene's [`Scene::irradiance_shift`]). Built once
/// per scene ([`crate::SceneSamplers`] keeps it) and shared by its uniform and power renderers.
///
/// Before, each scene kept a 32-byte record (position and `p_i`) per light, one cache line
/// per pick; reading the scene's arrays costs the power lane nothing more (the position
/// is its only load per pick), and the uniform lane one more load (the power).
#[derive(Clone, Debug)]
pub(crate) struct CpuLights {
    /// The scene's light positions (shared).
    pub(crate) positions: Arc<[DVec3]>,
    /// The scene's light powers `Φ_i` (shared).
    pub(crate) powers: Arc<[f64]>,
    /// The scale from a power to its normalized share `p_i`.
    pub(crate) pmf: PmfScale,
    /// The emission profiles, for a scene with spots or ranges (a copy, shared in turn).
    pub(crate) emission: Option<Arc<[Emission]>>,
}

impl CpuLights {
    /// The lights of `scene`, sharing its arrays (`O(1)` but for the profiles, `O(N)`).
    pub(crate) fn of(scene: &Scene) -> Self {
        Self {
            positions: Arc::clone(&scene.positions),
            powers: Arc::clone(scene.powers.shared()),
            pmf: scene.powers.pmf_scale(),
            emission: scene.emission.as_deref().map(Arc::from),
        }
    }

    /// No lights (the spatial scheme reads its sampler instead).
    pub(crate) fn none() -> Self {
        Self {
            positions: Arc::from([]),
            powers: Arc::from([]),
            pmf: PmfScale::ONE,
            emission: None,
        }
    }

    /// Heap bytes held beyond the scene's: the emission profiles' copy, if any.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.emission
            .as_ref()
            .map_or(0, |e| std::mem::size_of_val(&**e))
    }

    /// Whether `other` holds these very arrays (and profiles), so that they are held once.
    pub(crate) fn shares_with(&self, other: &CpuLights) -> bool {
        let same_emission = match (&self.emission, &other.emission) {
            (Some(x), Some(y)) => Arc::ptr_eq(x, y),
            (None, None) => true,
            _ => false,
        };
        !self.positions.is_empty()
            && Arc::ptr_eq(&self.positions, &other.positions)
            && same_emission
    }
}
