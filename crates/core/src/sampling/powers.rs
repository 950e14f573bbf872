//! Validated light powers: the only input every sampler is built from.

/// Why a list of light powers was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PowersError {
    /// The list holds no light at all.
    #[error("no lights: the power list is empty")]
    Empty,
    /// A power is NaN or infinite.
    #[error("power of light {index} is not finite ({value})")]
    NotFinite {
        /// Index of the offending light (0-based).
        index: usize,
        /// The value found there.
        value: f64,
    },
    /// A power is below zero.
    #[error("power of light {index} is negative ({value})")]
    Negative {
        /// Index of the offending light (0-based).
        index: usize,
        /// The value found there.
        value: f64,
    },
    /// Every power is zero, so no light can be picked with a probability proportional to it.
    #[error("all {count} powers are zero: nothing emits light")]
    AllZero {
        /// How many lights there are.
        count: usize,
    },
    /// More lights than a `u32` index (the GPU's alias word) can name.
    #[error("{count} lights exceed the limit of {max} (u32 indices)")]
    TooMany {
        /// How many lights were given.
        count: usize,
        /// The largest accepted count, `u32::MAX`.
        max: u32,
    },
}

/// A non-empty list of finite, non-negative light powers `Φ_i`, not all zero, with at most
/// `u32::MAX` entries.
///
/// Any finite non-negative `f64` is accepted, subnormals and values near `f64::MAX`
/// included. Normalization ([`LightPowers::normalized`]) first rescales by an exact power of
/// two, so `Σ Φ_i` never overflows even when every power is `f64::MAX`.
///
/// The powers are held shared (`Arc<[f64]>`): a clone of the list, or of a scene holding
/// it, costs no copy, and an editor can share the very array it validated
/// ([`LightPowers::from_shared`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LightPowers {
    powers: std::sync::Arc<[f64]>,
}

impl LightPowers {
    /// Validates `powers`; the error names the first offending index.
    pub fn new(powers: Vec<f64>) -> Result<Self, PowersError> {
        Self::from_shared(powers.into())
    }

    /// Validates a shared list of powers and keeps it, without a copy: the caller's `Arc`
    /// and the result hold the same array. The error names the first offending index.
    pub fn from_shared(powers: std::sync::Arc<[f64]>) -> Result<Self, PowersError> {
        check_count(powers.len())?;
        for (index, &value) in powers.iter().enumerate() {
            if !value.is_finite() {
                return Err(PowersError::NotFinite { index, value });
            }
            if value < 0.0 {
                return Err(PowersError::Negative { index, value });
            }
        }
        if powers.iter().all(|&p| p == 0.0) {
            return Err(PowersError::AllZero {
                count: powers.len(),
            });
        }
        Ok(Self { powers })
    }

    /// The powers as given.
    pub fn as_slice(&self) -> &[f64] {
        &self.powers
    }

    /// The shared array the powers live in (cloning it copies nothing).
    pub fn shared(&self) -> &std::sync::Arc<[f64]> {
        &self.powers
    }

    /// Number of lights `N` (at least 1).
    pub fn len(&self) -> usize {
        self.powers.len()
    }

    /// Heap bytes held: 8 bytes per light (held once however many lists share them).
    pub fn heap_bytes(&self) -> usize {
        std::mem::size_of_val::<[f64]>(&self.powers)
    }

    /// Always `false`: validation refuses empty lists. Present for API symmetry.
    pub fn is_empty(&self) -> bool {
        self.powers.is_empty()
    }

    /// The total power `Σ Φ_i`, which may be `+inf` for powers near `f64::MAX`; use
    /// [`LightPowers::normalized`] for probabilities.
    pub fn total(&self) -> f64 {
        self.powers.iter().sum()
    }

    /// The powers scaled by an exact power of two `2^-e` so that the largest lies in
    /// `[1, 2)`, and their sum `S` (so `Φ_i / Σ Φ = w_i / S`). Scaling by a power of two is
    /// exact, so small-integer inputs keep exact ratios (the worked example's `6/27` stays `6/27`).
    ///
    /// Returns `(w, S)`. `S ≤ 2N`, far from overflow. A power below `2^-1074` times the
    /// largest underflows to zero share: it is then treated like a zero power.
    pub fn normalized(&self) -> (Vec<f64>, f64) {
        let scale = pow2_scale_to_unit(self.max());
        let scaled: Vec<f64> = self.powers.iter().map(|&p| scale.apply(p)).collect();
        let sum = chunked_sum(&scaled);
        (scaled, sum)
    }

    /// What [`LightPowers::pmf`] divides by, without allocating: `p_i =`
    /// [`PmfScale::of`]`(Φ_i)`, bit for bit the entries of `pmf()`.
    pub fn pmf_scale(&self) -> PmfScale {
        let scale = pow2_scale_to_unit(self.max());
        let sum = chunked_sum_by(&self.powers, |p| scale.apply(p));
        PmfScale { scale, sum }
    }

