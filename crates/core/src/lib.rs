//! # lightpick-core
//!
//! The numerics behind lightpick: picking one of many point lights at random in
//! proportion to its power, and measuring what that buys.
//!
//! * [`LightPowers`] validates a set of powers (finite, non-negative, not all zero).
//! * [`AliasTable`] is Walker's alias method in its packed `u32` form, shared bit for bit
//!   with the GPU, built by one of two [`Construction`]s: an exact integer sweep (the fast
//!   default) or Vose's algorithm in `f64` (exact fractions such as 6/27). [`CdfTable`] and
//!   [`Uniform`] are the peers it is compared with.
//! * [`LightSampler`] is the one interface of every scheme: `pick_at(ctx, rng)` and
//!   `pmf_at(ctx, i)` at a [`ShadingContext`]; the point-free schemes ([`Sampler`]) ignore the
//!   context, the spatial one reads it, and [`SchemeSampler`] holds any of them.
//! * [`Rng`] is the one counter-based random number generator (the PCG hash of Jarzynski &
//!   Olano 2020) that the CPU and the WGSL shaders both implement.
//! * [`Welford`], [`analytic_moments`] and [`chi_square()`] measure estimators and samplers;
//!   [`point_estimate`] runs the estimator at one shading point under several pick rules at
//!   once (the worked example's 18, converging faster by power than uniformly).
//! * [`precision`] measures what each numerical choice of the alias table costs.
//! * [`walkthrough`] and [`construction`] hold the classroom's material: the classic
//!   explanation's steps with live numbers, and Vose's construction recorded step by step.
//! * [`spatial`] picks lights by their contribution at a shading point (exact for few
//!   lights, a light tree for many): the render-only scheme [`Scheme::Spatial`].
//! * [`SceneSamplers`]: a scene with its alias table and spatial sampler, built once and
//!   shared (`Arc`) by every renderer and view of it.
//! * [`scene`], [`render`] and `gpu`: scenes of point lights (and spots, ranges) over a
//!   receiver plane, read from JSON, glTF or CSV ([`scene::load`]), progressive renderers on
//!   the CPU (rayon) and the GPU (wgpu compute, feature `gpu`), error metrics.
//! * `draw` renders the diagrams, plots and image sheets headless (tiny-skia → PNG,
//!   feature `draw`).
//!
//! # Map
//! The folders are the topics: [`sampling`] (powers, the alias table and its peers, the one
//! interface, the RNG), [`stats`] (moments, chi-square, [`Scaled`] figures), [`lesson`] (the
//! worked example, the walkthrough, the construction trace, one shading point), [`scene`],
//! [`spatial`], [`render`], `gpu`, `draw`, [`precision`] and [`atomic_file`]. The types are
//! re-exported here, and the modules' former paths (`lightpick_core::walkthrough`, …) still
//! work.
//!
//! # Quick start
//! Build a table, sample one light and a batch (the batch holds exactly the picks of as
//! many single calls on the same stream):
//! ```
//! use lightpick_core::{AliasTable, LightPowers, Rng};
//!
//! let powers = LightPowers::new(vec![2.0, 5.0, 20.0])?;
//! let table = AliasTable::build(&powers);
//! let mut rng = Rng::new(1, 0); // seed 1, stream 0
//! let light = table.sample(&mut rng);
//! assert!(light < 3);
//!
//! let mut picks = vec![0u32; 10_000];
//! table.sample_into(&mut picks, &mut rng);
//! let share_of_light_3 = picks.iter().filter(|&&i| i == 2).count() as f64 / 1e4;
//! assert!((share_of_light_3 - 20.0 / 27.0).abs() < 0.02); // p = 20/27, σ ≈ 0.0044
//!
//! // The exact f64 construction gives the worked example's fractions.
//! let exact = AliasTable::build_exact(&powers);
//! assert_eq!(exact.thresholds(), &[6.0 / 27.0, 15.0 / 27.0, 1.0]);
//! assert_eq!(exact.aliases(), &[2, 2, 2]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//! Render a scene on the CPU and compare it with the exact image:
//! ```
//! use lightpick_core::Scheme;
//! use lightpick_core::render::{CpuRenderer, Reference, rmse};
//! use lightpick_core::scene::Scene;
//!
//! let scene = Scene::preset("worked-example")?; // the worked example's three lights over a 256×256 plane
//! let mut renderer = CpuRenderer::new(&scene, Scheme::Alias, 7);
//! renderer.accumulate(4); // 4 samples per pixel, deterministic for seed 7
//! assert_eq!(renderer.accumulator().image().len(), 256 * 256);
//! let reference = Reference::compute(&scene);
//! let error = rmse(renderer.accumulator(), &reference);
//! renderer.accumulate(60); // 64 spp: the error falls like 1/√spp
//! assert!(rmse(renderer.accumulator(), &reference) < error);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//! Draw the table diagram to PNG, headless (feature `draw`):
//! ```
//! # #[cfg(feature = "draw")]
//! # {
//! use lightpick_core::draw::{Style, encode_png, fraction_denominator, table_diagram};
//! use lightpick_core::{AliasTable, LightPowers};
//!
//! let powers = LightPowers::new(vec![2.0, 5.0, 20.0])?;
//! let table = AliasTable::build_exact(&powers);
//! let pixmap = table_diagram(&table, fraction_denominator(&powers), &Style::default())?;
//! let png = encode_png(&pixmap)?;
//! assert!(png.starts_with(b"\x89PNG"));
//! # }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//! Runnable examples: `cargo run -p lightpick-core --example quick_start` and
//! `--example snapshot_my_powers` (a deterministic snapshot test of your own powers).
//!
//! Nothing here depends on a UI toolkit.
//!
//! # Features
//! | feature | default | brings | adds |
//! | --- | --- | --- | --- |
//! | `gpu` | on | the module `gpu`: the wgpu compute renderer, histogram and spatial sampler, their WGSL | wgpu, naga, pollster (about 110 crates) |
//! | `draw` | on | the module `draw`: table diagrams, histograms, convergence plots, image sheets, PNG/EXR | tiny-skia, `ab_glyph`, image |
//! | `rand` | off | `rand_support`: the samplers as `rand::distr::Distribution<usize>` over any `rand::Rng`, and [`Rng`] as a `rand::Rng` | rand (traits only), `rand_core` |
//!
//! Without them (`default-features = false`) the crate is the alias table and its peers,
//! the RNG, estimators and metrics, scenes and their importers (JSON, glTF, CSV), the CPU
//! renderer, the spatial sampler and the light tree: 36 crates besides this one
//! (`cargo tree -e normal`), none of the GPU or drawing stack.
//!
//! # Determinism
//! Alias tables, light trees and CPU renders are the same bits whatever the thread count:
//! work is split by fixed index blocks, never by thread, and every reduction sums in a
//! fixed order. The integer alias table builds on every core of the current rayon pool
//! and equals the one-thread build bit for bit ([`AliasTable::build`]); its exactness
//! guarantees do not depend on the split. Tested on pools of 1, 2, 3 and 16 threads.

