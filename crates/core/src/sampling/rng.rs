//! The one random number generator of lightpick, shared bit for bit by the CPU and WGSL.
//!
//! # Algorithm
//! The PCG hash of Jarzynski & Olano, "Hash Functions for GPU Rendering" (JCGT 2020): a
//! 32-bit LCG step `s' = 747796405·s + 2891336453 (mod 2^32)` followed by PCG's RXS-M-XS
//! output permutation. Only 32-bit wrapping multiplies, adds, shifts and xors: WGSL's `u32`
//! does exactly the same arithmetic, so the GPU twin (`rng.wgsl`) reproduces every bit.
//!
//! # Stream layout
//! A generator is keyed by a 64-bit `seed` and a 64-bit `stream` (the sample index for
//! `sample`/`estimate`, `(pass_sample << 32) | pixel` for renderers). The initial state is
//! the hash chain
//! `pcg_hash(seed_lo ^ pcg_hash(seed_hi ^ pcg_hash(stream_lo ^ pcg_hash(stream_hi))))`.
//! Each [`Rng::next_u32`] outputs `pcg_hash(state)` and advances `state` by the LCG step, so
//! draw `k` of a stream depends only on `(seed, stream, k)`: any thread may compute any
//! sample, and CPU and GPU agree regardless of how work is split.

const LCG_MULTIPLIER: u32 = 747_796_405;
const LCG_INCREMENT: u32 = 2_891_336_453;
const PERMUTE_MULTIPLIER: u32 = 277_803_737;

/// The PCG hash: one LCG step then the RXS-M-XS permutation, a bijection on `u32`.
#[inline]
pub fn pcg_hash(input: u32) -> u32 {
    permute(lcg_step(input))
}

#[inline]
fn lcg_step(state: u32) -> u32 {
    state
        .wrapping_mul(LCG_MULTIPLIER)
        .wrapping_add(LCG_INCREMENT)
}

/// `(A, C)` with `lcg_step^k(s) = A·s + C (mod 2^32)`, by squaring (Brown 1994,
/// "Random number generation with arbitrary strides").
fn lcg_power(mut k: u64) -> (u32, u32) {
    let (mut mul, mut add) = (1u32, 0u32);
    let (mut step_mul, mut step_add) = (LCG_MULTIPLIER, LCG_INCREMENT);
    while k > 0 {
        if k & 1 == 1 {
            mul = mul.wrapping_mul(step_mul);
            add = add.wrapping_mul(step_mul).wrapping_add(step_add);
        }
        step_add = step_mul.wrapping_add(1).wrapping_mul(step_add);
        step_mul = step_mul.wrapping_mul(step_mul);
        k >>= 1;
    }
    (mul, add)
}

#[inline]
fn permute(state: u32) -> u32 {
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(PERMUTE_MULTIPLIER);
    (word >> 22) ^ word
}

/// Maps 32 random bits to `[0, 1)` exactly: `r · 2^-32` (every value representable).
#[inline]
pub fn unit_f64(r: u32) -> f64 {
    f64::from(r) * (1.0 / 4_294_967_296.0)
}

/// A counter-keyed PCG stream; see the module docs for the layout the GPU shares.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rng {
    state: u32,
}

impl Rng {
    /// The stream `stream` of generator `seed` (both split into 32-bit halves).
    #[inline]
    pub fn new(seed: u64, stream: u64) -> Self {
        let (seed_lo, seed_hi) = (seed as u32, (seed >> 32) as u32);
        let (stream_lo, stream_hi) = (stream as u32, (stream >> 32) as u32);
        let key = pcg_hash(seed_lo ^ pcg_hash(seed_hi ^ pcg_hash(stream_lo ^ pcg_hash(stream_hi))));
        Self { state: key }
    }

