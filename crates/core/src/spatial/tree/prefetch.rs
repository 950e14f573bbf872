//! A hint to the processor to start loading memory a descent will read soon.
//!
//! The lockstep descents of [`super::LightTree::sample_many`] know each pick's next node (or
//! leaf cluster) a whole round of the other picks' steps before they read it. Asking for
//! its cache lines then lets those loads (misses, among a million lights) run during that
//! round, where an ordinary load issued at the step itself would stall it. The same holds
//! for the first step of each pick, the entry its tile's cut takes, where the cut has left
//! the caches ([`super::LightTree::sample_many_cold`]): its alias column and entry are known
//! from the draw, a round of the other picks' draws ahead.

/// The fewest lights a tree of point lights must hold for its descents to prefetch: below,
/// its nodes and lights stay in the nearer caches and the hints only cost. Measured
/// (`lightpick bench`, spatial sample, two runs each, point lights over 16 × 16 m):
/// `heavy-tail`'s 10^4 lights 7 % slower with them, 2·10^4 uniform lights 11 % slower (the
/// app's passes of one sample a pixel within noise), 5·10^4 4 % faster (the app's 20 %),
/// 2·10^5 15–29 % and `million`'s 10^6 42–44 % faster (the app's 28 % and 49–57 %).
///
/// Trees over spots do not prefetch: at 10^5 spots over 16 × 16 m the hints (nodes, leaf
/// lights, and the first lines of each node's maps and of each leaf's profiles) made a
/// sample 5–8 % slower where a pixel takes many samples in a row and 8–13 % faster in the
/// app's passes: no gain worth the code.
pub(super) const PREFETCH_MIN_LIGHTS: usize = 1 << 15;

/// The most point lights a tree may hold and still start its cold lockstep picks
/// (`LightTree::sample_many_cold`) one by one. A larger one takes every pick's tile and
/// draw first and asks for the alias column and entry each will read in its tile's cut
/// (`LightTree::start_many`, `cut_words::prefetch_pick`), then picks. A tile's cut of up to
/// 256 entries is 3 kB of words, 4096 tiles 12 MB: a pass of one sample a pixel finds each
/// tile's cut gone from the nearer caches since the last pass, and a pick's column and
/// entry are two lines of it at random.
///
/// Measured with `cargo run --release -p lightpick-core --example pass_order` (one thread,
/// 256 × 256 pixels, tiles of 4), ns per pixel sample in passes of one sample a pixel
/// without → with the hints, in five runs: `heavy-tail` 1.31–1.46× faster (263.6 → 181.0 in
/// the last), `clusters-low` 1.29–1.52× (246.7 → 162.5), `grid` 1.09–2.16× (107.9 → 50.0);
/// `million` (cuts of 64 entries) 1.01× (its descents already prefetch); `equal` and
/// `stage`, which run the same code either way, 0.88× and 1.08× (the machine's noise).
/// Where a pixel takes its samples in a row the cut stays cached after the first, and the
/// two rounds only cost (`heavy-tail` 119.6 → 136.3 with every sample cold): the renderer
/// takes the cold picks for the first sample a call gives each pixel, the warm ones after.
/// At `equal`'s 64 lights (cuts of 64 single lights, which stay cached) the two rounds cost
/// 13–18 % (a scratch timer), so a tree of at most this many lights (a cut's most entries:
/// each light may stand alone in it) keeps the single round; trees over spots keep it too
/// (`stage` and `gallery` 1–3 % slower with it: their cuts are smaller).
pub(super) const CUT_PREFETCH_MIN_LIGHTS: usize = super::CUT_MAX_ENTRIES;

/// Asks for the cache lines of `value`, all of them.
#[inline]
pub(super) fn prefetch<T>(value: &T) {
    lines(std::ptr::from_ref(value).cast(), size_of::<T>());
}

/// Asks for the cache lines of every element of `values`.
#[inline]
pub(super) fn prefetch_all<T>(values: &[T]) {
    lines(values.as_ptr().cast(), size_of_val(values));
}

/// Asks for the cache lines of the `bytes` bytes from `start` (one hint each 64 bytes) to be
/// loaded into every cache level: a hint with no effect on any result, and none on
/// processors other than x86-64.
#[inline]
fn lines(start: *const i8, bytes: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let mut offset = 0;
        while offset < bytes {
            // SAFETY: a prefetch reads nothing and cannot fault, whatever the address; the
            // SSE instruction it compiles to is part of every x86-64 processor.
            #[allow(unsafe_code)]
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(offset));
            }
            offset += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (start, bytes);
}
