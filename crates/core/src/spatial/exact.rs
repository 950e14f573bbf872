//! Exact contribution sampling for few lights: `P(i | x) = p_i·G_i(x) / Σ_j p_j·G_j(x)`.

use glam::{DVec2, DVec3};

use super::{EXACT_MAX_LIGHTS, SpatialLight, SpatialPick, contributing, unit24};
use crate::powers::LightPowers;
use crate::rng::Rng;
use crate::scene::{Emission, EmissionShape};

/// Picks light `i` at `x` with probability `c_i/S`, `c_i = p_i·G_i(x)`, `S = Σ_j c_j`, so the
/// estimate `c_i / (c_i/S) = S` is the same for every pick: zero variance for the unoccluded
/// model, at `O(N)` per shading point (every `c_j` is evaluated).
///
/// The pick: one draw `u` ([`unit24`]), the first light whose running sum `c_0 + … + c_i`
/// exceeds `u·S` (the last light with `c_i > 0` should rounding leave none).
#[derive(Clone, Debug, PartialEq)]
pub struct ExactSampler {
    lights: Vec<(u32, SpatialLight)>,
    /// The lights' emission profiles, beside `lights` (empty for point lights).
    emission: Vec<EmissionShape>,
    n: usize,
}

impl ExactSampler {
    /// Keeps the contributing lights (`p_i > 0`, `z_i > 0`). Meant for at most
    /// [`EXACT_MAX_LIGHTS`] lights; more work too, at `O(N)` per pick.
    ///
    /// # Panics
    /// If `positions` and `powers` have different lengths.
    pub fn build(positions: &[DVec3], powers: &LightPowers) -> Self {
        Self::build_with_emission(positions, powers, None)
    }

    /// [`ExactSampler::build`] for lights with emission profiles (`None`: point lights).
    ///
    /// # Panics
    /// If the lengths differ.
    pub fn build_with_emission(
        positions: &[DVec3],
        powers: &LightPowers,
        emission: Option<&[Emission]>,
    ) -> Self {
        let mut lights = Vec::new();
        let mut profiles = Vec::new();
        for (i, l, e) in contributing(positions, powers, emission, false) {
            lights.push((i, l));
            profiles.extend(e);
        }
        Self {
            lights,
            emission: profiles,
            n: positions.len(),
        }
    }

    /// `c_k(x)` of the `k`-th contributing light.
    #[inline]
    fn contribution(&self, k: usize, x: DVec2) -> f64 {
        self.lights[k].1.contribution_with(self.emission.get(k), x)
    }

    /// What the emission factor of the `k`-th contributing light is evaluated with, when the
    /// scene has profiles.
    pub fn emission(&self, k: usize) -> Option<&EmissionShape> {
        self.emission.get(k)
    }

    /// Number of lights of the scene.
    pub fn light_count(&self) -> usize {
        self.n
    }

    /// Heap bytes held, by capacity: the contributing lights with their scene index and
    /// their emission profiles (at most [`super::EXACT_MAX_LIGHTS`] of each in practice).
    pub fn heap_bytes(&self) -> usize {
        self.lights.capacity() * std::mem::size_of::<(u32, SpatialLight)>()
            + self.emission.capacity() * std::mem::size_of::<EmissionShape>()
    }

    /// The pick at `x` (one draw), `None` when `S = 0`.
    #[inline]
    pub fn sample(&self, x: DVec2, rng: &mut Rng) -> Option<SpatialPick> {
        let mut c = [0.0f64; EXACT_MAX_LIGHTS];
        let mut total = 0.0;
        let small = self.lights.len() <= EXACT_MAX_LIGHTS;
        if small {
            for (k, ci) in c.iter_mut().enumerate().take(self.lights.len()) {
                *ci = self.contribution(k, x);
                total += *ci;
            }
        } else {
            total = (0..self.lights.len())
                .map(|k| self.contribution(k, x))
                .sum();
        }
        let u = unit24(rng.next_u32());
        if total <= 0.0 {
            return None;
        }
        let target = u * total;
        let (mut running, mut chosen) = (0.0, None);
        for (k, (index, _)) in self.lights.iter().enumerate() {
            let ck = if small { c[k] } else { self.contribution(k, x) };
            if ck > 0.0 {
                chosen = Some((*index, ck));
                running += ck;
                if running > target {
                    break;
                }
            }
        }
        chosen.map(|(light, ck)| SpatialPick {
            light,
            pdf: ck / total,
            estimate: total,
        })
    }

    /// `P(i | x) = c_i / S` (0 for a light that cannot contribute, or when `S = 0`).
    pub fn pdf(&self, x: DVec2, light: usize) -> f64 {
        let total: f64 = (0..self.lights.len())
            .map(|k| self.contribution(k, x))
            .sum();
        self.lights
            .iter()
            .position(|(i, _)| *i as usize == light)
            .map_or(0.0, |k| {
                if total > 0.0 {
                    self.contribution(k, x) / total
                } else {
                    0.0
                }
            })
    }

    /// `P(i | x) = c_i / S` of every light of the scene, indexed by scene index (`O(N)`).
    pub fn pdfs(&self, x: DVec2) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        let total: f64 = (0..self.lights.len())
            .map(|k| self.contribution(k, x))
            .sum();
        if total > 0.0 {
            for (k, (i, _)) in self.lights.iter().enumerate() {
                out[*i as usize] = self.contribution(k, x) / total;
            }
        }
        out
    }

    /// The contributing lights with their scene index.
    pub fn lights(&self) -> &[(u32, SpatialLight)] {
        &self.lights
    }
}
