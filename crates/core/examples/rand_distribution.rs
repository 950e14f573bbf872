//! The alias table as a `rand` distribution (`cargo run -p lightpick-core --features rand
//! --example rand_distribution`): draw light indices from any `rand` generator and compare
//! the frequencies with the pmf the table realizes.

use lightpick_core::{AliasTable, LightPowers};
use rand::SeedableRng as _;
use rand::distr::Distribution as _;

fn main() -> Result<(), lightpick_core::PowersError> {
    // The worked example: powers 2, 5, 20.
    let table = AliasTable::build(&LightPowers::new(vec![2.0, 5.0, 20.0])?);
    let mut rng = rand::rngs::StdRng::seed_from_u64(2024);
    let draws = 270_000;
    let mut counts = [0u32; 3];
    for light in (&table).sample_iter(&mut rng).take(draws) {
        counts[light] += 1;
    }
    let pmf = table.implied_pmf_packed();
    for (i, (&count, p)) in counts.iter().zip(pmf).enumerate() {
        println!(
            "light {i}: {:.4} of the draws, pmf {p:.4}",
            f64::from(count) / draws as f64
        );
    }
    Ok(())
}
