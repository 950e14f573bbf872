//! A light tree's refit to new powers allocates nothing: neither a point tree's nor a tree of
//! spots and ranges whose lanes are mapped over the receiver, cuts included. Counted by a
//! global allocator that tallies the allocations of the thread making them (the refit runs
//! on a one-thread pool, so all of its work is on that thread, and tests running beside it
//! on other threads are not counted).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use lightpick_core::LightPowers;
use lightpick_core::scene::{Emission, Scene};
use lightpick_core::spatial::SpatialSampler;

use crate::common::SplitMix;
use crate::common::scenes::{scattered, tilted_spot};

/// [`System`], counting each thread's allocations and reallocations.
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

fn count_one() {
    // `try_with`: a thread being torn down allocates too, after its counter is gone.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

fn allocations_here() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

// SAFETY: every call forwards to `System` with the same arguments. (A global allocator is
// an `unsafe` trait: the one use of `unsafe` here, allowed for it alone.)
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count_one();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// Powers `(i mod 7)·10^(i mod 3)`: lights going to power 0 and back, other shares
/// everywhere.
fn other_powers(n: usize) -> LightPowers {
    let p = (0..n)
        .map(|i| (i % 7) as f64 * 10f64.powi((i % 3) as i32))
        .collect();
    LightPowers::new(p).expect("valid powers")
}

#[test]
fn a_refit_allocates_nothing_for_points_spots_and_ranges() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");
    let scenes = ["heavy-tail", "grid", "stage", "gallery"]
        .map(|name| Scene::preset(name).expect("a preset"))
        .into_iter()
        .chain([spots_and_ranges(1500)]);
    for scene in scenes {
        let name = scene.name.clone();
        let mut sampler = SpatialSampler::for_scene(&scene);
        assert!(matches!(sampler, SpatialSampler::Tree(_)), "{name}: a tree");
        let mut edited = scene.clone();
        edited.powers = other_powers(scene.light_count());
        let counted = pool.install(|| {
            let before = allocations_here();
            sampler.refit(&edited);
            sampler.refit(&scene);
            allocations_here() - before
        });
        assert_eq!(counted, 0, "{name}: the refit allocated");
        // And it did refit: the tree is the fresh build's again.
        assert!(sampler == SpatialSampler::for_scene(&scene), "{name}");
    }
}

/// `n` lights over the plane of [`scattered`]: three in five spots (one in eight of those
/// tilted past the horizon), every third light with a range.
fn spots_and_ranges(n: usize) -> Scene {
    let scene = scattered(n, 11, 1.0, vec![1.0; n]);
    let mut d = SplitMix(12);
    let emission = (0..n)
        .map(|i| {
            let spot = (i % 5 < 3).then(|| {
                let tilt = if i % 8 == 0 { 1.7 } else { 0.4 };
                let outer = d.range(0.1, 1.3);
                tilted_spot(&mut d, outer, tilt, 0.0..0.9)
            });
            let range = (i % 3 == 1).then(|| d.range(0.5, 3.0));
            Emission::new(spot, range).expect("valid")
        })
        .collect();
    scene.with_emission(emission)
}
