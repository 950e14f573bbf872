//! wgpu compute kernels: the histogram of picks and the progressive renderer.
//!
//! Every kernel shares one WGSL prelude, `rng.wgsl`, prepended to the kernel's own source
//! when its pipeline is created ([`shader_source`]). The prelude is the bit-exact twin of
//! [`crate::Rng`] (the PCG hash of Jarzynski & Olano and its stream layout) and of the
//! integer sampling paths of [`crate::AliasTable`] and [`crate::Uniform`]:
//!
//! * `mulhi32(a, b) = ⌊a·b / 2^32⌋`, the high word of the 64-bit product, assembled from
//!   16-bit halves because WGSL has no 64-bit integers; the low word is the wrapping `a·b`.
//! * `pick_uniform(N, state)`, the twin of [`crate::Uniform::sample`]: Lemire's exact pick
//!   (draw `r`; while the low word `r·N mod 2^32` is below `t = 2^32 mod N = (0 − N) % N`,
//!   draw again from the same stream; return `mulhi32(r, N)`), each of `0..N` with
//!   probability exactly `1/N`; `t` is computed only on the rare draw with low word `< N`.
//!   `sample_uniform(r, N) = mulhi32(r, N)` is the raw one-draw map.
//! * `pick_light` (`pick.wgsl`, the twin of [`crate::Sampler::pick_light`]): uniform is
//!   `pick_uniform`; alias (the default) takes its column from `pick_uniform` and keeps it
//!   if the next draw `r2 < threshold_u32`, else its alias, so it realizes exactly
//!   [`crate::AliasTable::implied_pmf_packed`]; alias-one-random takes one draw, column =
//!   raw high word of `r·N`, keep test on the low word.
//!
//! All of it is `u32` arithmetic, so a GPU pick equals the CPU pick for the same stream;
//! the tests check this bit for bit. Floating-point estimates are `f32` on the GPU and are
//! compared with the `f64` CPU ones within derived bounds.
//!
//! [`crate::Scheme::Uniform`], [`crate::Scheme::Alias`], [`crate::Scheme::AliasOneRandom`] and
//! [`crate::Scheme::Spatial`] (`spatial.wgsl`, the twin of [`crate::spatial`]) run on the GPU; the
//! inverse-CDF peer is a CPU-only comparison ([`GpuError::UnsupportedScheme`]).
//!
//! # Limits
//! A device binds at most `max_storage_buffer_binding_size` bytes of a buffer (128 MiB on
//! Mesa's lavapipe, often 2–4 GiB on discrete GPUs). The per-light arrays are split over as
//! many bindings as they need (`split.rs`: chunks of `2^s` elements, a buffer each, read
//! through a generated accessor `NAME_at(i)`), so their size is bounded by the memory and
//! by the bindings a shader stage may have (`max_storage_buffers_per_shader_stage`, 32 on
//! lavapipe; beyond it [`GpuError::TooManyBindings`]), not by one binding. Memory per light
//! is unchanged by the split:
//!
//! | array | bytes per light | bindings at 128 MiB for `N` lights |
//! | --- | ---: | --- |
//! | renderer: `(x, y, z, p_i)` and the alias entry | 24 | `⌈N / 2^22⌉` (4 at `2^24`) |
//! | spatial scheme: contributing lights in leaf order | 16 | `⌈M / 2^23⌉` |
//! | spatial scheme: tree nodes (80 bytes, one per ~22 lights) | ~3.6 | 1 up to ~3.7·10^7 lights |
//! | histogram: packed table | 8 | `⌈N / 2^24⌉` (2 at `2^25`) |
//! | histogram: counts | 4 | `⌈N / 2^25⌉` |
//!
//! Scenes hold at most `2^24` lights ([`crate::scene::MAX_LIGHTS`]); the histogram takes any
//! [`crate::LightPowers`] (tested at `2^25`). The per-pixel sums (8 bytes per pixel) stay one
//! binding: 16.7 million pixels at 128 MiB, beyond which [`GpuError::BufferTooLarge`].

mod context;
mod emission;
mod error;
mod histogram;
mod measure;
mod pass_timer;
mod probe;
mod render_kernel;
mod renderer;
mod scheme;
mod spatial;
mod split;

pub use context::GpuContext;
pub use error::GpuError;
pub use histogram::{histogram, histogram_range, histogram_range_split};
pub use measure::{GpuPassMeasurement, measure_passes};
pub use pass_timer::{PassClock, PassTimer};
pub use probe::{probe_mulhi32, probe_pick_uniform, probe_rng};
pub use renderer::GpuRenderer;

/// The WGSL twin of [`crate::Rng`] and of the integer sampling paths; see the module docs.
pub const RNG_WGSL: &str = include_str!("rng.wgsl");

/// The WGSL twin of [`crate::Sampler::pick_light`] for the GPU schemes (the kernel defines
/// `fn alias_entry(column: u32) -> vec2<u32>`, the packed `(threshold, alias)` of a column).
pub const PICK_WGSL: &str = include_str!("pick.wgsl");

