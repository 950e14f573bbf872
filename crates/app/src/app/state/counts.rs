//! Picks per light for the sampling histograms, 4 bytes per light until a count needs more.

/// How many picks each light received: `u32` cells (4 bytes per light, not 8) until one
/// would pass `u32::MAX` (billions of picks of one light), then every cell is widened to
/// `u64` once, so counts never saturate whatever the run's length.
#[derive(Clone, Debug, PartialEq)]
pub enum PickCounts {
    /// Every count below `u32::MAX`.
    Narrow(Vec<u32>),
    /// Some count reached `u32::MAX`.
    Wide(Vec<u64>),
}

impl Default for PickCounts {
    fn default() -> Self {
        PickCounts::Narrow(Vec::new())
    }
}

impl PickCounts {
    /// `n` zero counts.
    pub fn zeros(n: usize) -> Self {
        PickCounts::Narrow(vec![0; n])
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        match self {
            PickCounts::Narrow(c) => c.len(),
            PickCounts::Wide(c) => c.len(),
        }
    }

    /// Whether there are no lights.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Light `i`'s count.
    pub fn get(&self, i: usize) -> u64 {
        match self {
            PickCounts::Narrow(c) => u64::from(c[i]),
            PickCounts::Wide(c) => c[i],
        }
    }

    /// Counts one more pick of light `i`.
    pub fn add(&mut self, i: usize) {
        match self {
            PickCounts::Narrow(c) if c[i] < u32::MAX - 1 => c[i] += 1,
            PickCounts::Narrow(c) => {
                let mut wide: Vec<u64> = c.iter().map(|&k| u64::from(k)).collect();
                wide[i] += 1;
                *self = PickCounts::Wide(wide);
            }
            PickCounts::Wide(c) => c[i] += 1,
        }
    }

    /// Every count, in light order.
    pub fn iter(&self) -> impl Iterator<Item = u64> + Clone + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// Heap bytes held, by capacity.
    pub fn heap_bytes(&self) -> usize {
        match self {
            PickCounts::Narrow(c) => c.capacity() * std::mem::size_of::<u32>(),
            PickCounts::Wide(c) => c.capacity() * std::mem::size_of::<u64>(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_reaching_u32_max_widens_every_cell() {
        let mut counts = PickCounts::Narrow(vec![u32::MAX - 2, 7]);
        counts.add(0);
        assert!(matches!(counts, PickCounts::Narrow(_)));
        assert_eq!(counts.heap_bytes(), 8);
        counts.add(0);
        counts.add(0);
        assert!(matches!(counts, PickCounts::Wide(_)));
        assert_eq!(
            counts.iter().collect::<Vec<_>>(),
            [u64::from(u32::MAX) + 1, 7]
        );
        assert_eq!(counts.heap_bytes(), 16);
    }
}
