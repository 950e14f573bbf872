//! The one-pass, one-thread construction the chunked one must equal bit for bit: the
//! masses of a single cumulative rounding over all lights, one pair of global index lists,
//! and one sweep. Tests only.

use super::quantize::{IdealMass, settle_remainder, split_ideal};
use super::{CAPACITY, REACH_FLAG, full, word};

/// The masses (with [`REACH_FLAG`]) of one sequential pass with the same `k`.
pub(super) fn masses(powers: &[f64]) -> Vec<u64> {
    let ideal = IdealMass::of_powers(powers);
    let mut fraction_sum = 0u64;
    let mut rounded_before = 0u64;
    let mut mass_sum = 0u64;
    let mut masses: Vec<u64> = powers
        .iter()
        .map(|&p| {
            let (whole, fraction) = split_ideal(ideal.of(p));
            fraction_sum += fraction;
            let rounded = (fraction_sum + (CAPACITY >> 1)) >> 32;
            let m = whole + rounded - rounded_before;
            rounded_before = rounded;
            mass_sum += m;
            m | if m == 0 && p > 0.0 { REACH_FLAG } else { 0 }
        })
        .collect();
    let wanted = powers.len() as u64 * CAPACITY;
    if mass_sum != wanted {
        settle_remainder(powers, ideal, &mut masses, wanted as i64 - mass_sum as i64);
    }
    masses
}

/// The packed table of `masses` by one sequential sweep over global lists (the small
/// indices ascending, then the large ones ascending).
pub(super) fn sweep(masses: &[u64]) -> Vec<u64> {
    let n = masses.len();
    let mass = |i: usize| masses[i] & !REACH_FLAG;
    let small: Vec<usize> = (0..n).filter(|&i| mass(i) < CAPACITY).collect();
    let large: Vec<usize> = (0..n).filter(|&i| mass(i) >= CAPACITY).collect();
    let mut table = vec![0u64; n];
    if n == 1 {
        table[0] = full(0);
        return table;
    }
    let (mut s, mut t) = (0, 0);
    let mut h = large[0];
    let mut w = mass(h);
    loop {
        if w >= CAPACITY {
            let Some(&l) = small.get(s) else { break };
            table[l] = word((mass(l) | masses[l] >> 63) as u32, h as u32);
            w = w + mass(l) - CAPACITY;
            s += 1;
        } else {
            let next = large[t + 1];
            table[h] = word(w as u32, next as u32);
            w = mass(next) + w - CAPACITY;
            h = next;
            t += 1;
        }
    }
    assert_eq!(w, CAPACITY, "the sweep ends with a full column");
    for &j in &large[t..] {
        table[j] = full(j);
    }
    table
}