pub mod atomic_file;
mod avx2;
mod cpu_lights;
#[cfg(feature = "draw")]
pub mod draw;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod lesson;
pub mod precision;
#[cfg(feature = "rand")]
pub mod rand_support;
pub mod render;
pub mod sampling;
pub mod scene;
mod scene_samplers;
mod scheme_sampler;
pub mod spatial;
pub mod stats;

// The modules' paths before the folders by topic, kept for whoever depends on them (and
// used inside the crate): `lightpick_core::walkthrough::…` still works.
pub(crate) use lesson::worked_example;
pub use lesson::{construction, fraction, inspect, point_estimate, walkthrough};
pub(crate) use sampling::{alias, cdf, light_sampler, powers, rng, sampler, uniform};
pub(crate) use stats::{chi_square, moments, scaled, welford};

pub use alias::{AliasTable, Construction, PackedAliasEntry};
pub use cdf::CdfTable;
pub use chi_square::{ChiSquare, chi_square, chi_square_cells};
pub use light_sampler::{LightSampler, Pick, PointFreeSampler, ShadingContext};
pub use moments::{EstimatorMoments, analytic_moments, contribution_unit};
pub use powers::{LightPowers, PmfScale, PowersError};
pub use rng::{Rng, pcg_hash, unit_f64};
pub use sampler::{NeedsShadingPoint, Sampler, Scheme, UnknownScheme};
pub use scaled::Scaled;
pub use scene_samplers::SceneSamplers;
pub use scheme_sampler::SchemeSampler;
pub use uniform::{Uniform, rejection_threshold};
pub use welford::Welford;
pub use worked_example::WorkedExample;
/// The worked example's former name.
#[deprecated(note = "renamed `WorkedExample`: \"seed\" now names random streams alone")]
pub type SeedExample = WorkedExample;
