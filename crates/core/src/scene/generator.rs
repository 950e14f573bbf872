//! Scenes generated from a seed: large presets are stored as a recipe, not light by light.
//!
//! # Reproducibility
//! Light `i` draws everything it needs from its own stream of the project's one generator,
//! `Rng::new(seed, i)` ([`crate::Rng`], the PCG hash): three 32-bit draws for its position,
//! then two for its power. A light therefore depends only on `(seed, i)` and on the recipe,
//! never on the thread that computed it or on the version of an external crate, so the same
//! file gives the same lights bit for bit everywhere.
//!
//! # Positions
//! `x = min + u·(max − min)` per axis, with `u = r·2^-32` uniform in `[0, 1)`: uniform in
//! the placement box.
//!
//! # Powers
//! From a 53-bit uniform `u ∈ [0, 1)` (two draws, see [`unit53`]) by inversion of the CDF:
//!
//! | distribution | density | sample |
//! | --- | --- | --- |
//! | `uniform {min, max}` | `1/(max − min)` on `[min, max)` | `min + u·(max − min)` |
//! | `exponential {mean}` | `e^{−x/mean}/mean`, `x ≥ 0` | `−mean·ln(1 − u)` |
//! | `pareto {scale, shape}` | `shape·scale^shape / x^{shape+1}`, `x ≥ scale` | `scale·(1 − u)^{−1/shape}` |
//! | `constant {value}` | all mass at `value` | `value` |
//! | `log-uniform {min, max}` | `1/(x·ln(max/min))` on `[min, max]` | `exp(ln min + u·ln(max/min))` |
//!
//! Since `1 − u ∈ [2^-53, 1]`, the exponential is at most `53·ln 2·mean ≈ 36.7·mean` and the
//! Pareto at most `scale·2^{53/shape}` (the truncation the 53-bit resolution implies).
//!
//! # Zeros and a dominant light
//! `zero_fraction = f ∈ [0, 1)` sets light `i` to zero exactly when
//! `⌊(i+1)·f⌋ > ⌊i·f⌋`: the zeros are spread evenly over the indices and there are exactly
//! `⌊N·f⌋` of them (the sum telescopes). Positions are i.i.d., so which indices are zero
//! does not bias where the zero lights are. `dominant {index, factor}` multiplies the drawn
//! power of light `index` by `factor` and exempts that light from zeroing: with a
//! `constant` distribution, that light is exactly `factor` times each of the others.

use glam::DVec3;
use rayon::prelude::*;

use super::error::SceneError;
use crate::rng::Rng;

/// The largest number of lights a scene may hold (`2^24`): the GPU stores at most a few
/// tens of bytes per light, and an explicit scene file of that size is already ~1 GB.
pub const MAX_LIGHTS: usize = 1 << 24;

/// How a generated scene draws its light powers; see the module docs for each density.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "distribution", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PowerDistribution {
    /// Uniform on `[min, max)`, `0 ≤ min ≤ max`, `max > 0`.
    Uniform {
        /// Lower bound (inclusive).
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Exponential with the given mean (`> 0`).
    Exponential {
        /// The mean `1/λ`.
        mean: f64,
    },
    /// Pareto (type I) with minimum `scale > 0` and tail index `shape > 0`: heavy-tailed,
    /// with infinite variance for `shape ≤ 2` and infinite mean for `shape ≤ 1`.
    Pareto {
        /// The minimum value `x_m`.
        scale: f64,
        /// The tail index `α`.
        shape: f64,
    },
    /// Every light the same power `value > 0`.
    Constant {
        /// The power.
        value: f64,
    },
    /// Log-uniform on `[min, max]`, `0 < min ≤ max`: equal mass per decade, for ranges such
    /// as `1e-30 … 1e30` that a linear uniform cannot span.
    LogUniform {
        /// Lower bound (positive).
        min: f64,
        /// Upper bound.
        max: f64,
    },
}

/// One light made `factor` times brighter than its drawn power.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dominant {
    /// Which light (default 0).
    #[serde(default)]
    pub index: u64,
    /// The multiplier (finite, `> 0`).
    pub factor: f64,
}

/// The axis-aligned box lights are placed in, uniformly.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// Lower corner `(x, y, z)` in the world.
    pub min: DVec3,
    /// Upper corner `(x, y, z)` in the world, each coordinate `≥` the lower one.
    pub max: DVec3,
}

