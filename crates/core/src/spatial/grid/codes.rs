//! A map's cell values as 8-bit codes on a logarithmic scale below the map's largest value
//! `s` ([`super`]'s docs, "Storage"): code `c > 0` stands for `s·2^((c − 255)/8)`, code 0 for
//! nothing; a value takes the nearest code, read from its ratio's bits.

use super::GRID_CELLS;
use crate::avx2::avx2_dispatch;

/// `2^(−r/8)` for `r = 0..8`: the fractional octave of a code.
const EIGHTH_OCTAVES: [f64; 8] = [
    1.0,
    0.917_004_043_204_671_2,
    0.840_896_415_253_714_5,
    0.771_105_412_703_970_4,
    std::f64::consts::FRAC_1_SQRT_2,
    0.648_419_777_325_504_8,
    0.594_603_557_501_360_5,
    0.545_253_866_332_628_8,
];

/// [`decode`] of every code, computed once (at compile time).
const DECODED: [f64; 256] = {
    let mut table = [0.0; 256];
    let mut code = 1;
    while code < 256 {
        let below = 255 - code;
        // 2^-(below / 8), exactly, from its exponent bits.
        let octaves = f64::from_bits(((1023 - below / 8) as u64) << 52);
        table[code] = EIGHTH_OCTAVES[below % 8] * octaves;
        code += 1;
    }
    table
};

/// The value code `code` stands for, as a fraction of the map's largest value:
/// `2^((code − 255)/8)`, 0 for code 0.
#[inline]
pub fn decode(code: u8) -> f64 {
    DECODED[code as usize]
}

/// `2^((2k − 1)/16)` for `k = 1..=8`, each rounded up to the next `f64`: where the
/// rounding of `8·log2(m)` (`m ∈ [1, 2)`) reaches `k` (a test checks them in integers).
const HALF_EIGHTH_OCTAVES: [f64; 8] = [
    1.044_273_782_427_414,
    1.138_788_634_756_691_8,
    1.241_857_812_073_484_2,
    1.354_255_546_936_892_9,
    1.476_826_145_939_499_3,
    1.610_490_331_949_254_5,
    1.756_252_160_373_299_7,
    1.915_206_561_397_147_4,
];

/// The code of `value` on a map whose largest value is `scale` (`value ≤ scale`): the
/// nearest code on the logarithmic scale, `255 + round(8·log2(value/scale))` clamped to
/// `1 ..= 255`, at least 1 for any positive value: from the ratio's bits, exactly, without a logarithm.
pub fn encode(value: f64, scale: f64) -> u8 {
    if !(value > 0.0 && scale > 0.0) {
        return 0;
    }
    encode_ratio(value / scale)
}

/// The code of a value `ratio` times the map's largest: `255 + round(8·log2(ratio))`
/// clamped to `1 ..= 255` for a positive ratio, 0 for 0, a negative ratio or NaN. Taken from
/// the ratio's bits without a branch or a logarithm, exactly: its binary exponent `e` gives
/// `8e`, and its significand `m ∈ [1, 2)` the rounding of `8·log2(m)`, by how many of
/// [`HALF_EIGHTH_OCTAVES`] it reaches (below `2^-1022` the clamp gives 1 whatever `m`).
#[inline(always)]
#[allow(
    clippy::inline_always,
    reason = "inlined into each compilation of the cells' loop"
)]
pub(super) fn encode_ratio(ratio: f64) -> u8 {
    const SIGNIFICAND: u64 = (1 << 52) - 1;
    let bits = ratio.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32 - 1023;
    let significand = f64::from_bits((bits & SIGNIFICAND) | (1023 << 52));
    let mut eighths = 0;
    for t in HALF_EIGHTH_OCTAVES {
        eighths += i32::from(significand >= t);
    }
    let code = (255 + 8 * exponent + eighths).clamp(1, 255) as u8;
    if ratio > 0.0 { code } else { 0 }
}

avx2_dispatch! {
    /// `codes[c] = encode_ratio(integral[c]·inverse)` for every cell; compiled for AVX2
    /// where the processor has it (checked at run time; the same codes).
    pub(super) fn encode_cells(
        codes: &mut [u8; GRID_CELLS],
        integral: &[f64; GRID_CELLS],
        inverse: f64,
    ) => encode_cells_in;
}

