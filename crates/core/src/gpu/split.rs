//! Arrays larger than one storage binding, split over several buffers.
//!
//! A device binds at most `max_storage_buffer_binding_size` bytes of one buffer (128 MiB on
//! Mesa's lavapipe), far less than the GPU's memory. A [`SplitArray`] of `len` elements of
//! `e` bytes keeps them in `⌈len / 2^s⌉` buffers of `2^s` elements each (the last one
//! shorter), with `2^s` the largest power of two such that `2^s · e` fits one binding
//! ([`GpuContext::storage_binding_limit`]). Each buffer is its own binding, and the kernel
//! reads element `i` from buffer `i >> s` at `i & (2^s − 1)` through an accessor that
//! [`declarations`] writes for it (`fn lights_at(i: u32) -> Light`, or for counters
//! `fn counts_add(i: u32, v: u32)`), so no kernel indexes a binding directly. One binding is
//! the common case and its accessor is a plain read.
//!
//! Memory per element is unchanged: only the binding is split, never the data.

use super::{GpuContext, GpuError};

/// How a kernel uses a split array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Access {
    /// `var<storage, read>` with the accessor `fn NAME_at(i: u32) -> T`.
    Read,
    /// `var<storage, read_write>` of `atomic<u32>` with `fn NAME_add(i: u32, v: u32)`.
    AtomicAdd,
}

/// What a kernel calls an array and what it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ArrayLayout {
    /// The WGSL name stem: bindings `NAME_0 …`, accessor `NAME_at` / `NAME_add`.
    pub(crate) name: &'static str,
    /// The WGSL element type (`Light`, `vec4<f32>`, `atomic<u32>`).
    pub(crate) element: &'static str,
    /// Bytes per element.
    pub(crate) bytes: u64,
}

/// One logical array stored in chunks of `2^shift` elements, a buffer each.
#[derive(Debug)]
pub(crate) struct SplitArray {
    element_bytes: u64,
    len: u64,
    shift: u32,
    buffers: Vec<wgpu::Buffer>,
}

impl SplitArray {
    /// Allocates `len` zeroed elements of `element_bytes` bytes (at least one element, so
    /// that a binding exists), in as many buffers as one binding's limit requires, with
    /// `usage` besides `STORAGE | COPY_DST`. `what` names the array in errors.
    pub(crate) fn zeroed(
        ctx: &GpuContext,
        what: &'static str,
        layout: ArrayLayout,
        len: u64,
        usage: wgpu::BufferUsages,
    ) -> Result<Self, GpuError> {
        let element_bytes = layout.bytes;
        let limit = ctx.storage_binding_limit();
        if element_bytes > limit {
            return Err(GpuError::BufferTooLarge {
                what,
                bytes: element_bytes,
                limit,
            });
        }
        // The largest 2^s elements within one binding (and within u32 indices).
        let shift = (limit / element_bytes).ilog2().min(31);
        let chunk = 1u64 << shift;
        let len = len.max(1);
        let chunks = len.div_ceil(chunk);
        let mut buffers = Vec::with_capacity(chunks as usize);
        for k in 0..chunks {
            let elements = chunk.min(len - k * chunk);
            buffers.push(super::zeroed_storage_buffer(
                ctx,
                what,
                elements * element_bytes,
                usage,
            )?);
        }
        Ok(Self {
            element_bytes,
            len,
            shift,
            buffers,
        })
    }

    /// [`SplitArray::zeroed`] holding `contents` (whole elements).
    pub(crate) fn with_contents(
        ctx: &GpuContext,
        what: &'static str,
        layout: ArrayLayout,
        contents: &[u8],
        usage: wgpu::BufferUsages,
    ) -> Result<Self, GpuError> {
        let array = Self::zeroed(
            ctx,
            what,
            layout,
            contents.len() as u64 / layout.bytes,
            usage,
        )?;
        array.write(ctx, what, contents)?;
        Ok(array)
    }

    /// Writes `contents` (whole elements, from element 0) across the chunks.
    pub(crate) fn write(
        &self,
        ctx: &GpuContext,
        what: &'static str,
        contents: &[u8],
    ) -> Result<(), GpuError> {
        let chunk_bytes = (1usize << self.shift) * self.element_bytes as usize;
        super::scoped(ctx, what, || {
            for (buffer, bytes) in self.buffers.iter().zip(contents.chunks(chunk_bytes)) {
                ctx.queue().write_buffer(buffer, 0, bytes);
            }
            Ok(())
        })
    }

