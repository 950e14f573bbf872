//! The chunked, parallel construction against the one-pass sequential one, on every pool.

use super::sweep::{Order, sweep};
use super::units::CHUNK;
use super::{build, quantize, reference};

/// A reproducible stream of uniforms in `[0, 1)` (`SplitMix64`).
pub(super) fn uniforms(seed: u64, n: usize) -> Vec<f64> {
    let mut state = seed;
    (0..n)
        .map(|_| {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

/// Power sets that exercise every path: ordinary, heavy tails, zeros, all equal (every
/// column full), lights too dim to get a unit (reach flags), and extreme magnitudes.
fn cases(n: usize) -> Vec<(&'static str, Vec<f64>)> {
    let u = uniforms(n as u64, n);
    vec![
        ("uniform", u.iter().map(|x| x + 0.01).collect()),
        ("pareto", u.iter().map(|x| (1.0 - x).powf(-1.5)).collect()),
        (
            "zeros",
            u.iter().map(|&x| if x < 0.4 { 0.0 } else { x }).collect(),
        ),
        ("equal", vec![3.0; n]),
        (
            "dim",
            u.iter()
                .enumerate()
                .map(|(i, x)| if i % 97 == 0 { 1e300 } else { x * 1e-300 })
                .collect(),
        ),
        (
            "extreme",
            u.iter()
                .map(|&x| if x < 0.5 { f64::MAX * x } else { 5e-324 })
                .collect(),
        ),
        ("sorted", (0..n).map(|i| (i as f64 + 1.0).powi(2)).collect()),
        // Every ideal mass but the first has the same fraction, so the fixed-point rounding
        // errors add up along a chunk and chunks' sums must be settled to their anchors.
        (
            "one-brighter",
            (0..n).map(|i| if i == 0 { 2.0 } else { 1.0 }).collect(),
        ),
    ]
}

/// The packed table of `powers`, built into fresh buffers.
pub(super) fn built(powers: &[f64]) -> Vec<u64> {
    let (mut table, mut heavy) = (Vec::new(), Vec::new());
    build(powers, &mut table, &mut heavy);
    table
}

/// A rayon pool of `threads` threads.
pub(super) fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a rayon pool")
}

#[test]
fn chunked_build_equals_the_sequential_one_on_every_pool() {
    for n in [2, 3, 1000, CHUNK, CHUNK + 1, 3 * CHUNK + 17, 9 * CHUNK - 5] {
        for (name, powers) in cases(n) {
            let want = reference::sweep(&reference::masses(&powers));
            for threads in [1, 2, 3, 16] {
                let got = pool(threads).install(|| built(&powers));
                assert!(
                    got == want,
                    "{name}, N = {n}, {threads} threads: the table differs from the sequential \
                     construction"
                );
            }
        }
    }
}

#[test]
fn rebuild_into_used_buffers_equals_a_fresh_build() {
    let n = 5 * CHUNK + 3;
    let cases = cases(n);
    let (mut table, mut heavy) = (Vec::new(), Vec::new());
    for (name, powers) in cases.iter().chain(cases.iter().rev()) {
        build(powers, &mut table, &mut heavy);
        assert!(table == built(powers), "{name}: rebuild differs");
    }
}

#[test]
fn pieces_need_nothing_from_the_pieces_after_them() {
    // Run last first: each piece then finds its successors' words already packed, so
    // reading a mass that was handed over would show. Run first first on plain words: the
    // path of targets without a usable `AtomicU64`.
    for (name, powers) in cases(9 * CHUNK - 5) {
        let want = reference::sweep(&reference::masses(&powers));
        for order in [Order::Reversed, Order::Forward] {
            let got = pool(16).install(|| {
                let n = powers.len();
                let (mut table, mut heavy) = (vec![0; n], vec![0; n.div_ceil(64)]);
                let census = quantize::quantize(&powers, &mut table, &mut heavy);
                sweep(&mut table, &heavy, &census, order);
                table
            });
            assert!(got == want, "{name}: pieces run {order:?} differ");
        }
    }
}
