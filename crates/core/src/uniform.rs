//! Uniform light selection: the unbiased, power-blind baseline.

/// Picks each of `N` lights with probability `1/N`, by the same multiply-high column pick
/// as the alias table: `⌊r·N / 2^32⌋`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Uniform {
    n: u32,
}

impl Uniform {
    /// Uniform selection over `n ≥ 1` lights.
    pub fn new(n: u32) -> Self {
        debug_assert!(n >= 1);
        Self { n }
    }

    /// Number of lights `N`.
    pub fn len(&self) -> usize {
        self.n as usize
    }

    /// Always `false`: there is at least one light.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The light `⌊r·N / 2^32⌋`.
    #[inline]
    pub fn sample_u32(&self, r: u32) -> u32 {
        ((u64::from(r) * u64::from(self.n)) >> 32) as u32
    }
}
