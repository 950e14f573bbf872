//! The one-thread construction the chunked, parallel one must equal bit for bit: the
//! masses by the quantization's rule written plainly, one pair of global index lists, and
//! one sweep. Tests only.

use super::quantize::IdealMass;
use super::units::{CAPACITY, CHUNK, REACH_FLAG, full};
use crate::alias::packed::packed_word;

/// The masses (with [`REACH_FLAG`]) by the quantization's rule, written plainly: per chunk,
/// the cumulative rounding of the fixed-point ideal masses from the chunk's anchor, then
/// the difference to the next anchor's rounding settled one unit per light from the
/// chunk's first light on (what is left goes one unit at a time to the light nearest to
/// taking it).
pub(super) fn masses(powers: &[f64]) -> Vec<u64> {
    let (ideal, anchors) = IdealMass::with_anchors(powers);
    let mut masses = Vec::with_capacity(powers.len());
    for (c, chunk) in powers.chunks(CHUNK).enumerate() {
        let fixed: Vec<u64> = chunk.iter().map(|&p| ideal.fixed(p)).collect();
        let mut sum = anchors[c];
        let mut own: Vec<u64> = fixed
            .iter()
            .map(|&x| {
                let before = ideal.rounded(sum);
                sum += x;
                ideal.rounded(sum) - before
            })
            .collect();
        let mut d = ideal.rounded(anchors[c + 1]) as i64 - ideal.rounded(sum) as i64;
        for (m, &p) in own.iter_mut().zip(chunk) {
            if d > 0 && ideal.gap(p, *m) > 0.0 {
                *m += 1;
                d -= 1;
            } else if d < 0 && ideal.gap(p, *m) < 0.0 {
                *m -= 1;
                d += 1;
            }
        }
        while d != 0 {
            let gaps = (0..own.len()).map(|i| (ideal.gap(chunk[i], own[i]), i));
            let i = if d > 0 {
                gaps.max_by(|a, b| a.0.total_cmp(&b.0))
            } else {
                gaps.filter(|&(_, i)| own[i] > 0)
                    .min_by(|a, b| a.0.total_cmp(&b.0))
            }
            .expect("a light to take the unit")
            .1;
            own[i] = own[i].saturating_add_signed(d.signum());
            d -= d.signum();
        }
        masses.extend(
            own.iter()
                .zip(chunk)
                .map(|(&m, &p)| m | if m == 0 && p > 0.0 { REACH_FLAG } else { 0 }),
        );
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
            table[l] = packed_word((mass(l) | masses[l] >> 63) as u32, h as u32);
            w = w + mass(l) - CAPACITY;
            s += 1;
        } else {
            let next = large[t + 1];
            table[h] = packed_word(w as u32, next as u32);
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
