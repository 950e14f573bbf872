//! The sampling panel's running histograms and chi-square tests of uniform and alias
//! picks, and "draw one sample" replayed on the diagram.

use std::sync::Arc;

use lightpick_core::{AliasTable, ChiSquare, Construction, Rng, Uniform, chi_square_cells};

use super::AppState;
use super::counts::PickCounts;

/// One "draw one sample" step, for the diagram to replay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OneDraw {
    /// First 32-bit random: picks the column by multiply-high.
    pub r1: u32,
    /// Second 32-bit random: compared with the column's threshold.
    pub r2: u32,
    /// The column `⌊r1·N/2^32⌋` (0-based).
    pub column: usize,
    /// `U1 = r1/2^32`.
    pub u1: f64,
    /// `U2 = r2/2^32`.
    pub u2: f64,
    /// The column's threshold.
    pub threshold: f64,
    /// Whether `U2 < threshold` (keep the column's own light).
    pub kept: bool,
    /// The light returned (0-based).
    pub light: u32,
}

/// Running histograms of uniform and alias picks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SamplingRun {
    /// Generation of the table the counts belong to.
    pub generation: u64,
    /// Lights per chi-square cell: 1 up to [`MAX_CHI_CELLS`] lights, else the lights are
    /// grouped (consecutive, fixed before any pick) into at most that many cells.
    pub per_cell: usize,
    /// Picks per cell by uniform selection.
    pub uniform_counts: PickCounts,
    /// Picks per cell by the alias table.
    pub alias_counts: PickCounts,
    /// Each cell's probability under the alias table, `Σ p_i` over its lights (the table's
    /// pmf itself when a cell is one light): the table's [`super::HistogramPmf`], shared.
    pub alias_cell_pmf: Arc<[f64]>,
    /// Picks so far (each scheme).
    pub picks: u64,
    /// Chi-square of the uniform counts against `1/N`.
    pub uniform_chi: Option<ChiSquare>,
    /// Chi-square of the alias counts against the pmf.
    pub alias_chi: Option<ChiSquare>,
    /// The last "draw one sample".
    pub last_draw: Option<OneDraw>,
    /// How many single draws were made (their stream index).
    pub draws: u64,
    /// Lights per histogram bar (1 for small tables).
    pub per_bin: usize,
    /// Uniform picks per bar.
    pub uniform_bins: Vec<u64>,
    /// Alias picks per bar.
    pub alias_bins: Vec<u64>,
    /// Expected alias frequency per bar (`Σ p_i` over its lights), shared with the table's
    /// [`super::HistogramPmf`].
    pub expected_bins: Arc<[f64]>,
    /// Expected uniform frequency per bar (its share of the lights).
    pub flat_bins: Vec<f64>,
}

impl SamplingRun {
    /// How many of the `n` lights chi-square cell `cell` holds: lights `c·k .. min((c + 1)·k,
    /// N)` with `k` = [`SamplingRun::per_cell`] (one light each up to the cell limit).
    pub fn cell_lights(&self, cell: usize, n: usize) -> usize {
        let per = self.per_cell.max(1);
        per.min(n.saturating_sub(cell * per))
    }

    /// Each cell's probability under uniform picking: its share of the `n` lights.
    pub fn uniform_cell_pmf(&self, n: usize) -> impl Iterator<Item = f64> + Clone + '_ {
        (0..self.uniform_counts.len()).map(move |c| self.cell_lights(c, n) as f64 / n as f64)
    }
}

/// The alias-table diagram shows at most this many columns (a window of a larger table).
pub const DIAGRAM_MAX_COLUMNS: usize = 64;

/// Histograms group lights into at most this many bars.
pub const MAX_BARS: usize = 48;

/// The chi-square tests count picks per light up to this many lights (`2^16`, the
/// classroom's exact tables), and per group of consecutive lights above, in at most this
/// many cells: the cells are fixed before sampling, so the test stays Pearson's, and the
/// counts cost 8 bytes per cell instead of per light.
pub const MAX_CHI_CELLS: usize = 1 << 16;

/// What the histograms expect of a table: the probability of each bar's lights and of each
/// chi-square cell's, computed once per table (beside the tree's refit when the powers
/// change) and shared by every restart of the histograms.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HistogramPmf {
    /// Lights per bar ([`MAX_BARS`] bars at most).
    pub per_bar: usize,
    /// Each bar's `Σ p_i`.
    pub bars: Arc<[f64]>,
    /// Lights per chi-square cell ([`MAX_CHI_CELLS`] cells at most).
    pub per_cell: usize,
    /// Each cell's `Σ p_i` (the pmf itself when a cell is one light).
    pub cells: Arc<[f64]>,
}