/// The recipe of a generated scene; see the module docs for how each light is drawn.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Generator {
    /// Number of lights, `1 ..= MAX_LIGHTS`.
    pub count: u64,
    /// The seed of every light's stream.
    pub seed: u64,
    /// How powers are drawn.
    pub power: PowerDistribution,
    /// Fraction of lights set to power zero, in `[0, 1)` (default 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub zero_fraction: f64,
    /// An optional light made brighter than the rest.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dominant: Option<Dominant>,
    /// Where lights are placed.
    pub placement: Placement,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference.
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// A uniform `f64` in `[0, 1)` with 53 random bits from two draws:
/// `(⌊a/2^5⌋·2^26 + ⌊b/2^6⌋) · 2^-53`, every multiple of `2^-53` equally likely.
#[inline]
pub(crate) fn unit53(rng: &mut Rng) -> f64 {
    let a = u64::from(rng.next_u32() >> 5);
    let b = u64::from(rng.next_u32() >> 6);
    ((a << 26) | b) as f64 * (1.0 / 9_007_199_254_740_992.0)
}

impl PowerDistribution {
    /// Checks the parameters; `field` is the path of this distribution in the file.
    fn validate(&self, field: &str) -> Result<(), SceneError> {
        let finite = |name: &str, v: f64| -> Result<(), SceneError> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(SceneError::NotFinite {
                    field: format!("{field}.{name}"),
                    value: v,
                })
            }
        };
        let positive = |name: &str, v: f64| -> Result<(), SceneError> {
            finite(name, v)?;
            if v > 0.0 {
                Ok(())
            } else {
                Err(SceneError::invalid(
                    format!("{field}.{name}"),
                    format!("must be positive (got {v})"),
                ))
            }
        };
        match *self {
            PowerDistribution::Uniform { min, max } => {
                finite("min", min)?;
                finite("max", max)?;
                if min < 0.0 {
                    return Err(SceneError::Negative {
                        field: format!("{field}.min"),
                        value: min,
                    });
                }
                positive("max", max)?;
                if max < min {
                    return Err(SceneError::invalid(
                        format!("{field}.max"),
                        format!("must be at least min ({max} < {min})"),
                    ));
                }
            }
            PowerDistribution::Exponential { mean } => positive("mean", mean)?,
            PowerDistribution::Pareto { scale, shape } => {
                positive("scale", scale)?;
                positive("shape", shape)?;
            }
            PowerDistribution::Constant { value } => positive("value", value)?,
            PowerDistribution::LogUniform { min, max } => {
                positive("min", min)?;
                positive("max", max)?;
                if max < min {
                    return Err(SceneError::invalid(
                        format!("{field}.max"),
                        format!("must be at least min ({max} < {min})"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The power for the 53-bit uniform `u ∈ [0, 1)` (inverse CDF, see the module docs).
    #[inline]
    pub(crate) fn sample(&self, u: f64) -> f64 {
        match *self {
            PowerDistribution::Uniform { min, max } => min + u * (max - min),
            PowerDistribution::Exponential { mean } => -mean * (1.0 - u).ln(),
            PowerDistribution::Pareto { scale, shape } => scale * (1.0 - u).powf(-1.0 / shape),
            PowerDistribution::Constant { value } => value,
            PowerDistribution::LogUniform { min, max } => {
                let (lo, hi) = (min.ln(), max.ln());
                // Clamp the rounding of exp/ln back into [min, max].
                (lo + u * (hi - lo)).exp().clamp(min, max)
            }
        }
    }
}

impl Generator {
    /// Checks every parameter; errors name the field under `generator`.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.count < 1 || self.count > MAX_LIGHTS as u64 {
            return Err(SceneError::out_of_range(
                "generator.count",
                self.count,
                1,
                MAX_LIGHTS,
            ));
        }
        self.power.validate("generator.power")?;
        let f = self.zero_fraction;
        if !f.is_finite() {
            return Err(SceneError::NotFinite {
                field: "generator.zero_fraction".into(),
                value: f,
            });
        }
        if !(0.0..1.0).contains(&f) {
            return Err(SceneError::out_of_range(
                "generator.zero_fraction",
                f,
                0,
                "1 (exclusive)",
            ));
        }
        if let Some(d) = &self.dominant {
            if d.index >= self.count {
                return Err(SceneError::out_of_range(
                    "generator.dominant.index",
                    d.index,
                    0,
                    self.count - 1,
                ));
            }
            if !d.factor.is_finite() {
                return Err(SceneError::NotFinite {
                    field: "generator.dominant.factor".into(),
                    value: d.factor,
                });
            }
            if d.factor <= 0.0 {
                return Err(SceneError::invalid(
                    "generator.dominant.factor",
                    format!("must be positive (got {})", d.factor),
                ));
            }
        }
        for axis in 0..3 {
            for (name, corner) in [("min", self.placement.min), ("max", self.placement.max)] {
                if !corner[axis].is_finite() {
                    return Err(SceneError::NotFinite {
                        field: format!("generator.placement.{name}[{axis}]"),
                        value: corner[axis],
                    });
                }
            }
            if self.placement.max[axis] < self.placement.min[axis] {
                return Err(SceneError::invalid(
                    format!("generator.placement.max[{axis}]"),
                    format!(
                        "must be at least placement.min[{axis}] ({} < {})",
                        self.placement.max[axis], self.placement.min[axis]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Whether light `i` is zeroed by `zero_fraction` (before the dominant exemption):
    /// `⌊(i+1)·f⌋ > ⌊i·f⌋`.
    #[inline]
    fn zeroed(&self, i: u64) -> bool {
        let f = self.zero_fraction;
        ((i + 1) as f64 * f).floor() > (i as f64 * f).floor()
    }

    /// Light `i`: its position and power, from the stream `Rng::new(seed, i)`.
    #[inline]
    pub fn light(&self, i: u64) -> (DVec3, f64) {
        let mut rng = Rng::new(self.seed, i);
        let (lo, hi) = (self.placement.min, self.placement.max);
        let mut position = DVec3::ZERO;
        for axis in 0..3 {
            let u = rng.next_unit();
            position[axis] = lo[axis] + u * (hi[axis] - lo[axis]);
        }
        let drawn = self.power.sample(unit53(&mut rng));
        let power = match &self.dominant {
            Some(d) if d.index == i => drawn * d.factor,
            _ if self.zeroed(i) => 0.0,
            _ => drawn,
        };
        (position, power)
    }

    /// Validates the recipe and draws every light, in parallel (the result does not depend
    /// on the thread count). Returns positions and powers, not yet checked as
    /// [`crate::LightPowers`] (a dominant factor may overflow a power to infinity).
    pub fn generate(&self) -> Result<(Vec<DVec3>, Vec<f64>), SceneError> {
        self.validate()?;
        // count ≤ MAX_LIGHTS = 2^24 fits usize (rayon indexes usize ranges, not u64 ones).
        Ok((0..self.count as usize)
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| self.light(i as u64))
            .unzip())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit53_spans_the_half_open_interval() {
        // Recover the 53-bit integer: it must be an integer below 2^53.
        let mut rng = Rng::new(3, 9);
        for _ in 0..1000 {
            let u = unit53(&mut rng);
            assert!((0.0..1.0).contains(&u));
            let k = u * 9_007_199_254_740_992.0;
            assert_eq!(k, k.floor());
        }
    }

    #[test]
    fn inverse_cdfs_hit_their_endpoints() {
        let pareto = PowerDistribution::Pareto {
            scale: 2.0,
            shape: 1.5,
        };
        assert_eq!(pareto.sample(0.0), 2.0);
        let expo = PowerDistribution::Exponential { mean: 3.0 };
        assert_eq!(expo.sample(0.0), 0.0);
        let log = PowerDistribution::LogUniform {
            min: 1e-30,
            max: 1e30,
        };
        // exp(ln x) is x up to a few ulps (the clamp keeps it inside [min, max]).
        assert!((log.sample(0.0) / 1e-30 - 1.0).abs() < 1e-13);
        assert!(log.sample(0.0) >= 1e-30);
        assert!((log.sample(0.5) - 1.0).abs() < 1e-12);
        let one_below = 1.0 - f64::EPSILON / 2.0;
        assert!(log.sample(one_below) <= 1e30);
        assert!(log.sample(one_below) > 0.99e30);
    }

    #[test]
    fn zeroing_rule_counts_exactly() {
        for (count, f) in [(10u64, 0.5), (7, 0.5), (1000, 0.3), (1, 0.9), (64, 0.0)] {
            let g = Generator {
                count,
                seed: 1,
                power: PowerDistribution::Constant { value: 1.0 },
                zero_fraction: f,
                dominant: None,
                placement: Placement {
                    min: DVec3::ZERO,
                    max: DVec3::ONE,
                },
            };
            let zeros = (0..count).filter(|&i| g.zeroed(i)).count() as u64;
            assert_eq!(zeros, (count as f64 * f).floor() as u64, "{count} {f}");
        }
    }
}
