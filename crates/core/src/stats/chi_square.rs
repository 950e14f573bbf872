//! Pearson's chi-square goodness-of-fit test of observed counts against a pmf.

use statrs::distribution::{ChiSquared, ContinuousCDF as _};

/// The result of [`chi_square`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ChiSquare {
    /// `χ² = Σ (O − E)² / E` over the pooled cells.
    pub chi2: f64,
    /// Degrees of freedom: pooled cells − 1.
    pub dof: usize,
    /// `P(X ≥ χ²)` for `X ~ χ²(dof)`; 1 when `dof = 0`, 0 when a count fell where `E = 0`.
    pub p_value: f64,
}

/// Tests `counts` against `expected_pmf` (same length, summing to 1).
///
/// Cells are pooled in index order until each pooled cell expects at least 5 counts (the
/// usual validity rule for the χ² approximation); a short tail joins the last pooled cell.
/// Cells of probability 0 are left out, and a count in one makes the fit impossible
/// (`χ² = ∞`, `p = 0`).
pub fn chi_square(counts: &[u64], expected_pmf: &[f64]) -> ChiSquare {
    debug_assert_eq!(counts.len(), expected_pmf.len());
    chi_square_cells(counts.iter().copied().zip(expected_pmf.iter().copied()))
}

/// [`chi_square`] over the cells `(count, expected probability)` in index order, walked
/// three times: for counts kept narrower than `u64`, or an expected pmf that is not stored
/// (uniform: `1/N` for every cell), without an `O(N)` copy of either.
pub fn chi_square_cells<I>(cells: I) -> ChiSquare
where
    I: Iterator<Item = (u64, f64)> + Clone,
{
    let total: u64 = cells.clone().map(|(c, _)| c).sum();
    let n = total as f64;
    if cells.clone().any(|(c, p)| p <= 0.0 && c > 0) {
        return ChiSquare {
            chi2: f64::INFINITY,
            dof: cells.count().saturating_sub(1),
            p_value: 0.0,
        };
    }
    // Pool (observed, expected) pairs.
    let mut pooled: Vec<(f64, f64)> = Vec::new();
    let mut open = (0.0, 0.0);
    for (c, p) in cells {
        if p <= 0.0 {
            continue;
        }
        open.0 += c as f64;
        open.1 += p * n;
        if open.1 >= 5.0 {
            pooled.push(open);
            open = (0.0, 0.0);
        }
    }
    if open.1 > 0.0 {
        match pooled.last_mut() {
            Some(last) => {
                last.0 += open.0;
                last.1 += open.1;
            }
            None => pooled.push(open),
        }
    }
    let chi2: f64 = pooled.iter().map(|&(o, e)| (o - e) * (o - e) / e).sum();
    let dof = pooled.len().saturating_sub(1);
    let p_value = if dof == 0 {
        1.0
    } else {
        ChiSquared::new(dof as f64).map_or(f64::NAN, |d| d.sf(chi2))
    };
    ChiSquare { chi2, dof, p_value }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perfect_fit_has_p_value_one() {
        let r = chi_square(&[20, 50, 200], &[2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]);
        assert!(r.chi2 < 1e-20);
        assert_eq!(r.dof, 2);
        assert!(r.p_value > 0.999_999);
    }

    #[test]
    fn gross_misfit_has_tiny_p_value() {
        let r = chi_square(&[500, 500], &[0.9, 0.1]);
        assert!(r.p_value < 1e-100, "{r:?}");
    }

    #[test]
    fn known_value_matches_table() {
        // χ² = (60−50)²/50 + (40−50)²/50 = 4 with 1 dof: p = 0.0455 (standard tables).
        let r = chi_square(&[60, 40], &[0.5, 0.5]);
        assert!((r.chi2 - 4.0).abs() < 1e-12);
        assert!((r.p_value - 0.045_500_263_9).abs() < 1e-9, "{}", r.p_value);
    }

    #[test]
    fn small_cells_are_pooled() {
        // Expected 2, 2, 2, 2, 92 for 100 samples: cells 0..=2 pool into one expecting 6,
        // cells 3..=4 into one expecting 94, so two cells and one degree of freedom.
        let pmf = [0.02, 0.02, 0.02, 0.02, 0.92];
        let r = chi_square(&[1, 3, 2, 2, 92], &pmf);
        assert_eq!(r.dof, 1);
        assert!(r.chi2 < 1e-12, "{r:?}");
    }

    #[test]
    fn cells_give_the_slices_result() {
        let (counts, pmf) = ([1u32, 3, 2, 2, 92], [0.02, 0.02, 0.02, 0.02, 0.92]);
        let wide: Vec<u64> = counts.iter().map(|&c| u64::from(c)).collect();
        let cells = counts.iter().map(|&c| u64::from(c)).zip(pmf);
        assert_eq!(chi_square_cells(cells), chi_square(&wide, &pmf));
    }

    #[test]
    fn count_in_an_impossible_cell_rejects() {
        let r = chi_square(&[5, 1], &[1.0, 0.0]);
        assert_eq!(r.p_value, 0.0);
        assert!(r.chi2.is_infinite());
    }
}