impl HistogramPmf {
    /// The bars' and cells' probabilities under `table`: its stored pmf summed group by
    /// group for the exact construction, the groups' exact masses for an integer-built one
    /// ([`AliasTable::packed_group_pmf`], one pass each and no pmf of `N`).
    pub fn of(table: &AliasTable) -> Self {
        let n = table.len();
        let (per_bar, per_cell) = (
            n.div_ceil(MAX_BARS).max(1),
            n.div_ceil(MAX_CHI_CELLS).max(1),
        );
        let groups = |per: usize| -> Arc<[f64]> {
            if table.construction() == Construction::Integer {
                table.packed_group_pmf(per).into()
            } else if per == 1 {
                table.pmf_slice().into()
            } else {
                table
                    .pmf_slice()
                    .chunks(per)
                    .map(|c| c.iter().sum())
                    .collect()
            }
        };
        Self {
            per_bar,
            bars: groups(per_bar),
            per_cell,
            cells: groups(per_cell),
        }
    }
}

impl AppState {
    /// Clears the histograms for the current table.
    pub fn restart_sampling(&mut self) {
        let n = self.built.len();
        let groups = &self.built.histogram_pmf;
        let (per_bin, per_cell) = (groups.per_bar, groups.per_cell);
        let (expected_bins, alias_cell_pmf) = (Arc::clone(&groups.bars), Arc::clone(&groups.cells));
        let (bars, cells) = (expected_bins.len(), alias_cell_pmf.len());
        let flat_bins = (0..bars)
            .map(|b| (((b + 1) * per_bin).min(n) - b * per_bin) as f64 / n as f64)
            .collect();
        self.sampling = SamplingRun {
            generation: self.built.generation,
            per_cell,
            uniform_counts: PickCounts::zeros(cells),
            alias_counts: PickCounts::zeros(cells),
            alias_cell_pmf,
            per_bin,
            uniform_bins: vec![0; bars],
            alias_bins: vec![0; bars],
            expected_bins,
            flat_bins,
            ..SamplingRun::default()
        };
    }

    /// Adds `count` picks of each scheme to the histograms (streams continue where the last
    /// call stopped, so the counts are reproducible from the seed).
    pub fn sample_picks(&mut self, count: u32) {
        if self.sampling.generation != self.built.generation {
            self.restart_sampling();
        }
        let built = Arc::clone(&self.built);
        let n = built.len() as u32;
        let uniform = Uniform::new(n);
        let seed = self.settings.seed;
        let start = self.sampling.picks;
        for k in start..start + u64::from(count) {
            // The exact picks of `Sampler::pick_light` (rejection keeps columns uniform).
            let mut rng = Rng::new(seed, k);
            let u = uniform.sample(&mut rng) as usize;
            self.sampling.uniform_counts.add(u / self.sampling.per_cell);
            self.sampling.uniform_bins[u / self.sampling.per_bin] += 1;
            let mut rng = Rng::new(seed ^ 0xA11A5, k);
            let a = built.table.sample(&mut rng) as usize;
            self.sampling.alias_counts.add(a / self.sampling.per_cell);
            self.sampling.alias_bins[a / self.sampling.per_bin] += 1;
        }
        self.sampling.picks += u64::from(count);
        // Chi-square is O(N): every frame for small tables, every 16th frame for large ones.
        if n <= 10_000 || self.frame.is_multiple_of(16) || count == 0 {
            self.update_chi_square();
        }
    }

    /// Recomputes both chi-square tests from the counts.
    pub fn update_chi_square(&mut self) {
        if self.sampling.picks == 0 {
            self.sampling.uniform_chi = None;
            self.sampling.alias_chi = None;
            return;
        }
        let n = self.built.len();
        let sampling = &self.sampling;
        let uniform = chi_square_cells(
            sampling
                .uniform_counts
                .iter()
                .zip(sampling.uniform_cell_pmf(n)),
        );
        let alias = chi_square_cells(
            sampling
                .alias_counts
                .iter()
                .zip(sampling.alias_cell_pmf.iter().copied()),
        );
        self.sampling.uniform_chi = Some(uniform);
        self.sampling.alias_chi = Some(alias);
    }