    /// The total power without overflow, as `(S, e)` with `Σ Φ_i = S · 2^e` up to the
    /// rounding of one sum: `S = Σ w_i` is the sum of [`LightPowers::normalized`]
    /// (`1 ≤ S ≤ 2N`) and `2^-e` the exact scale that maps the largest power into `[1, 2)`
    /// (`e` is the largest power's binary exponent, `-1074 ≤ e ≤ 1023`). Unlike
    /// [`LightPowers::total`], this stays finite when the total exceeds `f64::MAX`
    /// (two powers of `f64::MAX` give `S = 4 − 2^-51`, `e = 1023`).
    pub fn total_parts(&self) -> (f64, i32) {
        let (_, sum) = self.normalized();
        (sum, unit_exponent(self.max()))
    }

    /// `Σ Φ_i` whatever its magnitude: `S·2^e` of [`LightPowers::total_parts`], computed
    /// without allocating. Scaling every power by `2^k` adds `k` to its exponent and leaves
    /// its significand's bits alone.
    pub fn total_scaled(&self) -> crate::scaled::Scaled {
        let max = self.max();
        crate::scaled::Scaled::new(self.pmf_scale().sum, unit_exponent(max))
    }

    /// `log10 Σ Φ_i = log10 S + e · log10 2` from [`LightPowers::total_parts`]: finite for
    /// every valid list, so a total beyond `f64::MAX` (about `10^308.25`) can still be
    /// reported. Its absolute error is below `10^-13` (`|e| ≤ 1074` times the rounding of
    /// `log10 2`, plus that of `log10 S`).
    pub fn total_log10(&self) -> f64 {
        let (sum, exponent) = self.total_parts();
        sum.log10() + f64::from(exponent) * std::f64::consts::LOG10_2
    }

    /// The largest power (positive, since not all are zero).
    pub fn max(&self) -> f64 {
        self.powers.iter().copied().fold(0.0, f64::max)
    }

    /// The normalized power `p_i = Φ_i / Σ Φ` of every light, computed without overflow.
    pub fn pmf(&self) -> Vec<f64> {
        let (w, sum) = self.normalized();
        w.into_iter().map(|x| x / sum).collect()
    }
}

/// Refuses lists that are empty or longer than `u32::MAX` (tested without allocating them).
pub(crate) fn check_count(len: usize) -> Result<(), PowersError> {
    if len == 0 {
        return Err(PowersError::Empty);
    }
    if len > u32::MAX as usize {
        return Err(PowersError::TooMany {
            count: len,
            max: u32::MAX,
        });
    }
    Ok(())
}

/// An exact scaling by `2^k`, applied in up to two steps so `k` may exceed the `f64`
/// exponent range (a subnormal maximum needs `k > 1023`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pow2Scale {
    first: f64,
    second: f64,
}

impl Pow2Scale {
    /// `2^0`.
    pub(crate) const ONE: Pow2Scale = Pow2Scale {
        first: 1.0,
        second: 1.0,
    };

    /// Multiplies `x` by `2^k`; exact unless the result leaves the `f64` range.
    #[inline]
    pub(crate) fn apply(self, x: f64) -> f64 {
        x * self.first * self.second
    }
}

/// The binary exponent `e` of `max > 0`: `2^e ≤ max < 2^(e+1)`, subnormals included.
pub(crate) fn unit_exponent(max: f64) -> i32 {
    debug_assert!(max > 0.0 && max.is_finite());
    let bits = max.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal: 2^-1074 · mantissa, exponent of the leading bit.
        let mantissa = bits & ((1 << 52) - 1);
        -1074 + (63 - mantissa.leading_zeros() as i32)
    } else {
        biased - 1023
    }
}

/// The exact power-of-two scaling that maps `max > 0` into `[1, 2)`: `2^-e` with `e` its
/// [`unit_exponent`].
pub(crate) fn pow2_scale_to_unit(max: f64) -> Pow2Scale {
    let k = -unit_exponent(max);
    let half = k / 2;
    Pow2Scale {
        first: pow2(half),
        second: pow2(k - half),
    }
}

/// `2^k` for `k` in the normal exponent range `[-1022, 1023]`.
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// Sum with eight independent accumulators: vectorizes, and its rounding error grows like
/// `N/8` ulps in the worst case instead of `N`.
pub(crate) fn chunked_sum(values: &[f64]) -> f64 {
    chunked_sum_by(values, |v| v)
}

/// [`chunked_sum`] of `f(v)` over `values`, in the same order (the same bits as summing a
/// mapped copy).
fn chunked_sum_by(values: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    let mut lanes = [0.0f64; 8];
    let chunks = values.chunks_exact(8);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (lane, &v) in lanes.iter_mut().zip(chunk) {
            *lane += f(v);
        }
    }
    let mut total = lanes.iter().sum::<f64>();
    for &v in rest {
        total += f(v);
    }
    total
}