/// The full source of a kernel: the shared [`RNG_WGSL`] prelude followed by `parts` in order.
pub fn shader_source(parts: &[&str]) -> String {
    let mut source = String::from(RNG_WGSL);
    for part in parts {
        source.push('\n');
        source.push_str(part);
    }
    source
}

/// Threads per workgroup of the one-dimensional kernels.
pub(crate) const WORKGROUP_SIZE: u32 = 256;

/// Refuses a storage buffer of `bytes` beyond the device's buffer and binding limits.
pub(crate) fn check_storage_size(
    ctx: &GpuContext,
    what: &'static str,
    bytes: u64,
) -> Result<(), GpuError> {
    let limit = ctx.storage_binding_limit();
    if bytes > limit {
        return Err(GpuError::BufferTooLarge { what, bytes, limit });
    }
    Ok(())
}

/// A bind group of `pipeline`'s group 0 with `buffers[k]`, whole, at binding `k`.
pub(crate) fn bind_buffers(
    ctx: &GpuContext,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
        .iter()
        .enumerate()
        .map(|(k, buffer)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

/// Runs `f` inside validation, out-of-memory and internal error scopes, so that a wgpu
/// error becomes a [`GpuError::Wgpu`] instead of the default panic.
pub(crate) fn scoped<T>(
    ctx: &GpuContext,
    during: &'static str,
    f: impl FnOnce() -> Result<T, GpuError>,
) -> Result<T, GpuError> {
    let device = ctx.device();
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    let memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let result = f();
    let errors = [
        pollster::block_on(validation.pop()),
        pollster::block_on(memory.pop()),
        pollster::block_on(internal.pop()),
    ];
    if let Some(error) = errors.into_iter().flatten().next() {
        return Err(GpuError::Wgpu {
            during,
            reason: error.to_string(),
        });
    }
    result
}

/// Creates a compute pipeline (automatic layout) from `parts` behind the RNG prelude.
pub(crate) fn compute_pipeline(
    ctx: &GpuContext,
    label: &'static str,
    parts: &[&str],
    entry_point: &str,
) -> Result<wgpu::ComputePipeline, GpuError> {
    compute_pipeline_from_source(ctx, label, shader_source(parts), entry_point)
}

/// Creates a compute pipeline (automatic layout) from a whole WGSL `source`.
pub(crate) fn compute_pipeline_from_source(
    ctx: &GpuContext,
    label: &'static str,
    source: String,
    entry_point: &str,
) -> Result<wgpu::ComputePipeline, GpuError> {
    scoped(ctx, label, || {
        let module = ctx
            .device()
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        Ok(ctx
            .device()
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: None,
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            }))
    })
}

/// Creates a storage buffer holding `contents` (at least 4 bytes, zero-padded).
pub(crate) fn storage_buffer(
    ctx: &GpuContext,
    label: &'static str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> Result<wgpu::Buffer, GpuError> {
    let size = (contents.len() as u64).max(4).next_multiple_of(4);
    check_storage_size(ctx, label, size)?;
    scoped(ctx, label, || {
        let buffer = ctx.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        if !contents.is_empty() {
            ctx.queue().write_buffer(&buffer, 0, contents);
        }
        Ok(buffer)
    })
}

/// Creates a zero-filled storage buffer of `size` bytes (wgpu zero-initializes buffers).
pub(crate) fn zeroed_storage_buffer(
    ctx: &GpuContext,
    label: &'static str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> Result<wgpu::Buffer, GpuError> {
    let size = size.max(4).next_multiple_of(4);
    check_storage_size(ctx, label, size)?;
    scoped(ctx, label, || {
        Ok(ctx.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }))
    })
}

/// Workgroups `(x, y)` of [`WORKGROUP_SIZE`] threads covering `threads` threads, with `x`
/// within the device's per-dimension limit; kernels index `gid.y · x · WORKGROUP_SIZE + gid.x`.
pub(crate) fn workgroups_2d(ctx: &GpuContext, threads: u64) -> Result<(u32, u32), GpuError> {
    let max = u64::from(ctx.device().limits().max_compute_workgroups_per_dimension);
    let groups = threads.div_ceil(u64::from(WORKGROUP_SIZE)).max(1);
    let x = groups.min(max);
    let y = groups.div_ceil(x);
    if y > max {
        return Err(GpuError::Wgpu {
            during: "planning a dispatch",
            reason: format!("{threads} threads exceed {max}×{max} workgroups"),
        });
    }
    Ok((x as u32, y as u32))
}