    /// Draws one sample with two fresh randoms and records how the table answered.
    pub fn draw_one(&mut self) {
        let mut rng = Rng::new(self.settings.seed ^ 0xD12A_0001, self.sampling.draws);
        self.sampling.draws += 1;
        let table = &self.built.table;
        // U1 is the accepted draw of the exact column pick (a draw in the rare band that
        // would make columns unequal is redrawn); U2 is the next draw.
        let columns = Uniform::new(table.len() as u32);
        let (r1, column) = loop {
            let r = rng.next_u32();
            if let Some(c) = columns.accept(r) {
                break (r, c as usize);
            }
        };
        let r2 = rng.next_u32();
        let light = table.resolve(column, r2);
        let draw = OneDraw {
            r1,
            r2,
            column,
            u1: lightpick_core::unit_f64(r1),
            u2: lightpick_core::unit_f64(r2),
            threshold: table.threshold(column),
            kept: light as usize == column,
            light,
        };
        // Large tables show a window of columns: move it to the picked one.
        if table.len() > DIAGRAM_MAX_COLUMNS {
            self.diagram_offset = column.saturating_sub(DIAGRAM_MAX_COLUMNS / 2);
        }
        self.sampling.last_draw = Some(draw);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::scene_io;
    use crate::app::state::Settings;

    /// The picks of `sample_picks` recounted per light from the same streams.
    fn picks_per_light(state: &AppState, count: u64) -> (Vec<u64>, Vec<u64>) {
        let n = state.built.len();
        let uniform = Uniform::new(n as u32);
        let (mut u, mut a) = (vec![0u64; n], vec![0u64; n]);
        for k in 0..count {
            u[uniform.sample(&mut Rng::new(state.settings.seed, k)) as usize] += 1;
            let mut rng = Rng::new(state.settings.seed ^ 0xA11A5, k);
            a[state.built.table.sample(&mut rng) as usize] += 1;
        }
        (u, a)
    }

    #[test]
    fn chi_square_cells_are_lights_up_to_the_limit_and_fixed_groups_above() {
        // Small: one cell per light, the pmf itself, the counts per light.
        let mut state = AppState::new(scene_io::worked_example_scene(), Settings::default());
        state.sample_picks(2000);
        assert_eq!(state.sampling.per_cell, 1);
        assert_eq!(
            &*state.sampling.alias_cell_pmf,
            state.built.table.pmf_slice()
        );
        let (u, a) = picks_per_light(&state, 2000);
        assert_eq!(state.sampling.uniform_counts.iter().collect::<Vec<_>>(), u);
        assert_eq!(state.sampling.alias_counts.iter().collect::<Vec<_>>(), a);
        // Above 2^16 lights: groups of ⌈N / 2^16⌉ consecutive lights, each cell's count the
        // sum of its lights' and its probability the sum of theirs.
        let n = 3 * MAX_CHI_CELLS + 5;
        state.generate(n);
        while state.is_building() {
            std::thread::sleep(std::time::Duration::from_millis(5));
            state.poll_build();
        }
        assert_eq!(state.built.len(), n);
        state.sample_picks(50_000);
        let per_cell = n.div_ceil(MAX_CHI_CELLS);
        assert_eq!(state.sampling.per_cell, per_cell);
        let cells = n.div_ceil(per_cell);
        assert!(cells <= MAX_CHI_CELLS);
        assert_eq!(state.sampling.uniform_counts.len(), cells);
        let (u, a) = picks_per_light(&state, 50_000);
        let grouped = |v: &[u64]| v.chunks(per_cell).map(|c| c.iter().sum()).collect();
        let grouped_u: Vec<u64> = grouped(&u);
        let grouped_a: Vec<u64> = grouped(&a);
        assert_eq!(
            state.sampling.uniform_counts.iter().collect::<Vec<_>>(),
            grouped_u
        );
        assert_eq!(
            state.sampling.alias_counts.iter().collect::<Vec<_>>(),
            grouped_a
        );
        // The integer-built table's cells: its lights' exact masses over `N·2^32`.
        let masses = state.built.table.packed_masses();
        let denom = n as f64 * 4_294_967_296.0;
        for (c, &p) in state.sampling.alias_cell_pmf.iter().enumerate() {
            let lights = &masses[c * per_cell..((c + 1) * per_cell).min(n)];
            assert_eq!(p, lights.iter().sum::<u64>() as f64 / denom, "cell {c}");
        }
        // The tests run over the cells (dof below the cell count) and the samplers are right:
        // with these fixed seeds neither p-value is below 10^-3.
        for chi in [state.sampling.uniform_chi, state.sampling.alias_chi] {
            let chi = chi.expect("computed");
            assert!(chi.dof < cells && chi.dof > 100, "{chi:?}");
            assert!(chi.p_value > 1e-3, "{chi:?}");
        }
    }
}