/// [`encode_cells`]' body, inlined into each of its compilations.
#[allow(
    clippy::inline_always,
    reason = "compiled into the AVX2 instance too, where its loop widens"
)]
#[inline(always)]
fn encode_cells_in(codes: &mut [u8; GRID_CELLS], integral: &[f64; GRID_CELLS], inverse: f64) {
    for (code, &v) in codes.iter_mut().zip(integral) {
        *code = encode_ratio(v * inverse);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `a·b` of little-endian 64-bit limbs, exactly.
    fn times(a: &[u64], b: &[u64]) -> Vec<u64> {
        let mut out = vec![0u64; a.len() + b.len()];
        for (i, &x) in a.iter().enumerate() {
            let mut carry = 0u128;
            for (j, &y) in b.iter().enumerate() {
                let t = u128::from(x) * u128::from(y) + u128::from(out[i + j]) + carry;
                out[i + j] = t as u64;
                carry = t >> 64;
            }
            out[i + b.len()] = carry as u64;
        }
        out
    }

    /// Whether the integer `a` (limbs) is at least `2^power`.
    fn at_least_power_of_two(a: &[u64], power: usize) -> bool {
        let top = a
            .iter()
            .rposition(|&l| l != 0)
            .map_or(0, |i| 64 * i + 64 - a[i].leading_zeros() as usize);
        top > power
    }

    /// Each threshold `T_k` is the least `f64` with `T_k^16 ≥ 2^(2k−1)`, in integers:
    /// `T = M·2^-52` and `M^16` against `2^(2k−1+832)`, for `T` and the `f64` just below.
    #[test]
    fn half_eighth_octaves_are_the_least_doubles_past_their_powers() {
        let sixteenth = |m: u64| {
            let mut x = vec![m];
            for _ in 0..4 {
                x = times(&x, &x);
            }
            x
        };
        for (k, &t) in (1..).zip(&HALF_EIGHTH_OCTAVES) {
            let power = 2 * k - 1 + 16 * 52;
            let m = |x: f64| (x * (1u64 << 52) as f64) as u64;
            assert!(
                at_least_power_of_two(&sixteenth(m(t)), power),
                "T_{k} too small"
            );
            assert!(
                !at_least_power_of_two(&sixteenth(m(t.next_down())), power),
                "T_{k} not the least"
            );
        }
    }

    /// The codes from the ratio's bits are `255 + round(8·log2(ratio))` clamped, as the
    /// logarithm gives it wherever its rounding is not within `10^-9` of a tie, over ratios
    /// from `2^-40` to 1 and past them.
    #[test]
    fn codes_are_the_rounded_logarithm() {
        let written = |v: f64, s: f64| {
            let octaves = 8.0 * (v / s).log2();
            (255.0 + octaves.round()).clamp(1.0, 255.0) as u8
        };
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut compared = 0;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let exponent = -42.0 * (state >> 11) as f64 / (1u64 << 53) as f64;
            let ratio = exponent.exp2();
            let scale = 1.0 + (state & 0xff) as f64;
            let value = ratio * scale;
            let eighths = 8.0 * (value / scale).log2();
            if (eighths - eighths.floor() - 0.5).abs() < 1e-9 {
                continue;
            }
            compared += 1;
            assert_eq!(
                encode(value, scale),
                written(value, scale),
                "{value} / {scale}"
            );
        }
        assert!(compared > 190_000);
        // A map's cells: both compilations of the loop give every cell the same code.
        let mut integral = [0.0; GRID_CELLS];
        for v in &mut integral {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            *v = (-40.0 * (state >> 11) as f64 / (1u64 << 53) as f64).exp2();
        }
        integral[7] = 0.0;
        let (mut dispatched, mut baseline) = ([0; GRID_CELLS], [0; GRID_CELLS]);
        encode_cells(&mut dispatched, &integral, 1.0);
        encode_cells_in(&mut baseline, &integral, 1.0);
        assert_eq!(dispatched, baseline);
        assert_eq!(dispatched[7], 0);
        for (&code, &v) in dispatched.iter().zip(&integral) {
            assert_eq!(code, encode(v, 1.0));
        }
        for (v, s, code) in [
            (2.0, 1.0, 255),
            (1.0, 1.0, 255),
            (f64::MIN_POSITIVE, 1.0, 1),
            (5e-324, 1.0, 1),
            (0.0, 1.0, 0),
            (-1.0, 1.0, 0),
            (f64::NAN, 1.0, 0),
            (f64::INFINITY, f64::INFINITY, 0),
            (1.0, 0.0, 0),
        ] {
            assert_eq!(encode(v, s), code, "{v} / {s}");
        }
        // Each threshold and the double below it, on either side of a code.
        for (k, &t) in (1..).zip(&HALF_EIGHTH_OCTAVES) {
            let at = encode(t / 2.0, 1.0);
            assert_eq!(at, (247 + k) as u8);
            assert_eq!(encode(t.next_down() / 2.0, 1.0), at - 1);
        }
    }

    #[test]
    fn codes_round_trip_within_half_an_eighth_octave() {
        assert_eq!(decode(0), 0.0);
        assert_eq!(decode(255), 1.0);
        assert_eq!(encode(0.0, 1.0), 0);
        assert_eq!(encode(1.0, 1.0), 255);
        assert_eq!(encode(1e-300, 1.0), 1, "positive values keep a code");
        for k in 0..2000 {
            let v = 2f64.powf(-f64::from(k) / 97.0);
            let c = encode(v, 1.0);
            if v >= decode(1) {
                let ratio = decode(c) / v;
                let half = 2f64.powf(1.0 / 16.0) * (1.0 + 1e-12);
                assert!(ratio <= half && ratio >= 1.0 / half, "{v}: {ratio}");
            }
        }
        for (r, &m) in EIGHTH_OCTAVES.iter().enumerate() {
            assert!((m - 2f64.powf(-(r as f64) / 8.0)).abs() <= 1e-16);
        }
        for code in 1..=255u8 {
            let exact = 2f64.powf((f64::from(code) - 255.0) / 8.0);
            assert!((decode(code) - exact).abs() <= 1e-15 * exact, "{code}");
        }
    }
}
