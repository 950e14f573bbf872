//! Uniform integer picks over `0..N`: the unbiased, power-blind baseline scheme, and the
//! exact column pick the alias table shares.
//!
//! # The exact pick (the default): Lemire's nearly divisionless rejection
//! D. Lemire, "Fast Random Integer Generation in an Interval", ACM TOMACS 29(1), 2019.
//! Write `2^32 = Q·N + t` (`Q = ⌊2^32/N⌋`, `t = 2^32 mod N`, computed once as
//! `N.wrapping_neg() % N`). A 32-bit draw `r` gives `m = r·N` (64 bits); the draw is
//! *accepted* when the low word `m mod 2^32 ≥ t`, and then the pick is the high word
//! `⌊m / 2^32⌋`; otherwise the next draw of the same stream is tried. Column `c` receives
//! the `r` with `c·2^32 + t ≤ r·N < (c+1)·2^32`, a half-open interval of length
//! `2^32 − t = Q·N`, which holds exactly `Q` multiples of `N`: **every value `c ∈ 0..N`
//! is accepted for exactly `Q` of the `2^32` draws**, so the realized pmf is exactly `1/N`
//! (for independent uniform draws). `t` draws are rejected in all (`t < N` and
//! `t < 2^31`), so a draw is accepted with probability `Q·N/2^32 > 1/2` and a pick takes
//! `1/(1 − t/2^32) < 2` draws on average (`1 + 2.3·10⁻⁴` at `N = 10^6`). The loop also ends
//! deterministically: a stream's draws run through all `2^32` values before any repeats
//! (a full-period LCG under the bijective PCG hash, see [`crate::Rng`]), so at most `t`
//! consecutive draws can be rejected. The division `N.wrapping_neg() % N` is done once per
//! sampler (the GPU does it only on the rare draw with low word `< N`).
//!
//! # The raw pick (what the precision lab measures as "before")
//! [`Uniform::sample_u32`] maps one draw to `⌊r·N / 2^32⌋` without rejection: `t` columns
//! receive `Q + 1` draws and the others `Q`, so each column's weight differs from `1/N` by
//! less than `2^-32` absolute, a relative bias of up to `N·2^-32` (`2.3·10⁻⁴` at
//! `N = 10^6`); none when `N` is a power of two (`t = 0`, where both picks coincide).

use crate::rng::Rng;

/// Picks each of `N` lights with probability exactly `1/N` ([`Uniform::sample`], by
/// Lemire's rejection; see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Uniform {
    n: u32,
    /// `t = 2^32 mod N`: draws whose low word of `r·N` is below it are rejected.
    reject_below: u32,
}

impl Uniform {
    /// Uniform selection over `n ≥ 1` lights.
    pub fn new(n: u32) -> Self {
        debug_assert!(n >= 1);
        Self {
            n,
            reject_below: rejection_threshold(n),
        }
    }

    /// Number of lights `N`.
    pub fn len(&self) -> usize {
        self.n as usize
    }

    /// Always `false`: there is at least one light.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The rejection threshold `t = 2^32 mod N` of the exact pick ([`rejection_threshold`]).
    pub fn rejection_threshold(&self) -> u32 {
        self.reject_below
    }

    /// The exact pick: draws from `rng` until one is accepted ([`Uniform::accept`]) and
    /// returns its value, each of `0..N` with probability exactly `1/N`. Consumes one draw,
    /// plus one per rejected draw (probability `t/2^32 < N·2^-32` each).
    #[inline]
    pub fn sample(&self, rng: &mut Rng) -> u32 {
        let mut m = u64::from(rng.next_u32()) * u64::from(self.n);
        while (m as u32) < self.reject_below {
            m = u64::from(rng.next_u32()) * u64::from(self.n);
        }
        (m >> 32) as u32
    }

    /// One step of the exact pick: `Some(⌊r·N / 2^32⌋)` if the draw `r` is accepted (the
    /// low word of `r·N` is at least `t`), `None` if it is rejected. Each value of `0..N`
    /// is returned for exactly `⌊2^32/N⌋` of the `2^32` draws.
    #[inline]
    pub fn accept(&self, r: u32) -> Option<u32> {
        let m = u64::from(r) * u64::from(self.n);
        ((m as u32) >= self.reject_below).then_some((m >> 32) as u32)
    }

    /// The raw, slightly biased pick `⌊r·N / 2^32⌋` from one draw (multiply-high, no
    /// rejection): `2^32 mod N` values receive `⌊2^32/N⌋ + 1` draws and the others
    /// `⌊2^32/N⌋`, so each probability is off `1/N` by less than `2^-32`. Kept for the
    /// precision lab (the "before" figure) and the one-random alias speed option; the
    /// samplers use [`Uniform::sample`].
    #[inline]
    pub fn sample_u32(&self, r: u32) -> u32 {
        ((u64::from(r) * u64::from(self.n)) >> 32) as u32
    }
}

/// Lemire's rejection threshold `t = 2^32 mod N`, computed in 32 bits as
/// `(2^32 − N) mod N = N.wrapping_neg() % N` (0 when `N` is a power of two: no rejection).
///
/// # Panics
/// If `n` is 0.
#[inline]
pub fn rejection_threshold(n: u32) -> u32 {
    n.wrapping_neg() % n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threshold_is_two_to_the_32_mod_n() {
        for n in [
            1u32,
            2,
            3,
            5,
            1000,
            1 << 20,
            1_000_003,
            (1 << 31) + 1,
            u32::MAX,
        ] {
            assert_eq!(
                u64::from(rejection_threshold(n)),
                (1u64 << 32) % u64::from(n),
                "{n}"
            );
        }
    }

    #[test]
    fn power_of_two_never_rejects_and_equals_the_raw_pick() {
        let u = Uniform::new(1 << 10);
        assert_eq!(u.rejection_threshold(), 0);
        for r in [0, 1, 12_345, u32::MAX] {
            assert_eq!(u.accept(r), Some(u.sample_u32(r)));
        }
    }

    #[test]
    fn rejected_draws_are_skipped_in_stream_order() {
        // N = 2^31 + 1: t = 2^31 − 1, about half of all draws are rejected.
        let u = Uniform::new((1 << 31) + 1);
        let mut rejected_streams = 0;
        for stream in 0..64 {
            let mut draws = Rng::new(9, stream);
            let expected = loop {
                if let Some(v) = u.accept(draws.next_u32()) {
                    break v;
                }
            };
            let mut rng = Rng::new(9, stream);
            assert_eq!(u.sample(&mut rng), expected);
            // The same number of draws was consumed: the next draws agree.
            assert_eq!(rng.next_u32(), draws.next_u32());
            let mut first = Rng::new(9, stream);
            rejected_streams += usize::from(u.accept(first.next_u32()).is_none());
        }
        assert!(rejected_streams > 10, "{rejected_streams}");
    }
}
