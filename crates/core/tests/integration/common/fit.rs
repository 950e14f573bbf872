//! Goodness of fit of pick counts against the probabilities the sampler claims.

/// Asserts that `counts` (picks per light out of `draws`) fit the pdf `pdf(i)`: a light of
/// pdf 0 is never picked, and `χ² < dof + 5·√(2·dof)` over the others (beyond it is a > 5σ
/// event).
pub fn assert_picks_fit(counts: &[u64], draws: u64, pdf: impl Fn(usize) -> f64) {
    let (mut chi2, mut dof) = (0.0f64, -1.0f64);
    for (i, &c) in counts.iter().enumerate() {
        let e = pdf(i) * draws as f64;
        if e > 0.0 {
            chi2 += (c as f64 - e).powi(2) / e;
            dof += 1.0;
        } else {
            assert_eq!(c, 0, "light {i} has pdf 0 but was picked");
        }
    }
    assert!(
        chi2 < dof + 5.0 * (2.0 * dof).sqrt(),
        "χ² = {chi2}, dof = {dof}"
    );
}