    /// The chunk buffers, in order (bound whole, one binding each, after the kernel's others:
    /// [`super::bind_buffers`]).
    pub(crate) fn buffers(&self) -> &[wgpu::Buffer] {
        &self.buffers
    }

    /// Bytes held over all chunks.
    pub(crate) fn bytes(&self) -> u64 {
        self.len * self.element_bytes
    }

    /// How the array is split: its chunk count and `log2` of the chunk length.
    pub(crate) fn shape(&self) -> SplitShape {
        SplitShape {
            chunks: self.buffers.len(),
            shift: self.shift,
        }
    }

    /// Clears every chunk to zero.
    pub(crate) fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        for buffer in &self.buffers {
            encoder.clear_buffer(buffer, 0, None);
        }
    }

    /// Reads the whole array back (the chunks need `COPY_SRC`), waiting for queued work.
    pub(crate) fn read(&self, ctx: &GpuContext, what: &'static str) -> Result<Vec<u8>, GpuError> {
        let mut out = Vec::with_capacity(self.bytes() as usize);
        for buffer in &self.buffers {
            out.extend(super::read_buffer(ctx, what, buffer, buffer.size())?);
        }
        out.truncate(self.bytes() as usize);
        Ok(out)
    }
}

/// How a [`SplitArray`] is split: `chunks` buffers of `2^shift` elements (the last shorter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct SplitShape {
    /// Number of chunk buffers (bindings), at least 1.
    pub(crate) chunks: usize,
    /// `log2` of the elements per chunk.
    pub(crate) shift: u32,
}

/// The WGSL declarations of an array of `layout` split as `shape` (group 0, bindings
/// `first_binding …`) and of its accessor; see the module docs.
pub(crate) fn declarations(
    layout: ArrayLayout,
    shape: SplitShape,
    first_binding: u32,
    access: Access,
) -> String {
    use std::fmt::Write as _;
    let (name, element) = (layout.name, layout.element);
    let mut out = String::new();
    let qualifier = match access {
        Access::Read => "read",
        Access::AtomicAdd => "read_write",
    };
    for k in 0..shape.chunks {
        // Writing into a String cannot fail.
        let _ = writeln!(
            out,
            "@group(0) @binding({}) var<storage, {qualifier}> {name}_{k}: array<{element}>;",
            first_binding + k as u32
        );
    }
    let statement = |k: usize, index: &str| match access {
        Access::Read => format!("return {name}_{k}[{index}];"),
        Access::AtomicAdd => format!("atomicAdd(&{name}_{k}[{index}], v);"),
    };
    let signature = match access {
        Access::Read => format!("fn {name}_at(i: u32) -> {element}"),
        Access::AtomicAdd => format!("fn {name}_add(i: u32, v: u32)"),
    };
    if shape.chunks == 1 {
        let _ = writeln!(out, "{signature} {{ {} }}", statement(0, "i"));
        return out;
    }
    let last = shape.chunks - 1;
    let _ = writeln!(
        out,
        "{signature} {{\n    let j = i & {}u;\n    switch i >> {}u {{",
        (1u64 << shape.shift) - 1,
        shape.shift
    );
    for k in 0..last {
        let _ = writeln!(out, "        case {k}u: {{ {} }}", statement(k, "j"));
    }
    let _ = writeln!(
        out,
        "        default: {{ {} }}\n    }}\n}}",
        statement(last, "j")
    );
    out
}

/// Refuses a pipeline whose storage bindings exceed the device's per-stage limit, naming
/// what needs them.
pub(crate) fn check_bindings(
    ctx: &GpuContext,
    what: &'static str,
    storage_bindings: u32,
) -> Result<(), GpuError> {
    let limit = ctx.device().limits().max_storage_buffers_per_shader_stage;
    if storage_bindings > limit {
        return Err(GpuError::TooManyBindings {
            what,
            needed: storage_bindings,
            limit,
        });
    }
    Ok(())
}
