//! What the Precision panel measures: the precision lab's figures
//! (`lightpick_core::precision`) for the current powers, exact counts over the whole table,
//! computed on a background thread in the app and inline in tests.

use lightpick_core::LightPowers;
use lightpick_core::precision::{
    ColumnPickStats, PrecisionReport, f32_column_pick, multiply_high_column_pick,
};

/// The figures of one scene generation.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionMeasurement {
    /// The scene generation measured.
    pub generation: u64,
    /// Questions 1, 2 and 4.
    pub report: PrecisionReport,
    /// Question 3 with `f32(u)·N` (24-bit `u`), `None` when `N` does not fit a `u32`.
    pub f32_pick: Option<ColumnPickStats>,
    /// Question 3 with multiply-high `⌊r·N/2^32⌋`.
    pub multiply_high: Option<ColumnPickStats>,
}

/// The panel's measurement: the latest result and the one being computed.
pub type PrecisionRun = crate::app::background::Background<PrecisionMeasurement>;

impl crate::app::background::OfGeneration for PrecisionMeasurement {
    fn generation(&self) -> u64 {
        self.generation
    }
}

/// Every figure of the panel for `powers`.
pub fn measure(generation: u64, powers: &LightPowers) -> PrecisionMeasurement {
    let report = PrecisionReport::measure(powers, None);
    let n = u32::try_from(powers.len()).ok();
    PrecisionMeasurement {
        generation,
        report,
        f32_pick: n.map(f32_column_pick),
        multiply_high: n.map(multiply_high_column_pick),
    }
}
