//! What the per-tile cuts' tests share: a scene's light tree with its cuts, and the exact
//! mean variance of one sample of a spatial sampler over a set of points (of the cut tree
//! against the same tree from its root, too).

use glam::DVec2;
use lightpick_core::scene::Scene;
use lightpick_core::spatial::{LightTree, SpatialSampler};

/// The light tree `scene`'s spatial sampler uses, which must be cut per tile.
pub fn cut_tree(scene: &Scene) -> LightTree {
    match SpatialSampler::for_scene(scene) {
        SpatialSampler::Tree(tree) => {
            assert!(tree.tile_cuts().is_some(), "a scene's tree is cut per tile");
            tree
        }
        SpatialSampler::Exact(_) => panic!("enough lights for a tree"),
    }
}

/// The mean over `points` of the exact variance of one sample, `Σ c_i²/P_i − E²` with
/// `c_i = p_i·f_i(x)` and `P_i` the sampler's pdf at `x`; asserts `P_i > 0` wherever
/// `c_i > 0`.
pub fn mean_variance(scene: &Scene, sampler: &SpatialSampler, points: &[DVec2]) -> f64 {
    let pmf = scene.powers.pmf();
    let mut sum = 0.0;
    for &x in points {
        let pdf = sampler.pdfs(x);
        let (mut e, mut second) = (0.0, 0.0);
        for (i, &p) in pdf.iter().enumerate() {
            let c = pmf[i] * scene.light_term(i, x);
            assert!(c == 0.0 || p > 0.0, "a contributing light has P = 0 at {x}");
            e += c;
            if c > 0.0 {
                second += c * c / p;
            }
        }
        sum += second - e * e;
    }
    sum / points.len() as f64
}

/// The mean exact variance over `points` of `scene`'s cut tree ([`cut_tree`]) with its
/// per-tile cuts, and of the same tree descended from its root.
pub fn cut_and_root_variances(scene: &Scene, points: &[DVec2]) -> (f64, f64) {
    let tree = cut_tree(scene);
    let cut = mean_variance(scene, &SpatialSampler::Tree(tree.clone()), points);
    let root = mean_variance(scene, &SpatialSampler::Tree(tree.with_cuts(None)), points);
    (cut, root)
}
