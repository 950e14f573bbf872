//! The power distributions the lab measures on, drawn with the scene generator's recipe.

use glam::DVec3;

use crate::scene::{Generator, Placement, PowerDistribution};

/// A family of test powers. Light `i` is drawn from the stream `Rng::new(seed, i)` exactly
/// as a generated scene draws it ([`Generator::light`]), so a figure is reproducible from
/// `(distribution, N, seed)` alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Distribution {
    /// Uniform on `[0, 1)`: no structure, the easy case.
    Uniform,
    /// Exponential with mean 1 (the `million` preset's law).
    Exponential,
    /// Pareto with scale 1 and shape 1.2 (the `heavy-tail` preset's law): a few lights
    /// carry much of the power, so long donation chains.
    Pareto,
    /// Uniform on `[0.5, 2)` with exactly `⌊N/2⌋` lights at power 0 (the `zeros` preset's
    /// law): the test of leaks onto zero-power lights.
    WithZeros,
    /// Log-uniform on `[10^-30, 10^30]` (the `extreme-range` preset's law): `q_i` spans 60
    /// decades, most lights are tiny.
    LogUniform,
}

/// A distribution name that is not one of [`Distribution::ALL`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown distribution '{0}' (expected uniform, exponential, pareto, with-zeros, log-uniform)"
)]
pub struct UnknownDistribution(pub String);

impl Distribution {
    /// Every distribution, in display order.
    pub const ALL: [Distribution; 5] = [
        Distribution::Uniform,
        Distribution::Exponential,
        Distribution::Pareto,
        Distribution::WithZeros,
        Distribution::LogUniform,
    ];

    /// The distribution's command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Distribution::Uniform => "uniform",
            Distribution::Exponential => "exponential",
            Distribution::Pareto => "pareto",
            Distribution::WithZeros => "with-zeros",
            Distribution::LogUniform => "log-uniform",
        }
    }

    /// The generator recipe of `n` lights with this law.
    fn generator(self, n: usize, seed: u64) -> Generator {
        let (power, zero_fraction) = match self {
            Distribution::Uniform => (PowerDistribution::Uniform { min: 0.0, max: 1.0 }, 0.0),
            Distribution::Exponential => (PowerDistribution::Exponential { mean: 1.0 }, 0.0),
            Distribution::Pareto => (
                PowerDistribution::Pareto {
                    scale: 1.0,
                    shape: 1.2,
                },
                0.0,
            ),
            Distribution::WithZeros => (PowerDistribution::Uniform { min: 0.5, max: 2.0 }, 0.5),
            Distribution::LogUniform => (
                PowerDistribution::LogUniform {
                    min: 1e-30,
                    max: 1e30,
                },
                0.0,
            ),
        };
        Generator {
            count: n as u64,
            seed,
            power,
            zero_fraction,
            dominant: None,
            placement: Placement {
                min: DVec3::ZERO,
                max: DVec3::ONE,
            },
        }
    }

    /// `n` powers of this law from `seed` (not validated: uniform may, rarely, draw zeros,
    /// and a single light of `with-zeros` is positive). Any `n` is accepted, beyond the
    /// scene limit too.
    pub fn powers(self, n: usize, seed: u64) -> Vec<f64> {
        use rayon::prelude::*;
        let generator = self.generator(n, seed);
        (0..n as u64)
            .into_par_iter()
            .map(|i| generator.light(i).1)
            .collect()
    }
}

impl std::fmt::Display for Distribution {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Distribution {
    type Err = UnknownDistribution;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Distribution::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| UnknownDistribution(s.to_owned()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for d in Distribution::ALL {
            assert_eq!(d.name().parse::<Distribution>(), Ok(d));
        }
        assert!("gauss".parse::<Distribution>().is_err());
    }

    #[test]
    fn with_zeros_has_exactly_half_zeros() {
        let p = Distribution::WithZeros.powers(1001, 3);
        assert_eq!(p.iter().filter(|&&x| x == 0.0).count(), 500);
        assert!(p.iter().all(|&x| x == 0.0 || (0.5..2.0).contains(&x)));
    }
}