/// The exact power-of-two scale and the scaled sum `S` of a [`LightPowers`]: the normalized
/// power of a light is `Φ·2^-e / S` ([`LightPowers::pmf_scale`]).
#[derive(Clone, Copy, Debug)]
pub struct PmfScale {
    scale: Pow2Scale,
    sum: f64,
}

impl PmfScale {
    /// The identity: `p = Φ` (scale 1, sum 1), for a list that is one light of power 1.
    pub(crate) const ONE: PmfScale = PmfScale {
        scale: Pow2Scale::ONE,
        sum: 1.0,
    };

    /// `p = Φ·2^-e / S` of a light of power `power`: its [`PmfScale::weight`] over
    /// [`PmfScale::sum`].
    #[inline]
    pub fn of(&self, power: f64) -> f64 {
        self.weight(power) / self.sum
    }

    /// `w = Φ·2^-e`, the power scaled exactly (by a power of two) so that the largest lies
    /// in `[1, 2)`: what the pmf divides by [`PmfScale::sum`]. New powers that leave the
    /// largest one's binary exponent alone leave every other light's `w` unchanged, bit for
    /// bit, where its `p` changes with the sum.
    #[inline]
    pub fn weight(&self, power: f64) -> f64 {
        self.scale.apply(power)
    }

    /// `S = Σ_i w_i`, the sum the pmf divides by.
    #[inline]
    pub fn sum(&self) -> f64 {
        self.sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_is_refused() {
        assert_eq!(LightPowers::new(vec![]), Err(PowersError::Empty));
    }

    #[test]
    fn nan_and_infinity_name_their_index() {
        let err = LightPowers::new(vec![1.0, f64::NAN]).unwrap_err();
        assert!(matches!(err, PowersError::NotFinite { index: 1, .. }));
        let err = LightPowers::new(vec![f64::INFINITY, 1.0]).unwrap_err();
        assert!(matches!(err, PowersError::NotFinite { index: 0, .. }));
        assert!(err.to_string().contains("light 0"), "{err}");
    }

    #[test]
    fn negative_names_its_index() {
        let err = LightPowers::new(vec![1.0, 2.0, -0.5]).unwrap_err();
        assert_eq!(
            err,
            PowersError::Negative {
                index: 2,
                value: -0.5
            }
        );
        assert_eq!(err.to_string(), "power of light 2 is negative (-0.5)");
    }

    #[test]
    fn all_zero_is_refused() {
        assert_eq!(
            LightPowers::new(vec![0.0, 0.0, -0.0]),
            Err(PowersError::AllZero { count: 3 })
        );
    }

    #[test]
    fn too_many_is_refused_by_count() {
        assert!(check_count(u32::MAX as usize).is_ok());
        let err = check_count(u32::MAX as usize + 1).unwrap_err();
        assert!(matches!(err, PowersError::TooMany { .. }));
        assert!(err.to_string().contains("4294967296 lights"), "{err}");
    }

    #[test]
    fn total_parts_do_not_overflow() {
        let p = LightPowers::new(vec![f64::MAX, f64::MAX]).unwrap();
        assert_eq!(p.total(), f64::INFINITY);
        assert_eq!(p.total_parts(), (4.0 - 2.0 * f64::EPSILON, 1023));
        // log10(2·f64::MAX) = log10(f64::MAX) + log10 2 ≈ 308.5557.
        let expected = f64::MAX.log10() + std::f64::consts::LOG10_2;
        assert!((p.total_log10() - expected).abs() < 1e-13);
        let seed = LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap();
        assert_eq!(seed.total_parts(), (27.0 / 16.0, 4));
        assert!((seed.total_log10() - 27f64.log10()).abs() < 1e-15);
        let tiny = LightPowers::new(vec![f64::from_bits(1)]).unwrap();
        assert_eq!(tiny.total_parts(), (1.0, -1074));
    }

    #[test]
    fn two_max_powers_normalize_to_halves() {
        let powers = LightPowers::new(vec![f64::MAX, f64::MAX]).unwrap();
        assert_eq!(powers.pmf(), vec![0.5, 0.5]);
    }

    #[test]
    fn subnormal_powers_normalize_exactly() {
        let tiny = f64::from_bits(1); // 2^-1074
        let powers = LightPowers::new(vec![tiny, 3.0 * tiny]).unwrap();
        assert_eq!(powers.pmf(), vec![0.25, 0.75]);
    }

    #[test]
    fn seed_pmf_is_correctly_rounded() {
        let powers = LightPowers::new(vec![2.0, 5.0, 20.0]).unwrap();
        assert_eq!(powers.pmf(), vec![2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]);
    }

    #[test]
    fn pow2_scale_lands_in_unit_interval() {
        for max in [
            f64::MAX,
            1.0,
            3.0,
            1e-300,
            f64::MIN_POSITIVE,
            f64::from_bits(7),
        ] {
            let scaled = pow2_scale_to_unit(max).apply(max);
            assert!((1.0..2.0).contains(&scaled), "{max} -> {scaled}");
        }
    }
}