/// Creates a uniform buffer of `size` bytes.
pub(crate) fn uniform_buffer(ctx: &GpuContext, label: &'static str, size: u64) -> wgpu::Buffer {
    ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Copies the first `bytes` of `source` (which needs `COPY_SRC`) to the CPU, waiting for
/// all submitted work first.
pub(crate) fn read_buffer(
    ctx: &GpuContext,
    what: &'static str,
    source: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<u8>, GpuError> {
    let staging = ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("lightpick readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx
        .device()
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("lightpick readback"),
        });
    encoder.copy_buffer_to_buffer(source, 0, &staging, 0, bytes);
    ctx.queue().submit([encoder.finish()]);
    map_and_copy(ctx, what, &staging)
}

/// Maps a `MAP_READ` buffer, waits, and copies its bytes out.
pub(crate) fn map_and_copy(
    ctx: &GpuContext,
    what: &'static str,
    staging: &wgpu::Buffer,
) -> Result<Vec<u8>, GpuError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver outlives the poll below; a failed send only means it is gone.
        sender.send(result).ok();
    });
    ctx.device()
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Readback {
            what,
            reason: e.to_string(),
        })?;
    receiver
        .recv()
        .map_err(|e| GpuError::Readback {
            what,
            reason: e.to_string(),
        })?
        .map_err(|e| GpuError::Readback {
            what,
            reason: e.to_string(),
        })?;
    let bytes = staging
        .get_mapped_range(..)
        .map_err(|e| GpuError::Readback {
            what,
            reason: e.to_string(),
        })?
        .to_vec();
    staging.unmap();
    Ok(bytes)
}

/// Reinterprets read-back bytes as native-endian `u32` words.
pub(crate) fn words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|w| u32::from_ne_bytes([w[0], w[1], w[2], w[3]]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scheme;

    /// Every kernel parses and validates with naga, without needing a device, with its
    /// arrays in one binding and split over three.
    #[test]
    fn every_kernel_validates_with_naga() {
        use split::SplitShape;
        let one = SplitShape {
            chunks: 1,
            shift: 31,
        };
        let three = SplitShape {
            chunks: 3,
            shift: 20,
        };
        let mut kernels: Vec<(&str, String)> = vec![
            ("probe", shader_source(&[probe::PROBE_WGSL])),
            ("tonemap", shader_source(&[render_kernel::TONEMAP_WGSL])),
            ("rng alone", shader_source(&[])),
        ];
        for (label, shape) in [("one binding", one), ("three bindings", three)] {
            kernels.push((label, spatial::spatial_source(shape, shape, None, shape)));
            let shaped = spatial::ShapedSplit {
                shapes: shape,
                bounds: shape,
                codes: shape,
            };
            kernels.push((
                label,
                spatial::spatial_source(shape, shape, Some(shaped), shape),
            ));
            kernels.push((label, histogram::histogram_source(shape, shape)));
            kernels.push((label, render_kernel::render_source(shape, None)));
            kernels.push((label, render_kernel::render_source(shape, Some(shape))));
        }
        for (name, source) in kernels {
            let module = wgpu::naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
            wgpu::naga::valid::Validator::new(
                wgpu::naga::valid::ValidationFlags::all(),
                wgpu::naga::valid::Capabilities::default(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        }
    }

    /// A shader error becomes [`GpuError::Wgpu`] naming the problem, not wgpu's panic.
    #[test]
    fn invalid_wgsl_is_an_error_not_a_panic() {
        if std::env::var("LIGHTPICK_SKIP_GPU_TESTS").as_deref() == Ok("1") {
            eprintln!("GPU test skipped: LIGHTPICK_SKIP_GPU_TESTS=1");
            return;
        }
        let ctx = GpuContext::new().expect("a GPU adapter (or LIGHTPICK_SKIP_GPU_TESTS=1)");
        let kernel = "@compute @workgroup_size(1) fn main() { let alias = 1u; }";
        let err = compute_pipeline(&ctx, "bad kernel", &[kernel], "main").expect_err("invalid");
        let message = err.to_string();
        assert!(
            matches!(
                err,
                GpuError::Wgpu {
                    during: "bad kernel",
                    ..
                }
            ),
            "{message}"
        );
        assert!(message.contains("reserved"), "{message}");
    }

    #[test]
    fn the_prelude_comes_first_and_parts_follow_in_order() {
        let source = shader_source(&["// a", "// b"]);
        assert!(source.starts_with(RNG_WGSL));
        assert!(source.ends_with("\n// a\n// b"));
    }

    #[test]
    fn cdf_has_no_scheme_code() {
        use scheme::scheme_code;

        assert_eq!(scheme_code(Scheme::Uniform), Ok(0));
        assert_eq!(scheme_code(Scheme::Alias), Ok(1));
        assert_eq!(scheme_code(Scheme::AliasOneRandom), Ok(2));
        let err = scheme_code(Scheme::Cdf).expect_err("cdf");
        assert!(
            err.to_string()
                .starts_with("scheme 'cdf' is not supported on the GPU")
        );
    }

    #[test]
    fn words_are_native_endian_u32() {
        let bytes: Vec<u8> = [1u32, u32::MAX, 0x0102_0304]
            .iter()
            .flat_map(|w| w.to_ne_bytes())
            .collect();
        assert_eq!(words(&bytes), vec![1, u32::MAX, 0x0102_0304]);
    }
}
