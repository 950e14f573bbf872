//! One timed case of `bench`: a method at a size, what it drew from and what it cost.

use serde::Serialize;

/// One timed method at one `N`.
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// Number of lights.
    pub n: usize,
    /// What was timed (`alias`, `alias-one-random`, `cdf`, `uniform`, `alias+smallrng`,
    /// `rand_distr::WeightedAliasIndex`, `rand::WeightedIndex`).
    pub method: &'static str,
    /// The random generator the samples drew from.
    pub rng: &'static str,
    /// Median build time (powers to a ready table, allocation included), nanoseconds.
    pub build_ns: f64,
    /// Median time to rebuild an existing table of the same `N` in place (no allocation),
    /// nanoseconds, for the methods that can (`alias`, `alias-exact`, and the peer
    /// `rand_distr::WeightedAliasIndex`, which has no in-place rebuild: its build).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rebuild_ns: Option<f64>,
    /// Median time per sample, nanoseconds (for `tree-build`, `tree-refit`,
    /// `tree-refit-cuts` and `app-repower`: one pick of the light tree, without cuts, at a
    /// shading point).
    pub sample_ns: f64,
    /// Threads the timed build ran on: rayon's pool for the integer alias table (`alias`,
    /// `alias-batch`) and the light tree (`tree-build`, `tree-refit`, `tree-refit-cuts`), 1
    /// for `alias-1t` and the sequential constructions and peers (`app-repower`: the pool,
    /// for its table and tree). Picks always run on one thread.
    pub threads: usize,
    /// Minor page faults per build (`alias`, `alias-1t` and the peer alias table; Linux).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub build_faults: Option<f64>,
    /// Minor page faults per in-place rebuild (`alias`, `alias-1t`; Linux).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rebuild_faults: Option<f64>,
    /// Heap bytes per light of the structure built, by capacity
    /// ([`lightpick_core::spatial::LightTree::heap_bytes`]): `tree-build` the light tree
    /// over points, `tree-refit-spots` the tree over spots with its lanes' bounds and maps;
    /// neither with tile cuts (those belong to a receiver's pixel grid).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bytes_per_light: Option<f64>,
}

impl Case {
    /// Sets the page faults per build and per rebuild.
    pub fn set_faults(&mut self, build: Option<f64>, rebuild: Option<f64>) {
        (self.build_faults, self.rebuild_faults) = (build, rebuild);
    }
}
