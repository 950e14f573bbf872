//! lightpick-core in the `rand` ecosystem (cargo feature `rand`).
//!
//! * The samplers are [`rand::distr::Distribution<usize>`]: [`AliasTable`], [`CdfTable`],
//!   [`Uniform`] and [`Sampler`] draw a light index from **any** [`rand::Rng`], with the
//!   same arithmetic as their own `sample` methods: Lemire's exact column pick
//!   `⌊r·N/2^32⌋` (a draw whose low word `r·N mod 2^32` is below `2^32 mod N` is rejected
//!   and redrawn), then the alias table's keep test `r₂ < T_c` on the next 32 bits. So the
//!   realized pmf is exactly the one documented for each (for the alias table,
//!   [`AliasTable::implied_pmf_packed`]), whatever generator feeds it.
//! * The crate's own counter-based generator [`crate::Rng`] (bit for bit the WGSL one) is a
//!   [`rand::Rng`] too, so `rand`'s distributions and adaptors run on it; fed to a sampler it
//!   gives exactly the picks of the sampler's own `sample(&mut Rng)`.
//!
//! Without the feature the crate does not depend on `rand` at all. In method syntax a
//! sampler's own `sample(&mut lightpick_core::Rng)` comes first: call the distribution as
//! `Distribution::<usize>::sample(&table, &mut rng)` or iterate `(&table).sample_iter(rng)`.
//!
//! ```
//! use rand::SeedableRng as _;
//! use rand::distr::Distribution;
//! use lightpick_core::{AliasTable, LightPowers, Rng};
//!
//! let table = AliasTable::build(&LightPowers::new(vec![2.0, 5.0, 20.0])?);
//! // Any rand generator…
//! let mut counts = [0u32; 3];
//! let rng = rand::rngs::SmallRng::seed_from_u64(7);
//! for light in (&table).sample_iter(rng).take(27_000) {
//!     counts[light] += 1;
//! }
//! assert!(counts[2] > counts[1] && counts[1] > counts[0]);
//! // …or the crate's own, giving the picks of `AliasTable::sample` exactly.
//! let (mut a, mut b) = (Rng::new(1, 0), Rng::new(1, 0));
//! for _ in 0..1000 {
//!     let ours = table.sample(&mut a) as usize;
//!     assert_eq!(Distribution::<usize>::sample(&table, &mut b), ours);
//! }
//! # Ok::<(), lightpick_core::PowersError>(())
//! ```

use core::convert::Infallible;

use rand::distr::Distribution;
use rand::rand_core::{TryRng, utils};

use crate::alias::AliasTable;
use crate::cdf::CdfTable;
use crate::sampler::Sampler;
use crate::uniform::Uniform;

/// Lemire's exact pick of `0..n` from `rng`: `⌊r·n/2^32⌋` of the first draw whose low word
/// `r·n mod 2^32` is at least `reject_below = 2^32 mod n` (each value then has probability
/// exactly `1/n`).
#[inline]
fn exact_pick<R: rand::Rng + ?Sized>(n: u32, reject_below: u32, rng: &mut R) -> u32 {
    loop {
        let m = u64::from(rng.next_u32()) * u64::from(n);
        if (m as u32) >= reject_below {
            return (m >> 32) as u32;
        }
    }
}

impl Distribution<usize> for Uniform {
    /// Each of `0..N` with probability exactly `1/N` ([`Uniform::sample`]'s arithmetic).
    #[inline]
    fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> usize {
        exact_pick(self.len() as u32, self.rejection_threshold(), rng) as usize
    }
}

impl Distribution<usize> for AliasTable {
    /// Light `i` with probability exactly [`AliasTable::implied_pmf_packed`]`[i]`: the exact
    /// column pick, then the keep test on the next 32 bits ([`AliasTable::sample`]'s
    /// arithmetic).
    #[inline]
    fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> usize {
        let column = exact_pick(self.len() as u32, self.rejection_threshold(), rng);
        self.resolve(column as usize, rng.next_u32()) as usize
    }
}

impl Distribution<usize> for CdfTable {
    /// The light whose CDF interval holds `u = r·2^-32` ([`CdfTable::sample_u32`]).
    #[inline]
    fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> usize {
        self.sample_u32(rng.next_u32()) as usize
    }
}

impl Distribution<usize> for Sampler {
    /// The pick of the scheme this sampler implements ([`Sampler::pick_light`]'s arithmetic).
    #[inline]
    fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> usize {
        match self {
            Sampler::Uniform(u) => Distribution::<usize>::sample(u, rng),
            Sampler::Alias(table) => Distribution::<usize>::sample(table.as_ref(), rng),
            Sampler::AliasOneRandom(table) => table.sample_one_random(rng.next_u32()) as usize,
            Sampler::Cdf(cdf) => Distribution::<usize>::sample(cdf, rng),
        }
    }
}

impl TryRng for crate::rng::Rng {
    type Error = Infallible;

    /// [`crate::Rng::next_u32`].
    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        Ok(crate::rng::Rng::next_u32(self))
    }

    /// Two draws, the first in the low word.
    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        utils::next_u64_via_u32(self)
    }

    /// Draws in order, each as four little-endian bytes (the last one cut).
    #[inline]
    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        utils::fill_bytes_via_next_word(dst, || self.try_next_u32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{LightPowers, Rng, Scheme};

    /// The same picks as each sampler's own `pick_light` from the same stream: the
    /// Distribution impls add no arithmetic of their own.
    #[test]
    fn every_sampler_picks_as_it_does_with_its_own_generator() {
        // 7 lights: N not a power of two, so Lemire's rejection is exercised.
        let powers = LightPowers::new(vec![0.0, 1.0, 2.0, 5.0, 20.0, 0.5, 3.0]).unwrap();
        for scheme in [
            Scheme::Uniform,
            Scheme::Alias,
            Scheme::AliasOneRandom,
            Scheme::Cdf,
        ] {
            let sampler = Sampler::build(scheme, &powers);
            let (mut ours, mut theirs) = (Rng::new(3, 9), Rng::new(3, 9));
            for k in 0..20_000 {
                let expected = sampler.pick_light(&mut ours) as usize;
                let got = Distribution::<usize>::sample(&sampler, &mut theirs);
                assert_eq!(got, expected, "{scheme:?}, pick {k}");
            }
            // Both streams consumed the same draws.
            assert_eq!(ours, theirs, "{scheme:?}");
        }
    }

    #[test]
    fn the_crates_generator_is_a_rand_generator() {
        let mut a = Rng::new(5, 1);
        let mut b = a.clone();
        let x = rand::Rng::next_u64(&mut a);
        let (lo, hi) = (b.next_u32(), b.next_u32());
        assert_eq!(x, u64::from(lo) | (u64::from(hi) << 32));
        let mut bytes = [0u8; 6];
        rand::Rng::fill_bytes(&mut a, &mut bytes);
        let (w1, w2) = (b.next_u32().to_le_bytes(), b.next_u32().to_le_bytes());
        assert_eq!(bytes, [w1[0], w1[1], w1[2], w1[3], w2[0], w2[1]]);
    }
}