    /// The next 32 random bits: `pcg_hash(state)`, then `state` takes one LCG step.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let out = pcg_hash(self.state);
        self.state = lcg_step(self.state);
        out
    }

    /// Fills `out` with the next `out.len()` draws, exactly those of as many
    /// [`Rng::next_u32`] calls, and leaves the stream after them. Four lanes each step the
    /// LCG by `a^4` (jump-ahead), so the hashes do not wait on one multiply chain.
    pub fn fill(&mut self, out: &mut [u32]) {
        let (mul4, add4) = lcg_power(4);
        let mut lanes = [0u32; 4];
        let mut state = self.state;
        for lane in &mut lanes {
            state = lcg_step(state);
            *lane = state;
        }
        let done = out.len() - out.len() % 4;
        for chunk in out[..done].chunks_exact_mut(4) {
            for (out, lane) in chunk.iter_mut().zip(&mut lanes) {
                *out = permute(*lane);
                *lane = lane.wrapping_mul(mul4).wrapping_add(add4);
            }
        }
        // The lanes ran ahead of `self`: move it past the drawn values, then finish singly.
        self.advance(done as u64);
        for out in &mut out[done..] {
            *out = self.next_u32();
        }
    }

    /// Fills `even` and `odd` (of equal length `m`) with the next `2m` draws, alternately:
    /// draw `2k` into `even[k]`, draw `2k + 1` into `odd[k]`, exactly those of as many
    /// [`Rng::next_u32`] calls, and leaves the stream after them. Sixteen lanes (eight per
    /// parity) each step the LCG by `a^16`, so the hashes are independent and both outputs
    /// are written in order, without shuffles (what a batch of two-draw picks wants: its
    /// column draws in one array, its keep draws in another).
    ///
    /// # Panics
    /// If the slices differ in length.
    #[inline(always)]
    #[allow(
        clippy::inline_always,
        reason = "callers compiled for wider vectors (AVX2) widen its lanes too"
    )]
    pub fn fill_pairs(&mut self, even: &mut [u32], odd: &mut [u32]) {
        assert_eq!(even.len(), odd.len(), "one odd draw per even draw");
        let (mul16, add16) = lcg_power(16);
        let (mut even_lanes, mut odd_lanes) = ([0u32; 8], [0u32; 8]);
        let mut state = self.state;
        for (e, o) in even_lanes.iter_mut().zip(&mut odd_lanes) {
            *e = state;
            state = lcg_step(state);
            *o = state;
            state = lcg_step(state);
        }
        let done = even.len() - even.len() % 8;
        for (e8, o8) in even[..done]
            .chunks_exact_mut(8)
            .zip(odd[..done].chunks_exact_mut(8))
        {
            for (((e, o), el), ol) in e8
                .iter_mut()
                .zip(o8.iter_mut())
                .zip(&mut even_lanes)
                .zip(&mut odd_lanes)
            {
                *e = pcg_hash(*el);
                *o = pcg_hash(*ol);
                *el = el.wrapping_mul(mul16).wrapping_add(add16);
                *ol = ol.wrapping_mul(mul16).wrapping_add(add16);
            }
        }
        self.advance(2 * done as u64);
        for (e, o) in even[done..].iter_mut().zip(&mut odd[done..]) {
            *e = self.next_u32();
            *o = self.next_u32();
        }
    }

    /// Skips `k` draws in `O(log k)` (the LCG's jump-ahead), as if [`Rng::next_u32`] had
    /// been called `k` times.
    pub fn advance(&mut self, k: u64) {
        let (mul, add) = lcg_power(k);
        self.state = self.state.wrapping_mul(mul).wrapping_add(add);
    }

    /// A uniform `f64` in `[0, 1)` from one 32-bit draw ([`unit_f64`]).
    #[inline]
    pub fn next_unit(&mut self) -> f64 {
        unit_f64(self.next_u32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_deterministic_and_distinct() {
        let a: Vec<u32> = (0..4)
            .map({
                let mut r = Rng::new(7, 3);
                move |_| r.next_u32()
            })
            .collect();
        let mut again = Rng::new(7, 3);
        assert!(a.iter().all(|&x| x == again.next_u32()));
        let mut other = Rng::new(7, 4);
        assert_ne!(a[0], other.next_u32());
        let mut high = Rng::new(7, 3 | (1 << 32));
        assert_ne!(a[0], high.next_u32());
    }

    #[test]
    fn hash_is_a_bijection_on_a_sample_window() {
        let mut seen = std::collections::HashSet::new();
        for x in 0..200_000u32 {
            assert!(seen.insert(pcg_hash(x)));
        }
    }

    #[test]
    fn fill_and_advance_follow_the_stream() {
        for len in [0usize, 1, 3, 4, 5, 17, 1000] {
            let mut one = Rng::new(9, len as u64);
            let expected: Vec<u32> = (0..len).map(|_| one.next_u32()).collect();
            let mut batch = Rng::new(9, len as u64);
            let mut got = vec![0u32; len];
            batch.fill(&mut got);
            assert_eq!(got, expected, "len {len}");
            assert_eq!(batch, one, "state after {len}");
            let mut skipped = Rng::new(9, len as u64);
            skipped.advance(len as u64);
            assert_eq!(skipped, one, "advance({len})");
        }
    }

    #[test]
    fn fill_pairs_splits_the_stream_by_parity() {
        for len in [0usize, 1, 7, 8, 9, 17, 1000] {
            let mut one = Rng::new(5, len as u64);
            let expected: Vec<u32> = (0..2 * len).map(|_| one.next_u32()).collect();
            let mut pairs = Rng::new(5, len as u64);
            let (mut even, mut odd) = (vec![0u32; len], vec![0u32; len]);
            pairs.fill_pairs(&mut even, &mut odd);
            let interleaved: Vec<u32> = even.iter().zip(&odd).flat_map(|(&e, &o)| [e, o]).collect();
            assert_eq!(interleaved, expected, "len {len}");
            assert_eq!(pairs, one, "state after {len} pairs");
        }
    }

    #[test]
    fn unit_maps_extremes_inside_half_open_interval() {
        assert_eq!(unit_f64(0), 0.0);
        assert!(unit_f64(u32::MAX) < 1.0);
    }
}
