//! The same bits whatever the thread count: tables, light trees and their tiles' cuts, CPU
//! renders, references and sampled estimates built on rayon pools of 1, 2, 3 and 16
//! threads; and a refitted light tree (new powers, same lights) equals a fresh build bit for
//! bit, its cuts too.

use std::sync::Arc;

use crate::common::scenes::preset_at;
use lightpick_core::point_estimate::sampled_mean;
use lightpick_core::render::{CpuRenderer, Reference};
use lightpick_core::scene::Scene;
use lightpick_core::spatial::SpatialSampler;
use lightpick_core::{AliasTable, Construction, LightPowers, Sampler, SceneSamplers, Scheme};

const THREADS: [usize; 4] = [1, 2, 3, 16];

/// `f` on a fresh pool of `threads` threads.
fn on_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a rayon pool")
        .install(f)
}

/// The value of `f` on every pool of [`THREADS`], checked equal to the 1-thread one.
fn same_on_every_pool<T: Send + PartialEq + std::fmt::Debug>(
    what: &str,
    f: impl Fn() -> T + Send + Sync,
) {
    let one = on_pool(1, &f);
    for threads in THREADS {
        assert!(
            on_pool(threads, &f) == one,
            "{what}: {threads} threads differ"
        );
    }
}

fn heavy_tail() -> Scene {
    preset_at("heavy-tail", 24, 16)
}

#[test]
fn tables_are_the_same_on_every_pool() {
    let powers = heavy_tail().powers;
    for construction in [Construction::Integer, Construction::Exact] {
        same_on_every_pool(&format!("{construction:?} table"), || {
            AliasTable::build_with(&powers, construction)
                .packed()
                .to_vec()
        });
    }
}

#[test]
fn a_many_chunk_table_is_the_same_on_every_pool() {
    // Thirteen of the build's chunks of 16384 lights, so its passes and its sweep split
    // differently on every pool: a heavy tail with zeros and lights too dim for one unit.
    let powers: Vec<f64> = (0..200_003u32)
        .map(|i| {
            let u = f64::from(lightpick_core::pcg_hash(i)) / f64::from(u32::MAX);
            match i % 11 {
                0 => 0.0,
                1 => u * 1e-290,
                _ => (1.0 - u).max(1e-9).powf(-1.5),
            }
        })
        .collect();
    let powers = LightPowers::new(powers).expect("valid powers");
    same_on_every_pool("200003-light integer table", || {
        AliasTable::build(&powers).packed().to_vec()
    });
}

#[test]
fn trees_renders_references_and_estimates_are_the_same_on_every_pool() {
    let scene = heavy_tail();
    same_on_every_pool("light tree", || SpatialSampler::for_scene(&scene));
    same_on_every_pool("reference", || {
        Reference::compute(&scene).in_unit().to_vec()
    });
    for scheme in [Scheme::Uniform, Scheme::Alias, Scheme::Spatial] {
        same_on_every_pool(&format!("{scheme} render"), || {
            let mut r = CpuRenderer::new(&scene, scheme, 5);
            r.accumulate(3);
            r.accumulate(2);
            r.accumulator().clone()
        });
    }
    let contributions: Vec<f64> = (0..scene.light_count())
        .map(|i| (i % 13) as f64 + 0.5)
        .collect();
    let sampler = Sampler::build(Scheme::Alias, &scene.powers);
    same_on_every_pool("sampled estimate", || {
        sampled_mean(&sampler, &contributions, 300_000, 7)
    });
}

#[test]
fn repowered_samplers_equal_a_fresh_build() {
    for name in ["worked-example", "heavy-tail", "stage"] {
        let scene = Arc::new(Scene::preset(name).expect("preset"));
        let before = SceneSamplers::new(Arc::clone(&scene), Construction::Integer);
        before.spatial();
        // New powers: reversed, one set to zero.
        let mut powers: Vec<f64> = scene.powers.as_slice().iter().rev().copied().collect();
        powers[0] = 0.0;
        if powers.iter().all(|&p| p == 0.0) {
            powers[1] = 1.0;
        }
        let mut edited = (*scene).clone();
        edited.powers = LightPowers::new(powers).expect("valid");
        assert!(scene.same_geometry(&edited));
        let edited = Arc::new(edited);
        let refitted = on_pool(2, || before.repowered(Arc::clone(&edited)));
        let fresh = SceneSamplers::new(Arc::clone(&edited), Construction::Integer);
        assert_eq!(refitted.table().packed(), fresh.table().packed(), "{name}");
        assert!(
            refitted.spatial_if_built().expect("refitted with the tree") == fresh.spatial(),
            "{name}: refit differs from a fresh build"
        );
        // The tiles' cuts, made when first needed, too: cut after the refit on two threads
        // and fresh on one, the same words.
        if let (SpatialSampler::Tree(a), SpatialSampler::Tree(b)) = (
            &**refitted.spatial_if_built().expect("built"),
            &**fresh.spatial(),
        ) {
            let (cuts_a, cuts_b) = (a.tile_cuts().expect("cut"), b.tile_cuts().expect("cut"));
            let words_a = on_pool(2, || cuts_a.gpu_words(a));
            let words_b = on_pool(1, || cuts_b.gpu_words(b));
            assert!(words_a == words_b, "{name}: the refit's cuts differ");
        }
    }
}

#[test]
fn tile_cuts_are_the_same_on_every_pool() {
    for name in ["heavy-tail", "stage"] {
        let scene = preset_at(name, 40, 24);
        same_on_every_pool(&format!("{name} tile cuts"), || {
            let SpatialSampler::Tree(tree) = SpatialSampler::for_scene(&scene) else {
                panic!("a tree");
            };
            tree.tile_cuts().expect("cut").gpu_words(&tree)
        });
    }
}
